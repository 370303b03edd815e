//! Hand-worked periods of the estimator (eq. F2–F9, docs/domain.md §3) with numbers chosen
//! so every step is exact in I32F32: J = 1/2 kg·m², h = 1/16 s (J/h = 8), r = 1/2 m.
//! Each expected value is the equation evaluated by hand in the comment above it.

use super::*;

fn fx(x: f64) -> Fx {
    Fx::from_num(x)
}

fn settings() -> EstimatorSettings {
    EstimatorSettings {
        stator_resistance: fx(0.5),
        inertia: fx(0.5),
        viscous_nominal: Fx::ZERO,
        coulomb_nominal: fx(8.0),
        friction_f: [Fx::ZERO, Fx::ZERO],
        friction_g: [Fx::ZERO, Fx::ZERO],
        min_speed: fx(5.0),
        switch_threshold: fx(0.25),
        slip_gain: fx(0.5),
        slip_hold_periods: 2,
        workpiece_radius: fx(0.5),
    }
}

const H: f64 = 0.0625;

/// Signals at speed `omega` with I = `i` A, V = `v` V, Σi² = `amps_sq` and measured power
/// `p_o`.
fn signals(omega: f64, i: f64, v: f64, amps_sq: f64, p_o: f64) -> DriveSignals {
    DriveSignals {
        omega: fx(omega),
        p_o: fx(p_o),
        force_measured: Fx::ZERO,
        v_line: fx(v),
        i_line: fx(i),
        amps_sq: fx(amps_sq),
    }
}

#[test]
fn one_period_from_powers_to_force() {
    let mut e = Estimator::new(&settings(), fx(H));
    // P_i = 1.5·4·100 = 600 W, P_s = 0.5·48 = 24 W, P_g = 576 W = P_o: the measured power.
    let est = e.step(&signals(8.0, 4.0, 100.0, 48.0, 576.0));
    assert_eq!(
        (est.p_i, est.p_g, est.p_used),
        (fx(600.0), fx(576.0), fx(576.0))
    );
    assert!(!est.fast);
    // T_e = 576 / 8 = 72; first period: Δω = 0, B = 0: T_t = 72; c = 72 − 8 = 64, f = g = 0:
    // T_c = 2·64 / (1 + 1) = 64; F = 64 / 0.5 = 128 N.
    assert_eq!(
        (est.t_e, est.t_t, est.t_c, est.force),
        (fx(72.0), fx(72.0), fx(64.0), fx(128.0))
    );
    // Next period 4 rad/s faster: T_t = T_e − (J/h)·4 = 576/12 − 32 = 16; c = 8, T_c = 8.
    let est = e.step(&signals(12.0, 4.0, 100.0, 48.0, 576.0));
    assert_eq!(
        (est.t_e, est.t_t, est.t_c, est.force),
        (fx(48.0), fx(16.0), fx(8.0), fx(16.0))
    );
    // Below the speed floor of 5 rad/s the torque is 0; at the floor it is P / 5.
    let est = e.step(&signals(4.0, 4.0, 100.0, 48.0, 576.0));
    assert_eq!(est.t_e, Fx::ZERO);
    let est = e.step(&signals(5.0, 4.0, 100.0, 48.0, 500.0));
    assert_eq!(
        est.t_e,
        fx(100.0),
        "P_o = 500 W (within the switch threshold of P_g)"
    );
}

#[test]
fn the_switch_selects_the_fast_estimate_and_holds_it() {
    let mut e = Estimator::new(&settings(), fx(H));
    // |P_g − P_o| = 576 − 400 = 176 > 0.25·400: fast, P = 0.5·576 = 288, T_e = 36.
    let est = e.step(&signals(8.0, 4.0, 100.0, 48.0, 400.0));
    assert!(est.fast);
    assert_eq!((est.p_used, est.t_e), (fx(288.0), fx(36.0)));
    // P_o = 500: 76 ≤ 125, but the hold of 2 periods keeps the fast estimate once more.
    let est = e.step(&signals(8.0, 4.0, 100.0, 48.0, 500.0));
    assert!(est.fast);
    let est = e.step(&signals(8.0, 4.0, 100.0, 48.0, 500.0));
    assert!(!est.fast);
    assert_eq!((est.p_used, est.t_e), (fx(500.0), fx(62.5)));
    // P_o = 512: |64| ≤ 128, slow; a negative P_o counts by its magnitude:
    // |576 + 256| = 832 > 0.25·256: fast.
    assert!(!e.step(&signals(8.0, 4.0, 100.0, 48.0, 512.0)).fast);
    assert!(e.step(&signals(8.0, 4.0, 100.0, 48.0, -256.0)).fast);
    // Just under the threshold, 576 − 461 = 115 ≤ 0.25·461 = 115.25: slow.
    let mut e = Estimator::new(&settings(), fx(H));
    assert!(!e.step(&signals(8.0, 4.0, 100.0, 48.0, 461.0)).fast);
}

#[test]
fn the_switch_sees_both_signs() {
    // F9 as paper F's eq. (9) states it, |P_g − P_o| > Δ_th·|P_o|: the fast estimate when P_g
    // runs ahead of the lagging P_o (a cut starts) and when it falls behind it (a cut ends).
    // P_o = 1000 W above P_g = 576 W: |576 − 1000| = 424 > 0.25·1000: fast.
    let mut e = Estimator::new(&settings(), fx(H));
    let est = e.step(&signals(8.0, 4.0, 100.0, 48.0, 1000.0));
    assert!(est.fast);
    assert_eq!(est.p_used, fx(288.0));
    // The same magnitude the other way round switches too: 576 − 400 = 176 > 100.
    let mut e = Estimator::new(&settings(), fx(H));
    assert!(e.step(&signals(8.0, 4.0, 100.0, 48.0, 400.0)).fast);
    // The falling side's edge: exactly at the threshold, |576 − 768| = 192 = 0.25·768, not
    // above it: slow; one watt more, 193 > 192.25: fast.
    let mut e = Estimator::new(&settings(), fx(H));
    let est = e.step(&signals(8.0, 4.0, 100.0, 48.0, 768.0));
    assert!(!est.fast);
    assert_eq!(est.p_used, fx(768.0));
    let mut e = Estimator::new(&settings(), fx(H));
    assert!(e.step(&signals(8.0, 4.0, 100.0, 48.0, 769.0)).fast);
}

#[test]
fn viscous_friction_and_the_load_dependent_terms() {
    // B = 1/4: T_t = T_e − B·ω = 72 − 2 = 70; c = 62, T_c = 62.
    let mut s = settings();
    s.viscous_nominal = fx(0.25);
    let mut e = Estimator::new(&s, fx(H));
    let est = e.step(&signals(8.0, 4.0, 100.0, 48.0, 576.0));
    assert_eq!((est.t_t, est.t_c), (fx(70.0), fx(62.0)));
    // f = 15/16 + (1/128)·8 = 1: (1 + f)·T_c = c = 64 → T_c = 32.
    let mut s = settings();
    s.friction_f = [fx(0.9375), fx(1.0 / 128.0)];
    let mut e = Estimator::new(&s, fx(H));
    assert_eq!(e.step(&signals(8.0, 4.0, 100.0, 48.0, 576.0)).t_c, fx(32.0));
    // g = 1/64 + (1/512)·8 = 1/32: g·T_c² + T_c = 64 → T_c = 32 (√(1 + 4·64/32) = 3).
    let mut s = settings();
    s.friction_g = [fx(1.0 / 64.0), fx(1.0 / 512.0)];
    let mut e = Estimator::new(&s, fx(H));
    assert_eq!(e.step(&signals(8.0, 4.0, 100.0, 48.0, 576.0)).t_c, fx(32.0));
    // 1 + f is kept at least 1/2: f = −0.5 − 0.01·8 acts as −0.5, so
    // T_c = 2·64 / (0.5 + √0.25) = 128.
    let mut s = settings();
    s.friction_f = [fx(-0.5), fx(-0.01)];
    let mut e = Estimator::new(&s, fx(H));
    assert_eq!(
        e.step(&signals(8.0, 4.0, 100.0, 48.0, 576.0)).t_c,
        fx(128.0)
    );
}

/// A no-load period at speed `omega` (rad/s) with air-gap power `p_g` (W) and P_o = P_g
/// (F9 stays on P_o); R_s = 0 and I = 1 A, so P_g = 1.5·V. The identification torque is
/// `y = P_g/ω − (J/h)·Δω` with J/h = 8, and the slip gain (1/2 in [`settings`]) is not
/// applied to it.
fn no_load(e: &mut Estimator, omega: f64, p_g: f64) {
    e.step(&signals(omega, 1.0, p_g / 1.5, 0.0, p_g));
}

fn no_load_settings(viscous: f64) -> EstimatorSettings {
    EstimatorSettings {
        stator_resistance: Fx::ZERO,
        viscous_nominal: fx(viscous),
        ..settings()
    }
}

#[test]
fn identification_solves_b_and_coulomb_from_steady_periods() {
    let mut e = Estimator::new(&no_load_settings(0.0), fx(H));
    assert!(!e.identifying());
    e.start_identification();
    assert!(e.identifying());
    // ω = 8, P_g = 24: first period, Δω = 0 but no steady period before it: not collected.
    no_load(&mut e, 8.0, 24.0);
    // Steady again: collected, y = 24/8 = 3.
    no_load(&mut e, 8.0, 24.0);
    // ω = 16 (Δω = 8): inertia torque 8·8 = 64, P_g/ω = 1104/16 = 69; 16·64 > 69: not
    // steady, not collected; the next period at 16 follows it: not collected either.
    no_load(&mut e, 16.0, 1104.0);
    no_load(&mut e, 16.0, 72.0);
    // Collected: y = 72/16 = 4.5.
    no_load(&mut e, 16.0, 72.0);
    // The same at ω = 24 (P_g/ω = 2016/24 = 84 after the jump): y = 144/24 = 6.
    no_load(&mut e, 24.0, 2016.0);
    no_load(&mut e, 24.0, 144.0);
    no_load(&mut e, 24.0, 144.0);
    e.finish_identification();
    assert!(!e.identifying());
    assert!(e.identified());
    // Points (8, 3), (16, 4.5), (24, 6): n = 3, Σω = 48, Σω² = 896, Σy = 13.5,
    // Σωy = 24 + 72 + 144 = 240; B = (3·240 − 48·13.5) / (3·896 − 48²) = 72/384 = 3/16,
    // T_fco = (13.5 − 48·3/16)/3 = 1.5.
    assert_eq!((e.viscous(), e.coulomb()), (fx(0.1875), fx(1.5)));
}

#[test]
fn a_period_is_steady_up_to_an_inertia_torque_of_a_sixteenth() {
    let mut e = Estimator::new(&no_load_settings(0.0), fx(H));
    e.start_identification();
    no_load(&mut e, 8.0, 24.0);
    no_load(&mut e, 8.0, 24.0); // collected: (8, 3)
                                // Δω = 3/8: inertia torque 8·3/8 = 3; P_g/ω = 402/8.375 = 48 = 16·3: steady,
                                // collected, y = 48 − 3 = 45.
    no_load(&mut e, 8.375, 402.0);
    // Δω = 3/8 again, P_g/ω = 210/8.75 = 24 < 48: not steady, not collected.
    no_load(&mut e, 8.75, 210.0);
    e.finish_identification();
    // Speeds 8 and 8.375: n·Σω² − (Σω)² = 2·134.140625 − 16.375² = 0.140625, below
    // n²·1 (rad/s)²: B stays 0 and T_fco = mean(y) = (3 + 45)/2 = 24.
    assert_eq!((e.viscous(), e.coulomb()), (Fx::ZERO, fx(24.0)));
}

#[test]
fn identification_at_constant_speed_keeps_b() {
    // ω = 8 throughout, no variance: B stays 1/4; the second and third periods are
    // collected, T_fco = mean(y) − B·8 = 3 − 2 = 1.
    let mut e = Estimator::new(&no_load_settings(0.25), fx(H));
    e.start_identification();
    for _ in 0..3 {
        no_load(&mut e, 8.0, 24.0);
    }
    e.finish_identification();
    assert_eq!((e.viscous(), e.coulomb()), (fx(0.25), fx(1.0)));
    assert!(e.identified());
}

#[test]
fn identification_without_periods_or_start_changes_nothing() {
    let mut e = Estimator::new(&no_load_settings(0.25), fx(H));
    e.finish_identification();
    assert!(!e.identified());
    e.start_identification();
    e.finish_identification();
    assert!(!e.identified());
    assert_eq!((e.viscous(), e.coulomb()), (fx(0.25), fx(8.0)));
    // Periods outside an identification are not collected (y = 768/8 = 96 here), but
    // they count as the steady period before the first one inside it.
    no_load(&mut e, 8.0, 768.0);
    e.start_identification();
    no_load(&mut e, 8.0, 24.0);
    e.finish_identification();
    assert_eq!(e.coulomb(), fx(1.0), "3 − 0.25·8");
}
