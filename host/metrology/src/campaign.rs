//! The fault campaign (`tooltouch faults`): how often a machine that misbehaves gets a
//! wrong diameter through as a good one.
//!
//! Over fault kind × level × decision method, `measurements` closed-loop measurements each
//! (the simulated lathe with one `[lathe.faults]` entry set, [`FaultKind::faults`]), every
//! measurement is classified ([`Class`]) against the same part measured on a clean lathe:
//!
//! - **flagged**: the status named a fault (the CNC alarms);
//! - **unconfirmed**: no fault, but the decision was not confirmed (the CNC re-measures);
//! - **silent-wrong**: accepted (decided, confirmed, no fault) and the diameter off by more
//!   than the tolerance: 3σ of the budget's repeatability for the method, or of the clean
//!   run's scatter where the budget refuses (the density detector), at least one scale
//!   count on the diameter;
//! - **silent-harmless**: accepted and within the tolerance;
//! - **no-decision-unflagged**: no decision and no fault (the CNC would feed on).
//!
//! "Off" is measured from the clean run's reading of the same part: the true mean
//! diameter of that Z plus the method's mean error on the clean lathe (its bias), so a
//! method's bias is not counted as a fault's.
//!
//! Cells are independent and run in parallel; a shard (`k/n`) runs the cells whose index is
//! `k` modulo `n`, and [`merge`] joins shards into exactly the unsharded result.

use crate::budget::{predict, Variant};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use tooltouch_model::measure::config::DecisionMethod;
use tooltouch_model::MeasureSettings;
use tooltouch_plant::lathe::faults::{BrokenWire, Chips, CoolantBridge, Emi, LatheFaults};
use tooltouch_plant::lathe::{LatheScenario, ScenarioError};
use tooltouch_plant::measurement_cycle::{self, MeasurementReport};

/// A kind of machine fault the campaign puts on the lathe, at a level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FaultKind {
    /// Chips: contact bursts of 1.2 revolutions; level: bursts per second.
    Chips,
    /// A coolant bridge at the arm, 5 ms; level: probability per approach.
    CoolantBridge,
    /// EMI on the contact line, spikes up to 8 clocks (longer than the default filter);
    /// level: spikes per second.
    EmiContact,
    /// EMI on the FES line; level: spikes per second.
    EmiFes,
    /// EMI on the index line; level: spikes per second.
    EmiIndex,
    /// EMI on both scale lines at once; level: spikes per second.
    EmiScale,
    /// FES pulses lost; level: probability per pulse.
    FesLost,
    /// FES pulses doubled; level: probability per pulse.
    FesDoubled,
    /// Index pulses lost; level: probability per pulse.
    IndexLost,
    /// Index pulses doubled; level: probability per pulse.
    IndexDoubled,
    /// The contact wire broken from power-on; level: ignored (1).
    BrokenContact,
    /// The FES track broken from power-on; level: ignored (1).
    BrokenFes,
}

impl FaultKind {
    /// Every kind, in the campaign's order.
    pub const ALL: [FaultKind; 12] = [
        FaultKind::Chips,
        FaultKind::CoolantBridge,
        FaultKind::EmiContact,
        FaultKind::EmiFes,
        FaultKind::EmiIndex,
        FaultKind::EmiScale,
        FaultKind::FesLost,
        FaultKind::FesDoubled,
        FaultKind::IndexLost,
        FaultKind::IndexDoubled,
        FaultKind::BrokenContact,
        FaultKind::BrokenFes,
    ];

    /// The kind's name, as in settings and reports.
    pub fn name(self) -> &'static str {
        match self {
            FaultKind::Chips => "chips",
            FaultKind::CoolantBridge => "coolant-bridge",
            FaultKind::EmiContact => "emi-contact",
            FaultKind::EmiFes => "emi-fes",
            FaultKind::EmiIndex => "emi-index",
            FaultKind::EmiScale => "emi-scale",
            FaultKind::FesLost => "fes-lost",
            FaultKind::FesDoubled => "fes-doubled",
            FaultKind::IndexLost => "index-lost",
            FaultKind::IndexDoubled => "index-doubled",
            FaultKind::BrokenContact => "broken-contact",
            FaultKind::BrokenFes => "broken-fes",
        }
    }

    /// The kind named `name`.
    pub fn named(name: &str) -> Option<FaultKind> {
        FaultKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// What the level counts.
    pub fn unit(self) -> &'static str {
        match self {
            FaultKind::Chips
            | FaultKind::EmiContact
            | FaultKind::EmiFes
            | FaultKind::EmiIndex
            | FaultKind::EmiScale => "per second",
            FaultKind::CoolantBridge => "per approach",
            FaultKind::FesLost
            | FaultKind::FesDoubled
            | FaultKind::IndexLost
            | FaultKind::IndexDoubled => "per pulse",
            FaultKind::BrokenContact | FaultKind::BrokenFes => "broken",
        }
    }

    /// The default campaign's levels.
    pub fn default_levels(self) -> &'static [f64] {
        match self {
            FaultKind::Chips => &[1.0, 5.0, 20.0],
            FaultKind::CoolantBridge => &[0.1, 0.5, 1.0],
            FaultKind::EmiContact | FaultKind::EmiFes | FaultKind::EmiIndex => {
                &[10.0, 100.0, 1000.0]
            }
            FaultKind::EmiScale => &[1.0, 10.0, 100.0],
            FaultKind::FesLost | FaultKind::FesDoubled => &[0.001, 0.01, 0.333],
            FaultKind::IndexLost | FaultKind::IndexDoubled => &[0.05, 0.3, 1.0],
            FaultKind::BrokenContact | FaultKind::BrokenFes => &[1.0],
        }
    }

    /// The largest level that makes sense (probabilities 1, rates 1e6 per second).
    pub fn max_level(self) -> f64 {
        match self.unit() {
            "per second" => 1e3,
            _ => 1.0,
        }
    }

    /// The lathe's faults for this kind at `level`.
    pub fn faults(self, level: f64) -> LatheFaults {
        let emi = |f: fn(&mut Emi, f64)| {
            let mut e = Emi {
                length_cycles: 8,
                ..Emi::default()
            };
            f(&mut e, level);
            LatheFaults {
                emi: e,
                ..LatheFaults::default()
            }
        };
        match self {
            FaultKind::Chips => LatheFaults {
                chips: Chips {
                    rate_hz: level,
                    length_revs: 1.2,
                },
                ..LatheFaults::default()
            },
            FaultKind::CoolantBridge => LatheFaults {
                coolant_bridge: CoolantBridge {
                    probability: level,
                    length_ms: 5.0,
                },
                ..LatheFaults::default()
            },
            FaultKind::EmiContact => emi(|e, l| e.contact_hz = l),
            FaultKind::EmiFes => emi(|e, l| e.fes_hz = l),
            FaultKind::EmiIndex => emi(|e, l| e.index_hz = l),
            FaultKind::EmiScale => emi(|e, l| e.scale_hz = l),
            FaultKind::FesLost => LatheFaults {
                fes_lost: level,
                ..LatheFaults::default()
            },
            FaultKind::FesDoubled => LatheFaults {
                fes_doubled: level,
                ..LatheFaults::default()
            },
            FaultKind::IndexLost => LatheFaults {
                index_lost: level,
                ..LatheFaults::default()
            },
            FaultKind::IndexDoubled => LatheFaults {
                index_doubled: level,
                ..LatheFaults::default()
            },
            FaultKind::BrokenContact => LatheFaults {
                broken_wire: BrokenWire::Contact,
                ..LatheFaults::default()
            },
            FaultKind::BrokenFes => LatheFaults {
                broken_wire: BrokenWire::Fes,
                ..LatheFaults::default()
            },
        }
    }
}

/// What became of one measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Class {
    /// The status named a fault.
    Flagged,
    /// No fault, but not confirmed.
    Unconfirmed,
    /// Accepted, and off by more than the tolerance.
    SilentWrong,
    /// Accepted, within the tolerance.
    SilentHarmless,
    /// No decision, no fault.
    NoDecisionUnflagged,
}

impl Class {
    /// Every class, in report order.
    pub const ALL: [Class; 5] = [
        Class::Flagged,
        Class::Unconfirmed,
        Class::SilentWrong,
        Class::SilentHarmless,
        Class::NoDecisionUnflagged,
    ];

    /// The class's name, as in reports.
    pub fn name(self) -> &'static str {
        match self {
            Class::Flagged => "flagged",
            Class::Unconfirmed => "unconfirmed",
            Class::SilentWrong => "silent-wrong",
            Class::SilentHarmless => "silent-harmless",
            Class::NoDecisionUnflagged => "no-decision-unflagged",
        }
    }
}

/// Measurements per class, in [`Class::ALL`] order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClassCounts {
    /// The status named a fault.
    pub flagged: u32,
    /// No fault, not confirmed.
    pub unconfirmed: u32,
    /// Accepted and wrong.
    pub silent_wrong: u32,
    /// Accepted and right.
    pub silent_harmless: u32,
    /// No decision, no fault.
    pub no_decision_unflagged: u32,
}

impl ClassCounts {
    fn add(&mut self, class: Class) {
        *self.slot(class) += 1;
    }
    fn slot(&mut self, class: Class) -> &mut u32 {
        match class {
            Class::Flagged => &mut self.flagged,
            Class::Unconfirmed => &mut self.unconfirmed,
            Class::SilentWrong => &mut self.silent_wrong,
            Class::SilentHarmless => &mut self.silent_harmless,
            Class::NoDecisionUnflagged => &mut self.no_decision_unflagged,
        }
    }
    /// The count of `class`.
    pub fn of(&self, class: Class) -> u32 {
        let mut c = *self;
        *c.slot(class)
    }
    /// Every measurement counted.
    pub fn total(&self) -> u32 {
        Class::ALL.iter().map(|&c| self.of(c)).sum()
    }
}

/// The campaign's settings (`tooltouch faults --config`, `[campaign]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CampaignSpec {
    /// Fault kinds, by name; empty: every kind.
    pub kinds: Vec<FaultKind>,
    /// Levels for every kind; empty: each kind's defaults ([`FaultKind::default_levels`]).
    pub levels: Vec<f64>,
    /// Decision methods.
    pub methods: Vec<DecisionMethod>,
    /// Measurements per cell, `1..=1000`.
    pub measurements: u32,
}

impl Default for CampaignSpec {
    /// Every kind at its default levels, the three methods, 20 measurements per cell.
    fn default() -> Self {
        CampaignSpec {
            kinds: Vec::new(),
            levels: Vec::new(),
            methods: vec![
                DecisionMethod::Counter,
                DecisionMethod::Density,
                DecisionMethod::SinglePulse,
            ],
            measurements: 20,
        }
    }
}

/// A campaign setting out of range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CampaignError {
    /// A field of the campaign's own settings.
    #[error("campaign field `{field}`: {reason}")]
    Field {
        /// The field.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The lathe or the measurement settings.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// Shards of different campaigns, or not every slice.
    #[error("merge: {0}")]
    Merge(String),
}

/// One cell of the campaign: a kind at a level, a method.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellKey {
    /// The fault.
    pub kind: FaultKind,
    /// Its level.
    pub level: f64,
    /// The decision method.
    pub method: DecisionMethod,
}

/// One cell's result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellResult {
    /// Its position in the campaign's cell list.
    pub index: usize,
    /// The cell.
    pub key: CellKey,
    /// Measurements per class.
    pub counts: ClassCounts,
    /// The largest error of an accepted measurement, µm (0 when none was accepted).
    pub worst_accepted_error_um: f64,
}

/// The clean lathe's reading per method: the reference every cell is judged against.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CleanReference {
    /// The decision method.
    pub method: DecisionMethod,
    /// Measurements per class on the clean lathe (a false alarm is any but silent-harmless).
    pub counts: ClassCounts,
    /// Mean error of the clean readings against the true mean diameter, µm.
    pub bias_um: f64,
    /// The tolerance of a right reading, µm (3σ, at least one count on the diameter).
    pub tolerance_um: f64,
    /// Where the σ comes from: `budget` or `clean run` (the budget refuses the method).
    pub tolerance_from: String,
}

/// A whole campaign or one shard of it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CampaignResults {
    /// The spec's cells in order.
    pub cells_total: usize,
    /// The shard `(k, n)` this result holds, `None` for a whole campaign.
    pub shard: Option<(usize, usize)>,
    /// The clean references.
    pub clean: Vec<CleanReference>,
    /// The cells this result holds, by index.
    pub cells: Vec<CellResult>,
}

impl CampaignSpec {
    /// Checks the spec; errors name the field.
    pub fn validate(&self) -> Result<(), CampaignError> {
        if !(1..=1000).contains(&self.measurements) {
            return Err(CampaignError::Field {
                field: "measurements",
                reason: format!("{} is out of range: allowed 1..=1000", self.measurements),
            });
        }
        if self.methods.is_empty() {
            return Err(CampaignError::Field {
                field: "methods",
                reason: "no method: give at least one of counter, density, single-pulse".into(),
            });
        }
        for (i, &l) in self.levels.iter().enumerate() {
            let most = self
                .kinds()
                .iter()
                .map(|k| k.max_level())
                .fold(f64::INFINITY, f64::min);
            if !(l.is_finite() && l > 0.0 && l <= most) {
                return Err(CampaignError::Field {
                    field: "levels",
                    reason: format!(
                        "level {i} = {l} is out of range: allowed above 0 and at most {most} \
                         (probabilities are at most 1, rates at most 1000 per second)"
                    ),
                });
            }
        }
        Ok(())
    }

    fn kinds(&self) -> Vec<FaultKind> {
        if self.kinds.is_empty() {
            FaultKind::ALL.to_vec()
        } else {
            self.kinds.clone()
        }
    }

    /// Every cell, in a fixed order: kind, level, method.
    pub fn cells(&self) -> Vec<CellKey> {
        let mut out = Vec::new();
        for kind in self.kinds() {
            let levels: Vec<f64> = if self.levels.is_empty() || kind.unit() == "broken" {
                kind.default_levels().to_vec()
            } else {
                self.levels.clone()
            };
            for level in levels {
                for &method in &self.methods {
                    out.push(CellKey {
                        kind,
                        level,
                        method,
                    });
                }
            }
        }
        out
    }
}

/// A decision method's name in reports: `counter`, `density`, `single pulse`.
pub fn method_name(method: DecisionMethod) -> &'static str {
    match method {
        DecisionMethod::Counter => "counter",
        DecisionMethod::Density => "density",
        DecisionMethod::SinglePulse => "single pulse",
    }
}

/// The settings of one method's runs.
fn with_method(measure: &MeasureSettings, method: DecisionMethod) -> MeasureSettings {
    MeasureSettings { method, ..*measure }
}

/// The lathe `base` measuring `n` times with `faults`.
fn scenario(base: &LatheScenario, faults: LatheFaults, n: u32) -> LatheScenario {
    let mut s = base.clone();
    s.faults = faults;
    s.cycle.repeats = n;
    s.cycle.averages_per_z = 1;
    s
}

/// The clean reference of `method`.
fn clean_reference(
    base: &LatheScenario,
    measure: &MeasureSettings,
    method: DecisionMethod,
    n: u32,
) -> Result<(CleanReference, Vec<MeasurementReport>), CampaignError> {
    let settings = with_method(measure, method);
    let config = settings.validate().map_err(|e| CampaignError::Field {
        field: "measure",
        reason: e.to_string(),
    })?;
    let s = scenario(base, LatheFaults::default(), n);
    let run = measurement_cycle::run(&s, &config, &mut |_| {})?;
    let errors: Vec<f64> = run
        .measurements
        .iter()
        .filter_map(|m| m.error_vs_mean_um)
        .collect();
    let count = errors.len().max(1) as f64;
    let bias_um = errors.iter().sum::<f64>() / count;
    let clean_sigma =
        (errors.iter().map(|e| (e - bias_um).powi(2)).sum::<f64>() / (count - 1.0).max(1.0)).sqrt();
    let variant = Variant {
        method,
        rule: settings.contact_rule,
    };
    let budget_sigma = match method {
        DecisionMethod::Density => None,
        _ => predict(&config, &s, variant)
            .prediction()
            .map(|p| p.repeatability_2sigma_um() / 2.0),
    };
    let (sigma, from) = match budget_sigma {
        Some(sigma) => (sigma, "budget"),
        None => (clean_sigma, "clean run"),
    };
    let one_count = 2.0 * base.scale_resolution_um;
    let mut reference = CleanReference {
        method,
        counts: ClassCounts::default(),
        bias_um,
        tolerance_um: (3.0 * sigma).max(one_count),
        tolerance_from: from.into(),
    };
    for m in &run.measurements {
        reference.counts.add(classify(m, &reference).0);
    }
    Ok((reference, run.measurements))
}

/// The class of measurement `m` and, when accepted, its error from the clean reading, µm.
fn classify(m: &MeasurementReport, reference: &CleanReference) -> (Class, Option<f64>) {
    if m.faults != 0 {
        return (Class::Flagged, None);
    }
    if m.decision_position.is_none() {
        return (Class::NoDecisionUnflagged, None);
    }
    if !m.accepted {
        return (Class::Unconfirmed, None);
    }
    let error = m
        .latched_diameter_mm
        .map(|d| (d - m.true_mean_diameter_mm) * 1000.0 - reference.bias_um)
        .unwrap_or(f64::INFINITY);
    if error.abs() > reference.tolerance_um {
        (Class::SilentWrong, Some(error))
    } else {
        (Class::SilentHarmless, Some(error))
    }
}

/// Runs the campaign `spec` on the lathe `base` with the measurement settings `measure`
/// (its method replaced by each cell's), the cells of `shard` only (`(k, n)`: index `% n ==
/// k`). `progress` is called after each cell.
pub fn run(
    spec: &CampaignSpec,
    base: &LatheScenario,
    measure: &MeasureSettings,
    shard: Option<(usize, usize)>,
    progress: &(dyn Fn() + Sync),
) -> Result<CampaignResults, CampaignError> {
    spec.validate()?;
    let cells = spec.cells();
    let clean: Vec<CleanReference> = spec
        .methods
        .par_iter()
        .map(|&method| clean_reference(base, measure, method, spec.measurements).map(|c| c.0))
        .collect::<Result<_, _>>()?;
    let mine: Vec<(usize, CellKey)> = cells
        .iter()
        .copied()
        .enumerate()
        .filter(|(i, _)| shard.is_none_or(|(k, n)| i % n == k))
        .collect();
    let results: Vec<CellResult> =
        mine.par_iter()
            .map(|&(index, key)| {
                let reference = clean
                    .iter()
                    .find(|c| c.method == key.method)
                    .expect("a reference per method");
                let config = with_method(measure, key.method).validate().map_err(|e| {
                    CampaignError::Field {
                        field: "measure",
                        reason: e.to_string(),
                    }
                })?;
                let s = scenario(base, key.kind.faults(key.level), spec.measurements);
                let run = measurement_cycle::run(&s, &config, &mut |_| {})?;
                let mut counts = ClassCounts::default();
                let mut worst: f64 = 0.0;
                for m in &run.measurements {
                    let (class, error) = classify(m, reference);
                    counts.add(class);
                    if let Some(e) = error {
                        worst = worst.max(e.abs());
                    }
                }
                progress();
                Ok(CellResult {
                    index,
                    key,
                    counts,
                    worst_accepted_error_um: worst,
                })
            })
            .collect::<Result<_, CampaignError>>()?;
    Ok(CampaignResults {
        cells_total: cells.len(),
        shard,
        clean,
        cells: results,
    })
}

/// Joins the shards of one campaign into the whole result (exactly the unsharded run's).
pub fn merge(parts: &[CampaignResults]) -> Result<CampaignResults, CampaignError> {
    let first = parts
        .first()
        .ok_or_else(|| CampaignError::Merge("no slice given".into()))?;
    let n = first.shard.map_or(1, |s| s.1);
    let mut seen = vec![false; n];
    let mut cells = Vec::new();
    for p in parts {
        if p.cells_total != first.cells_total || p.clean != first.clean {
            return Err(CampaignError::Merge(
                "the slices are of different campaigns (cells or clean references differ)".into(),
            ));
        }
        let (k, pn) = p
            .shard
            .ok_or_else(|| CampaignError::Merge("a whole campaign is not a slice".into()))?;
        if pn != n || seen[k] {
            return Err(CampaignError::Merge(format!(
                "slice {k}/{pn} is given twice or belongs to a split other than /{n}"
            )));
        }
        seen[k] = true;
        cells.extend(p.cells.iter().cloned());
    }
    if let Some(k) = seen.iter().position(|s| !s) {
        return Err(CampaignError::Merge(format!("slice {k}/{n} is missing")));
    }
    cells.sort_by_key(|c| c.index);
    Ok(CampaignResults {
        cells_total: first.cells_total,
        shard: None,
        clean: first.clean.clone(),
        cells,
    })
}

#[cfg(test)]
mod tests;
