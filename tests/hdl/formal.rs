//! The formal equivalence proof of the generated front end against the reference written
//! from the model's semantics (`tooltouch_hdl_gen::formal`, yosys `sat -tempinduct`):
//!
//! - the default configuration is proven (k-induction completes);
//! - every injected fault (`tooltouch_hdl_gen::Fault`) fails the proof with a counterexample
//!   from power-on, which, written as a VCD, `tooltouch vectors` turns into the golden
//!   model's response and `tooltouch check` then finds the faulty design's difference in;
//! - (ignored by default; `cargo xtask formal` runs it) the structural variants
//!   (`tooltouch_hdl_gen::formal::variants`) and random configurations are proven:
//!   `TOOLTOUCH_FORMAL_CONFIGS=N` random ones (default 4).
//!
//! Each proof prints its verdict, induction length and wall time (`--nocapture`).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::process::Command;
use tooltouch_hdl_gen::formal::{
    miter, prove, prove_miter, write_counterexample_vcd, Verdict, MAX_INDUCTION,
};
use tooltouch_hdl_gen::{Fault, Options};
use tooltouch_model::measure::config::{ChargeLaw, DecisionMethod};
use tooltouch_model::{FrontEnd, MeasureConfig, MeasureSettings};
use tooltouch_plant::random::random_config;

/// The faults the proof must refute: the two structural ones (a proof takes about a
/// minute each) and the design omitting the `contact_at_arm` condition. The one-LSB parameter faults and the rule faults are refuted by
/// simulation on the stress vectors (tests/hdl/stress.rs). The match fails to compile
/// when a variant is added, so a new fault is placed in one list or the other.
fn faults() -> Vec<Fault> {
    let all = [
        Fault::FesBeforeIndex,
        Fault::FireThresholdPlusOne,
        Fault::ContactAtArmNotRaised,
    ];
    for f in Fault::ALL {
        match f {
            Fault::None
            | Fault::FesBeforeIndex
            | Fault::FireThresholdPlusOne
            | Fault::ContactAtArmNotRaised => {}
            Fault::FireThresholdMinusOne
            | Fault::RearmThresholdPlusOne
            | Fault::RearmThresholdMinusOne
            | Fault::IdefPlusOne
            | Fault::IdefMinusOne
            | Fault::GlitchFilterPlusOne
            | Fault::GlitchFilterMinusOne
            | Fault::ChargeStepPlusOne
            | Fault::ChargeStepMinusOne
            | Fault::DischargeStepPlusOne
            | Fault::DischargeStepMinusOne
            | Fault::StickyNotReloadedWhileDisarmed
            | Fault::LatchNotClearedByArm => {}
        }
    }
    all.to_vec()
}

/// Proves `config` with `options` in `dir`, printing the verdict; panics unless proven.
fn assert_proven(name: &str, config: &MeasureConfig, options: &Options, dir: &Path) {
    let proof = prove(config, options, dir, MAX_INDUCTION)
        .unwrap_or_else(|e| panic!("{name}: the proof did not run: {e}"));
    println!(
        "formal {name}: {:?}, reset {}, in {:.1} s ({})",
        proof.verdict,
        if proof.reset_proven {
            "proven"
        } else {
            "NOT proven"
        },
        proof.seconds,
        proof.dir.display()
    );
    assert!(
        proof.reset_proven,
        "{name}: one clock of rst does not lead to a state where every assertion holds; \
         files in {}",
        proof.dir.display()
    );
    match proof.verdict {
        Verdict::Proven { .. } => {}
        Verdict::Counterexample(t) => panic!(
            "{name} ({:?}): the designs differ or an invariant fails after {} clocks: {:?}; \
             files in {}",
            config.settings(),
            t.pins.len(),
            t.failed,
            proof.dir.display()
        ),
        Verdict::Undecided { depth } => panic!(
            "{name} ({:?}): not proven: the base case holds for {depth} clocks but the \
             induction step fails at every length up to it; files in {}",
            config.settings(),
            proof.dir.display()
        ),
    }
}

#[test]
fn hdl_formal_default_configuration_is_proven() {
    let work = tempfile::tempdir().expect("temporary folder");
    assert_proven(
        "default",
        &MeasureConfig::default(),
        &Options::default(),
        work.path(),
    );
}

/// A small configuration in which both faults show within a few clocks: no glitch
/// filter, a capacitor that reaches the fire threshold in one contact pulse, a counter
/// deciding on the third contact pulse.
fn small_config() -> MeasureSettings {
    MeasureSettings {
        pulses_per_rev: 16,
        i_def: 2,
        charge_bits: 4,
        charge_law: ChargeLaw::Linear {
            charge_step: 8,
            discharge_step: 1,
        },
        fire_threshold: 8,
        rearm_threshold: 1,
        glitch_cycles: 0,
        scale_bits: 8,
        method: DecisionMethod::Density,
        ..Default::default()
    }
}

/// Runs the built `tooltouch` with `args`; returns its exit code and output.
fn tooltouch(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .args(args)
        .output()
        .expect("running tooltouch");
    (
        out.status.code().unwrap_or(-1),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

#[test]
fn hdl_formal_every_fault_fails_with_a_counterexample_that_tooltouch_check_replays() {
    let settings = small_config();
    let config = settings.validate().expect("valid small configuration");
    let work = tempfile::tempdir().expect("temporary folder");
    let toml_path = work.path().join("settings.toml");
    let mut table = toml::Table::new();
    table.insert(
        "measure".into(),
        toml::Value::try_from(settings).expect("settings as TOML"),
    );
    std::fs::write(&toml_path, toml::to_string(&table).expect("TOML text")).expect("writing");
    // The correct design is proven in this configuration.
    assert_proven(
        "small",
        &config,
        &Options::default(),
        &work.path().join("None"),
    );
    for fault in faults() {
        let dir = work.path().join(format!("{fault:?}"));
        let options = Options {
            fault,
            ..Options::default()
        };
        let proof = prove(&config, &options, &dir, MAX_INDUCTION).expect("the proof runs");
        println!(
            "formal {fault:?}: {:?} in {:.1} s",
            proof.verdict, proof.seconds
        );
        let Verdict::Counterexample(trace) = proof.verdict else {
            panic!(
                "{fault:?}: expected a counterexample, got {:?}",
                proof.verdict
            )
        };
        assert!(
            trace
                .failed
                .iter()
                .any(|a| !a.starts_with("ok_ref_") && !a.starts_with("ok_model_")),
            "{fault:?}: the counterexample must break a comparison with the design, not only \
             the reference's own invariants: {:?}",
            trace.failed
        );
        // The trace is real: the model on its pins differs from the faulty design's
        // outputs after some clock.
        let mut fe = FrontEnd::new(&config);
        let differs = trace.pins.iter().zip(&trace.outputs).any(|(&p, o)| {
            fe.clock(tooltouch_model::measure::frontend::Pins(p));
            tooltouch_hdl_gen::output_values(&config, &fe.outputs()) != *o
        });
        assert!(
            differs || trace.failed.iter().any(|a| a == "ok_mcu_rdata"),
            "{fault:?}: the counterexample's outputs equal the model's: {trace:?}"
        );
        // Replay: the golden model's response to the counterexample's pins, then check.
        let vcd = dir.join("counterexample.vcd");
        write_counterexample_vcd(&config, &trace, 50_000_000, &vcd).expect("writing the VCD");
        let golden = dir.join("golden");
        let (code, out) = tooltouch(&[
            "vectors",
            "--stimulus",
            vcd.to_str().expect("UTF-8 path"),
            "--config",
            toml_path.to_str().expect("UTF-8 path"),
            "--out",
            golden.to_str().expect("UTF-8 path"),
        ]);
        assert_eq!(code, 0, "{fault:?}: tooltouch vectors failed:\n{out}");
        let (code, out) = tooltouch(&[
            "check",
            "--expected",
            golden.join("golden.vcd").to_str().expect("UTF-8 path"),
            "--dut",
            vcd.to_str().expect("UTF-8 path"),
        ]);
        println!("{fault:?}: tooltouch check: {}", out.trim());
        if differs {
            assert_eq!(
                code, 1,
                "{fault:?}: tooltouch check must find the difference:\n{out}"
            );
            assert!(out.contains("MISMATCH"), "{fault:?}: {out}");
        }
    }
}

/// The latency and arithmetic properties are not vacuous: each one, stated one clock or one
/// sign off, fails with a counterexample that names it (in the small configuration with a
/// one-clock glitch filter, where each shows within the base case's 12 clocks).
#[test]
fn hdl_formal_properties_stated_wrongly_fail() {
    let config = MeasureSettings {
        glitch_cycles: 1,
        ..small_config()
    }
    .validate()
    .expect("valid configuration");
    let options = Options::default();
    let work = tempfile::tempdir().expect("temporary folder");
    let wrong = [
        (
            "the armed output one clock early",
            "(hist[6 * (gj + 2) + 0] != ref_armed)",
            "(hist[6 * (gj + 1) + 0] != ref_armed)",
            "ok_latency_levels",
        ),
        (
            "the armed output changing one clock late",
            "(hist[6 * (gj + 2) + 0] == ref_armed)",
            "(hist[6 * (gj + 3) + 0] == ref_armed)",
            "ok_latency_levels",
        ),
        (
            "the filter passing a level one clock early",
            "(hist[6 * (gj + 1) + 1] != probe_r_filtered[1])",
            "(hist[6 * (gj + 0) + 1] != probe_r_filtered[1])",
            "ok_latency_filter",
        ),
        (
            "the position stepping the other way",
            "ref_position == held_position + held_position_step",
            "ref_position == held_position - held_position_step",
            "ok_model_position",
        ),
        (
            "a contact pulse lowering the charge",
            "ref_charge >= held_charge_base",
            "ref_charge < held_charge_base",
            "ok_model_charge",
        ),
    ];
    for (i, (what, from, to, assertion)) in wrong.iter().enumerate() {
        let mut m = miter(&config, &options);
        assert!(
            m.file.text.contains(from),
            "{what}: `{from}` is not in the miter:\n{}",
            m.file.text
        );
        m.file.text = m.file.text.replace(from, to);
        let proof = prove_miter(
            &config,
            &options,
            &m,
            &work.path().join(format!("wrong{i}")),
            MAX_INDUCTION,
        )
        .expect("the proof runs");
        let Verdict::Counterexample(trace) = proof.verdict else {
            panic!("{what}: expected a counterexample, got {:?}", proof.verdict)
        };
        println!(
            "formal, {what}: a counterexample of {} clocks failing {:?} in {:.1} s",
            trace.pins.len(),
            trace.failed,
            proof.seconds
        );
        assert!(
            trace.failed.iter().any(|a| a == assertion),
            "{what}: expected {assertion} to fail, failed: {:?}",
            trace.failed
        );
    }
}

/// How many random configurations [`hdl_formal_variants_and_random_configs_are_proven`]
/// proves: `TOOLTOUCH_FORMAL_CONFIGS`, default 4.
fn random_count() -> u64 {
    std::env::var("TOOLTOUCH_FORMAL_CONFIGS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(4)
}

#[test]
#[ignore = "minutes: run by `cargo xtask formal`"]
fn hdl_formal_variants_and_random_configs_are_proven() {
    let work = tempfile::tempdir().expect("temporary folder");
    let mut cases = tooltouch_hdl_gen::formal::variants();
    for i in 0..random_count() {
        let mut rng = ChaCha8Rng::seed_from_u64(0xf0_4a1 + i);
        let options = Options {
            mcu_diagnostics: i % 2 == 1,
            ..Options::default()
        };
        cases.push((format!("random {i}"), random_config(&mut rng), options));
    }
    for (i, (name, config, options)) in cases.iter().enumerate() {
        assert_proven(name, config, options, &work.path().join(format!("case{i}")));
    }
}
