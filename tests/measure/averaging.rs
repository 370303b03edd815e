//! The scatter of `measure` and S8's averaging, on draws of the cycle's clearance, Z dwell
//! and seed: neither may depend on the cycle's timing, because the slow spindle errors'
//! phase at an approach's start is the cause's own (a cage, a belt), not the cycle's
//! (`tooltouch_plant::lathe::SlowHarmonic`).
//!
//! Tolerances are the sampling error of a standard deviation, and nothing else: from n
//! independent values its relative standard error is `1/√(2(n − 1))`. Each bound is three
//! of those (a drawn case fails by chance about once in 700):
//! - **one run's σ** against the budget's 1σ (`tooltouch budget`): n = [`RUN`] measurements,
//!   3/√(2·(RUN − 1)) = 17 %. The budget's own model error is below that at the defaults
//!   (counter/sticky 0.72 predicted, 0.72 simulated over 400; docs/accuracy.md).
//! - **the mean of m at one Z** against `σ/√m`: σ of one from the run's m·Z measurements,
//!   σ of the mean from its Z per-Z means, the ratio's relative standard error
//!   `√(1/(2(Z − 1)) + 1/(2(mZ − 1)))` (upper bound: both are from the same values, which
//!   correlates them); three of those is 22–26 % at Z = [`Z_POSITIONS`]. The roughness is
//!   off, so every Z sees the same surface and the repeats at one Z differ only by what S8
//!   averages (the slow errors, the decision grid, the quantization); with roughness on,
//!   each Z's own roughness is the part S8 keeps.
//!
//! The figures are printed with `--nocapture`.

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{RngAlgorithm, TestRng, TestRunner};
use rayon::prelude::*;
use tooltouch_metrology::averaging::per_z_means;
use tooltouch_metrology::budget::{predict, Outcome, Variant};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::lathe::{CycleSettings, LatheScenario};
use tooltouch_plant::measurement_cycle::{self, MeasurementReport, Spread};
use tooltouch_settings::Settings;

/// Measurements of one `measure` run.
const RUN: u32 = 160;
/// Z positions of an averaging run.
const Z_POSITIONS: u32 = 100;

/// The cycle's timing and the seed, drawn.
#[derive(Clone, Copy, Debug)]
struct Timing {
    clearance_um: f64,
    z_dwell_ms: f64,
    seed: u64,
}

/// Clearances from just above the default path's reach (about 9 µm) to 40 µm, dwells from
/// none to half a second (0–6.7 revolutions at 800 rpm).
fn timing() -> impl Strategy<Value = Timing> {
    (10.0..40.0f64, 0.0..500.0f64, 1u64..100_000).prop_map(|(clearance_um, z_dwell_ms, seed)| {
        Timing {
            clearance_um,
            z_dwell_ms,
            seed,
        }
    })
}

/// `n` draws of [`timing`], deterministic.
fn draws(n: usize) -> Vec<Timing> {
    let mut runner = TestRunner::new_with_rng(
        ProptestConfig::default(),
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    (0..n)
        .map(|_| timing().new_tree(&mut runner).unwrap().current())
        .collect()
}

fn with_timing(base: &LatheScenario, t: Timing, cycle: CycleSettings) -> LatheScenario {
    LatheScenario {
        seed: t.seed,
        cycle: CycleSettings {
            clearance_um: t.clearance_um,
            z_dwell_ms: t.z_dwell_ms,
            ..cycle
        },
        ..base.clone()
    }
}

fn run(config: &MeasureConfig, s: &LatheScenario) -> Vec<MeasurementReport> {
    let r = measurement_cycle::run(s, config, &mut |_| {}).unwrap();
    assert_eq!(r.summary.decided, r.summary.measurements);
    r.measurements
}

fn sigma_um(reports: &[MeasurementReport]) -> f64 {
    Spread::of(reports.iter().map(|r| r.diameter_mm)).std * 1000.0
}

#[test]
fn one_runs_sigma_is_the_budgets_whatever_the_clearance_dwell_and_seed() {
    let (config, base) = Settings::default().resolve().unwrap();
    let variant = Variant {
        method: config.settings().method,
        rule: config.settings().contact_rule,
    };
    let band = 3.0 / (2.0 * (f64::from(RUN) - 1.0)).sqrt();
    let found: Vec<(Timing, f64, f64)> = draws(4)
        .into_par_iter()
        .map(|t| {
            let s = with_timing(
                &base,
                t,
                CycleSettings {
                    repeats: RUN,
                    ..base.cycle
                },
            );
            let predicted = match predict(&config, &s, variant) {
                Outcome::Predicted(p) => p.sigma_um,
                Outcome::Refused { reason, .. } => panic!("{t:?} refused: {reason}"),
            };
            (t, predicted, sigma_um(&run(&config, &s)))
        })
        .collect();
    for (t, predicted, simulated) in found {
        let line = format!(
            "{t:?}: σ of {RUN} measurements {simulated:.3} µm, budget {predicted:.3} µm \
             (±{:.0} %)",
            band * 100.0
        );
        eprintln!("{line}");
        assert!((simulated / predicted - 1.0).abs() <= band, "{line}");
    }
}

#[test]
fn sigma_of_the_mean_falls_as_one_over_root_m_whatever_the_clearance_and_dwell() {
    let (config, mut base) = Settings::default().resolve().unwrap();
    base.random_um = 0.0;
    let cases: Vec<(u32, Timing)> = [2u32, 4, 8].into_iter().zip(draws(3)).collect();
    let found: Vec<(u32, Timing, f64, f64, usize)> = cases
        .into_par_iter()
        .map(|(m, t)| {
            let s = with_timing(
                &base,
                t,
                CycleSettings {
                    averages_per_z: m,
                    repeats: m * Z_POSITIONS,
                    ..base.cycle
                },
            );
            let reports = run(&config, &s);
            let means = per_z_means(&reports);
            assert!(means.iter().all(|z| z.m == m as usize));
            // The mean of one Z's approaches has the σ/√m it reports.
            for z in &means {
                assert!((z.sigma_of_mean_um - z.sigma_um / f64::from(m).sqrt()).abs() < 1e-9);
            }
            let sigma_mean = Spread::of(means.iter().map(|z| Some(z.diameter_mm))).std * 1000.0;
            (m, t, sigma_um(&reports), sigma_mean, means.len())
        })
        .collect();
    for (m, t, sigma_1, sigma_mean, z) in found {
        assert_eq!(z, Z_POSITIONS as usize);
        assert!(
            sigma_1 > 0.2,
            "σ of one measurement {sigma_1:.3} µm: nothing to average"
        );
        let n = f64::from(m * Z_POSITIONS);
        let band =
            3.0 * (1.0 / (2.0 * (f64::from(Z_POSITIONS) - 1.0)) + 1.0 / (2.0 * (n - 1.0))).sqrt();
        let ratio = sigma_mean / sigma_1;
        let s8 = 1.0 / f64::from(m).sqrt();
        let line = format!(
            "m = {m}, {t:?}: σ of the mean {sigma_mean:.3} µm, σ of one {sigma_1:.3} µm, \
             ratio {ratio:.3} against S8's 1/√m = {s8:.3} (±{:.0} %)",
            band * 100.0
        );
        eprintln!("{line}");
        assert!((ratio / s8 - 1.0).abs() <= band, "{line}");
    }
}
