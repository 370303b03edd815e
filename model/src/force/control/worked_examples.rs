//! Hand-worked periods of the three controllers (docs/domain.md §3) with every output
//! written out. Gains and periods are powers of two, so each product is exact and each
//! expected value below is the formula evaluated by hand: PI `u = K_p·e + I`,
//! `I += K_i·h·e`; adaptive `f += K̄_c·h·e`, `K̂ = F̂_c / f`, `K̄_c = K / K̂`; fuzzy by the
//! rule table and the centroid of symmetric output shapes.

use super::*;
use crate::force::control::fuzzy::{infer, memberships, normalize, LIMIT, STANDARD_RULES};

fn fx(x: f64) -> Fx {
    Fx::from_num(x)
}

fn out(override_pct: u8, saturated: bool) -> ControlOutput {
    ControlOutput {
        override_pct,
        saturated,
    }
}

/// PI with K_p = 1/8 %/N, K_i = 2 %/(N·s), h = 1/16 s (K_i·h = 1/8), starting at 100 %.
fn pi(i_min: f64, i_max: f64, start: u8) -> Pi {
    let s = PiSettings {
        kp: fx(0.125),
        ki: fx(2.0),
        integrator_min: fx(i_min),
        integrator_max: fx(i_max),
    };
    Pi::new(&s, fx(0.0625), start)
}

#[test]
fn pi_periods_by_hand() {
    let mut c = pi(0.0, 255.0, 100);
    assert_eq!(c.integral(), fx(100.0));
    // e = 80: u = 10 + 100, I = 100 + 10.
    assert_eq!(c.step(fx(500.0), fx(420.0)), out(110, false));
    assert_eq!(c.integral(), fx(110.0));
    // e = 0: u = I.
    assert_eq!(c.step(fx(500.0), fx(500.0)), out(110, false));
    // e = −20: u = −2.5 + 110 = 107.5 → 108 (ties away from zero), I = 107.5.
    assert_eq!(c.step(fx(500.0), fx(520.0)), out(108, false));
    assert_eq!(c.integral(), fx(107.5));
    // e = 2000: u = 250 + 107.5 > 255, pushing further out: I holds.
    assert_eq!(c.step(fx(2500.0), fx(500.0)), out(255, true));
    assert_eq!(c.integral(), fx(107.5));
    // e = −2000: u < 0, pushing further down: I holds.
    assert_eq!(c.step(fx(500.0), fx(2500.0)), out(0, true));
    assert_eq!(c.integral(), fx(107.5));
    // e = −1000 from I = 107.5: u = −125 + 107.5 < 0 and e < 0: holds again; e = +1
    // integrates (1/8).
    c.step(fx(0.0), fx(1000.0));
    assert_eq!(c.integral(), fx(107.5));
    c.step(fx(1.0), fx(0.0));
    assert_eq!(c.integral(), fx(107.625));
}

#[test]
fn pi_integrates_out_of_saturation_when_the_error_turns() {
    // I = 250: e = 80 gives u = 260 > 255 (saturated, winding up: hold); e = −8 gives
    // u = 249 (inside): integrates to 249.
    let mut c = pi(0.0, 255.0, 250);
    assert_eq!(c.step(fx(80.0), fx(0.0)), out(255, true));
    assert_eq!(c.integral(), fx(250.0));
    assert_eq!(c.step(fx(0.0), fx(8.0)), out(249, false));
    assert_eq!(c.integral(), fx(249.0));
    // I = 2: e = −24 gives u = −1 (saturated low, e < 0: hold); e = +8: u = 3, I = 3.
    let mut c = pi(0.0, 255.0, 2);
    assert_eq!(c.step(fx(0.0), fx(24.0)), out(0, true));
    assert_eq!(c.integral(), fx(2.0));
    assert_eq!(c.step(fx(8.0), fx(0.0)), out(3, false));
    assert_eq!(c.integral(), fx(3.0));
}

#[test]
fn pi_integrator_stays_inside_its_clamps() {
    let mut c = pi(90.0, 120.0, 50);
    assert_eq!(c.integral(), fx(90.0), "reset clamps up");
    c.reset(200);
    assert_eq!(c.integral(), fx(120.0), "reset clamps down");
    c.reset(100);
    // e = 200: u = 25 + 100 = 125, I = 100 + 25 → 120.
    assert_eq!(c.step(fx(200.0), fx(0.0)), out(125, false));
    assert_eq!(c.integral(), fx(120.0));
    // e = −400: u = −50 + 120 = 70, I = 120 − 50 → 90.
    assert_eq!(c.step(fx(0.0), fx(400.0)), out(70, false));
    assert_eq!(c.integral(), fx(90.0));
}

/// Adaptive with open-loop gain `k`, K̂ in [1/2, 16] starting at `initial`, h = 1/16 s,
/// re-estimated while f ≥ 5 % and F̂_c ≥ 50 N.
fn adaptive(k: f64, initial: f64, shift: u8) -> Adaptive {
    let s = AdaptiveSettings {
        open_loop_gain: fx(k),
        gain_min: fx(0.5),
        gain_max: fx(16.0),
        initial_gain: fx(initial),
        gain_filter_shift: shift,
        min_override: fx(5.0),
        min_force: fx(50.0),
    };
    Adaptive::new(&s, fx(0.0625), 100)
}

#[test]
fn adaptive_periods_by_hand() {
    let mut c = adaptive(4.0, 4.0, 0);
    assert_eq!(c.controller_gain(), fx(1.0), "4 / 4");
    // e = 300: f = 100 + 1·(1/16)·300 = 118.75 → 119; K̂ = 200 / 100 = 2, K̄_c = 2.
    assert_eq!(c.override_state(), fx(100.0));
    assert_eq!(c.step(fx(500.0), fx(200.0)), out(119, false));
    assert_eq!(
        c.override_state(),
        fx(118.75),
        "the state keeps what the output rounds"
    );
    assert_eq!((c.gain_estimate(), c.controller_gain()), (fx(2.0), fx(2.0)));
    // F̂_c = 30 < 50 N: K̂ holds; f = 118.75 + 2·(1/16)·470 = 177.5 → 178.
    assert_eq!(c.step(fx(500.0), fx(30.0)), out(178, false));
    assert_eq!(c.override_state(), fx(177.5));
    assert_eq!(c.gain_estimate(), fx(2.0));
    // e = −3500: f = 177.5 − 437.5 < 0 → 0; K̂ = 4000 / 177.5 > 16 → 16, K̄_c = 1/4.
    assert_eq!(c.step(fx(500.0), fx(4000.0)), out(0, true));
    assert_eq!(
        (c.gain_estimate(), c.controller_gain()),
        (fx(16.0), fx(0.25))
    );
    // f = 0 < 5 %: K̂ holds; f = 0 + (1/4)(1/16)·400 = 6.25 → 6.
    assert_eq!(c.step(fx(500.0), fx(100.0)), out(6, false));
    assert_eq!(c.gain_estimate(), fx(16.0));
    // f = 6.25 ≥ 5: f = 12.5 → 13; K̂ = 100 / 6.25 = 16.
    assert_eq!(c.step(fx(500.0), fx(100.0)), out(13, false));
    // F̂_c = 50 at f = 12.5: K̂ = 4, K̄_c = 1; f = 12.5 + (1/4)(1/16)·450 = 19.53… → 20.
    assert_eq!(c.step(fx(500.0), fx(50.0)), out(20, false));
    assert_eq!((c.gain_estimate(), c.controller_gain()), (fx(4.0), fx(1.0)));
    // A reset moves the override and keeps the estimate.
    c.reset(40);
    assert_eq!(c.override_state(), fx(40.0));
    assert_eq!(c.gain_estimate(), fx(4.0));
    assert_eq!(c.step(fx(0.0), fx(0.0)), out(40, false));
}

#[test]
fn adaptive_estimate_is_low_passed_and_clamped_low() {
    // Shift 1: K̂ += (2 − 4) / 2 = 3; K̄_c = 6 / 3 = 2.
    let mut c = adaptive(6.0, 4.0, 1);
    c.step(fx(200.0), fx(200.0));
    assert_eq!((c.gain_estimate(), c.controller_gain()), (fx(3.0), fx(2.0)));
    // F̂_c / f = 50 / 100 = 1/2, the floor: K̂ += (0.5 − 4) / 2 = −1.75.
    let mut c = adaptive(6.0, 4.0, 1);
    c.step(fx(50.0), fx(50.0));
    assert_eq!(c.gain_estimate(), fx(2.25));
    // With no filter the estimate follows F̂_c / f down to the floor of 1/2.
    let mut c = adaptive(4.0, 4.0, 0);
    c.step(fx(50.0), fx(50.0));
    assert_eq!((c.gain_estimate(), c.controller_gain()), (fx(0.5), fx(8.0)));
}

#[test]
fn memberships_by_hand() {
    assert_eq!(memberships(0), [0, 0, 0, 1024, 0, 0, 0]);
    assert_eq!(memberships(512), [0, 0, 0, 512, 512, 0, 0]);
    assert_eq!(memberships(-100), [0, 0, 100, 924, 0, 0, 0]);
    assert_eq!(memberships(-3072), [1024, 0, 0, 0, 0, 0, 0]);
    assert_eq!(memberships(5000), [0, 0, 0, 0, 0, 0, 1024], "clamped to PB");
    assert_eq!(memberships(i32::MIN), [1024, 0, 0, 0, 0, 0, 0]);
}

#[test]
fn inference_by_hand() {
    // One rule at full strength: the centroid of a whole output triangle is its centre.
    assert_eq!(infer(&STANDARD_RULES, 1024, 0), 1024, "PS, ZE → PS");
    assert_eq!(infer(&STANDARD_RULES, 1024, 1024), 2048, "PS, PS → PM");
    assert_eq!(infer(&STANDARD_RULES, -2048, 0), -2048, "NM, ZE → NM");
    // e half ZE, half PS: ZE and PS both at 512, a shape symmetric about 512.
    assert_eq!(infer(&STANDARD_RULES, 512, 0), 512);
    assert_eq!(infer(&STANDARD_RULES, 0, -512), -512);
    // A table whose only rule maps ZE, ZE to PB: at rest the output is PB's clipped half
    // triangle (2.75 spans, as in the standard table at LIMIT).
    let mut rules = [[crate::force::control::fuzzy::NO_RULE; 7]; 7];
    rules[3][3] = 3;
    assert_eq!(infer(&rules, 0, 0), 11 * 1024 / 4);
    // Inputs where no rule fires: 0.
    assert_eq!(infer(&rules, LIMIT, 0), 0);
}

#[test]
fn normalize_rounds_half_away_and_clamps() {
    assert_eq!(normalize(fx(2.5), fx(1.0)), 3);
    assert_eq!(normalize(fx(2.5), fx(-1.0)), -3);
    assert_eq!(normalize(fx(0.5), fx(3.0)), 2);
    assert_eq!(normalize(fx(1000.0), fx(10.0)), LIMIT);
    assert_eq!(normalize(fx(1000.0), fx(-10.0)), -LIMIT);
}

#[test]
fn fuzzy_periods_by_hand() {
    // GE = 2, GΔE = 1, GΔU = 1/64 %: e = 512 N is PS, a full output set is 16 %.
    let s = FuzzySettings {
        ge: fx(2.0),
        gde: fx(1.0),
        gdu: fx(1.0 / 64.0),
        rules: STANDARD_RULES,
    };
    let mut c = Fuzzy::new(&s, 100);
    assert_eq!((c.override_state(), c.previous_error()), (fx(100.0), None));
    // First period: Δe = 0; PS, ZE → PS: +16.
    assert_eq!(c.step(fx(600.0), fx(88.0)), out(116, false));
    assert_eq!(
        (c.override_state(), c.previous_error()),
        (fx(116.0), Some(fx(512.0)))
    );
    assert_eq!(c.step(fx(600.0), fx(88.0)), out(132, false));
    // e = 0, Δe = −512: ZE, half ZE half NS → centroid −512: −8.
    assert_eq!(c.step(fx(600.0), fx(600.0)), out(124, false));
    assert_eq!(c.step(fx(600.0), fx(600.0)), out(124, false));
    // A reset forgets the previous error: Δe = 0 again.
    c.reset(50);
    assert_eq!((c.override_state(), c.previous_error()), (fx(50.0), None));
    assert_eq!(c.step(fx(600.0), fx(88.0)), out(66, false));
    // Saturation: from 250, +16 → 255, flagged.
    c.reset(250);
    assert_eq!(c.step(fx(600.0), fx(88.0)), out(255, true));
}

#[test]
fn the_controller_enum_dispatches_to_its_kernel() {
    let pi_s = PiSettings {
        kp: fx(0.125),
        ki: fx(2.0),
        integrator_min: fx(0.0),
        integrator_max: fx(255.0),
    };
    let settings = ControllerSettings::Pi(pi_s);
    assert_eq!(settings.name(), "pi");
    let mut c = Controller::new(&settings, fx(0.0625), 100);
    assert_eq!(c.step(fx(500.0), fx(420.0)), out(110, false));
    c.reset(30);
    assert_eq!(c.step(fx(0.0), fx(0.0)), out(30, false));
    let a = ControllerSettings::Adaptive(adaptive::DEFAULT_ADAPTIVE);
    assert_eq!(a.name(), "adaptive");
    let mut c = Controller::new(&a, fx(0.0625), 100);
    c.reset(70);
    assert_eq!(c.step(fx(0.0), fx(0.0)), out(70, false));
    let f = ControllerSettings::Fuzzy(fuzzy::DEFAULT_FUZZY);
    assert_eq!(f.name(), "fuzzy");
    let mut c = Controller::new(&f, fx(0.0625), 100);
    c.reset(80);
    assert_eq!(c.step(fx(0.0), fx(0.0)), out(80, false));
}

#[test]
fn clamp_override_flags_both_sides() {
    assert_eq!(clamp_override(fx(-0.5)), (Fx::ZERO, true));
    assert_eq!(clamp_override(Fx::ZERO), (Fx::ZERO, false));
    assert_eq!(clamp_override(fx(255.0)), (fx(255.0), false));
    assert_eq!(clamp_override(fx(255.25)), (fx(255.0), true));
    assert_eq!(quantize(fx(0.5)), 1);
    assert_eq!(quantize(fx(254.5)), 255);
}
