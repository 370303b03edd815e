//! Physics of the measurement (docs/domain.md §2.1, §2.2, eq. S10) on the default lathe (D = 40 mm,
//! 800 rpm, f_r = 0.001 mm/rev, 0.1 µm scale, 50 MHz) without its spindle-path loads, 10
//! measurements each.

use tooltouch_model::measure::config::DecisionMethod;
use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_plant::lathe::{LatheScenario, RetractAt, SpindlePath};
use tooltouch_plant::measurement_cycle::{self, CycleRun};

fn config(method: DecisionMethod) -> MeasureConfig {
    MeasureSettings {
        method,
        ..Default::default()
    }
    .validate()
    .unwrap()
}

/// The default lathe with no spindle-path loads (and the 8 µm approach clearance that
/// needs): the methods' physics on the surface that was cut; the path's own effect is
/// tests/measure/spindle_path.rs's.
fn lathe() -> LatheScenario {
    let mut s = LatheScenario {
        spindle_path: SpindlePath::none(),
        ..LatheScenario::default()
    };
    s.cycle.clearance_um = 8.0;
    s
}

fn run(method: DecisionMethod, scenario: &LatheScenario) -> CycleRun {
    measurement_cycle::run(scenario, &config(method), &mut |_| {}).unwrap()
}

fn without_slow_errors() -> LatheScenario {
    let mut s = lathe();
    s.slow.iter_mut().for_each(|h| h.amplitude_um = 0.0);
    s
}

#[test]
fn single_pulse_measures_near_the_largest_diameter() {
    let r = run(DecisionMethod::SinglePulse, &lathe());
    let s = &r.summary;
    assert_eq!(s.decided, 10);
    // Δ_f = e + Δφ (S4): within the slow axis errors plus half a revolution's feed of the
    // largest diameter, and far above the mean.
    assert!(s.error_vs_largest_um.mean.abs() < 2.0, "{s:?}");
    assert!(s.error_vs_mean_um.mean > 4.0, "{s:?}");
    // Decides at the first contact.
    assert!(s.revs_to_decision.max < 0.01, "{s:?}");
}

#[test]
fn fifty_percent_counter_measures_near_the_mean_diameter() {
    let r = run(DecisionMethod::Counter, &lathe());
    let s = &r.summary;
    assert_eq!(s.decided, 10);
    // Near the mean: within the feed of the deciding revolution (2·f_r on the
    // diameter = 2 µm) plus one more for the slow errors, and far below the largest.
    assert!(s.error_vs_mean_um.mean.abs() < 3.0, "{s:?}");
    assert!(s.error_vs_largest_um.mean < -6.0, "{s:?}");
    // Decides after first contact and before contact is permanent.
    assert!(s.revs_to_decision.min > 1.0, "{s:?}");
    assert!(s.revs_to_decision.mean < s.revs_to_permanent.mean, "{s:?}");
}

#[test]
fn the_fifty_percent_scatter_comes_from_the_slow_spindle_errors() {
    let quantum = lathe().scale_resolution_um * 2.0;
    let with = run(DecisionMethod::Counter, &lathe()).summary;
    let without = run(DecisionMethod::Counter, &without_slow_errors()).summary;
    let (with_um, without_um) = (
        with.diameter_mm.std * 1000.0,
        without.diameter_mm.std * 1000.0,
    );
    // Without them the scatter collapses to the scale's quantization (S10) ...
    assert!(
        without_um <= quantum,
        "scatter {without_um} µm vs one count {quantum} µm"
    );
    // ... with them it is several counts.
    assert!(
        with_um >= 2.0 * quantum,
        "scatter {with_um} µm vs one count {quantum} µm"
    );
}

#[test]
fn burst_density_grows_to_permanent_contact() {
    let r = run(DecisionMethod::Counter, &lathe());
    for m in &r.measurements {
        let f = &m.contact_fraction;
        assert!(
            f.first().copied() == Some(0.0),
            "no contact at the start: {f:?}"
        );
        assert!(*f.last().unwrap() > 0.999, "permanent at the end: {f:?}");
        // Intermittent in between: some revolution has partial contact.
        assert!(f.iter().any(|&x| x > 0.05 && x < 0.95), "{f:?}");
        assert!(m.revs_to_permanent.unwrap() > m.revs_to_decision.unwrap());
        let counts = &m.window_counts;
        assert!(counts.iter().any(|&c| c > 512), "{counts:?}");
    }
}

#[test]
fn retract_at_decision_stops_the_feed_after_the_cnc_reaction() {
    let mut s = lathe();
    s.cycle.retract_at = RetractAt::Decision;
    s.cycle.repeats = 3;
    let r = run(DecisionMethod::Counter, &s);
    let reaction = (s.cycle.cnc_reaction_us * 50.0) as u64;
    for m in &r.measurements {
        assert_eq!(m.stop_cycle, m.decision_cycle.unwrap() + reaction + 1);
        assert!(m.permanent_contact_cycle.is_none());
    }
}

#[test]
fn runs_are_reproducible_and_seeded() {
    let mut s = lathe();
    s.cycle.repeats = 2;
    let a = run(DecisionMethod::Counter, &s);
    let b = run(DecisionMethod::Counter, &s);
    assert_eq!(a.stimulus, b.stimulus);
    s.seed = 2;
    let c = run(DecisionMethod::Counter, &s);
    assert_ne!(a.stimulus, c.stimulus);
}
