//! The checkers must catch a wrong design: a deliberately broken variant of the generated
//! Verilog (a fault injected by hdl-gen, tests only) fails the self-checking testbench,
//! and its VCD dump fails `tooltouch check --expected golden.vcd --dut dut.vcd`, while
//! the correct design passes both.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::process::Command;
use tooltouch_cosim::hdl::cosim::{cosim, CosimPlan};
use tooltouch_cosim::hdl::runner::Simulator;
use tooltouch_hdl_gen::{Fault, Options};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::random::random_stimulus;
use tooltouch_plant::stimulus::Stimulus;

fn stimulus(config: &MeasureConfig) -> Stimulus {
    let mut rng = ChaCha8Rng::seed_from_u64(0xfa17);
    random_stimulus(&mut rng, config, 50_000_000, 40_000)
}

fn plan(fault: Fault, plusargs: &[&str]) -> CosimPlan {
    CosimPlan {
        options: Options {
            fault,
            ..Options::default()
        },
        simulators: vec![Simulator::Icarus],
        plusargs: plusargs.iter().map(|s| s.to_string()).collect(),
        ..CosimPlan::default()
    }
}

#[test]
fn hdl_injected_faults_fail_the_self_checking_testbench() {
    // Equal steps that divide the fire threshold: every rise from empty passes through it.
    let config = tooltouch_model::MeasureSettings {
        charge_law: tooltouch_model::measure::config::ChargeLaw::Linear {
            charge_step: 4096,
            discharge_step: 4096,
        },
        fire_threshold: 32768,
        rearm_threshold: 8192,
        ..Default::default()
    }
    .validate()
    .expect("valid test configuration");
    let s = stimulus(&config);
    // Preconditions that make both faults observable in this stimulus: the charge sits
    // exactly on the fire threshold at some clock, and an index and an FES edge act in the
    // same clock while armed and in contact.
    let fire = config.settings().fire_threshold;
    let mut fe = tooltouch_model::FrontEnd::new(&config);
    let (mut on_threshold, mut index_with_fes) = (false, false);
    for p in s.cycles() {
        let before = fe.outputs();
        let edges = fe.clock(p);
        on_threshold |= fe.outputs().charge == fire;
        let both = tooltouch_model::measure::frontend::pin::INDEX
            | tooltouch_model::measure::frontend::pin::FES;
        index_with_fes |= edges.changed & edges.levels & both == both && before.armed;
    }
    assert!(
        on_threshold,
        "the stimulus never brings the charge to the fire threshold"
    );
    assert!(
        index_with_fes,
        "the stimulus has no same-clock index and FES edges"
    );
    let work = tempfile::tempdir().expect("temporary folder");
    for (fault, signal) in [
        (Fault::None, None),
        (Fault::FesBeforeIndex, Some("count")),
        (Fault::FireThresholdPlusOne, Some("density_")),
    ] {
        let dir = work.path().join(format!("{fault:?}"));
        let mut p = plan(fault, &[]);
        if fault == Fault::FesBeforeIndex {
            // Verilator too, once: its $fatal must fail the run the same way.
            p.simulators.push(Simulator::Verilator);
        }
        let report = cosim(&config, std::slice::from_ref(&s), &dir, &p).expect("cosim runs");
        for run in &report.runs {
            match signal {
                None => assert!(run.passed, "the correct design failed: {}", run.output),
                Some(name) => {
                    assert!(!run.passed, "{fault:?} was not caught by {}", run.simulator);
                    let m = run.first_mismatch.as_deref().unwrap_or("");
                    assert!(
                        m.starts_with("MISMATCH cycle ") && m.contains(&format!("signal {name}")),
                        "{fault:?} in {}: {m}",
                        run.simulator
                    );
                }
            }
        }
    }
}

fn check(golden: &Path, dut: &Path) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .arg("check")
        .arg("--expected")
        .arg(golden)
        .arg("--dut")
        .arg(dut)
        .output()
        .expect("running tooltouch check");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

#[test]
fn hdl_tooltouch_check_catches_a_broken_verilog_from_its_vcd() {
    let config = MeasureConfig::default();
    let mut s = stimulus(&config);
    // The golden VCD writer (host/vectors/src/vcd.rs) skips clock 0 when the stimulus starts
    // with all pins low (a settled front end), leaving the golden trace without values
    // until the first pin change; start with arm high so clock 0 is written.
    if s.segments.first().is_some_and(|seg| seg.pins.0 == 0) {
        s.segments.remove(0);
    }
    let work = tempfile::tempdir().expect("temporary folder");
    let golden = work.path().join("golden.vcd");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&golden).expect("golden.vcd"));
    tooltouch_vectors::vcd::write_golden(&mut f, &s, &config, None).expect("writing golden");
    drop(f);
    for fault in [Fault::None, Fault::FesBeforeIndex] {
        let dir = work.path().join(format!("{fault:?}"));
        let report = cosim(
            &config,
            std::slice::from_ref(&s),
            &dir,
            &plan(fault, &["+vcd", "+nostop"]),
        )
        .expect("cosim");
        let dut = dir.join("case0/dut.vcd");
        assert!(dut.is_file(), "the testbench wrote no dut.vcd");
        let (ok, text) = check(&golden, &dut);
        match fault {
            Fault::None => {
                assert!(report.runs[0].passed);
                assert!(ok, "check rejected the correct design:\n{text}");
            }
            _ => {
                assert!(!report.runs[0].passed);
                assert!(!ok, "check accepted {fault:?}:\n{text}");
                assert!(
                    text.contains("cycle ") && text.contains("signal count"),
                    "check's report of {fault:?}: {text}"
                );
            }
        }
    }
}
