//! Stress stimuli close what random ones leave open: every fault hdl-gen injects fails the
//! self-checking testbench and `tooltouch check` on the stress vectors
//! (`tooltouch vectors --stress SEED`) of the default configuration and of a density-method,
//! exponential-law one, except the faults a configuration makes equivalent (no output can
//! show them there, with why), which must then pass. Each mismatch's report is checked
//! like `faults.rs` checks it (the differing signals, the pins before, the MCU read, the
//! window files).
//!
//! Short by default (seed 1, a 2 000-clock random tail); `TOOLTOUCH_STRESS_SEEDS=1,2,3` and
//! `TOOLTOUCH_STRESS_RANDOM=<clocks>` run more.

use crate::faults::{assert_mismatch_report, check_with_reports};
use tooltouch_hdl_gen::{Fault, Options};
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_plant::stress::{stress_stimulus, StressSize};
use tooltouch_rtl_sim::cosim::{cosim, CosimPlan};
use tooltouch_rtl_sim::runner::Simulator;
use tooltouch_vectors::coverage::coverage;

/// The two configurations of the acceptance: the default (pulse counter, linear law) and a
/// density-method one with the exponential law.
fn configurations() -> [(&'static str, MeasureConfig); 2] {
    [
        ("default", MeasureConfig::default()),
        (
            "density/exponential",
            MeasureSettings {
                method: DecisionMethod::Density,
                charge_law: ChargeLaw::Exponential {
                    charge_shift: 3,
                    discharge_shift: 4,
                },
                ..MeasureSettings::default()
            }
            .validate()
            .expect("a valid configuration"),
        ),
    ]
}

/// Why no stimulus can show `fault` at `config` (an equivalent mutant), if so.
fn equivalent(fault: Fault, config: &MeasureConfig) -> Option<&'static str> {
    let s = config.settings();
    match fault {
        Fault::IdefPlusOne | Fault::IdefMinusOne if s.method != DecisionMethod::Counter => {
            Some("the pulse counter's decision drives no output unless it is the decision method")
        }
        Fault::StickyNotReloadedWhileDisarmed if s.contact_rule == ContactRule::Sampled => {
            Some("the sampled rule never reads the sticky bit")
        }
        _ => None,
    }
}

fn env_list(name: &str, default: &[u64]) -> Vec<u64> {
    std::env::var(name).map_or_else(
        |_| default.to_vec(),
        |v| {
            v.split(',')
                .map(|x| {
                    x.trim()
                        .parse()
                        .unwrap_or_else(|_| panic!("{name}: `{x}` is not a number"))
                })
                .collect()
        },
    )
}

#[test]
fn hdl_stress_vectors_catch_every_fault() {
    let seeds = env_list("TOOLTOUCH_STRESS_SEEDS", &[1]);
    let random = env_list("TOOLTOUCH_STRESS_RANDOM", &[2_000])[0];
    let size = StressSize {
        random_cycles: random,
        ..StressSize::default()
    };
    let work = tempfile::tempdir().expect("temporary folder");
    let mut table = Vec::new();
    for (name, config) in configurations() {
        for &seed in &seeds {
            let s = stress_stimulus(&config, seed, 50_000_000, &size);
            let period_ns = 1_000_000_000 / u64::from(s.clock_hz);
            // The behaviours the faults need are reached (the coverage of the same pins).
            let cov = coverage(&s, &config);
            for needed in [
                "window ends with count i_def - 1",
                "window ends with count i_def =",
                "window ends with count i_def + 1",
                "sticky bit reloaded by a pulse while disarmed",
                "arm rising edge clears held latches",
                "charge fire_threshold - 1",
                "charge reaches fire_threshold",
                "charge rearm_threshold - 1",
                "charge rearm_threshold =",
                "fes: pulse of glitch_cycles = 4 clocks (rejected)",
                "fes: pulse of glitch_cycles + 1",
            ] {
                let bin = cov
                    .bins
                    .iter()
                    .find(|b| b.name.starts_with(needed))
                    .unwrap_or_else(|| panic!("no bin `{needed}`"));
                assert!(
                    bin.hits > 0,
                    "{name} seed {seed}: `{}` not reached:\n{}",
                    bin.name,
                    cov.table()
                );
            }
            let dir = work
                .path()
                .join(format!("{}-{seed}", name.replace('/', "-")));
            std::fs::create_dir_all(&dir).expect("folder");
            let golden = dir.join("golden.vcd");
            let mut f =
                std::io::BufWriter::new(std::fs::File::create(&golden).expect("golden.vcd"));
            tooltouch_vectors::vcd::write_golden(&mut f, &s, &config, None)
                .expect("writing golden");
            drop(f);
            for fault in std::iter::once(Fault::None).chain(Fault::ALL) {
                if !fault.applies_to(&config) {
                    table.push(format!(
                        "{name:<20} {seed:>4} {fault:<32?} not injectable here"
                    ));
                    continue;
                }
                let run_dir = dir.join(format!("{fault:?}"));
                let plan = CosimPlan {
                    options: Options {
                        fault,
                        ..Options::default()
                    },
                    simulators: vec![Simulator::Icarus],
                    plusargs: vec!["+vcd".into(), "+nostop".into()],
                    ..CosimPlan::default()
                };
                let report =
                    cosim(&config, std::slice::from_ref(&s), &run_dir, &plan).expect("cosim");
                let run = &report.runs[0];
                let dut = run_dir.join("case0/dut.vcd");
                let (code, text, json, window) = check_with_reports(&golden, &dut, &run_dir);
                let first = text.lines().next().unwrap_or("").to_string();
                table.push(format!(
                    "{name:<20} {seed:>4} {fault:<32?} testbench {:<6} check {}",
                    if run.passed { "passes" } else { "FAILS" },
                    first
                ));
                match (fault, equivalent(fault, &config)) {
                    (Fault::None, _) => {
                        assert!(
                            run.passed,
                            "{name}: the correct design failed: {}",
                            run.output
                        );
                        assert_eq!(code, Some(0), "{name}: {text}");
                    }
                    (_, Some(why)) => {
                        assert!(
                            run.passed && code == Some(0),
                            "{fault:?} at {name} should be equivalent ({why}): {text}"
                        );
                        let last = table.len() - 1;
                        table[last].push_str(&format!("  (equivalent: {why})"));
                    }
                    (_, None) => {
                        let tb = run.first_mismatch.clone().unwrap_or_default();
                        assert!(
                            !run.passed,
                            "{fault:?} passed the testbench at {name} seed {seed}"
                        );
                        assert_mismatch_report(
                            &format!("{fault:?} at {name}"),
                            code,
                            &text,
                            &json,
                            &tb,
                            &window,
                            period_ns,
                        );
                    }
                }
            }
        }
    }
    eprintln!("{}", table.join("\n"));
}
