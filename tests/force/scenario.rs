//! Scenario tests of the force path (the experiment of docs/domain.md §3): the depth step at 500 N
//! with each controller, on measured and on estimated force, closed through the fixed-point
//! model; and the estimator against the plant's truth.

use tooltouch_model::force::config::ForceSource;
use tooltouch_plant::drive::scenario::{
    run, scenario_settings, ControlScenario, ControllerKind, Engine,
};

fn scenario(kind: ControllerKind, source: ForceSource) -> ControlScenario {
    let config = scenario_settings(kind, source)
        .validate()
        .expect("scenario settings are valid");
    ControlScenario::new(config)
}

#[test]
fn every_controller_brings_the_force_back_after_the_depth_step() {
    for kind in ControllerKind::ALL {
        for source in [ForceSource::Measured, ForceSource::Estimated] {
            let sc = scenario(kind, source);
            let r = run(&sc, Engine::Model, false);
            let m = r.metrics;
            println!("{} {:?}: {:?}", kind.name(), source, m);
            // back within 500 N ± 5 % and staying there, well before the end of the cut
            assert!(
                m.settling_s < 3.0,
                "{} on {:?} force: settling {} s",
                kind.name(),
                source,
                m.settling_s
            );
            assert!(
                m.steady_error_n.abs() < 25.0,
                "{} on {:?} force: steady-state error {} N",
                kind.name(),
                source,
                m.steady_error_n
            );
            // the last second's true force, period by period, within ±5 %
            let end = *r.trace.t.last().unwrap();
            for (t, f) in r.trace.t.iter().zip(&r.trace.force_true) {
                if *t > end - 1.0 {
                    assert!((f - 500.0).abs() <= 25.0, "{} at {t}: {f} N", kind.name());
                }
            }
        }
    }
}

#[test]
fn estimated_force_control_stays_close_to_measured_force_control() {
    for kind in ControllerKind::ALL {
        let m = run(&scenario(kind, ForceSource::Measured), Engine::Model, false);
        let e = run(
            &scenario(kind, ForceSource::Estimated),
            Engine::Model,
            false,
        );
        // mean absolute difference of the true force, from 0.5 s after engagement
        let (mut sum, mut n) = (0.0, 0);
        for (i, t) in m.trace.t.iter().enumerate() {
            if *t > 3.5 {
                sum += (m.trace.force_true[i] - e.trace.force_true[i]).abs();
                n += 1;
            }
        }
        let mad = sum / n as f64;
        println!(
            "{}: mean |F_measured-run − F_estimated-run| = {mad:.1} N",
            kind.name()
        );
        assert!(mad < 15.0, "{}: {mad} N", kind.name());
        assert!(
            (m.metrics.iae - e.metrics.iae).abs() < 0.6 * m.metrics.iae,
            "{}: IAE {} vs {}",
            kind.name(),
            m.metrics.iae,
            e.metrics.iae
        );
    }
}

#[test]
fn estimator_tracks_the_true_force_and_identifies_friction() {
    let sc = scenario(ControllerKind::Pi, ForceSource::Measured);
    let r = run(&sc, Engine::Model, false);
    let (b, t_fco) = r.identified;
    println!("identified B = {b}, T_fco = {t_fco}");
    assert!(
        (b - sc.drive.viscous).abs() < 0.5 * sc.drive.viscous + 0.002,
        "B = {b}"
    );
    assert!((t_fco - sc.drive.coulomb).abs() < 0.3, "T_fco = {t_fco}");
    let (mut sum, mut n) = (0.0, 0);
    for (i, t) in r.trace.t.iter().enumerate() {
        if (5.0..8.0).contains(t) || *t > 10.0 {
            sum += r.trace.force_est[i] - r.trace.force_true[i];
            n += 1;
        }
    }
    let bias = sum / n as f64;
    println!("estimator bias in steady cutting: {bias:.1} N");
    // F9: the fast electrical estimate takes over right after the depth step (P_o lags
    // 0.3 s behind) and hands back to the smooth P_o once it has caught up
    let fast_at = |from: f64, to: f64| {
        r.trace
            .t
            .iter()
            .zip(&r.trace.fast)
            .filter(|(t, f)| (from..to).contains(*t) && **f)
            .count()
    };
    println!(
        "fast periods: 8.0-8.5 s {}, 11-13 s {}",
        fast_at(8.0, 8.5),
        fast_at(11.0, 13.0)
    );
    assert!(
        fast_at(8.0, 8.5) >= 4,
        "F9 must switch to the fast estimate at the step"
    );
    assert!(
        fast_at(11.0, 13.0) < 10,
        "F9 must hand back to P_o in steady cutting"
    );
    assert!(bias.abs() < 25.0, "bias {bias} N");
}

#[test]
fn float_reference_closes_the_loop_like_the_model() {
    for kind in ControllerKind::ALL {
        let sc = scenario(kind, ForceSource::Estimated);
        let m = run(&sc, Engine::Model, false);
        let f = run(&sc, Engine::Reference, false);
        println!(
            "{}: model {:?}\n   float {:?}",
            kind.name(),
            m.metrics,
            f.metrics
        );
        assert!((m.metrics.iae - f.metrics.iae).abs() < 0.15 * f.metrics.iae);
        assert!((m.metrics.overshoot_pct - f.metrics.overshoot_pct).abs() < 5.0);
    }
}
