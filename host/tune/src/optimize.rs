//! Word lengths and gains chosen, not only swept (`tooltouch tune optimize`): the cheapest
//! point of a search space that meets tolerances against the float references, found
//! without running the whole grid.
//!
//! The space is a sweep spec (`[space]`, the keys of [`SweepSpec`]; for the force path its
//! `[space.force]` table). Its categorical parameters (method × contact rule × charge law,
//! or controller × force source) make *families*; each family's numeric parameters are
//! *axes* (their values sorted). The search, per family:
//!
//! - **measurement path** (cost from the [`CostModel`], known before a point is simulated):
//!   start with the word lengths and the glitch filter at their largest values and every
//!   other axis at its middle value; while the point misses a tolerance, move along the
//!   axis whose values (others held) reduce the violation most (a line search per axis);
//!   then **bisect per axis**: of the axis' values that cost less than the current point,
//!   sorted by cost, find the cheapest that still meets every tolerance, assuming that
//!   a cheaper value along one axis never meets a tolerance a dearer one misses (true of
//!   word lengths); repeat over the axes until none moves; then try each axis' neighbours
//!   at no more cost (a cheaper one, or one as cheap with a smaller error), which catches
//!   where that assumption fails, and bisect again after a move. Families whose cheapest
//!   conceivable point (each axis at its cheapest value: the cost model is a sum of
//!   per-parameter terms) costs more than the best point found are skipped.
//! - **force path** (cost = the fixed-point kernel's IAE, known only by simulating):
//!   compass search from the axes' middle values: try the points a step up and down each
//!   axis (a quarter of the longest axis at first), move to the best that improves, halve
//!   the step when none does, stop when a step of one value improves nothing. It finds a
//!   local optimum; the tests state how far from the swept one. With
//!   `cost = "firmware_instructions"` the same search minimizes the instructions the Nucleo
//!   image spends per control period ([`crate::firmware_cost`]: each point executed under
//!   QEMU, its force outputs checked bit for bit), under the tolerances — `iae` among them,
//!   to say how good the gains must be. Each family's start point is evaluated first; the
//!   families are searched cheapest first, and one whose start point costs more than the
//!   best answer by over [`GAINS_COST_SPREAD`] is skipped.
//!
//! Every simulated point is an *evaluation* (logged, counted against `[limits]`); a point
//! is simulated once. The answer is the cheapest point meeting every tolerance (ties: the
//! smaller error of the first constraint).

use crate::cost::CostModel;
use crate::firmware_cost::CostImage;
use crate::scenario::{self, Approach};
use crate::spec::{method_name, rule_name, Axes, Law, SweepSpec};
use crate::{point_settings, row, Row};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::time::Instant;
use tooltouch_firmware_runner::CosimError;
use tooltouch_model::measure::config::{ContactRule, DecisionMethod};
use tooltouch_plant::drive::scenario::{run, ControlScenario, Engine};
use tooltouch_settings::force_design::{ForcePoint, ForceSpec};
use tooltouch_settings::values::{err, Names, SpecError, Values};

/// Which path is tuned.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TunedPath {
    /// The measurement front end (FPGA).
    Measure,
    /// The force controllers' gains (firmware).
    Force,
}

/// The cost to minimize.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CostKind {
    /// iCE40 logic cells of the tuning cost model (measurement path; the default).
    LogicCells,
    /// Flip-flops of the tuning cost model (measurement path).
    FlipFlops,
    /// IAE of the fixed-point force kernel on the depth-step scenario, N·s (force path;
    /// its default).
    IaeModel,
    /// Instructions the Nucleo image spends on the force path per control period, measured
    /// by executing it under QEMU on the depth-step scenario ([`crate::firmware_cost`];
    /// force path).
    FirmwareInstructions,
}

impl CostKind {
    /// The name in a spec file.
    pub fn name(self) -> &'static str {
        match self {
            CostKind::LogicCells => "logic_cells",
            CostKind::FlipFlops => "flip_flops",
            CostKind::IaeModel => "iae_model",
            CostKind::FirmwareInstructions => "firmware_instructions",
        }
    }
}

/// Tolerances: a point meets one when its value is at most the tolerance. `None`: not
/// constrained. A measurement point must in any case decide on some scenario and miss no
/// decision its float reference takes (or the reverse).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Constraints {
    /// Mean |latched diameter − float reference's| over the decided scenarios, µm.
    pub diameter_error_um: Option<f64>,
    /// Largest |latched diameter − float reference's|, µm.
    pub max_diameter_error_um: Option<f64>,
    /// Mean |decision revolution − float reference's|, revolutions.
    pub revolution_error: Option<f64>,
    /// |IAE of the fixed-point kernel − IAE of the float reference|, N·s (force path).
    pub iae_difference: Option<f64>,
    /// Largest |override of the fixed-point kernel − float reference's| over the control
    /// ticks, percentage points (force path).
    pub override_difference: Option<f64>,
    /// IAE of the fixed-point kernel on the depth-step scenario, N·s (force path): how
    /// good the gains must be, when the cost is not the IAE itself.
    pub iae: Option<f64>,
}

/// Limits of the search: it stops at whichever comes first, and answers with the best
/// point found so far.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Limits {
    /// Evaluations (simulated points), `1..=1000000`.
    pub evaluations: u32,
    /// Wall-clock seconds, above 0.
    pub seconds: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            evaluations: 1000,
            seconds: 600.0,
        }
    }
}

/// An optimizer spec (`tooltouch tune optimize --spec FILE`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimizeSpec {
    /// `measure` or `force`.
    pub path: TunedPath,
    /// `logic_cells` (default) or `flip_flops` for the measurement path, `iae_model`
    /// (default) or `firmware_instructions` for the force path.
    #[serde(default)]
    pub cost: Option<CostKind>,
    /// The search space: a sweep spec (parameters not given keep the default sweep's
    /// values); the force path searches its `[space.force]` table.
    #[serde(default)]
    pub space: SweepSpec,
    /// Tolerances.
    #[serde(default)]
    pub constraints: Constraints,
    /// Limits.
    #[serde(default)]
    pub limits: Limits,
}

/// The dotted key a TOML error is about: the one in backticks of the message (`unknown
/// field `x``, `missing field `x``) or the key on the line the error points at, under the
/// table header above it.
fn toml_error_key(text: &str, e: &toml::de::Error) -> String {
    let msg = e.message();
    let named = msg
        .split('`')
        .nth(1)
        .filter(|_| msg.contains(" field `"))
        .map(str::to_string);
    let Some(span) = e.span() else {
        return named.unwrap_or_else(|| "(file)".into());
    };
    let header = |l: &str| {
        l.trim()
            .trim_matches(|c| c == '[' || c == ']')
            .trim()
            .to_string()
    };
    let at = span.start.min(text.len());
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..].lines().next().unwrap_or("").trim();
    if line.starts_with('[') && named.is_none() {
        return header(line);
    }
    // The table the line is in: its own header line, or the last header above it.
    let table = if line.starts_with('[') {
        Some(header(line))
    } else {
        text[..line_start]
            .lines()
            .rev()
            .find(|l| l.trim().starts_with('['))
            .map(header)
    };
    let key = named.or_else(|| {
        line.split_once('=')
            .map(|(k, _)| k.trim().trim_matches('"').to_string())
    });
    match (table, key) {
        (Some(t), Some(k)) => format!("{t}.{k}"),
        (Some(t), None) => t,
        (None, Some(k)) => k,
        (None, None) => "(file)".into(),
    }
}

impl OptimizeSpec {
    /// Parses and checks a spec: an error names the key (`constraints.diameter_error_um`).
    pub fn from_toml(text: &str) -> Result<OptimizeSpec, SpecError> {
        let spec: OptimizeSpec = toml::from_str(text)
            .map_err(|e| err(&toml_error_key(text, &e), e.message().trim().to_string()))?;
        spec.check()?;
        Ok(spec)
    }

    /// The cost this spec minimizes.
    pub fn cost_kind(&self) -> CostKind {
        self.cost.unwrap_or(match self.path {
            TunedPath::Measure => CostKind::LogicCells,
            TunedPath::Force => CostKind::IaeModel,
        })
    }

    /// Checks the keys' values and that each applies to the path.
    pub fn check(&self) -> Result<(), SpecError> {
        let c = &self.constraints;
        let all = [
            ("diameter_error_um", c.diameter_error_um, TunedPath::Measure),
            (
                "max_diameter_error_um",
                c.max_diameter_error_um,
                TunedPath::Measure,
            ),
            ("revolution_error", c.revolution_error, TunedPath::Measure),
            ("iae_difference", c.iae_difference, TunedPath::Force),
            (
                "override_difference",
                c.override_difference,
                TunedPath::Force,
            ),
            ("iae", c.iae, TunedPath::Force),
        ];
        for (key, value, path) in all {
            let key = format!("constraints.{key}");
            if let Some(v) = value {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(err(&key, format!("{v} is not a tolerance: allowed ≥ 0")));
                }
                if path != self.path {
                    return Err(err(
                        &key,
                        format!(
                            "applies to path = \"{}\", this spec tunes path = \"{}\"",
                            path_name(path),
                            path_name(self.path)
                        ),
                    ));
                }
            }
        }
        let cost_ok = matches!(
            (self.path, self.cost_kind()),
            (
                TunedPath::Measure,
                CostKind::LogicCells | CostKind::FlipFlops
            ) | (
                TunedPath::Force,
                CostKind::IaeModel | CostKind::FirmwareInstructions
            )
        );
        if !cost_ok {
            return Err(err(
                "cost",
                format!(
                    "`{}` is not a cost of path = \"{}\": allowed {}",
                    self.cost_kind().name(),
                    path_name(self.path),
                    match self.path {
                        TunedPath::Measure => "logic_cells, flip_flops",
                        TunedPath::Force => "iae_model, firmware_instructions",
                    }
                ),
            ));
        }
        let l = &self.limits;
        if !(1..=1_000_000).contains(&l.evaluations) {
            return Err(err(
                "limits.evaluations",
                format!("{} is out of range: allowed 1..=1000000", l.evaluations),
            ));
        }
        if !(l.seconds.is_finite() && l.seconds > 0.0) {
            return Err(err(
                "limits.seconds",
                format!("{} is out of range: allowed > 0", l.seconds),
            ));
        }
        match self.path {
            TunedPath::Measure => {
                self.space
                    .axes()
                    .map_err(|e| err(&format!("space.{}", e.parameter), e.message))?;
                if !(1..=1000).contains(&self.space.scenarios) {
                    return Err(err(
                        "space.scenarios",
                        format!("{} is out of range: allowed 1..=1000", self.space.scenarios),
                    ));
                }
                if !(1..=10_000).contains(&self.space.approach.revolutions) {
                    return Err(err(
                        "space.approach.revolutions",
                        format!(
                            "{} is out of range: allowed 1..=10000",
                            self.space.approach.revolutions
                        ),
                    ));
                }
            }
            TunedPath::Force => {
                force_axes(&self.space.force)?;
            }
        }
        Ok(())
    }
}

/// Whether a measured value (`None`: not measured, e.g. nothing decided, or NaN) is
/// within its tolerance.
fn meets(v: Option<f64>, tol: f64) -> bool {
    v.is_some_and(|v| v <= tol)
}

fn path_name(p: TunedPath) -> &'static str {
    match p {
        TunedPath::Measure => "measure",
        TunedPath::Force => "force",
    }
}

/// What one evaluation measured.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Metrics {
    /// Scenarios where both the model and the reference decided (measurement path).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decided: Option<u32>,
    /// Scenarios where only one of them decided (measurement path).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub misses: Option<u32>,
    /// Mean |diameter error|, µm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diameter_error_um: Option<f64>,
    /// Largest |diameter error|, µm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_diameter_error_um: Option<f64>,
    /// Mean |revolution error|, revolutions.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub revolution_error: Option<f64>,
    /// Estimated flip-flops.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flip_flops: Option<u32>,
    /// Estimated logic cells.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub logic_cells: Option<u32>,
    /// IAE of the fixed-point kernel, N·s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub iae_model: Option<f64>,
    /// IAE of the float reference, N·s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub iae_reference: Option<f64>,
    /// |iae_model − iae_reference|, N·s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub iae_difference: Option<f64>,
    /// Largest |override difference| over the ticks, percentage points.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub override_difference: Option<f64>,
    /// Overshoot after the depth step (model), %.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub overshoot_pct: Option<f64>,
    /// Instructions the Nucleo image spent on the force path per control period (when the
    /// cost is `firmware_instructions`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub firmware_instructions: Option<f64>,
}

/// One line of the evaluation log.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Evaluation {
    /// 1, 2, … in the order they ran.
    pub evaluation: usize,
    /// Seconds since the search started, when it finished.
    pub seconds: f64,
    /// The family: `counter sticky linear`, `pi estimated`.
    pub family: String,
    /// Each axis' value.
    pub parameters: BTreeMap<String, u32>,
    /// The cost minimized.
    pub cost: f64,
    /// What was measured.
    pub metrics: Metrics,
    /// The constraints the point misses (`misses`, `decided` for a measurement point that
    /// missed a decision or took none), empty when it meets them all.
    pub violated: Vec<String>,
}

impl Evaluation {
    /// Whether it meets every tolerance.
    pub fn feasible(&self) -> bool {
        self.violated.is_empty()
    }
}

/// A spec no evaluated point meets.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Unmet {
    /// The constraint (`constraints.diameter_error_um`, or `misses` / `decided`).
    pub constraint: String,
    /// Its tolerance.
    pub tolerance: f64,
    /// The best value of it any evaluation reached (`None`: none measured it).
    pub best: Option<f64>,
}

impl std::fmt::Display for Unmet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.constraint.as_str(), self.best) {
            ("decided", _) => write!(
                f,
                "no evaluated point decided on any scenario (`decided`: lengthen the approach or \
                 widen the space)"
            ),
            ("misses", Some(b)) => write!(
                f,
                "every evaluated point missed a decision its float reference took, or took one \
                 it did not (`misses`): the fewest is {b}"
            ),
            (c, Some(b)) => write!(
                f,
                "no point meets `{c}` ≤ {}: the best value reached is {b}",
                self.tolerance
            ),
            (c, None) => write!(
                f,
                "no point meets `{c}` ≤ {}: no evaluated point measured it",
                self.tolerance
            ),
        }
    }
}

/// The search's result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Optimum {
    /// Every evaluation, in order.
    pub evaluations: Vec<Evaluation>,
    /// The answer (an index into `evaluations`), if some point meets every tolerance.
    pub best: Option<usize>,
    /// Why it stopped early (`evaluation limit 100`, `time limit 60 s`), `None`: done.
    pub stopped: Option<String>,
    /// Points in the whole space (what a sweep would run).
    pub grid_points: u128,
    /// The answer's settings file (`tune point`'s format), if any.
    pub settings_toml: Option<String>,
    /// Without an answer: the constraint that kept the closest point out.
    pub unmet: Option<Unmet>,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// An axis of a family: its name and values, ascending.
#[derive(Clone, Debug)]
struct Axis {
    name: &'static str,
    values: Vec<u32>,
}

fn axis(name: &'static str, v: &[u32]) -> Axis {
    let mut values = v.to_vec();
    values.sort_unstable();
    values.dedup();
    Axis { name, values }
}

/// What a family's categorical parameters are.
#[derive(Clone, Copy, Debug)]
enum Categories {
    Measure(DecisionMethod, ContactRule, Law),
    Force(&'static str, &'static str),
}

#[derive(Clone, Debug)]
struct Family {
    categories: Categories,
    axes: Vec<Axis>,
}

impl Family {
    fn name(&self) -> String {
        match self.categories {
            Categories::Measure(m, r, l) => format!(
                "{} {} {}",
                method_name(m),
                rule_name(r),
                match l {
                    Law::Linear => "linear",
                    Law::Exponential => "exponential",
                }
            ),
            Categories::Force(c, s) => format!("{c} {s}"),
        }
    }
    fn size(&self) -> u128 {
        self.axes.iter().map(|a| a.values.len() as u128).product()
    }
}

fn measure_families(a: &Axes) -> Vec<Family> {
    let mut out = Vec::new();
    for &m in &a.methods {
        for &r in &a.rules {
            let mut laws = a.laws.clone();
            laws.dedup();
            for &l in &laws {
                let (c, d) = match l {
                    Law::Linear => (
                        axis("charge_pulses", &a.cp),
                        axis("discharge_pulses", &a.dp),
                    ),
                    Law::Exponential => {
                        (axis("charge_shift", &a.cs), axis("discharge_shift", &a.ds))
                    }
                };
                out.push(Family {
                    categories: Categories::Measure(m, r, l),
                    axes: vec![
                        axis("charge_bits", &a.charge_bits),
                        axis("scale_bits", &a.scale_bits),
                        axis("glitch_cycles", &a.glitch),
                        c,
                        d,
                        axis("fire_percent", &a.fire),
                        axis("rearm_percent", &a.rearm),
                        axis("window_revs", &a.window),
                        axis("i_def", &a.i_def),
                    ],
                });
            }
        }
    }
    out
}

fn force_axes(f: &ForceSpec) -> Result<Vec<Family>, SpecError> {
    let key = |p: &str| format!("space.{p}");
    let names =
        |n: &Names, p: &str, known: &[&'static str]| -> Result<Vec<&'static str>, SpecError> {
            let table: Vec<(&str, &'static str)> = known.iter().map(|k| (*k, *k)).collect();
            n.expand(&key(p), &table)
        };
    let controllers = match &f.controller {
        Names::List(v) if v.is_empty() => {
            return Err(err("space.force.controller", "no controllers to tune"))
        }
        n => names(n, "force.controller", &["pi", "adaptive", "fuzzy"])?,
    };
    let sources = names(
        &f.force_source,
        "force.force_source",
        &["estimated", "measured"],
    )?;
    let kps = f.kp_percent.expand(&key("force.kp_percent"), 1, 1000)?;
    let kis = f.ki_percent.expand(&key("force.ki_percent"), 1, 1000)?;
    let mut out = Vec::new();
    for &s in &sources {
        for &c in &controllers {
            let mut axes = vec![axis("kp_percent", &kps)];
            if c != "adaptive" {
                axes.push(axis("ki_percent", &kis));
            }
            out.push(Family {
                categories: Categories::Force(c, s),
                axes,
            });
        }
    }
    Ok(out)
}

/// A point of a family: each axis' value index.
type Coords = Vec<usize>;

/// Why a search stopped.
struct Stopped(String);

/// A point's measurements, before the constraints are applied.
enum Measured {
    Measure(Box<Row>),
    Force(Metrics),
}

struct Search<'a> {
    spec: &'a OptimizeSpec,
    approaches: Vec<Approach>,
    model: CostModel,
    start: Instant,
    evaluations: Vec<Evaluation>,
    cache: HashMap<(usize, Coords), Option<usize>>,
    progress: &'a (dyn Fn(&Evaluation) + Sync),
    /// The image measuring `firmware_instructions`.
    firmware: Option<CostImage>,
    /// Why the firmware could not measure a point (the search stops).
    firmware_failure: Option<String>,
}

impl Search<'_> {
    fn parameters(&self, fam: &Family, x: &Coords) -> BTreeMap<String, u32> {
        fam.axes
            .iter()
            .zip(x)
            .map(|(a, &i)| (a.name.to_string(), a.values[i]))
            .collect()
    }

    /// The single-point sweep spec of a measurement point.
    fn measure_spec(&self, fam: &Family, x: &Coords) -> SweepSpec {
        let Categories::Measure(m, r, l) = fam.categories else {
            unreachable!("a measurement family")
        };
        let mut s = self.spec.space.clone();
        s.method = Names::List(vec![method_name(m).into()]);
        s.contact_rule = Names::List(vec![rule_name(r).into()]);
        s.law = Names::List(vec![match l {
            Law::Linear => "linear".into(),
            Law::Exponential => "exponential".into(),
        }]);
        for (a, &i) in fam.axes.iter().zip(x) {
            let v = Values::One(i64::from(a.values[i]));
            match a.name {
                "charge_bits" => s.charge_bits = v,
                "scale_bits" => s.scale_bits = v,
                "glitch_cycles" => s.glitch_cycles = v,
                "charge_pulses" => s.charge_pulses = v,
                "discharge_pulses" => s.discharge_pulses = v,
                "charge_shift" => s.charge_shift = v,
                "discharge_shift" => s.discharge_shift = v,
                "fire_percent" => s.fire_percent = v,
                "rearm_percent" => s.rearm_percent = v,
                "window_revs" => s.window_revs = v,
                _ => s.i_def = v,
            }
        }
        s
    }

    fn force_point(&self, fam: &Family, x: &Coords) -> Option<ForcePoint> {
        let Categories::Force(c, src) = fam.categories else {
            unreachable!("a force family")
        };
        let v = |name: &str| {
            fam.axes
                .iter()
                .zip(x)
                .find(|(a, _)| a.name == name)
                .map_or(Values::One(100), |(a, &i)| {
                    Values::One(i64::from(a.values[i]))
                })
        };
        let f = ForceSpec {
            controller: Names::List(vec![c.into()]),
            kp_percent: v("kp_percent"),
            ki_percent: v("ki_percent"),
            force_source: Names::List(vec![src.into()]),
        };
        f.points().ok()?.into_iter().next()
    }

    /// The cost of a measurement point without simulating it (`None`: the model refuses
    /// the combination, e.g. a re-arm threshold above the fire threshold).
    fn known_cost(&self, fam: &Family, x: &Coords) -> Option<f64> {
        let point = self
            .measure_spec(fam, x)
            .points()
            .ok()?
            .into_iter()
            .next()?;
        let config = point.settings.validate().ok()?;
        let c = self.model.estimate(&config);
        Some(match self.spec.cost_kind() {
            CostKind::FlipFlops => f64::from(c.flip_flops),
            _ => f64::from(c.logic_cells),
        })
    }

    /// Evaluates a point (once: later calls return the first evaluation). `Ok(None)`: a
    /// combination the model refuses (not an evaluation).
    fn eval(&mut self, f: usize, fam: &Family, x: &Coords) -> Result<Option<usize>, Stopped> {
        if let Some(&hit) = self.cache.get(&(f, x.clone())) {
            return Ok(hit);
        }
        let limits = &self.spec.limits;
        if self.evaluations.len() >= limits.evaluations as usize {
            return Err(Stopped(format!("evaluation limit {}", limits.evaluations)));
        }
        if self.start.elapsed().as_secs_f64() >= limits.seconds {
            return Err(Stopped(format!("time limit {} s", limits.seconds)));
        }
        let measured = match fam.categories {
            Categories::Measure(..) => {
                let point = self
                    .measure_spec(fam, x)
                    .points()
                    .ok()
                    .and_then(|p| p.into_iter().next());
                point
                    .map(|p| Measured::Measure(Box::new(row(0, &p, &self.approaches, &self.model))))
            }
            Categories::Force(..) => match self.force_point(fam, x) {
                None => None,
                Some(p) => {
                    let mut m = force_metrics(&p);
                    if let Some(image) = &self.firmware {
                        match firmware_instructions(image, &p) {
                            Ok(i) => m.firmware_instructions = i,
                            Err(e) => {
                                self.firmware_failure = Some(format!("{}: {e}", fam.name()));
                                return Err(Stopped("firmware measurement".into()));
                            }
                        }
                    }
                    Some(Measured::Force(m))
                }
            },
        };
        let Some(measured) = measured else {
            self.cache.insert((f, x.clone()), None);
            return Ok(None);
        };
        let (cost, metrics) = match measured {
            Measured::Measure(r) => (
                match self.spec.cost_kind() {
                    CostKind::FlipFlops => f64::from(r.flip_flops),
                    _ => f64::from(r.logic_cells),
                },
                Metrics {
                    decided: Some(r.decided),
                    misses: Some(r.misses),
                    diameter_error_um: r.diameter_error_um,
                    max_diameter_error_um: r.max_diameter_error_um,
                    revolution_error: r.revolution_error,
                    flip_flops: Some(r.flip_flops),
                    logic_cells: Some(r.logic_cells),
                    ..Metrics::default()
                },
            ),
            Measured::Force(m) => (
                match self.spec.cost_kind() {
                    CostKind::FirmwareInstructions => m.firmware_instructions,
                    _ => m.iae_model,
                }
                .unwrap_or(f64::INFINITY),
                m,
            ),
        };
        let violated = self
            .constraints(&metrics)
            .into_iter()
            .filter(|(_, tol, v)| !meets(*v, *tol))
            .map(|(k, _, _)| k)
            .collect();
        let e = Evaluation {
            evaluation: self.evaluations.len() + 1,
            seconds: self.start.elapsed().as_secs_f64(),
            family: fam.name(),
            parameters: self.parameters(fam, x),
            cost,
            metrics,
            violated,
        };
        (self.progress)(&e);
        self.evaluations.push(e);
        let i = self.evaluations.len() - 1;
        self.cache.insert((f, x.clone()), Some(i));
        Ok(Some(i))
    }

    /// Each constraint's key, tolerance and the point's value (`None`: not measured).
    fn constraints(&self, m: &Metrics) -> Vec<(String, f64, Option<f64>)> {
        let c = &self.spec.constraints;
        let mut out = Vec::new();
        if self.spec.path == TunedPath::Measure {
            out.push(("misses".to_string(), 0.0, m.misses.map(f64::from)));
            out.push((
                "decided".to_string(),
                0.0,
                m.decided.map(|d| if d == 0 { 1.0 } else { 0.0 }),
            ));
        }
        let keyed = [
            (
                "diameter_error_um",
                c.diameter_error_um,
                m.diameter_error_um,
            ),
            (
                "max_diameter_error_um",
                c.max_diameter_error_um,
                m.max_diameter_error_um,
            ),
            ("revolution_error", c.revolution_error, m.revolution_error),
            ("iae_difference", c.iae_difference, m.iae_difference),
            (
                "override_difference",
                c.override_difference,
                m.override_difference,
            ),
            ("iae", c.iae, m.iae_model),
        ];
        for (k, tol, v) in keyed {
            if let Some(tol) = tol {
                out.push((format!("constraints.{k}"), tol, v));
            }
        }
        out
    }

    /// How far a point is from meeting every tolerance: the sum of each excess over its
    /// tolerance (at least a unit of its quantity), 0 when feasible.
    fn violation(&self, i: usize) -> f64 {
        let e = &self.evaluations[i];
        self.constraints(&e.metrics)
            .iter()
            .map(|(k, tol, v)| match v {
                None => 1e6,
                Some(v) if k == "misses" || k == "decided" => 1e3 * v,
                Some(v) => (v - tol).max(0.0) / tol.max(0.01),
            })
            .sum()
    }

    /// The error ties are broken by: the first constraint's value (the mean diameter
    /// error, or the IAE difference, when none is given).
    fn tie_error(&self, i: usize) -> f64 {
        let e = &self.evaluations[i];
        let first = self
            .constraints(&e.metrics)
            .into_iter()
            .find(|(k, _, _)| k.starts_with("constraints."))
            .and_then(|(_, _, v)| v);
        first
            .or(e.metrics.diameter_error_um)
            .or(e.metrics.iae_difference)
            .unwrap_or(f64::INFINITY)
    }

    fn better(&self, a: usize, b: usize) -> bool {
        let (ea, eb) = (&self.evaluations[a], &self.evaluations[b]);
        ea.cost < eb.cost || (ea.cost == eb.cost && self.tie_error(a) < self.tie_error(b))
    }

    fn feasible(&self, i: Option<usize>) -> bool {
        i.is_some_and(|i| self.evaluations[i].feasible())
    }

    fn start_point(&self, fam: &Family) -> Coords {
        fam.axes
            .iter()
            .map(|a| match a.name {
                "charge_bits" | "scale_bits" | "glitch_cycles" => a.values.len() - 1,
                _ => (a.values.len() - 1) / 2,
            })
            .collect()
    }

    /// Moves `x` to a point that meets every tolerance, by line searches along the axes
    /// on the violation; `None` if no move helps.
    fn make_feasible(
        &mut self,
        f: usize,
        fam: &Family,
        mut x: Coords,
    ) -> Result<Option<(Coords, usize)>, Stopped> {
        let mut here = self.eval(f, fam, &x)?;
        if here.is_none() {
            // A refused start: the first valid value along some axis.
            'find: for (k, a) in fam.axes.iter().enumerate() {
                for i in 0..a.values.len() {
                    let mut y = x.clone();
                    y[k] = i;
                    if let Some(e) = self.eval(f, fam, &y)? {
                        x = y;
                        here = Some(e);
                        break 'find;
                    }
                }
            }
        }
        let Some(mut cur) = here else { return Ok(None) };
        while !self.evaluations[cur].feasible() {
            let mut best: Option<(Coords, usize)> = None;
            for (k, a) in fam.axes.iter().enumerate() {
                for i in 0..a.values.len() {
                    let mut y = x.clone();
                    y[k] = i;
                    if let Some(e) = self.eval(f, fam, &y)? {
                        let v = self.violation(e);
                        let beat = best
                            .as_ref()
                            .map_or(self.violation(cur), |b| self.violation(b.1));
                        if v < beat {
                            best = Some((y, e));
                        }
                    }
                }
            }
            match best {
                Some((y, e)) => {
                    x = y;
                    cur = e;
                }
                None => return Ok(None),
            }
        }
        Ok(Some((x, cur)))
    }

    /// The measurement path's descent in one family (see the module's doc).
    fn descend(&mut self, f: usize, fam: &Family) -> Result<Option<usize>, Stopped> {
        let Some((mut x, mut cur)) = self.make_feasible(f, fam, self.start_point(fam))? else {
            return Ok(None);
        };
        loop {
            // Bisection per axis, repeated until no axis moves.
            loop {
                let mut moved = false;
                for k in 0..fam.axes.len() {
                    let here = self.evaluations[cur].cost;
                    let mut cands: Vec<(f64, usize)> = (0..fam.axes[k].values.len())
                        .filter_map(|i| {
                            let mut y = x.clone();
                            y[k] = i;
                            self.known_cost(fam, &y)
                                .filter(|&c| c < here)
                                .map(|c| (c, i))
                        })
                        .collect();
                    cands.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                    let (mut lo, mut hi) = (0, cands.len());
                    let mut found = None;
                    while lo < hi {
                        let mid = (lo + hi) / 2;
                        let mut y = x.clone();
                        y[k] = cands[mid].1;
                        let e = self.eval(f, fam, &y)?;
                        if self.feasible(e) {
                            hi = mid;
                            found = e.map(|e| (y, e));
                        } else {
                            lo = mid + 1;
                        }
                    }
                    if let Some((y, e)) = found {
                        x = y;
                        cur = e;
                        moved = true;
                    }
                }
                if !moved {
                    break;
                }
            }
            // Neighbours at no more cost: cheaper, or as cheap with a smaller error.
            let mut best: Option<(Coords, usize)> = None;
            for k in 0..fam.axes.len() {
                for step in [-1i64, 1] {
                    let i = x[k] as i64 + step;
                    if i < 0 || i >= fam.axes[k].values.len() as i64 {
                        continue;
                    }
                    let mut y = x.clone();
                    y[k] = i as usize;
                    let c = self.known_cost(fam, &y);
                    if c.is_none_or(|c| c > self.evaluations[cur].cost) {
                        continue;
                    }
                    let e = self.eval(f, fam, &y)?;
                    if let Some(e) = e.filter(|&e| self.evaluations[e].feasible()) {
                        let beat = best.as_ref().map_or(cur, |b| b.1);
                        if self.better(e, beat) {
                            best = Some((y, e));
                        }
                    }
                }
            }
            match best {
                Some((y, e)) => {
                    x = y;
                    cur = e;
                }
                None => return Ok(Some(cur)),
            }
        }
    }

    /// The force path's pattern (compass) search in one family: from the middle, try
    /// the points `step` values up and down each axis, move to the best that improves,
    /// halve the step when none does, until a step of one value improves nothing.
    fn pattern(&mut self, f: usize, fam: &Family) -> Result<Option<usize>, Stopped> {
        let mut x = self.start_point(fam);
        let Some(mut cur) = self.eval(f, fam, &x)? else {
            return Ok(None);
        };
        let longest = fam.axes.iter().map(|a| a.values.len()).max().unwrap_or(1);
        let mut step = (longest / 4).max(1) as i64;
        loop {
            let mut best: Option<(Coords, usize)> = None;
            for k in 0..fam.axes.len() {
                for dir in [-1i64, 1] {
                    let i = x[k] as i64 + dir * step;
                    if i < 0 || i >= fam.axes[k].values.len() as i64 {
                        continue;
                    }
                    let mut y = x.clone();
                    y[k] = i as usize;
                    let Some(e) = self.eval(f, fam, &y)? else {
                        continue;
                    };
                    let beat = best.as_ref().map_or(cur, |b| b.1);
                    let improves = match (
                        self.evaluations[e].feasible(),
                        self.evaluations[beat].feasible(),
                    ) {
                        (true, true) => self.better(e, beat),
                        (true, false) => true,
                        (false, true) => false,
                        (false, false) => self.violation(e) < self.violation(beat),
                    };
                    if improves {
                        best = Some((y, e));
                    }
                }
            }
            match best {
                Some((y, e)) => {
                    x = y;
                    cur = e;
                }
                None if step > 1 => step /= 2,
                None => return Ok(self.evaluations[cur].feasible().then_some(cur)),
            }
        }
    }

    /// The cheapest conceivable cost of a measurement family (each axis at its cheapest
    /// value, the others at the start point's): a lower bound, the cost model being a sum
    /// of per-parameter terms.
    fn lower_bound(&self, fam: &Family) -> f64 {
        let mut x = self.start_point(fam);
        for k in 0..fam.axes.len() {
            let best = (0..fam.axes[k].values.len())
                .filter_map(|i| {
                    let mut y = x.clone();
                    y[k] = i;
                    self.known_cost(fam, &y).map(|c| (c, i))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((_, i)) = best {
                x[k] = i;
            }
        }
        self.known_cost(fam, &x).unwrap_or(f64::NEG_INFINITY)
    }
}

/// Runs one force point with both engines: the IAEs, their difference, the largest
/// override difference over the ticks and the model's overshoot.
pub fn force_metrics(p: &ForcePoint) -> Metrics {
    let Ok(config) = p.settings.validate() else {
        return Metrics::default();
    };
    let sc = ControlScenario::new(config);
    let (m, r) = rayon::join(
        || run(&sc, Engine::Model, false),
        || run(&sc, Engine::Reference, false),
    );
    let override_difference = m
        .trace
        .override_pct
        .iter()
        .zip(&r.trace.override_pct)
        .map(|(a, b)| f64::from(a.abs_diff(*b)))
        .fold(0.0, f64::max);
    Metrics {
        iae_model: Some(m.metrics.iae),
        iae_reference: Some(r.metrics.iae),
        iae_difference: Some((m.metrics.iae - r.metrics.iae).abs()),
        override_difference: Some(override_difference),
        overshoot_pct: Some(m.metrics.overshoot_pct),
        ..Metrics::default()
    }
}

/// How much the gains can move a force point's firmware cost, as a fraction of it: a family
/// whose start point costs more than the best answer by this much is skipped. The gains
/// move it by less than 0.1 % on the tested spaces (their saturation and rule branches; the
/// controller's code, 5–6 %), so 1 % is a wide margin.
pub const GAINS_COST_SPREAD: f64 = 0.01;

/// The force path's instructions per control period of point `p` on `image` (`None`: the
/// point's settings are refused, so it has no scenario).
fn firmware_instructions(image: &CostImage, p: &ForcePoint) -> Result<Option<f64>, CosimError> {
    let Ok(config) = p.settings.validate() else {
        return Ok(None);
    };
    let cost = image.measure(std::slice::from_ref(&config))?;
    Ok(cost.first().map(|c| c.per_period))
}

/// Searches `spec`'s space for the cheapest point meeting its tolerances, calling
/// `progress` after each evaluation.
pub fn optimize(
    spec: &OptimizeSpec,
    progress: &(dyn Fn(&Evaluation) + Sync),
) -> Result<Optimum, SpecError> {
    spec.check()?;
    let start = Instant::now();
    let families = match spec.path {
        TunedPath::Measure => measure_families(&spec.space.axes()?),
        TunedPath::Force => force_axes(&spec.space.force)?,
    };
    let approaches = match spec.path {
        TunedPath::Measure => (1..=u64::from(spec.space.scenarios))
            .into_par_iter()
            .map(|seed| scenario::approach(&spec.space.approach, seed))
            .collect(),
        TunedPath::Force => Vec::new(),
    };
    let mut s = Search {
        spec,
        approaches,
        model: CostModel::fitted(),
        start,
        evaluations: Vec::new(),
        cache: HashMap::new(),
        progress,
        firmware: match spec.cost_kind() {
            CostKind::FirmwareInstructions => Some(CostImage::build().map_err(|e| {
                err(
                    "cost",
                    format!("`firmware_instructions` executes the Nucleo image: {e}"),
                )
            })?),
            _ => None,
        },
        firmware_failure: None,
    };
    let grid_points = families.iter().map(Family::size).sum();
    let mut stopped = None;
    let mut order: Vec<(f64, usize)> = Vec::new();
    for (i, fam) in families.iter().enumerate() {
        let bound = match (spec.path, spec.cost_kind()) {
            (TunedPath::Measure, _) => s.lower_bound(fam),
            // The firmware's cost is the controller's more than its gains': each family's
            // start point bounds what its other gains can cost.
            (TunedPath::Force, CostKind::FirmwareInstructions) => {
                match s.eval(i, fam, &s.start_point(fam)) {
                    Ok(Some(e)) => s.evaluations[e].cost * (1.0 - GAINS_COST_SPREAD),
                    Ok(None) => f64::NEG_INFINITY,
                    Err(Stopped(why)) => {
                        stopped = Some(why);
                        break;
                    }
                }
            }
            (TunedPath::Force, _) => 0.0,
        };
        order.push((bound, i));
    }
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut best: Option<usize> = None;
    for (bound, f) in order {
        if stopped.is_some() {
            break;
        }
        if best.is_some_and(|b| bound > s.evaluations[b].cost) {
            continue;
        }
        let fam = &families[f];
        let found = match spec.path {
            TunedPath::Measure => s.descend(f, fam),
            TunedPath::Force => s.pattern(f, fam),
        };
        match found {
            Ok(Some(e)) => {
                if best.is_none_or(|b| s.better(e, b)) {
                    best = Some(e);
                }
            }
            Ok(None) => {}
            Err(Stopped(why)) => {
                stopped = Some(why);
                break;
            }
        }
    }
    if let Some(why) = s.firmware_failure.take() {
        return Err(err(
            "cost",
            format!("`firmware_instructions`: the Nucleo image could not measure {why}"),
        ));
    }
    // After a stop, the best feasible point seen is the answer.
    if stopped.is_some() {
        for i in 0..s.evaluations.len() {
            if s.evaluations[i].feasible() && best.is_none_or(|b| s.better(i, b)) {
                best = Some(i);
            }
        }
    }
    let settings_toml = best
        .map(|b| answer_settings(&s, &families, b))
        .transpose()
        .map_err(|e| err("(answer)", e.to_string()))?;
    let unmet = match best {
        Some(_) => None,
        None => unmet(&s),
    };
    Ok(Optimum {
        seconds: start.elapsed().as_secs_f64(),
        evaluations: s.evaluations,
        best,
        stopped,
        grid_points,
        settings_toml,
        unmet,
    })
}

/// The constraint that kept the closest point out (the one it misses most, relative to
/// its tolerance), and the best value of it over every evaluation.
fn unmet(s: &Search<'_>) -> Option<Unmet> {
    let closest =
        (0..s.evaluations.len()).min_by(|&a, &b| s.violation(a).total_cmp(&s.violation(b)))?;
    let cons = s.constraints(&s.evaluations[closest].metrics);
    let unmet: Vec<&(String, f64, Option<f64>)> =
        cons.iter().filter(|(_, tol, v)| !meets(*v, *tol)).collect();
    let implicit = ["decided", "misses"]
        .into_iter()
        .find_map(|k| unmet.iter().find(|c| c.0 == k).copied());
    let ratio = |(_, tol, v): &(String, f64, Option<f64>)| {
        v.map_or(f64::INFINITY, |v| (v - tol) / tol.max(0.01))
    };
    let worst = implicit.or_else(|| {
        unmet
            .into_iter()
            .max_by(|a, b| ratio(a).total_cmp(&ratio(b)))
    })?;
    let best = s
        .evaluations
        .iter()
        .filter_map(|e| {
            s.constraints(&e.metrics)
                .into_iter()
                .find(|(k, _, _)| *k == worst.0)
                .and_then(|(_, _, v)| v)
        })
        .min_by(f64::total_cmp);
    Some(Unmet {
        constraint: worst.0.clone(),
        tolerance: worst.1,
        best,
    })
}

fn answer_settings(s: &Search<'_>, families: &[Family], b: usize) -> anyhow::Result<String> {
    let e = &s.evaluations[b];
    let (f, x) = s
        .cache
        .iter()
        .find(|(_, v)| **v == Some(b))
        .map(|(k, _)| k.clone())
        .ok_or_else(|| anyhow::anyhow!("the answer's point is not in the cache"))?;
    let fam = &families[f];
    match fam.categories {
        Categories::Measure(..) => {
            let point = s
                .measure_spec(fam, &x)
                .points()?
                .into_iter()
                .next()
                .ok_or_else(|| anyhow::anyhow!("the answer makes no point"))?;
            let comment = format!(
                "tooltouch tune optimize, measurement point: {}, {} logic cells, mean |diameter error| {} µm",
                e.family,
                e.metrics.logic_cells.unwrap_or(0),
                e.metrics
                    .diameter_error_um
                    .map_or_else(|| "n/a".to_string(), |d| format!("{d:.3}"))
            );
            point_settings::measurement_toml(&point.settings, &comment)
        }
        Categories::Force(..) => {
            let p = s
                .force_point(fam, &x)
                .ok_or_else(|| anyhow::anyhow!("the answer makes no force point"))?;
            let firmware = e
                .metrics
                .firmware_instructions
                .map_or_else(String::new, |i| {
                    format!(", {i:.1} firmware instructions per control period")
                });
            let comment = format!(
                "tooltouch tune optimize, force point: {} at kp {} % / ki {} % of the design, IAE {:.3} N·s{firmware}",
                e.family,
                p.kp_percent,
                p.ki_percent,
                e.metrics.iae_model.unwrap_or(e.cost)
            );
            point_settings::force_toml(&p, &comment)
        }
    }
}

/// The evaluation log as JSON lines (one [`Evaluation`] a line).
pub fn log_lines(o: &Optimum) -> String {
    let mut out = String::new();
    for e in &o.evaluations {
        out.push_str(&serde_json::to_string(e).unwrap_or_default());
        out.push('\n');
    }
    out
}
