//! Fixed-point tuning sweeps (`tooltouch tune`): run every point of a [`SweepSpec`] (word
//! lengths, charge laws and their steps or shifts, thresholds, glitch filter, decision
//! method) over a set of seeded approach [`scenario`]s, measure each point's error against
//! the float [`reference`] and its FPGA [`cost`], and mark the Pareto front of accuracy
//! (latched-diameter error) against cost (logic cells). The [`force`] part sweeps the
//! force controllers' gains and compares the fixed-point kernels' IAE with the float
//! references'.
//!
//! A sweep is deterministic: every point is computed on its own from the spec, so a sweep
//! split with [`Shard`]s and joined with [`merge`] gives exactly the unsharded result.
//!
//! Draws nothing and parses no command line (the Python package links it): the command
//! line draws `pareto.svg` from [`output::pareto_rows`]; `cargo xtask imports` keeps
//! plotters, clap and indicatif out of the wheel.

pub mod cost;
pub mod evaluate;
pub mod firmware_cost;
pub mod force;
pub mod optimize;
pub mod output;
pub mod point_settings;
pub mod ranges;
pub mod reference;
pub mod scenario;
pub mod spec;

pub use spec::{Overrides, Point, Shard, SweepSpec};
pub use tooltouch_settings::values::SpecError;

use cost::CostModel;
use evaluate::{evaluate, Outcome};
use rayon::prelude::*;
use scenario::Approach;
use serde::{Deserialize, Serialize};
use tooltouch_model::measure::config::ChargeLaw;
use tooltouch_settings::force_design::ForcePoint;

/// Format tag of `results.json`.
pub const FORMAT: &str = "tooltouch-tune-1";

/// One sweep point's results.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The point's index in the sweep.
    pub index: usize,
    /// Decision method.
    pub method: String,
    /// Contact rule.
    pub contact_rule: String,
    /// Capacitor width, bits.
    pub charge_bits: u8,
    /// Scale position width, bits.
    pub scale_bits: u8,
    /// Glitch filter, clocks.
    pub glitch_cycles: u8,
    /// Counter threshold, pulses.
    pub i_def: u32,
    /// Counting window, revolutions.
    pub window_revs: u8,
    /// `linear` or `exponential`.
    pub law: String,
    /// Charge step (linear, LSBs) or charge shift (exponential).
    pub charge: u32,
    /// Discharge step (linear, LSBs) or discharge shift (exponential).
    pub discharge: u32,
    /// Fire threshold, LSBs.
    pub fire_threshold: u32,
    /// Re-arm threshold, LSBs.
    pub rearm_threshold: u32,
    /// Estimated flip-flops.
    pub flip_flops: u32,
    /// Estimated logic cells.
    pub logic_cells: u32,
    /// Scenarios where both the model and the reference decided.
    pub decided: u32,
    /// Scenarios where only one of them decided.
    pub misses: u32,
    /// Mean |latched diameter − reference diameter| over the decided scenarios, µm.
    pub diameter_error_um: Option<f64>,
    /// Largest |latched diameter − reference diameter|, µm.
    pub max_diameter_error_um: Option<f64>,
    /// Mean |decision revolution − reference decision revolution|, revolutions.
    pub revolution_error: Option<f64>,
    /// On its method's Pareto front of `diameter_error_um` against `logic_cells` (points
    /// with a miss are never on it).
    pub pareto: bool,
}

/// A sweep's (or a slice's) results, as written to `results.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Results {
    /// [`FORMAT`].
    pub format: String,
    /// The spec the points come from.
    pub spec: SweepSpec,
    /// The slice, for a sharded run; `None` for a whole sweep (or a merge).
    pub shard: Option<Shard>,
    /// Measurement points in the whole sweep (indices `0..points`).
    pub points: usize,
    /// Force points in the whole sweep (indices `points..points + force_points`).
    pub force_points: usize,
    /// Measurement rows, by index.
    pub rows: Vec<Row>,
    /// Force-control rows, by index.
    pub force: Vec<force::ForceRow>,
}

/// Errors of a sweep.
#[derive(Debug, thiserror::Error)]
pub enum TuneError {
    /// A bad spec.
    #[error(transparent)]
    Spec(#[from] SpecError),
    /// Slices that do not make one sweep.
    #[error("merge: {0}")]
    Merge(String),
}

/// One measurement point's row: its cost and its errors against the float reference over
/// `approaches` (the scenarios run in parallel, their outcomes summed in order).
pub(crate) fn row(index: usize, point: &Point, approaches: &[Approach], model: &CostModel) -> Row {
    let s = &point.settings;
    let config = s.validate().unwrap_or_default();
    let cost = model.estimate(&config);
    let (law, charge, discharge) = match s.charge_law {
        ChargeLaw::Linear {
            charge_step,
            discharge_step,
        } => ("linear", charge_step, discharge_step),
        ChargeLaw::Exponential {
            charge_shift,
            discharge_shift,
        } => (
            "exponential",
            u32::from(charge_shift),
            u32::from(discharge_shift),
        ),
    };
    let (mut decided, mut misses) = (0u32, 0u32);
    let (mut sum_d, mut max_d, mut sum_r) = (0.0f64, 0.0f64, 0.0f64);
    let outcomes: Vec<Outcome> = approaches
        .par_iter()
        .map(|a| evaluate(a, &config, &point.intent))
        .collect();
    for outcome in outcomes {
        match outcome {
            Outcome::Both {
                revolution_error,
                diameter_error_um,
            } => {
                decided += 1;
                sum_d += diameter_error_um.abs();
                max_d = max_d.max(diameter_error_um.abs());
                sum_r += revolution_error.unsigned_abs() as f64;
            }
            Outcome::Miss => misses += 1,
            Outcome::Neither => {}
        }
    }
    let mean = |x: f64| (decided > 0).then(|| x / f64::from(decided));
    Row {
        index,
        method: spec::method_name(s.method).into(),
        contact_rule: spec::rule_name(s.contact_rule).into(),
        charge_bits: s.charge_bits,
        scale_bits: s.scale_bits,
        glitch_cycles: s.glitch_cycles,
        i_def: s.i_def,
        window_revs: s.window_revs,
        law: law.into(),
        charge,
        discharge,
        fire_threshold: s.fire_threshold,
        rearm_threshold: s.rearm_threshold,
        flip_flops: cost.flip_flops,
        logic_cells: cost.logic_cells,
        decided,
        misses,
        diameter_error_um: mean(sum_d),
        max_diameter_error_um: (decided > 0).then_some(max_d),
        revolution_error: mean(sum_r),
        pareto: false,
    }
}

/// Marks, for each decision method, the Pareto front of `diameter_error_um` (smaller is
/// better) against `logic_cells` (smaller is better) among the rows without a miss. Per
/// method, because the method is a design choice made first (its reference device
/// differs); word lengths, steps and filters are then tuned within it.
pub fn mark_pareto(rows: &mut [Row]) {
    let key = |r: &Row| match (r.misses, r.diameter_error_um) {
        (0, Some(e)) => Some((r.method.clone(), e, r.logic_cells)),
        _ => None,
    };
    let keys: Vec<Option<(String, f64, u32)>> = rows.iter().map(key).collect();
    for (i, r) in rows.iter_mut().enumerate() {
        r.pareto = match &keys[i] {
            None => false,
            Some((m, e, c)) => !keys
                .iter()
                .flatten()
                .any(|(m2, e2, c2)| m2 == m && e2 <= e && c2 <= c && (e2 < e || c2 < c)),
        };
    }
}

/// Runs the points of `spec` in `shard` (all of them for `None`) on all cores, calling
/// `progress()` after each point. Rows come back by index, Pareto-marked within the run
/// (a merge marks the front again over the whole sweep).
pub fn run(
    spec: &SweepSpec,
    shard: Option<Shard>,
    progress: &(dyn Fn() + Sync),
) -> Result<Results, TuneError> {
    let points = spec.points()?;
    let force_points = spec.force.points()?;
    let approaches: Vec<Approach> = (1..=u64::from(spec.scenarios))
        .into_par_iter()
        .map(|seed| scenario::approach(&spec.approach, seed))
        .collect();
    let model = CostModel::fitted();
    let mine: Vec<(usize, &Point)> = points
        .iter()
        .enumerate()
        .filter(|(i, _)| shard.is_none_or(|s| s.contains(*i)))
        .collect();
    let mut rows: Vec<Row> = mine
        .par_iter()
        .map(|&(i, s)| {
            let r = row(i, s, &approaches, &model);
            progress();
            r
        })
        .collect();
    rows.sort_by_key(|r| r.index);
    if shard.is_none() {
        mark_pareto(&mut rows);
    }
    let base = points.len();
    let mine: Vec<(usize, &ForcePoint)> = force_points
        .iter()
        .enumerate()
        .map(|(i, p)| (base + i, p))
        .filter(|(i, _)| shard.is_none_or(|s| s.contains(*i)))
        .collect();
    let mut force_rows: Vec<force::ForceRow> = mine
        .par_iter()
        .map(|&(i, p)| {
            let r = force::row(i, p);
            progress();
            r
        })
        .collect();
    force_rows.sort_by_key(|r| r.index);
    Ok(Results {
        format: FORMAT.into(),
        spec: spec.clone(),
        shard,
        points: points.len(),
        force_points: force_points.len(),
        rows,
        force: force_rows,
    })
}

/// Number of points `spec` runs in `shard`.
pub fn points_in(spec: &SweepSpec, shard: Option<Shard>) -> Result<usize, TuneError> {
    let n = spec.points()?.len() + spec.force.points()?.len();
    Ok((0..n)
        .filter(|&i| shard.is_none_or(|s| s.contains(i)))
        .count())
}

/// Joins the slices of one sweep: they must share the spec and the slice count, and
/// together hold every point exactly once. The result equals the unsharded run.
pub fn merge(parts: &[Results]) -> Result<Results, TuneError> {
    let first = parts
        .first()
        .ok_or_else(|| TuneError::Merge("no results to merge".into()))?;
    // `points` and `force_points` come from the files: nothing is sized by them, they
    // are checked against the rows present, and added without overflow.
    let mut rows: Vec<Row> = Vec::with_capacity(parts.iter().map(|p| p.rows.len()).sum());
    let mut force_rows: Vec<force::ForceRow> =
        Vec::with_capacity(parts.iter().map(|p| p.force.len()).sum());
    for (i, p) in parts.iter().enumerate() {
        if p.format != FORMAT {
            return Err(TuneError::Merge(format!(
                "part {i}: format `{}`, expected `{FORMAT}`",
                p.format
            )));
        }
        if p.spec != first.spec || p.points != first.points || p.force_points != first.force_points
        {
            return Err(TuneError::Merge(format!(
                "part {i} comes from a different sweep spec than part 0"
            )));
        }
        rows.extend(p.rows.iter().cloned());
        force_rows.extend(p.force.iter().cloned());
    }
    rows.sort_by_key(|r| r.index);
    force_rows.sort_by_key(|r| r.index);
    let indices = rows
        .iter()
        .map(|r| r.index)
        .chain(force_rows.iter().map(|r| r.index));
    let mut n = 0;
    for (i, index) in indices.enumerate() {
        if index != i {
            let (what, which) = if index < i {
                ("twice", index)
            } else {
                ("missing", i)
            };
            return Err(TuneError::Merge(format!(
                "point {which} is {what} (is a shard missing or given twice?)"
            )));
        }
        n += 1;
    }
    let stated = first.points.checked_add(first.force_points);
    if stated != Some(n) || rows.len() != first.points {
        return Err(TuneError::Merge(format!(
            "{n} points present ({} measurement, {} force), the results.json files say `points` = {}, `force_points` = {} (is a shard missing?)",
            rows.len(),
            force_rows.len(),
            first.points,
            first.force_points
        )));
    }
    mark_pareto(&mut rows);
    Ok(Results {
        format: FORMAT.into(),
        spec: first.spec.clone(),
        shard: None,
        points: first.points,
        force_points: first.force_points,
        rows,
        force: force_rows,
    })
}
