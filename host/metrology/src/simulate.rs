//! The same figures as the budget, simulated: the closed-loop measurement cycle on the
//! golden model (`crate::measurement_cycle`), repeated, for one method and contact rule.
//!
//! The budget takes the slow spindle errors' phase at an approach's start as unknown; the
//! simulated lathe draws it per approach (`tooltouch_plant::lathe::SlowHarmonic`), so the
//! measurements of one run are already independent draws. They are made in runs of
//! [`RUN_LENGTH`], each with its own seed, only to run in parallel, and pooled.

use crate::budget::{Reference, Variant};
use rayon::prelude::*;
use serde::Serialize;
use tooltouch_model::validation::ConfigError;
use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_plant::lathe::surface::mix;
use tooltouch_plant::lathe::{LatheScenario, ScenarioError};
use tooltouch_plant::measurement_cycle::{self, Summary};

/// Simulated figures of one variant.
#[derive(Clone, Debug, Serialize)]
pub struct Simulated {
    /// The variant.
    pub variant: Variant,
    /// Measurements made.
    pub repeats: u32,
    /// Measurements that decided.
    pub decided: usize,
    /// Mean error against the variant's reference (the true mean or largest diameter), µm.
    pub bias_um: f64,
    /// Its standard error, µm (`σ/√n` of the errors).
    pub bias_standard_error_um: f64,
    /// 1σ of the decided diameter, µm.
    pub sigma_um: f64,
    /// Mean error against the true mean, µm.
    pub bias_vs_mean_um: f64,
    /// Mean error against the true largest, µm.
    pub bias_vs_largest_um: f64,
    /// Revolutions from first contact to the decision, mean.
    pub revs_to_decision: f64,
    /// Revolutions from first contact to permanent contact, mean.
    pub revs_to_permanent: f64,
    /// The run's whole summary.
    pub summary: Summary,
}

/// Measurements per simulated run (see the module's doc).
pub const RUN_LENGTH: u32 = 20;

/// `settings` with the variant's method and contact rule.
pub fn config_of(
    settings: &MeasureSettings,
    variant: Variant,
) -> Result<MeasureConfig, ConfigError> {
    MeasureSettings {
        method: variant.method,
        contact_rule: variant.rule,
        ..*settings
    }
    .validate()
}

/// Runs `repeats` measurements of `scenario` (with its seed replaced by `seed`) for
/// `variant`.
pub fn simulate(
    settings: &MeasureSettings,
    scenario: &LatheScenario,
    variant: Variant,
    repeats: u32,
    seed: u64,
) -> Result<Simulated, SimulateError> {
    let config = config_of(settings, variant).map_err(SimulateError::Measure)?;
    let runs = repeats.div_ceil(RUN_LENGTH);
    let reports: Vec<Vec<_>> = (0..runs)
        .into_par_iter()
        .map(|k| {
            let mut s = scenario.clone();
            s.seed = mix(seed, 0x00b0_d6e7, u64::from(k));
            s.cycle.repeats = RUN_LENGTH.min(repeats - k * RUN_LENGTH);
            measurement_cycle::run(&s, &config, &mut |_| {})
                .map(|r| r.measurements)
                .map_err(SimulateError::Lathe)
        })
        .collect::<Result<_, _>>()?;
    let all: Vec<_> = reports.into_iter().flatten().collect();
    let t = Summary::of(&all, scenario.scale_resolution_um);
    let errors = match variant.reference() {
        Reference::Mean => &t.error_vs_mean_um,
        Reference::Largest => &t.error_vs_largest_um,
    };
    Ok(Simulated {
        variant,
        repeats,
        decided: t.decided,
        bias_um: errors.mean,
        bias_standard_error_um: errors.std / (errors.n.max(1) as f64).sqrt(),
        sigma_um: t.diameter_mm.std * 1000.0,
        bias_vs_mean_um: t.error_vs_mean_um.mean,
        bias_vs_largest_um: t.error_vs_largest_um.mean,
        revs_to_decision: t.revs_to_decision.mean,
        revs_to_permanent: t.revs_to_permanent.mean,
        summary: t,
    })
}

/// A simulation that could not run.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// The model's settings are out of range.
    #[error("[measure] {0}")]
    Measure(ConfigError),
    /// The lathe's settings are out of range.
    #[error("[lathe] {0}")]
    Lathe(ScenarioError),
}
