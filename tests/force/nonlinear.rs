//! The nonlinear, time-varying process (docs/control.md, "The nonlinear process") and F9 in
//! both directions: the plant's steady force follows the Kienzle law's feed exponent, not
//! F10's, the three controllers designed on its linearization bring the force back after
//! the depth step on measured and estimated force, and F9 switches to the fast estimate on
//! a rising load and on a falling one (eq. (9)'s |P_g − P_o|: the start and the end of a
//! cut).

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

/// F9 on an open-loop depth step at 8 s from `before` to `after` mm: whether it switched to
/// the fast estimate within a second of the step, and the 63 % delays of the synthesized,
/// power-only and electrical estimates and of the dynamometer, s.
fn f9_on_a_depth_step(before: f64, after: f64) -> (bool, [f64; 4]) {
    let mut sc = depth_step_scenario(1);
    sc.depth.before = before;
    sc.depth.after = after;
    let r = run(&sc, Engine::Model, false);
    let tr = &r.trace;
    let fast =
        tr.t.iter()
            .zip(&tr.fast)
            .any(|(t, f)| *t > 8.0 && *t <= 9.0 && *f);
    let delay = |x: &[f64]| delay_63(tr, x, 8.0, DEPTH_LEVELS).unwrap_or(f64::NAN);
    (
        fast,
        [
            delay(&tr.force_est),
            delay(&tr.force_power_only),
            delay(&tr.force_electrical),
            delay(&tr.force_meas),
        ],
    )
}

#[test]
fn f9_switches_at_the_start_and_at_the_end_of_a_cut() {
    // Eq. (9) is |P_g − P_o| > Δ_th·|P_o|: the load rising (the depth steps up 1 → 1.5 mm,
    // P_g runs ahead of the lagging P_o) and the load falling (1.5 → 1 mm, P_g drops below
    // it) both switch, and the synthesized estimate follows the step within the fast
    // path's lag: at most one period (0.05 s) behind the electrical estimate, at most
    // 0.1 s behind the dynamometer, and at least 0.15 s ahead of the power-only estimate
    // (whose lag is P_o's 0.3 s).
    for (before, after) in [(1.0, 1.5), (1.5, 1.0)] {
        let (fast, [synthesized, power_only, electrical, dynamometer]) =
            f9_on_a_depth_step(before, after);
        let what = format!(
            "{before} -> {after} mm: synthesized {synthesized:.3} s, power-only \
             {power_only:.3} s, electrical {electrical:.3} s, dynamometer {dynamometer:.3} s"
        );
        assert!(fast, "{what}: no switch to the fast estimate");
        assert!(synthesized <= electrical + 0.05, "{what}");
        assert!(synthesized <= dynamometer + 0.1, "{what}");
        assert!(synthesized + 0.15 < power_only, "{what}");
    }
}
