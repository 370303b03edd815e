//! The bench harness's model runs do the same work: plain clocking, fast-forward and the
//! event level give identical results on the realistic stimulus and on the tuning
//! scenarios, and the HDL timing path runs the runner's bit-for-bit testbench.

use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_rtl_sim::speed;
use tooltouch_tune::scenario::{approach, ApproachSettings};

#[test]
fn plain_fast_forward_and_event_level_agree_on_the_realistic_stimulus() {
    let config = MeasureConfig::default();
    let stim = speed::realistic_stimulus(&config, 1).unwrap();
    let plain = speed::run_plain(&stim, &config);
    let (ff, clocked) = speed::run_fast_forward_counted(&stim, &config);
    assert_eq!(plain, ff);
    assert_eq!(plain.cycles, stim.total_cycles());
    assert!(
        plain.edge_clocks > 1000,
        "the stimulus exercises the kernel"
    );
    assert!(plain.outputs.register_now, "the measurement decided");
    assert!(
        clocked < plain.cycles / 10,
        "fast-forward skips settled clocks"
    );
    let events = speed::events(&stim, &config);
    assert_eq!(speed::run_events(&events, &config), plain.outputs);
}

#[test]
fn the_runs_agree_on_every_tuning_scenario_and_configuration() {
    let s = ApproachSettings {
        rpm: 6000.0,
        pulses_per_rev: 64,
        revolutions: 8,
        ..Default::default()
    };
    for seed in 1..=3 {
        let a = approach(&s, seed);
        for glitch in [0, 3] {
            let config = MeasureSettings {
                pulses_per_rev: 64,
                i_def: 32,
                glitch_cycles: glitch,
                ..Default::default()
            }
            .validate()
            .unwrap();
            let plain = speed::run_plain(&a.stimulus, &config);
            assert_eq!(plain, speed::run_fast_forward(&a.stimulus, &config));
            let events = speed::events(&a.stimulus, &config);
            assert_eq!(speed::run_events(&events, &config), plain.outputs);
        }
    }
}

#[test]
fn a_changed_stimulus_changes_the_digest() {
    // The digest is what the bench compares: it must see a single moved edge.
    let config = MeasureConfig::default();
    let stim = speed::prefix(&speed::realistic_stimulus(&config, 1).unwrap(), 5_000_000);
    let mut moved = stim.clone();
    let i = (moved.segments.len() / 2..moved.segments.len() - 1)
        .find(|&i| moved.segments[i].cycles > 100 && moved.segments[i + 1].cycles > 100)
        .unwrap();
    moved.segments[i].cycles += 1;
    moved.segments[i + 1].cycles -= 1;
    assert_ne!(
        speed::run_plain(&stim, &config).digest,
        speed::run_plain(&moved, &config).digest
    );
}

#[test]
fn the_hdl_timing_path_runs_the_bit_for_bit_testbench() {
    let config = MeasureConfig::default();
    let stim = speed::prefix(&speed::realistic_stimulus(&config, 1).unwrap(), 200_000);
    let dir = tempfile::tempdir().unwrap();
    let t = speed::hdl::time_simulator(
        tooltouch_rtl_sim::runner::Simulator::Icarus,
        &config,
        &stim,
        dir.path(),
    )
    .unwrap_or_else(|e| panic!("{e:#} (is Icarus installed? run `cargo xtask setup`)"));
    assert_eq!(t.cycles, stim.total_cycles());
    assert!(t.seconds > 0.0);
}

#[test]
fn the_bare_verilator_loop_ends_with_the_models_outputs() {
    let config = MeasureConfig::default();
    let stim = speed::prefix(&speed::realistic_stimulus(&config, 1).unwrap(), 2_000_000);
    let plain = speed::run_plain(&stim, &config);
    let dir = tempfile::tempdir().unwrap();
    let t = speed::verilator::time_bare_verilator(&config, &stim, &plain.outputs, dir.path())
        .unwrap_or_else(|e| panic!("{e:#} (is Verilator installed? run `cargo xtask setup`)"));
    assert_eq!(t.cycles, stim.total_cycles());
    // A wrong expectation must be caught: the harness checks the outputs it times.
    let mut wrong = plain.outputs;
    wrong.pulses = wrong.pulses.wrapping_add(1);
    let e = speed::verilator::time_bare_verilator(&config, &stim, &wrong, dir.path())
        .unwrap_err()
        .to_string();
    assert!(e.contains("signal pulses expected"), "{e}");
}
