//! The force estimator characterized the way paper F characterizes it (docs/domain.md §3,
//! docs/estimator.md): each of the three estimates — power-only (F4–F8 on the lagging
//! measured power P_o), fast electrical (F4–F8 on k_slip·P_g, eq. F2) and synthesized (F9's
//! choice between them, what the kernel outputs) — against the dynamometer channel, on two
//! runs of the control scenario's plant ([`super::scenario`]) with force control *off*, so
//! the estimate cannot shape the force it is judged on:
//!
//! - **depth step**: the tool engages at 3 s at the manual override and the depth of cut steps
//!   from 1 to 1.5 mm at 8 s (an open-loop force step of about 60 %);
//! - **run-up**: the spindle runs up from 600 to 800 rpm with the no-load identification and
//!   never cuts (every estimate should read 0 N).
//!
//! The figures are period by period (20 Hz, what a controller receives): the error is
//! `estimate − dynamometer` (both period averages), the steady state the windows
//! [`DEPTH_STEADY`] and [`RUN_UP_STEADY`], the delay the time from the depth step until a
//! series has covered 63 % of its own step (linear between periods), the peak error the
//! largest |error| in [`DEPTH_TRANSIENT`] or [`RUN_UP_TRANSIENT`]. Always the fixed-point
//! model engine: the figures describe the kernel the firmware runs.

use super::scenario::{run, scenario_settings, ControlScenario, ControllerKind, Engine, Trace};
use serde::Serialize;
use tooltouch_model::force::config::ForceSource;

/// Steady-state windows of the depth step, s (half-open `(from, to]`): before the step
/// (2 s after engagement) and after it (2 s after the step, P_o's lag long settled).
pub const DEPTH_STEADY: [(f64, f64); 2] = [(5.0, 8.0), (10.0, 13.0)];
/// The depth step's transient window, s: the peak error is looked for here.
pub const DEPTH_TRANSIENT: (f64, f64) = (8.0, 10.0);
/// Levels before and after the step for the 63 % delay, s.
pub const DEPTH_LEVELS: [(f64, f64); 2] = [(7.0, 8.0), (10.0, 11.0)];
/// Steady-state window of the run-up (after the identification), s.
pub const RUN_UP_STEADY: (f64, f64) = (3.0, 4.0);
/// The run-up's transient window, s: the speed ramp and P_o settling after it.
pub const RUN_UP_TRANSIENT: (f64, f64) = (0.5, 3.0);
/// Length of the run-up run, s.
pub const RUN_UP_DURATION: f64 = 4.0;

/// Which estimate a row describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum EstimateKind {
    /// F4–F8 on the measured power P_o alone.
    PowerOnly,
    /// F4–F8 on the fast electrical power k_slip·P_g (F2) alone.
    Electrical,
    /// F9's synthesis: the kernel's estimate.
    Synthesized,
}

impl EstimateKind {
    /// The three, in table order.
    pub const ALL: [EstimateKind; 3] = [
        EstimateKind::PowerOnly,
        EstimateKind::Electrical,
        EstimateKind::Synthesized,
    ];
    /// Name in the table and the files.
    pub fn name(self) -> &'static str {
        match self {
            EstimateKind::PowerOnly => "power-only",
            EstimateKind::Electrical => "electrical",
            EstimateKind::Synthesized => "synthesized",
        }
    }
    /// The estimate's series in a trace.
    pub fn series(self, tr: &Trace) -> &[f64] {
        match self {
            EstimateKind::PowerOnly => &tr.force_power_only,
            EstimateKind::Electrical => &tr.force_electrical,
            EstimateKind::Synthesized => &tr.force_est,
        }
    }
}

/// One estimate's figures on one run. Percentages are of the dynamometer force over the
/// same periods (absent on the run-up, where it is 0).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EstimateFigures {
    /// `depth-step` or `run-up`.
    pub scenario: &'static str,
    /// `power-only`, `electrical` or `synthesized`.
    pub estimate: &'static str,
    /// Mean error in steady state, N.
    pub mean_error_n: f64,
    /// Mean error in steady state, % of the mean dynamometer force.
    pub mean_error_pct: Option<f64>,
    /// Standard deviation of the error in steady state, N.
    pub sd_error_n: f64,
    /// Standard deviation of the error in % of each period's dynamometer force.
    pub sd_error_pct: Option<f64>,
    /// Time from the depth step to 63 % of the estimate's step, s.
    pub delay_s: Option<f64>,
    /// The same delay less the dynamometer's own, s.
    pub lag_behind_dynamometer_s: Option<f64>,
    /// Largest |error| in the transient window, N.
    pub peak_error_n: f64,
    /// Switches from P_o to the fast estimate during the run (synthesized only).
    pub switches: Option<u32>,
    /// Share of the steady-state periods on the fast estimate, % (synthesized only).
    pub fast_share_pct: Option<f64>,
}

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct EstimatorReport {
    /// Noise seed of both runs.
    pub seed: u64,
    /// The plant's viscous friction B, N·m·s/rad.
    pub plant_viscous: f64,
    /// B identified over the run-up, N·m·s/rad.
    pub identified_viscous: f64,
    /// The plant's Coulomb friction T_fco, N·m.
    pub plant_coulomb: f64,
    /// T_fco identified over the run-up, N·m.
    pub identified_coulomb: f64,
    /// Dynamometer delay on the depth step (63 %), s.
    pub dynamometer_delay_s: f64,
    /// Rows: depth step then run-up, each power-only, electrical, synthesized.
    pub rows: Vec<EstimateFigures>,
    /// The depth-step run's trace (for the plot).
    #[serde(skip)]
    pub depth_step: Trace,
    /// The run-up's trace (for the plot).
    #[serde(skip)]
    pub run_up: Trace,
}

/// The depth-step scenario with force control off (see the module header).
pub fn depth_step_scenario(seed: u64) -> ControlScenario {
    let config = scenario_settings(ControllerKind::Pi, ForceSource::Measured)
        .validate()
        .expect("the scenario's default settings are valid");
    let mut sc = ControlScenario::new(config);
    sc.force_control = false;
    sc.seed = seed;
    sc
}

/// The run-up without cutting (see the module header).
pub fn run_up_scenario(seed: u64) -> ControlScenario {
    let mut sc = depth_step_scenario(seed);
    sc.duration = RUN_UP_DURATION;
    sc.engage_at = f64::INFINITY;
    sc
}

fn inside(t: f64, (from, to): (f64, f64)) -> bool {
    t > from && t <= to
}

fn mean_sd(xs: &[f64]) -> (f64, f64) {
    let n = xs.len().max(1) as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

fn mean_in(tr: &Trace, x: &[f64], window: (f64, f64)) -> f64 {
    let v: Vec<f64> =
        tr.t.iter()
            .zip(x)
            .filter(|(t, _)| inside(**t, window))
            .map(|(_, x)| *x)
            .collect();
    mean_sd(&v).0
}

/// Time after `step_at` at which `x` first covers 63 % of the way from its level in
/// `levels[0]` to its level in `levels[1]`, linear between periods; `None` if it never does.
pub fn delay_63(tr: &Trace, x: &[f64], step_at: f64, levels: [(f64, f64); 2]) -> Option<f64> {
    let (x0, x1) = (mean_in(tr, x, levels[0]), mean_in(tr, x, levels[1]));
    let target = x0 + 0.63 * (x1 - x0);
    let up = x1 >= x0;
    let reached = |v: f64| if up { v >= target } else { v <= target };
    let mut prev: Option<(f64, f64)> = None;
    for (&t, &v) in tr.t.iter().zip(x) {
        if t > step_at && reached(v) {
            let at = match prev {
                Some((tp, vp)) if (v - vp).abs() > 0.0 && tp >= step_at => {
                    tp + (target - vp) / (v - vp) * (t - tp)
                }
                _ => t,
            };
            return Some(at - step_at);
        }
        prev = Some((t, v));
    }
    None
}

/// Rising edges of F9's fast-estimate flag.
fn switches(tr: &Trace) -> u32 {
    let mut n = 0;
    let mut was = false;
    for &f in &tr.fast {
        if f && !was {
            n += 1;
        }
        was = f;
    }
    n
}

/// One estimate's figures on a trace: steady windows `steady`, transient window `transient`,
/// and, for a depth step, `(step_at, the dynamometer's own delay)`.
pub fn figures(
    scenario: &'static str,
    kind: EstimateKind,
    tr: &Trace,
    steady: &[(f64, f64)],
    transient: (f64, f64),
    delay: Option<(f64, f64)>,
) -> EstimateFigures {
    let x = kind.series(tr);
    let (mut err, mut err_pct, mut dyn_sum, mut fast) = (Vec::new(), Vec::new(), 0.0, 0usize);
    let mut peak: f64 = 0.0;
    for (i, &t) in tr.t.iter().enumerate() {
        let e = x[i] - tr.force_meas[i];
        if steady.iter().any(|&w| inside(t, w)) {
            err.push(e);
            dyn_sum += tr.force_meas[i];
            if tr.force_meas[i].abs() > 1.0 {
                err_pct.push(100.0 * e / tr.force_meas[i]);
            }
            fast += usize::from(tr.fast[i]);
        }
        if inside(t, transient) {
            peak = peak.max(e.abs());
        }
    }
    let (mean_n, sd_n) = mean_sd(&err);
    let cutting = dyn_sum.abs() > err.len() as f64;
    let synthesized = kind == EstimateKind::Synthesized;
    let delay_s = delay.and_then(|(step_at, dyn_delay)| {
        delay_63(tr, x, step_at, DEPTH_LEVELS).map(|d| (d, d - dyn_delay))
    });
    EstimateFigures {
        scenario,
        estimate: kind.name(),
        mean_error_n: mean_n,
        mean_error_pct: cutting.then(|| 100.0 * mean_n * err.len() as f64 / dyn_sum),
        sd_error_n: sd_n,
        sd_error_pct: cutting.then(|| mean_sd(&err_pct).1),
        delay_s: delay_s.map(|d| d.0),
        lag_behind_dynamometer_s: delay_s.map(|d| d.1),
        peak_error_n: peak,
        switches: synthesized.then(|| switches(tr)),
        fast_share_pct: synthesized.then(|| 100.0 * fast as f64 / err.len().max(1) as f64),
    }
}

/// Runs both scenarios with noise `seed` and measures the three estimates.
pub fn report(seed: u64) -> EstimatorReport {
    let depth_sc = depth_step_scenario(seed);
    let depth = run(&depth_sc, Engine::Model, false);
    let run_up_sc = run_up_scenario(seed);
    let run_up = run(&run_up_sc, Engine::Model, false);
    let step_at = depth_sc.depth.step_at;
    let dynamometer_delay_s =
        delay_63(&depth.trace, &depth.trace.force_meas, step_at, DEPTH_LEVELS).unwrap_or(f64::NAN);
    let mut rows = Vec::new();
    for kind in EstimateKind::ALL {
        rows.push(figures(
            "depth-step",
            kind,
            &depth.trace,
            &DEPTH_STEADY,
            DEPTH_TRANSIENT,
            Some((step_at, dynamometer_delay_s)),
        ));
    }
    for kind in EstimateKind::ALL {
        rows.push(figures(
            "run-up",
            kind,
            &run_up.trace,
            &[RUN_UP_STEADY],
            RUN_UP_TRANSIENT,
            None,
        ));
    }
    EstimatorReport {
        seed,
        plant_viscous: run_up_sc.drive.viscous,
        identified_viscous: run_up.identified.0,
        plant_coulomb: run_up_sc.drive.coulomb,
        identified_coulomb: run_up.identified.1,
        dynamometer_delay_s,
        rows,
        depth_step: depth.trace,
        run_up: run_up.trace,
    }
}

fn opt(x: Option<f64>, width: usize, precision: usize, unit: &str) -> String {
    match x {
        Some(v) => format!("{:>w$}", format!("{v:.precision$}{unit}"), w = width),
        None => format!("{:>width$}", "-"),
    }
}

impl EstimatorReport {
    /// The terminal table, line by line.
    pub fn table(&self) -> Vec<String> {
        let mut lines = vec![
            format!(
                "estimator vs dynamometer (force control off, seed {}): identified B = {:.5} N·m·s/rad \
                 (plant {}, {:+.1}%), T_fco = {:.3} N·m (plant {}, {:+.1}%); dynamometer delay {:.2} s",
                self.seed,
                self.identified_viscous,
                self.plant_viscous,
                100.0 * (self.identified_viscous / self.plant_viscous - 1.0),
                self.identified_coulomb,
                self.plant_coulomb,
                100.0 * (self.identified_coulomb / self.plant_coulomb - 1.0),
                self.dynamometer_delay_s,
            ),
            format!(
                "{:<11} {:<12} {:>9} {:>8} {:>8} {:>7} {:>8} {:>8} {:>10} {:>8} {:>6}",
                "scenario",
                "estimate",
                "mean err",
                "mean %",
                "sd err",
                "sd %",
                "delay",
                "lag",
                "peak err",
                "switches",
                "fast %"
            ),
        ];
        for r in &self.rows {
            lines.push(format!(
                "{:<11} {:<12} {:>7.1} N {} {:>6.1} N {} {} {} {:>8.1} N {:>8} {}",
                r.scenario,
                r.estimate,
                r.mean_error_n,
                opt(r.mean_error_pct, 8, 2, "%"),
                r.sd_error_n,
                opt(r.sd_error_pct, 7, 2, "%"),
                opt(r.delay_s, 8, 2, "s"),
                opt(r.lag_behind_dynamometer_s, 8, 2, "s"),
                r.peak_error_n,
                r.switches.map_or("-".to_string(), |n| n.to_string()),
                opt(r.fast_share_pct, 6, 0, ""),
            ));
        }
        lines
    }

    /// The rows as CSV (header and one line per row; absent figures are empty fields).
    pub fn csv(&self) -> Result<String, csv::Error> {
        let mut w = csv::Writer::from_writer(Vec::new());
        for r in &self.rows {
            w.serialize(r)?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| csv::Error::from(e.into_error()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// The report as pretty JSON (everything but the traces).
    pub fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string_pretty(self)
    }
}
