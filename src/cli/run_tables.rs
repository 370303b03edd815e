//! The CSV and JSON files of `tooltouch control` and `tooltouch wear` (docs/control.md,
//! docs/wear.md): the metrics their terminal tables show (one row per run) and the time
//! series their plots draw (one row per sample). Each table is one `Serialize` row type
//! written twice — by `csv` (a header of the field names, one line per row) and by
//! `serde_json` (an array of objects with the same names) — so the columns are typed once.
//! Kept apart from the subcommands so that each adds only a call.

use anyhow::{Context, Result};
use serde::Serialize;
use std::path::Path;
use tooltouch_plant::drive::scenario::{Metrics, Run};
use tooltouch_plant::milling::WearRun;

/// Writes `rows` as `<stem>.csv` and `<stem>.json` into `dir`.
pub fn write_table<T: Serialize>(dir: &Path, stem: &str, rows: &[T]) -> Result<()> {
    let path = dir.join(format!("{stem}.csv"));
    let mut w =
        csv::Writer::from_path(&path).with_context(|| format!("writing {}", path.display()))?;
    for row in rows {
        w.serialize(row)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    w.flush()
        .with_context(|| format!("writing {}", path.display()))?;
    let path = dir.join(format!("{stem}.json"));
    let json = serde_json::to_string_pretty(rows).context("encoding a table as JSON")?;
    std::fs::write(&path, json + "\n").with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

/// The two file names of a table written by [`write_table`].
pub fn table_files(stem: &str) -> [String; 2] {
    [format!("{stem}.csv"), format!("{stem}.json")]
}

/// One row of `control.csv` / `control.json`: a run's metrics, as the terminal table.
#[derive(Clone, Debug, Serialize)]
pub struct ControlMetrics {
    /// Controller: `pi`, `adaptive`, `fuzzy`.
    pub controller: &'static str,
    /// Force feedback: `estimated`, `measured`.
    pub force: &'static str,
    /// Engine: `model` or `reference`.
    pub engine: &'static str,
    /// Noise seed.
    pub seed: u64,
    /// Peak force above the reference after the depth step, % of the reference.
    pub overshoot_pct: f64,
    /// Settling time after the depth step, s (`inf` in CSV, `null` in JSON: never).
    pub settling_s: f64,
    /// Mean force error over the last second, N.
    pub steady_error_n: f64,
    /// Integral of |F_r − F| from engagement to the end, N·s.
    pub iae_ns: f64,
    /// Smallest override while controlling, %.
    pub override_min_pct: u8,
    /// Largest override while controlling, %.
    pub override_max_pct: u8,
}

impl ControlMetrics {
    /// The row of one run.
    pub fn new(
        controller: &'static str,
        force: &'static str,
        engine: &'static str,
        seed: u64,
        m: &Metrics,
    ) -> ControlMetrics {
        ControlMetrics {
            controller,
            force,
            engine,
            seed,
            overshoot_pct: m.overshoot_pct,
            settling_s: m.settling_s,
            steady_error_n: m.steady_error_n,
            iae_ns: m.iae,
            override_min_pct: m.override_range.0,
            override_max_pct: m.override_range.1,
        }
    }
}

/// One row of `<controller>_<force>.csv` / `.json`: a sample of the plotted time series.
#[derive(Clone, Debug, Serialize)]
pub struct ControlSample {
    /// Time, s.
    pub t_s: f64,
    /// Force reference, N.
    pub reference_n: f64,
    /// True cutting force (mean over the sample period), N.
    pub force_true_n: f64,
    /// Estimated force, N.
    pub force_estimated_n: f64,
    /// Dynamometer force (period mean), N.
    pub force_measured_n: f64,
    /// Feed override, %.
    pub override_pct: u8,
}

/// The plotted series of control run `r` (force reference `reference_n`, N).
pub fn control_series(r: &Run, reference_n: f64) -> Vec<ControlSample> {
    let tr = &r.trace;
    (0..tr.t.len())
        .map(|i| ControlSample {
            t_s: tr.t[i],
            reference_n,
            force_true_n: tr.force_true.get(i).copied().unwrap_or(f64::NAN),
            force_estimated_n: tr.force_est.get(i).copied().unwrap_or(f64::NAN),
            force_measured_n: tr.force_meas.get(i).copied().unwrap_or(f64::NAN),
            override_pct: tr.override_pct.get(i).copied().unwrap_or(0),
        })
        .collect()
}

/// One row of `wear_vb.csv` / `.json`: the mean cutting power of one condition set at one
/// flank wear VB (W7), and the motor power it draws (W9's p_i + P̄/η).
#[derive(Clone, Debug, Serialize)]
pub struct WearVbRow {
    /// Condition set, from 0 (order of first use in the cuts).
    pub set: usize,
    /// Depth of cut b, mm.
    pub depth_mm: f64,
    /// Feed per tooth s_z, mm.
    pub feed_per_tooth_mm: f64,
    /// Spindle speed, rpm.
    pub rpm: f64,
    /// Flank wear VB, mm.
    pub vb_mm: f64,
    /// Mean cutting power P̄ (W7), W.
    pub mean_cutting_power_w: f64,
    /// Motor power p_i + P̄/η, W.
    pub motor_power_w: f64,
}

/// P̄(VB) for VB from 0 to the larger of `vb_max` and [VB] in 0.05 mm steps (at most 201
/// steps), every condition set per VB.
pub fn wear_vb_table(sc: &tooltouch_plant::milling::WearScenario, vb_max: f64) -> Vec<WearVbRow> {
    let (sets, _) = sc.condition_sets();
    let top = vb_max.max(sc.vb_limit_mm).clamp(0.0, 10.0);
    let steps = ((top / 0.05).ceil() as usize).min(200);
    let mut rows = Vec::new();
    for i in 0..=steps {
        let vb = i as f64 * 0.05;
        for (k, (c, idle)) in sets.iter().enumerate() {
            let p = sc.milling.mean_power(vb, c);
            rows.push(WearVbRow {
                set: k,
                depth_mm: c.depth_mm,
                feed_per_tooth_mm: c.feed_per_tooth_mm,
                rpm: c.rpm,
                vb_mm: vb,
                mean_cutting_power_w: p,
                motor_power_w: idle + p / sc.milling.efficiency,
            });
        }
    }
    rows
}

/// One row of `wear.csv` / `wear.json`: a run's alarm, as the terminal table.
#[derive(Clone, Debug, Serialize)]
pub struct WearVerdict {
    /// Tool: `new` or `worn`.
    pub tool: &'static str,
    /// Threshold: `constant` or `updating`.
    pub threshold: &'static str,
    /// Time of the first alarm, s (empty in CSV, `null` in JSON: none).
    pub alarm_at_s: Option<f64>,
    /// Watched power p̄ at the alarm, W (where the plot marks it).
    pub alarm_power_w: Option<f64>,
    /// The cut (from 1) the alarm came in.
    pub alarm_cut: Option<usize>,
    /// `right`, `false-alarm` or `missed`.
    pub verdict: &'static str,
}

/// One row of `wear_<tool>.csv` / `.json`: a sample of the plotted series of one tool,
/// both thresholds side by side.
#[derive(Clone, Debug, Serialize)]
pub struct WearSample {
    /// Time, s.
    pub t_s: f64,
    /// True motor power (period mean), W.
    pub motor_power_w: f64,
    /// The monitor's low-passed power p̄, W.
    pub monitored_power_w: f64,
    /// Allowed power of the constant threshold, W.
    pub constant_threshold_w: f64,
    /// Allowed power of the updating threshold, W.
    pub updating_threshold_w: f64,
    /// The constant threshold's alarm is latched.
    pub constant_alarm: bool,
    /// The updating threshold's alarm is latched.
    pub updating_alarm: bool,
    /// Flank wear VB, mm.
    pub vb_mm: f64,
}

/// The plotted series of one tool's two runs (`constant`, then `updating`).
pub fn wear_series(constant: &WearRun, updating: &WearRun) -> Vec<WearSample> {
    (0..constant.t.len())
        .map(|i| WearSample {
            t_s: constant.t[i],
            motor_power_w: constant.power_true.get(i).copied().unwrap_or(f64::NAN),
            monitored_power_w: constant.power.get(i).copied().unwrap_or(f64::NAN),
            constant_threshold_w: constant.allowed.get(i).copied().unwrap_or(f64::NAN),
            updating_threshold_w: updating.allowed.get(i).copied().unwrap_or(f64::NAN),
            constant_alarm: constant.alarm.get(i).copied().unwrap_or(false),
            updating_alarm: updating.alarm.get(i).copied().unwrap_or(false),
            vb_mm: constant.vb.get(i).copied().unwrap_or(f64::NAN),
        })
        .collect()
}
