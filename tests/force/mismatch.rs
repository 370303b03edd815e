//! The estimator against drives that are not its model (docs/estimator.md, "A plant that is
//! not the estimator"): the mismatch is large enough to matter with the estimator's default
//! settings, the identification of f(ω), g(ω), slip gain and Δ_th recovers the drive's
//! friction and brings the synthesized estimate within its stated bound over the whole
//! range (a property over random drives and seeds), the winding conventions the rms-based
//! F2–F3 cannot see do not change the estimate, and bad plans are refused.
//! A dozen cases by default; `PROPTEST_CASES` (or `TOOLTOUCH_CASES`) runs more.

use proptest::prelude::*;
use std::f64::consts::PI;
use tooltouch_model::force::config::ForceSource;
use tooltouch_model::force::estimator::settings::EstimatorSettings;
use tooltouch_plant::drive::identify::{identify, IdentificationPlan};
use tooltouch_plant::drive::mismatch::{
    DriveMismatch, MismatchPoint, MismatchRange, SensedPhases, Winding, WindingConnection,
};
use tooltouch_plant::drive::mismatch_report::{
    identified_scenario, nominal_scenario, sweep_drives, synthesized, SweepDrive,
};
use tooltouch_plant::drive::scenario::{scenario_settings, ClosedLoop, ControllerKind};
use tooltouch_plant::drive::{DepthProfile, DriveParams, Plant, ProcessParams};

/// The stated bound on the synthesized estimate with identified settings, over
/// [`MismatchRange`]: steady mean error within 1 % of the dynamometer, sd within 1 %, and
/// on time on the depth step (lag behind the dynamometer at most 0.15 s, where the
/// power-only estimate's is 0.33 s).
const MEAN_BOUND_PCT: f64 = 1.0;
const SD_BOUND_PCT: f64 = 1.0;
const LAG_BOUND_S: f64 = 0.15;

fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| tooltouch_model::testing::cases(default))
}

fn drive(name: &str) -> SweepDrive {
    sweep_drives()
        .into_iter()
        .find(|d| d.name == name)
        .unwrap_or_else(|| panic!("no sweep drive {name}"))
}

#[test]
fn the_mismatch_matters_with_the_default_settings() {
    // friction 0.10·T_c + 0.004·T_c² (+ slopes) against the estimator's 0.05 and 0.002: the
    // steady estimate reads high by several percent; a power factor of cos 40° at the cut
    // makes P̂_g read 13 % above P_o, so F9 never leaves the fast estimate.
    let high = synthesized(&nominal_scenario(&drive("friction high"), 1));
    assert!(high.mean_error_pct > 5.0, "{high:?}");
    let angle = synthesized(&nominal_scenario(&drive("angle 40° rated"), 1));
    assert!(angle.fast_share_pct > 90.0, "{angle:?}");
    assert!(angle.mean_error_pct > 5.0, "{angle:?}");
}

#[test]
fn identification_recovers_the_drives_friction() {
    let d = drive("friction high");
    let base = EstimatorSettings::default();
    let id = identify(
        &d.drive,
        Some(&d.mismatch),
        &IdentificationPlan::default(),
        &base,
        3,
    )
    .expect("three speeds and loaded points");
    // B and T_fco from the no-load points: within 5 % and 2 %
    assert!((id.viscous / d.drive.viscous - 1.0).abs() < 0.05, "{id:?}");
    assert!((id.coulomb / d.drive.coulomb - 1.0).abs() < 0.02, "{id:?}");
    // F8's δT_f within 0.03 N·m (1.5 N of force at 20 mm) at every speed and load of the
    // range the controllers use (5–20 N·m of cutting torque, 600–1000 rpm)
    for rpm in [600.0, 800.0, 1000.0] {
        let w = rpm * 2.0 * PI / 60.0;
        for t_c in [5.0, 10.0, 15.0, 20.0] {
            let truth = d.mismatch.load_friction(&d.drive, w, t_c);
            let f = id.friction_f[0] + id.friction_f[1] * w;
            let g = id.friction_g[0] + id.friction_g[1] * w;
            let fitted = f * t_c + g * t_c * t_c;
            assert!(
                (fitted - truth).abs() < 0.03,
                "{rpm} rpm, T_c {t_c}: δT_f {fitted} against {truth}"
            );
        }
    }
    assert!(id.load_fit_rms_nm < 0.02, "{}", id.load_fit_rms_nm);
}

#[test]
fn a_plan_without_two_speeds_or_a_load_is_refused() {
    let base = EstimatorSettings::default();
    let d = DriveParams::default();
    let one_speed = IdentificationPlan {
        speeds_rpm: vec![800.0],
        settle_s: 0.5,
        average_s: 0.2,
        ..IdentificationPlan::default()
    };
    assert!(identify(&d, None, &one_speed, &base, 1).is_none());
    let no_load = IdentificationPlan {
        loads_n: vec![0.0],
        settle_s: 0.5,
        average_s: 0.2,
        ..IdentificationPlan::default()
    };
    assert!(identify(&d, None, &no_load, &base, 1).is_none());
}

/// Period-average air-gap power F2–F3 computes from a plant with `winding` at 800 rpm and
/// 600 N, one value per control period over 2 s.
fn air_gap_power(winding: Winding) -> Vec<f64> {
    let config = scenario_settings(ControllerKind::Pi, ForceSource::Measured)
        .validate()
        .expect("valid");
    let s = config.settings();
    let omega = 800.0 * 2.0 * PI / 60.0;
    let depth = DepthProfile {
        before: 1.0,
        after: 1.0,
        step_at: f64::INFINITY,
    };
    let mut plant = Plant::new(
        DriveParams::default(),
        ProcessParams::default(),
        depth,
        &s.scales,
        f64::from(s.sample_hz),
        omega,
        7,
    );
    plant.mismatch = Some(DriveMismatch {
        winding,
        ..DriveMismatch::default()
    });
    plant.engaged = true;
    let mut lp = ClosedLoop::new(&config, plant);
    let mut out = Vec::new();
    for _ in 0..2000 {
        lp.plant.set_speed(omega);
        lp.step(|c| c);
        if lp.samples().is_multiple_of(u64::from(s.samples_per_period)) {
            out.push(lp.kernel().estimate().p_g.to_num::<f64>());
        }
    }
    out
}

#[test]
fn phase_sequence_sensed_pair_and_current_direction_do_not_change_f2_f3() {
    let reference = air_gap_power(Winding::default());
    for sensed in [SensedPhases::UV, SensedPhases::UW, SensedPhases::VW] {
        for negative_sequence in [false, true] {
            for current_reversed in [false, true] {
                let w = Winding {
                    connection: WindingConnection::Star,
                    negative_sequence,
                    sensed,
                    current_reversed,
                };
                let p = air_gap_power(w);
                // the same noise draws; only the codes' rounding differs: 0.5 % per period
                for (i, (a, b)) in reference.iter().zip(&p).enumerate().skip(4) {
                    assert!(
                        (a - b).abs() <= 0.005 * a.abs().max(100.0),
                        "{w:?}, period {i}: P_g {b} W against {a} W"
                    );
                }
            }
        }
    }
}

#[test]
fn a_delta_winding_changes_the_copper_loss_not_the_power() {
    // the same star-equivalent resistance: the line current is the same
    let d = DriveParams::default();
    let star = DriveMismatch::default();
    let mut delta_drive = d;
    delta_drive.stator_resistance = 3.0 * d.stator_resistance;
    let delta = DriveMismatch {
        winding: Winding {
            connection: WindingConnection::Delta,
            ..Winding::default()
        },
        ..DriveMismatch::default()
    };
    for p_g in [100.0, 1000.0, 3000.0] {
        let a = star.line_current(&d, p_g, 10.0);
        let b = delta.line_current(&delta_drive, p_g, 10.0);
        assert!((a - b).abs() < 1e-9 * a, "{p_g} W: {a} A against {b} A");
        // √3·V·I·cos φ − 3·R·I² = P_g, the power balance the current solves
        let phi = star.current_angle(10.0);
        let balance =
            3f64.sqrt() * d.line_voltage * a * phi.cos() - 3.0 * d.stator_resistance * a * a;
        assert!((balance - p_g).abs() < 1e-6 * p_g);
    }
}

fn winding_strategy() -> impl Strategy<Value = Winding> {
    (any::<bool>(), any::<bool>(), 0..3usize, any::<bool>()).prop_map(
        |(delta, negative_sequence, sensed, current_reversed)| Winding {
            connection: if delta {
                WindingConnection::Delta
            } else {
                WindingConnection::Star
            },
            negative_sequence,
            sensed: [SensedPhases::UV, SensedPhases::UW, SensedPhases::VW][sensed],
            current_reversed,
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: cases(12),
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x0a15_3a7c),
        ..ProptestConfig::default()
    })]

    /// Over the whole [`MismatchRange`] (power factor, R_s, J, slip stiffness, F8 and its
    /// slopes, winding), with the settings the identification finds on that drive, the
    /// synthesized estimate stays within the stated bound on the depth step.
    #[test]
    fn identified_settings_keep_the_estimate_within_its_bound(
        at in prop::array::uniform9(0.0..=1.0f64),
        winding in winding_strategy(),
        seed in any::<u64>(),
    ) {
        let (drive, mismatch) =
            MismatchRange::default().drive(&DriveParams::default(), &MismatchPoint { at, winding });
        let d = SweepDrive { name: "random", drive, mismatch };
        let base = EstimatorSettings::default();
        let id = identify(&drive, Some(&mismatch), &IdentificationPlan::default(), &base, seed)
            .expect("the default plan identifies");
        let f = synthesized(&identified_scenario(&d, &id, seed));
        prop_assert!(f.mean_error_pct.abs() <= MEAN_BOUND_PCT, "{f:?} {id:?}");
        prop_assert!(f.sd_error_pct <= SD_BOUND_PCT, "{f:?}");
        prop_assert!(f.lag_s.is_some_and(|l| l <= LAG_BOUND_S), "{f:?} {id:?}");
    }
}
