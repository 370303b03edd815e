//! The nonlinear, time-varying process (docs/control.md, "The nonlinear process") and F9's
//! sign condition: the plant's steady force follows the Kienzle law's feed exponent, not
//! F10's, the three controllers designed on its linearization bring the force back after
//! the depth step on measured and estimated force, and F9 switches to the fast estimate on
//! a rising load but not on a falling one (the paper's "positive difference").

use tooltouch_model::force::config::ForceSource;
use tooltouch_plant::drive::estimator_report::{delay_63, depth_step_scenario, DEPTH_LEVELS};
use tooltouch_plant::drive::kienzle::KienzleProcess;
use tooltouch_plant::drive::scenario::{
    kienzle_settings, run, ControlScenario, ControllerKind, Engine,
};

/// Mean true force over 4–7 s of an open-loop cut at `override_pct`, no drift or wander.
fn steady_force(kienzle: Option<KienzleProcess>, override_pct: u8) -> f64 {
    let mut sc = depth_step_scenario(1);
    sc.process.ks_drift = 0.0;
    sc.depth.step_at = f64::INFINITY;
    sc.kienzle = kienzle;
    let mut s = *sc.config.settings();
    s.manual_override = override_pct;
    sc.config = s.validate().expect("valid");
    let r = run(&sc, Engine::Model, false);
    let v: Vec<f64> = r
        .trace
        .t
        .iter()
        .zip(&r.trace.force_true)
        .filter(|(t, _)| **t > 4.0 && **t <= 7.0)
        .map(|(_, f)| *f)
        .collect();
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn the_steady_force_follows_the_feed_exponent() {
    let k = KienzleProcess {
        ks_wander: 0.0,
        ..KienzleProcess::default()
    };
    // halving the feed: 0.5^0.75 = 0.595 of the force (F10: 0.5), within 1 % (the ripple)
    let ratio = steady_force(Some(k), 50) / steady_force(Some(k), 100);
    assert!((ratio - 0.5f64.powf(0.75)).abs() < 0.01, "{ratio}");
    let linear = steady_force(None, 50) / steady_force(None, 100);
    assert!((linear - 0.5).abs() < 0.01, "{linear}");
    // at the reference feed (100 %) the law equals F10: 2000·1·0.3 = 600 N
    let at_ref = steady_force(Some(k), 100);
    assert!((at_ref - 600.0).abs() < 6.0, "{at_ref}");
}

fn kienzle_scenario(kind: ControllerKind, source: ForceSource, seed: u64) -> ControlScenario {
    let k = KienzleProcess::default();
    let config = kienzle_settings(kind, source, &k)
        .validate()
        .expect("valid");
    let mut sc = ControlScenario::new(config).with_kienzle_process();
    sc.seed = seed;
    sc
}

#[test]
fn every_controller_brings_the_force_back_on_the_nonlinear_process() {
    for kind in ControllerKind::ALL {
        for source in [ForceSource::Measured, ForceSource::Estimated] {
            let r = run(&kienzle_scenario(kind, source, 2), Engine::Model, false);
            let m = r.metrics;
            assert!(m.settling_s < 3.0, "{} {source:?}: {m:?}", kind.name());
            assert!(
                m.steady_error_n.abs() < 25.0,
                "{} {source:?}: {m:?}",
                kind.name()
            );
            assert!(m.overshoot_pct < 40.0, "{} {source:?}: {m:?}", kind.name());
        }
    }
}

#[test]
fn f9_switches_on_a_rising_load_only() {
    // open loop: the depth steps up 1 → 1.5 mm, or down 1.5 → 1 mm, at 8 s
    let fast_after_step = |before: f64, after: f64| {
        let mut sc = depth_step_scenario(1);
        sc.depth.before = before;
        sc.depth.after = after;
        let r = run(&sc, Engine::Model, false);
        let tr = &r.trace;
        let fast =
            tr.t.iter()
                .zip(&tr.fast)
                .any(|(t, f)| *t > 8.0 && *t <= 9.0 && *f);
        let synthesized = delay_63(tr, &tr.force_est, 8.0, DEPTH_LEVELS).unwrap_or(f64::NAN);
        let power_only = delay_63(tr, &tr.force_power_only, 8.0, DEPTH_LEVELS).unwrap_or(f64::NAN);
        (fast, synthesized, power_only)
    };
    let (fast, synthesized, power_only) = fast_after_step(1.0, 1.5);
    assert!(fast, "the rising step switches to the fast estimate");
    assert!(
        synthesized + 0.15 < power_only,
        "{synthesized} {power_only}"
    );
    // falling: P_g drops below the lagging P_o, a negative difference: F9 stays on P_o and
    // the synthesized estimate falls as late as the power-only one
    let (fast, synthesized, power_only) = fast_after_step(1.5, 1.0);
    assert!(!fast, "the falling step stays on P_o");
    assert!(
        (synthesized - power_only).abs() < 0.03,
        "{synthesized} {power_only}"
    );
}
