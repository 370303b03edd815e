//! The reference front end (`tooltouch_hdl_gen::reference`, the plain RTL the formal proof
//! compares the optimized design with) is itself checked against the golden model: the
//! same self-checking testbench and vectors as the optimized design's co-simulation
//! (`tests/hdl/cosim.rs`), with the reference standing in for `tt_frontend`, in Verilator
//! and Icarus; and the same lint gates (`verilator --lint-only -Wall`, yosys `check` with no
//! latch; the reference as its own top) for every structural variant of the formal proof.
//!
//! `TOOLTOUCH_CASES=N` raises the number of random configurations (default 3).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::path::Path;
use std::process::Command;
use tooltouch_hdl_gen::{
    reference, testbench, verilator_main, Options, TestbenchSpec, REFERENCE_TOP, TOP,
};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::random::{random_config, random_stimulus};
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_rtl_sim::runner::{build, run, CxxOpt, Simulator};
use tooltouch_vectors::hex::{golden_vectors, write_vectors};

/// Stimuli per configuration and their length, clocks.
const STIMULI: usize = 2;
const CYCLES: u64 = 20_000;

/// Runs the reference (as module `tt_frontend`) against the model's vectors of `stimuli`
/// in both simulators; `Err` names the first failure.
fn cosim_reference(
    config: &MeasureConfig,
    options: &Options,
    stimuli: &[Stimulus],
    work: &Path,
) -> Result<(), String> {
    let mut vectors = Vec::new();
    for (i, s) in stimuli.iter().enumerate() {
        let v = golden_vectors(config, s).map_err(|e| e.to_string())?;
        write_vectors(&work.join(format!("case{i}")), &v).map_err(|e| e.to_string())?;
        vectors.push(v);
    }
    let spec = TestbenchSpec {
        clock_hz: stimuli[0].clock_hz,
        stim_depth: vectors.iter().map(|v| v.stim_words).max().unwrap_or(2),
        expect_depth: vectors.iter().map(|v| v.expect_words).max().unwrap_or(2),
        mcu_diagnostics: options.mcu_diagnostics,
    };
    let tb = testbench(config, &spec).ok_or("no testbench for this clock")?;
    let rtl = work.join("rtl");
    std::fs::create_dir_all(&rtl).map_err(|e| e.to_string())?;
    let mut files = Vec::new();
    for f in [reference(config, options, TOP), tb] {
        let p = rtl.join(&f.name);
        std::fs::write(&p, &f.text).map_err(|e| e.to_string())?;
        files.push(p);
    }
    if let Some(main) = verilator_main(config, &spec) {
        let p = rtl.join(&main.name);
        std::fs::write(&p, &main.text).map_err(|e| e.to_string())?;
        files.push(p);
    }
    for sim in [Simulator::Verilator, Simulator::Icarus] {
        let b = build(sim, &files, &work.join(format!("build_{sim}")), CxxOpt::O1)
            .map_err(|e| e.to_string())?;
        for (i, v) in vectors.iter().enumerate() {
            let r = run(&b, &work.join(format!("case{i}")), &[]).map_err(|e| e.to_string())?;
            if !r.passed {
                return Err(format!(
                    "{sim} case {i}: {}",
                    r.first_mismatch.as_deref().unwrap_or(&r.output)
                ));
            }
            if r.cycles != v.cycles {
                return Err(format!(
                    "{sim} case {i}: {} cycles simulated, the model {}",
                    r.cycles, v.cycles
                ));
            }
        }
    }
    Ok(())
}

#[test]
fn hdl_reference_matches_the_model_in_verilator_and_icarus() {
    let n = u64::from(tooltouch_model::testing::cases(3));
    let work = tempfile::tempdir().expect("temporary folder");
    // The default configuration, then random ones (every other with the MCU's
    // diagnostic counters readable).
    let failures: Vec<String> = (0..=n)
        .into_par_iter()
        .filter_map(|i| {
            let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_7ef0 + i);
            let config = if i == 0 {
                MeasureConfig::default()
            } else {
                random_config(&mut rng)
            };
            let clock_hz = 50_000_000;
            let stimuli: Vec<_> = (0..STIMULI)
                .map(|_| random_stimulus(&mut rng, &config, clock_hz, CYCLES))
                .collect();
            let options = Options {
                mcu_diagnostics: i % 2 == 1,
                ..Options::default()
            };
            let dir = work.path().join(format!("config{i}"));
            cosim_reference(&config, &options, &stimuli, &dir)
                .err()
                .map(|e| format!("config {i} ({:?}): {e}", config.settings()))
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} configurations failed:\n{}",
        failures.len(),
        n + 1,
        failures.join("\n")
    );
}

#[test]
fn hdl_reference_lint_verilator_wall_and_yosys_check_are_clean() {
    let work = tempfile::tempdir().expect("temporary folder");
    for (i, (name, config, options)) in tooltouch_hdl_gen::formal::variants().iter().enumerate() {
        let dir = work.path().join(format!("v{i}"));
        std::fs::create_dir_all(&dir).expect("folder");
        let f = reference(config, options, REFERENCE_TOP);
        let p = dir.join(&f.name);
        std::fs::write(&p, &f.text).expect("writing the reference");
        let lint = Command::new("verilator")
            .args(["--lint-only", "-Wall", "--top-module", REFERENCE_TOP])
            .arg(&p)
            .output()
            .expect("verilator is not installed: run `cargo xtask setup`");
        let text = String::from_utf8_lossy(&lint.stderr);
        assert!(
            lint.status.success() && !text.contains("%Warning"),
            "variant {name}: verilator --lint-only -Wall:\n{text}"
        );
        let check = Command::new("yosys")
            .args(["-q", "-p"])
            .arg(format!(
                "read_verilog {}; hierarchy -check -top {REFERENCE_TOP}; proc; check -assert; \
                 select -assert-none t:$dlatch t:$adlatch t:$dlatchsr t:$sr",
                p.display()
            ))
            .output()
            .expect("yosys is not installed: run `cargo xtask setup`");
        assert!(
            check.status.success(),
            "variant {name}: yosys check:\n{}{}",
            String::from_utf8_lossy(&check.stdout),
            String::from_utf8_lossy(&check.stderr)
        );
    }
}
