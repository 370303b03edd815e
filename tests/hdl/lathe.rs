//! Co-simulation on the lathe simulator's closed-loop measurement cycle (approach,
//! decision, retract, Z step, repeat), run fast and coarse (4800 rpm at a 1 MHz clock) so
//! a whole cycle is a few hundred thousand clocks: Verilator and Icarus must match the
//! golden cycle model on every cycle. Prints both simulators' speeds (cycles/s; not
//! asserted).

use tooltouch_model::{FrontEnd, MeasureConfig};
use tooltouch_plant::lathe::LatheScenario;
use tooltouch_plant::measurement_cycle::closed_loop_stimulus;
use tooltouch_rtl_sim::cosim::{cosim, CosimPlan};
use tooltouch_rtl_sim::runner::CxxOpt;

fn scenario() -> LatheScenario {
    let mut s = LatheScenario {
        clock_hz: 1_000_000,
        rpm: 4800.0,
        // A verification lathe: the measuring path is the machining path.
        spindle_path: tooltouch_plant::lathe::SpindlePath::none(),
        ..LatheScenario::default()
    };
    // More measurements (a longer stimulus, for speed figures) via TOOLTOUCH_LATHE_REPEATS.
    s.cycle.repeats = std::env::var("TOOLTOUCH_LATHE_REPEATS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2);
    s.cycle.clearance_um = 3.0;
    s.cycle.z_dwell_ms = 0.2;
    s.cycle.retract_mm_per_s = 2.0;
    s
}

#[test]
fn hdl_lathe_measurement_cycle_matches_the_model_in_verilator_and_icarus() {
    let config = MeasureConfig::default();
    let stimulus = closed_loop_stimulus(&scenario(), &config).expect("valid scenario");
    // It is a real measurement: the model decides at least once.
    let mut fe = FrontEnd::new(&config);
    let decided = stimulus.cycles().any(|p| {
        fe.clock(p);
        fe.outputs().register_now
    });
    assert!(decided, "the scenario never reached a decision");
    let work = tempfile::tempdir().expect("temporary folder");
    let plan = CosimPlan {
        opt: CxxOpt::O3,
        ..CosimPlan::default()
    };
    let report = cosim(&config, &[stimulus], work.path(), &plan).expect("cosim runs");
    for r in &report.runs {
        assert!(
            r.passed,
            "{}: {}",
            r.simulator,
            r.first_mismatch.as_deref().unwrap_or(&r.output)
        );
        println!(
            "{}: {} cycles in {:.3} s = {:.0} cycles/s",
            r.simulator,
            r.cycles,
            r.seconds,
            r.cycles_per_second()
        );
    }
    for (sim, s) in &report.build_seconds {
        println!("{sim} build: {s:.1} s");
    }
}
