//! Properties of the force-path kernels: the override range for any input, anti-windup,
//! integral action on a constant plant, panic-freedom of the whole kernel on any ADC
//! codes, and the fixed-point controllers against their float references.
//! Case counts rise with TOOLTOUCH_CASES.

use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::force::control::adaptive::DEFAULT_ADAPTIVE;
use tooltouch_model::force::control::fuzzy::DEFAULT_FUZZY;
use tooltouch_model::force::control::pi::DEFAULT_PI;
use tooltouch_model::force::control::{
    clamp_override, Controller, ControllerSettings, ForceController,
};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::force::sampling::AdcCodes;
use tooltouch_model::testing;
use tooltouch_model::units::Fx;
use tooltouch_plant::reference::{
    controller_f, f, state_of, ControllerF, ControllerStateF, ReferenceStack,
};

fn h() -> Fx {
    Fx::lit("0.05")
}

fn all_controllers() -> [ControllerSettings; 3] {
    [
        ControllerSettings::Pi(DEFAULT_PI),
        ControllerSettings::Adaptive(DEFAULT_ADAPTIVE),
        ControllerSettings::Fuzzy(DEFAULT_FUZZY),
    ]
}

fn any_fx() -> impl Strategy<Value = Fx> {
    prop_oneof![
        any::<i64>().prop_map(Fx::from_bits),
        (-5000i32..5000).prop_map(Fx::from_num),
        Just(Fx::MAX),
        Just(Fx::MIN),
        Just(Fx::ZERO),
    ]
}

/// Fresh cases every run (`PROPTEST_RNG_SEED` reproduces one); the cases that failed once
/// are kept in `properties.regressions` beside this file and replayed first.
fn config() -> ProptestConfig {
    ProptestConfig {
        cases: testing::cases(64),
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("regressions"))),
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    /// For any reference/force sequence, every controller's override is the rounded,
    /// clamped demand: in 0..=255, and 0 or 255 whenever it reports saturation... and it
    /// never panics, even on the extreme I32F32 values.
    #[test]
    fn override_stays_in_range_for_any_input(
        seq in prop::collection::vec((any_fx(), any_fx()), 1..200),
        start in any::<u8>(),
    ) {
        for settings in all_controllers() {
            let mut c = Controller::new(&settings, h(), start);
            for &(r, f) in &seq {
                let o = c.step(r, f);
                if o.saturated {
                    prop_assert!(o.override_pct == 0 || o.override_pct == 255,
                        "{}: saturated at {}", settings.name(), o.override_pct);
                }
            }
        }
    }

    /// After any length of saturation (tool in air: zero force, demand above 255 %), the
    /// integrator has stopped within one step of the saturation boundary instead of
    /// winding up, and the PI leaves saturation within 2 periods of the tool touching.
    #[test]
    fn pi_recovers_quickly_after_a_long_saturation(
        periods in 20usize..20_000,
        overshoot in 20i32..400,
    ) {
        let mut c = Controller::new(&ControllerSettings::Pi(DEFAULT_PI), h(), 100);
        let r = Fx::from_num(500);
        let mut saturated = false;
        for _ in 0..periods {
            let o = c.step(r, Fx::ZERO);
            saturated = o.saturated;
        }
        prop_assert!(saturated, "500 N of error must saturate the PI");
        prop_assert_eq!(c.step(r, Fx::ZERO).override_pct, 255);
        let Controller::Pi(pi) = &c else { unreachable!() };
        // boundary: K_p·e + I = 255; one more integration step of K_i·h·e past it at most
        let e = Fx::from_num(500);
        let bound = Fx::from_num(255) - DEFAULT_PI.kp * e + DEFAULT_PI.ki * h() * e;
        prop_assert!(pi.integral() <= bound, "integrator wound up to {}", pi.integral());
        let f = Fx::from_num(500 + overshoot);
        let mut left = None;
        for k in 0..10 {
            if c.step(r, f).override_pct < 255 {
                left = Some(k);
                break;
            }
        }
        prop_assert!(matches!(left, Some(k) if k < 2), "left saturation after {:?}", left);
    }

    /// On a constant plant — F10 with K from a third to 4/3 of the nominal 6 N/% and the
    /// nominal τ_p = 0.08 s, discretized with a zero-order hold at h: F(i+1) = a·F(i) +
    /// (1 − a)·K·override(i), a = e^(−h/τ_p) — the integral action brings the error to
    /// within the quantization: the mean error over 40 periods is within half an override
    /// step (K/2 newtons) and no period is off by more than one step (K newtons). The lag
    /// matters: on a lag-free static plant the fuzzy PI's Δe path — near zero, Mamdani
    /// min–max with centroid has about twice its linear-region gain (a clipped ZE plus a
    /// thin PS tail) — makes a quantization limit cycle over several override values for
    /// K above ~4 N/%.
    #[test]
    fn integral_action_removes_the_steady_state_error(
        k_milli in 2000i64..8_000,
        reference in 200i32..1000,
    ) {
        let k = Fx::from_num(k_milli) / 1000;
        let r = Fx::from_num(reference);
        // reachable: the reference needs at most 250 % override
        prop_assume!(i64::from(reference) * 1000 <= k_milli * 250);
        for settings in all_controllers() {
            let mut c = Controller::new(&settings, h(), 100);
            let a = (-0.05f64 / 0.08).exp();
            let kf = k.to_num::<f64>();
            let mut u = 100u8;
            let mut force = kf * 100.0;
            let mut plant = |u: u8| {
                force = a * force + (1.0 - a) * kf * f64::from(u);
                Fx::from_num(force)
            };
            for _ in 0..600 {
                let f = plant(u);
                u = c.step(r, f).override_pct;
            }
            let mut sum = Fx::ZERO;
            for _ in 0..40 {
                let f = plant(u);
                prop_assert!((r - f).abs() <= k, "{}: error {} N with K = {}",
                    settings.name(), r - f, k);
                sum += r - f;
                u = c.step(r, f).override_pct;
            }
            prop_assert!((sum / 40).abs() <= k / 2, "{}: mean error {} N with K = {}",
                settings.name(), sum / 40, k);
        }
    }

    /// The whole kernel never panics on any ADC codes and events, and its override stays
    /// within 0..=255.
    #[test]
    fn kernel_survives_any_codes(
        codes in prop::collection::vec(prop::array::uniform8(any::<u16>()), 1..400),
        which in 0usize..3,
    ) {
        let s = ForceSettings { controller: all_controllers()[which], ..Default::default() };
        let mut k = ForceKernel::new(&s.validate().unwrap());
        k.apply(ForceEvent::Identify(true));
        for (i, c) in codes.iter().enumerate() {
            k.apply(ForceEvent::Sample(AdcCodes {
                speed: c[0], power: c[1], force: c[2],
                volts: [c[3], c[4], c[5]], amps: [c[6], c[7]],
            }));
            if i % 7 == 0 { k.apply(ForceEvent::Tick); }
            if i == 100 { k.apply(ForceEvent::Identify(false)); k.apply(ForceEvent::Control(true)); }
            if i % 50 == 3 { k.apply(ForceEvent::Conditions(c[0] as u8)); }
        }
        // the override is a u8 (0..=255 by type); with control off it is the manual one
        let o = k.outputs();
        prop_assert!(o.control_enabled || o.override_pct == s.manual_override);
    }

    /// One period from a shared state: the float reference is re-synchronized to the
    /// fixed-point kernel's state before every period, then both take the same inputs (any
    /// I32F32 force in 0..1500 N, fractions included). The overrides differ by at most one
    /// point, and at all only where the float demand lies within the rounding of a tie
    /// k + ½; the next states agree within the rounding bound, except the PI's across an
    /// anti-windup switch within that rounding (see [`one_step_agrees`]).
    #[test]
    fn controllers_agree_for_one_period_from_a_shared_state(
        forces in prop::collection::vec(0i64..(1500i64 << 32), 1..300),
    ) {
        for settings in all_controllers() {
            let mut fx = Controller::new(&settings, h(), 100);
            let mut fl = controller_f(&settings, 0.05, 100);
            for &bits in &forces {
                let force = Fx::from_bits(bits);
                fl.set_state(&state_of(&fx)).unwrap();
                if let Err(why) = one_step_agrees(&mut fx, fl.as_mut(), force) {
                    prop_assert!(false, "{}: {why}", settings.name());
                }
            }
        }
    }

    /// The fixed-point controllers track their float references over whole sequences
    /// (integer forces 0..1500 N, the same inputs each period, never re-synchronized): the
    /// overrides differ by at most one point in every period whose states keep the demands
    /// less than a point apart ([`lock_step_gap`]). The PI's and the fuzzy PI's state
    /// difference is checked to grow by at most one period's rounding per period, so the
    /// PI's overrides are checked in every period (300 · 2^-16 % apart at most); the fuzzy
    /// PI's and the adaptive controller's wherever their observed state difference allows.
    /// The PI is followed up to the first period whose float demand lies within that gap of
    /// an anti-windup switching point: from there the two may part for good — one
    /// integrates a period the other holds, up to K_i·h·|e| = 32 points at |e| = 1000 N,
    /// and nothing pulls them back together (the regression case parted by 29 points).
    #[test]
    fn fixed_point_controllers_track_their_float_references(
        forces in prop::collection::vec(0i32..1500, 1..300),
    ) {
        for settings in all_controllers() {
            let mut fx = Controller::new(&settings, h(), 100);
            let mut fl = controller_f(&settings, 0.05, 100);
            let mut state_bound = 0.0;
            for (period, &f) in forces.iter().enumerate() {
                let force = Fx::from_num(f);
                let e = f64::from(500 - f);
                let (drift, grows_at_most) = lock_step_gap(&state_of(&fx), &fl.state(), e);
                let gap = drift + grows_at_most;
                let demand = fl.demand(500.0, f64::from(f));
                if matches!(settings, ControllerSettings::Pi(_)) && near_a_switch(demand, e, gap) {
                    break;
                }
                if !matches!(settings, ControllerSettings::Adaptive(_)) {
                    prop_assert!(drift <= state_bound,
                        "{}: state {drift} apart after {period} periods, bound {state_bound}",
                        settings.name());
                    state_bound += grows_at_most;
                }
                let a = fx.step(Fx::from_num(500), force);
                let (_, q, _) = fl.step(500.0, f64::from(f));
                if gap < 1.0 {
                    prop_assert!(a.override_pct.abs_diff(q) <= 1,
                        "{}: fixed {} vs float {q} in period {period}",
                        settings.name(), a.override_pct);
                }
            }
        }
    }
}

/// One I32F32 LSB, 2^-32.
const LSB: f64 = 1.0 / 4_294_967_296.0;

/// Bound on one period's difference, fixed point against float from the same state, of
/// every continuous quantity of the PI and the adaptive controller (demand, next
/// integrator, override state, K̂, K̄_c), %, or %/(N·s) or N/%: 2^-16.
///
/// Every I32F32 product and quotient is within one LSB (2^-32) of the exact one; the f64
/// side is exact but for ~2^-53 relative (values below 2^12), and it reads the same gains
/// (every I32F32 value is an f64). What differs beyond one LSB is a constant times the
/// error |e| ≤ 2^10 N: `K_i·h` and `K̄_c·h` are rounded once in I32F32 and h = 0.05 s is
/// itself rounded (the float uses 0.05), so the integrator's and the adaptive override's
/// increment differ by at most (1 + K̄_c,max)·2^-32·|e| with K̄_c,max = 4/0.5 = 8 %/(N·s),
/// below 2^-18. K̂'s update (one quotient, one shift, each within an LSB) and K̄_c =
/// 4/K̂ (amplifying K̂'s error by 4/K̂² ≤ 16) stay below 2^-26. 2^-16 leaves ample room.
const ROUNDING: f64 = 65536.0 * LSB;

/// Bound on one period's difference of the fuzzy PI's demand and override state, %:
/// 40 normalized units times GΔU (0.125 % for the defaults).
///
/// After the input scaling the fuzzy kernel is exact integer arithmetic, but it scales
/// e and Δe to whole normalized units (`round(g·x)`, within ½ unit + one LSB) where the float
/// reference does not round, and truncates the centroid to a whole unit. The centroid
/// `C = Σ u_p·μ_p / Σ μ_p` moves by `Σ_p |u_p − C|·|Δμ_p| / Σ μ_p` when the inputs move:
/// every μ_p moves at most as far as the inputs (memberships of slope one, min and max), Σ_p
/// |u_p − C| ≤ 256·(0 + 1 + … + 24) = 76800 units over the 25 output points, and with the
/// full standard rule table some rule fires with strength ≥ ½ (memberships partition
/// unity, so one set of each input is ≥ ½), so Σ μ_p ≥ 2·512 (its centre and a neighbour).
/// Hence the centroid moves ≤ 75 units per unit of input, ≤ 37.6 for the ½-unit scaling,
/// plus < 1 of truncation and an LSB of `GΔU·Δu`: < 40 units.
fn fuzzy_rounding() -> f64 {
    40.0 * f(DEFAULT_FUZZY.gdu)
}

/// Whether a period's float PI `demand` (%) with error `e` (N) lies within `gap` of an
/// anti-windup switching point: the integrator holds while the demand is above 255 % and
/// the error positive, or below 0 % and the error negative; at such a demand a fixed-point
/// demand `gap` away may take the other branch.
fn near_a_switch(demand: f64, e: f64, gap: f64) -> bool {
    (e > 0.0 && (demand - 255.0).abs() <= gap) || (e < 0.0 && demand.abs() <= gap)
}

/// How far apart the fixed-point and float demands can be in a period with error `e` (N)
/// given their states: `(drift, rounding)` — what the state difference contributes, and
/// what one period's rounding adds (also the most the PI's and the fuzzy PI's state
/// difference grows by in a period: their state maps, `I ↦ clamp(I + K_i·h·e)` and
/// `u ↦ clamp(u + GΔU·Δu(e, Δe))` with Δu independent of u, are 1-Lipschitz). The
/// adaptive controller's is not — K̂ is re-estimated from F̂_c / f, so an override-state
/// difference feeds back through the gain, and K̂ is re-estimated or held on a threshold
/// of f — so its gap is taken as observed.
fn lock_step_gap(fixed: &ControllerStateF, float: &ControllerStateF, e: f64) -> (f64, f64) {
    match (fixed, float) {
        (ControllerStateF::Pi { integral: a }, ControllerStateF::Pi { integral: b }) => {
            ((a - b).abs(), ROUNDING)
        }
        (
            ControllerStateF::Adaptive {
                feed: a,
                controller_gain: ka,
                ..
            },
            ControllerStateF::Adaptive {
                feed: b,
                controller_gain: kb,
                ..
            },
        ) => ((a - b).abs() + 0.05 * e.abs() * (ka - kb).abs(), ROUNDING),
        (
            ControllerStateF::Fuzzy {
                override_state: a,
                previous_error: pa,
            },
            ControllerStateF::Fuzzy {
                override_state: b,
                previous_error: pb,
            },
        ) => {
            // integer forces: the errors are exact on both sides
            assert_eq!(pa, pb);
            ((a - b).abs(), fuzzy_rounding())
        }
        _ => unreachable!("the float reference is built from the same settings"),
    }
}

/// One period of `fixed` and of `float` (re-synchronized to it) with reference 500 N and
/// `force`: the one-period agreement, or what broke it.
///
/// - The overrides are the demands clamped to [0, 255] and rounded to the nearest
///   integer: demands less than a point apart give overrides at most one point apart, and
///   equal ones unless the float demand is within the rounding of a tie k + ½.
/// - The next states agree within the rounding, but for one exception: the PI's anti-windup
///   decision (hold the integrator while the demand is beyond 0 or 255 % and the error
///   pushes further out) may differ where the float demand is within the rounding of its
///   switching point; then the fixed-point integrator is the other branch's, held or
///   integrated. The adaptive controller's one decision (re-estimate K̂ only while f ≥
///   `min_override` and F̂_c ≥ `min_force`) reads the shared state and the input, so it is
///   the same on both sides.
fn one_step_agrees(
    fixed: &mut Controller,
    float: &mut dyn ControllerF,
    force: Fx,
) -> Result<(), String> {
    let (r, fo) = (500.0, f(force));
    let e = r - fo;
    let before = state_of(fixed);
    let rounding = match before {
        ControllerStateF::Fuzzy { .. } => fuzzy_rounding(),
        _ => ROUNDING,
    };
    let demand = float.demand(r, fo);
    let out = fixed.step(Fx::from_num(500), force);
    let (u, q, _) = float.step(r, fo);
    let tie_distance = ((u - u.floor()) - 0.5).abs();
    if out.override_pct != q && (out.override_pct.abs_diff(q) > 1 || tie_distance > rounding) {
        return Err(format!(
            "fixed {} vs float {q} ({u} %, {tie_distance} from a tie)",
            out.override_pct
        ));
    }
    let apart = |a: f64, b: f64, what: &str| -> Result<(), String> {
        if (a - b).abs() <= rounding {
            Ok(())
        } else {
            Err(format!(
                "{what}: fixed {a} vs float {b} (demand {demand} %, e {e} N)"
            ))
        }
    };
    match (state_of(fixed), float.state(), before) {
        (
            ControllerStateF::Pi { integral: a },
            ControllerStateF::Pi { integral: b },
            ControllerStateF::Pi { integral: held },
        ) => {
            if near_a_switch(demand, e, rounding) {
                let p = DEFAULT_PI;
                let integrated =
                    (held + f(p.ki) * 0.05 * e).clamp(f(p.integrator_min), f(p.integrator_max));
                apart(a, b, "integrator")
                    .or_else(|_| apart(a, held, "integrator held"))
                    .or_else(|_| apart(a, integrated, "integrator integrated"))
            } else {
                apart(a, b, "integrator")
            }
        }
        (
            ControllerStateF::Adaptive {
                feed: a,
                gain_estimate: ka,
                controller_gain: ga,
            },
            ControllerStateF::Adaptive {
                feed: b,
                gain_estimate: kb,
                controller_gain: gb,
            },
            _,
        ) => apart(a, b, "override state")
            .and(apart(ka, kb, "gain estimate"))
            .and(apart(ga, gb, "controller gain")),
        (
            ControllerStateF::Fuzzy {
                override_state: a,
                previous_error: pa,
            },
            ControllerStateF::Fuzzy {
                override_state: b,
                previous_error: pb,
            },
            _,
        ) => apart(a, b, "override state").and(apart(
            pa.unwrap_or(f64::NAN),
            pb.unwrap_or(f64::NAN),
            "previous error",
        )),
        _ => unreachable!("the float reference is built from the same settings"),
    }
}

/// The one-period exception is real: a shared integrator of 100 % and an error just past
/// (255 − 100) % / K_p, so that K_p·e exceeds 155 % by less than one LSB. The fixed-point
/// product drops that excess, its demand is exactly 255 % and it integrates (a demand at the
/// range's end is not saturated); the float demand is past 255 % and its PI holds. The
/// integrators part by K_i·h·e ≈ 31 % after one period, as [`one_step_agrees`] allows.
#[test]
fn the_pi_anti_windup_decision_may_flip_within_one_lsb_of_its_switch() {
    let kp_bits = i128::from(DEFAULT_PI.kp.to_bits());
    let e_bits = ((155i128 << 64) + kp_bits - 1) / kp_bits;
    let e = Fx::from_bits(i64::try_from(e_bits).unwrap());
    let force = Fx::from_num(500) - e;
    let settings = ControllerSettings::Pi(DEFAULT_PI);
    let mut fx = Controller::new(&settings, h(), 100);
    let mut fl = controller_f(&settings, 0.05, 100);
    fl.set_state(&state_of(&fx)).unwrap();
    let demand = fl.demand(500.0, f(force));
    assert!(
        demand > 255.0,
        "the float demand {demand} is past the switch"
    );
    one_step_agrees(&mut fx, fl.as_mut(), force).unwrap();
    let (ControllerStateF::Pi { integral: fixed }, ControllerStateF::Pi { integral: float }) =
        (state_of(&fx), fl.state())
    else {
        unreachable!("both are PIs")
    };
    assert_eq!(float, 100.0, "the float PI held");
    assert!(
        fixed - float > 30.0,
        "the fixed-point PI integrated: {fixed}"
    );
}

#[test]
fn clamp_reports_saturation() {
    assert_eq!(clamp_override(Fx::from_num(300)), (Fx::from_num(255), true));
    assert_eq!(clamp_override(Fx::from_num(-1)), (Fx::ZERO, true));
    assert_eq!(clamp_override(Fx::from_num(7)), (Fx::from_num(7), false));
}

/// The estimator converges on a constant-torque plant: constant codes of a steady cut
/// (speed, measured power, balanced phase signals) give a constant force estimate, equal
/// to the float reference's within 0.1 N after the first periods.
#[test]
fn estimator_converges_on_a_constant_torque_plant() {
    use std::f64::consts::PI;
    let s = ForceSettings::default();
    let config = s.validate().unwrap();
    let mut k = ForceKernel::new(&config);
    let mut r = ReferenceStack::new(&s);
    // 83.8 rad/s, 1.2 kW shaft power, balanced phases: P_o/ω = 14.3 N·m
    let theta_step = 2.0 * PI * 26.7 / 1000.0;
    let mut last = Vec::new();
    for i in 0..2000u32 {
        let th = f64::from(i) * theta_step;
        let ph = |k: f64, amp: f64, lag: f64| {
            (2048.0 + amp * (th - 2.0 * PI * k / 3.0 - lag).sin()).round() as u16
        };
        let codes = AdcCodes {
            speed: 1676,
            power: 480,
            force: 2048,
            volts: [
                ph(0.0, 1131.0, 0.0),
                ph(1.0, 1131.0, 0.0),
                ph(2.0, 1131.0, 0.0),
            ],
            // 4.14 A rms: P_g ≈ 1216 W, within Δ_th of P_o = 1200 W, so F9 keeps P_o
            amps: [ph(0.0, 1171.0, PI / 6.0), ph(1.0, 1171.0, PI / 6.0)],
        };
        k.apply(ForceEvent::Sample(codes));
        r.apply(ForceEvent::Sample(codes));
        if (i + 1) % 50 == 0 {
            k.apply(ForceEvent::Tick);
            r.apply(ForceEvent::Tick);
            last.push((k.outputs().force_estimate.to_num::<f64>(), r.estimate.force));
        }
    }
    assert!(
        !k.outputs().fast_estimate,
        "steady state must use the measured power"
    );
    let settled = &last[10..];
    let first = settled[0].0;
    for &(fixed, float) in settled {
        assert!(
            (fixed - first).abs() < 1.0,
            "estimate wanders: {fixed} vs {first}"
        );
        assert!(
            (fixed - float).abs() < 0.1,
            "fixed {fixed} vs float {float}"
        );
    }
    // P_o/ω − B·ω − T_fco with the default estimator settings, through F8, over r
    let t_e = 480.0 * 2.5 / (1676.0 * 0.05);
    let c = t_e - 0.005 * 83.8 - 1.0;
    let t_c = 2.0 * c / (1.05 + (1.05f64 * 1.05 + 4.0 * 0.002 * c).sqrt());
    assert!(
        (first - t_c / 0.02).abs() < 1.0,
        "{first} vs {}",
        t_c / 0.02
    );
}

#[test]
fn pi_settings_from_the_design_are_valid() {
    use tooltouch_model::force::config::ForceSource;
    use tooltouch_plant::drive::kienzle::KienzleProcess;
    use tooltouch_plant::drive::scenario::{kienzle_settings, scenario_settings, ControllerKind};
    use tooltouch_plant::reference::design::{pi_settings, NominalProcess};
    // The Ziegler–Nichols design on the nominal F10, and the PI of every scenario built on it.
    let (kp, ki) = NominalProcess::default().ziegler_nichols_pi();
    let designed = pi_settings(kp, ki);
    designed.validate().unwrap();
    let kienzle = KienzleProcess::default();
    for source in [ForceSource::Estimated, ForceSource::Measured] {
        for settings in [
            scenario_settings(ControllerKind::Pi, source),
            kienzle_settings(ControllerKind::Pi, source, &kienzle),
        ] {
            let ControllerSettings::Pi(pi) = settings.controller else {
                panic!("a PI scenario without a PI: {:?}", settings.controller);
            };
            assert_eq!(pi, designed);
            pi.validate().unwrap();
            settings.validate().unwrap();
        }
    }
    // The design on other nominal processes, and scaled as the force sweep's
    // `kp_percent`/`ki_percent` scale it (its defaults 50..=200 %), stays inside the PI's
    // ranges.
    for (ks, tau_p) in [(500.0, 0.02), (2000.0, 0.08), (6000.0, 0.5)] {
        let (kp, ki) = NominalProcess {
            ks,
            tau_p,
            ..NominalProcess::default()
        }
        .ziegler_nichols_pi();
        for scale in [0.5, 1.0, 2.0] {
            let s = pi_settings(kp * scale, ki * scale);
            s.validate()
                .unwrap_or_else(|e| panic!("K_s {ks}, τ_p {tau_p}, ×{scale}: {e}"));
        }
    }
}
