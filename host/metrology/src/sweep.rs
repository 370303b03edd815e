//! The budget over the variants and over a sweep of one setting: the work behind
//! `tooltouch budget` (the CLI only parses and prints).

use crate::budget::{predict, Outcome, Variant};
use crate::simulate::{config_of, simulate, SimulateError, Simulated};
use rayon::prelude::*;
use serde::Serialize;
use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_plant::lathe::LatheScenario;

/// The setting a sweep varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Sweep {
    /// A factor on every slow spindle error amplitude.
    SlowGain,
    /// The radial feed, µm per revolution.
    FeedUm,
    /// The non-cancelling fraction of the per-revolution errors.
    Mismatch,
    /// The roughness, µm 1σ.
    Random,
}

impl Sweep {
    /// Every sweep with its name on the command line.
    pub const ALL: [(Sweep, &'static str); 4] = [
        (Sweep::SlowGain, "slow-gain"),
        (Sweep::FeedUm, "feed-um"),
        (Sweep::Mismatch, "mismatch"),
        (Sweep::Random, "random"),
    ];

    /// The sweep's default values.
    pub fn default_values(self) -> Vec<f64> {
        match self {
            Sweep::SlowGain => vec![0.0, 0.5, 1.0, 1.5, 2.0, 3.0],
            Sweep::FeedUm => vec![0.5, 0.75, 1.0, 1.5, 2.0],
            Sweep::Mismatch => vec![0.0, 0.1, 0.2, 0.4],
            Sweep::Random => vec![0.0, 0.1, 0.2, 0.4],
        }
    }

    /// `base` with the swept setting at `value`.
    pub fn apply(self, base: &LatheScenario, value: f64) -> LatheScenario {
        let mut s = base.clone();
        match self {
            Sweep::SlowGain => s.slow.iter_mut().for_each(|h| h.amplitude_um *= value),
            Sweep::FeedUm => s.feed_mm_per_rev = value / 1000.0,
            Sweep::Mismatch => s.repeating_mismatch = value,
            Sweep::Random => s.random_um = value,
        }
        s
    }

    /// The axis label.
    pub fn label(self) -> &'static str {
        match self {
            Sweep::SlowGain => "slow-error gain",
            Sweep::FeedUm => "feed, µm/rev",
            Sweep::Mismatch => "repeating mismatch",
            Sweep::Random => "roughness, µm (1σ)",
        }
    }
}

impl std::str::FromStr for Sweep {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        Sweep::ALL
            .iter()
            .find(|(_, n)| *n == name)
            .map(|(s, _)| *s)
            .ok_or_else(|| {
                let names: Vec<&str> = Sweep::ALL.iter().map(|(_, n)| *n).collect();
                format!("unknown sweep `{name}` (one of {})", names.join(", "))
            })
    }
}

/// The budget of every [`Variant`] on `scenario`: each variant's model configuration from
/// `measure` with its method and rule (`config` where that is out of range).
pub fn predict_variants(
    measure: &MeasureSettings,
    config: &MeasureConfig,
    scenario: &LatheScenario,
) -> Vec<Outcome> {
    Variant::ALL
        .par_iter()
        .map(|&v| {
            let c = config_of(measure, v).unwrap_or(*config);
            predict(&c, scenario, v)
        })
        .collect()
}

/// `n` seeded simulations of each predicted variant of `outcomes` (`None` where refused).
pub fn simulate_variants(
    measure: &MeasureSettings,
    scenario: &LatheScenario,
    outcomes: &[Outcome],
    n: u32,
) -> Result<Vec<Option<Simulated>>, SimulateError> {
    outcomes
        .par_iter()
        .map(|o| match o {
            Outcome::Predicted(p) => {
                simulate(measure, scenario, p.variant, n, scenario.seed).map(Some)
            }
            Outcome::Refused { .. } => Ok(None),
        })
        .collect()
}
