//! The estimator on drives that are not its model (docs/estimator.md, "A plant that is not
//! the estimator"): for each drive of a sweep over [`MismatchRange`] — one mismatch at a time
//! at its range's ends, the two corners of the whole range, and one drive outside it — the
//! depth step of [`super::estimator_report`] (force control off), the synthesized estimate
//! against the dynamometer, twice:
//!
//! - **nominal**: the estimator's default settings with the kernel's own no-load
//!   identification of B and T_fco, as `tooltouch control` runs it;
//! - **identified**: the settings [`super::identify`] finds on that drive (B, T_fco, f(ω),
//!   g(ω), slip gain, R_s), the kernel's identification off.

use super::estimator_report::{
    delay_63, depth_step_scenario, figures, EstimateKind, DEPTH_LEVELS, DEPTH_STEADY,
    DEPTH_TRANSIENT,
};
use super::identify::{identify, IdentificationPlan, Identified};
use super::mismatch::{
    DriveMismatch, MismatchPoint, MismatchRange, SensedPhases, Winding, WindingConnection,
};
use super::scenario::{run, ControlScenario, Engine};
use super::DriveParams;
use serde::Serialize;

/// One drive of the sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepDrive {
    /// Row name.
    pub name: &'static str,
    /// Drive constants.
    pub drive: DriveParams,
    /// Its mismatch.
    pub mismatch: DriveMismatch,
}

/// The sweep's drives (module header), from the estimator's own (`nominal`).
pub fn sweep_drives() -> Vec<SweepDrive> {
    let range = MismatchRange::default();
    let nominal = DriveParams::default();
    // the point of the range that is the estimator's model (as far as the range reaches it)
    let base_at = [
        (30.0 - 25.0) / 15.0,
        0.0,
        (1.0 - 0.9) / 0.5,
        0.5,
        0.5,
        (0.05 - 0.02) / 0.08,
        0.5,
        0.0,
        0.0,
    ];
    let at = |changes: &[(usize, f64)]| {
        let mut a = base_at;
        for &(i, x) in changes {
            a[i] = x;
        }
        a
    };
    let point =
        |a: [f64; 9], winding: Winding| range.drive(&nominal, &MismatchPoint { at: a, winding });
    let mut rows: Vec<(&'static str, [f64; 9], Winding)> = vec![
        ("estimator's model", base_at, Winding::default()),
        ("angle 25° rated", at(&[(0, 0.0)]), Winding::default()),
        ("angle 40° rated", at(&[(0, 1.0)]), Winding::default()),
        ("angle +15° at no load", at(&[(1, 1.0)]), Winding::default()),
        ("R_s +40 %", at(&[(2, 1.0)]), Winding::default()),
        ("R_s −10 %", at(&[(2, 0.0)]), Winding::default()),
        ("J +15 %", at(&[(3, 1.0)]), Winding::default()),
        ("J −15 %", at(&[(3, 0.0)]), Winding::default()),
        ("slip stiffness −30 %", at(&[(4, 0.0)]), Winding::default()),
        (
            "friction high",
            at(&[(5, 1.0), (6, 1.0), (7, 1.0), (8, 1.0)]),
            Winding::default(),
        ),
        (
            "friction low",
            at(&[(5, 0.0), (6, 0.0)]),
            Winding::default(),
        ),
    ];
    let other_winding = Winding {
        connection: WindingConnection::Delta,
        negative_sequence: true,
        sensed: SensedPhases::UW,
        current_reversed: true,
    };
    rows.push(("delta, u-w-v, sensed u-w reversed", base_at, other_winding));
    rows.push(("range corner low", [0.0; 9], Winding::default()));
    rows.push(("range corner high", [1.0; 9], other_winding));
    let mut drives: Vec<SweepDrive> = rows
        .into_iter()
        .map(|(name, a, w)| {
            let (drive, mismatch) = point(a, w);
            SweepDrive {
                name,
                drive,
                mismatch,
            }
        })
        .collect();
    // outside the range: an induction motor at full flux, 75° at no load
    let (drive, mut mismatch) = point(base_at, Winding::default());
    mismatch.current_angle_no_load_deg = 75.0;
    drives.push(SweepDrive {
        name: "outside: 75° at no load",
        drive,
        mismatch,
    });
    drives
}

/// The synthesized estimate's figures on one drive with one set of estimator settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SynthesizedFigures {
    /// Steady mean error, % of the dynamometer.
    pub mean_error_pct: f64,
    /// Standard deviation of the error, % of each period's dynamometer force.
    pub sd_error_pct: f64,
    /// Lag behind the dynamometer on the step (63 %), s (`None`: never reached).
    pub lag_s: Option<f64>,
    /// Largest |error| in the step's transient, N.
    pub peak_error_n: f64,
    /// Share of steady periods on F9's fast estimate, %.
    pub fast_share_pct: f64,
}

/// One row of the sweep.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepRow {
    /// Drive name.
    pub drive: &'static str,
    /// Current angle at rated load, degrees.
    pub current_angle_rated_deg: f64,
    /// Current angle at no load, degrees.
    pub current_angle_no_load_deg: f64,
    /// The drive's stator resistance (per winding), Ω.
    pub stator_resistance: f64,
    /// Delta winding.
    pub delta: bool,
    /// Inertia, kg·m².
    pub inertia: f64,
    /// Slip stiffness, N·m·s/rad.
    pub slip_stiffness: f64,
    /// F8 of the drive: `[f0, f1, g0, g1]`.
    pub friction: [f64; 4],
    /// The estimator's defaults, kernel identification on.
    pub nominal: SynthesizedFigures,
    /// What the identification found.
    pub identified: Option<Identified>,
    /// With the identified settings, kernel identification off.
    pub with_identified: Option<SynthesizedFigures>,
}

/// The depth step on `drive` with `sc`'s settings: the synthesized estimate's figures.
pub fn synthesized(sc: &ControlScenario) -> SynthesizedFigures {
    let r = run(sc, Engine::Model, false);
    let step_at = sc.depth.step_at;
    let dyn_delay = delay_63(&r.trace, &r.trace.force_meas, step_at, DEPTH_LEVELS).unwrap_or(0.0);
    let f = figures(
        "depth-step",
        EstimateKind::Synthesized,
        &r.trace,
        &DEPTH_STEADY,
        DEPTH_TRANSIENT,
        Some((step_at, dyn_delay)),
    );
    SynthesizedFigures {
        mean_error_pct: f.mean_error_pct.unwrap_or(f64::NAN),
        sd_error_pct: f.sd_error_pct.unwrap_or(f64::NAN),
        lag_s: f.lag_behind_dynamometer_s,
        peak_error_n: f.peak_error_n,
        fast_share_pct: f.fast_share_pct.unwrap_or(0.0),
    }
}

/// The depth step (force control off, noise `seed`) on `d`, with the estimator's defaults.
pub fn nominal_scenario(d: &SweepDrive, seed: u64) -> ControlScenario {
    let mut sc = depth_step_scenario(seed);
    sc.drive = d.drive;
    sc.mismatch = Some(d.mismatch);
    sc
}

/// The same with the settings `id` found, the kernel's identification off.
pub fn identified_scenario(d: &SweepDrive, id: &Identified, seed: u64) -> ControlScenario {
    let mut sc = nominal_scenario(d, seed);
    let mut settings = *sc.config.settings();
    settings.estimator = id.settings(&settings.estimator);
    if let Ok(config) = settings.validate() {
        sc.config = config;
    }
    sc.identify = (sc.identify.0, sc.identify.0);
    sc
}

/// One drive's row.
pub fn sweep_row(d: &SweepDrive, seed: u64) -> SweepRow {
    let sc = nominal_scenario(d, seed);
    let nominal = synthesized(&sc);
    let identified = identify(
        &d.drive,
        Some(&d.mismatch),
        &IdentificationPlan::default(),
        &sc.config.settings().estimator,
        seed,
    );
    let with_identified = identified
        .as_ref()
        .map(|id| synthesized(&identified_scenario(d, id, seed)));
    SweepRow {
        drive: d.name,
        current_angle_rated_deg: d.mismatch.current_angle_rated_deg,
        current_angle_no_load_deg: d.mismatch.current_angle_no_load_deg,
        stator_resistance: d.drive.stator_resistance,
        delta: d.mismatch.winding.connection == WindingConnection::Delta,
        inertia: d.drive.inertia,
        slip_stiffness: d.drive.slip_stiffness,
        friction: [
            d.drive.friction_f0,
            d.mismatch.friction_f1,
            d.drive.friction_g0,
            d.mismatch.friction_g1,
        ],
        nominal,
        identified,
        with_identified,
    }
}

/// The whole sweep.
#[derive(Clone, Debug, Serialize)]
pub struct MismatchReport {
    /// Noise seed.
    pub seed: u64,
    /// Rows, in [`sweep_drives`] order.
    pub rows: Vec<SweepRow>,
}

/// Runs the sweep with noise `seed`.
pub fn report(seed: u64) -> MismatchReport {
    MismatchReport {
        seed,
        rows: sweep_drives().iter().map(|d| sweep_row(d, seed)).collect(),
    }
}

fn lag(x: Option<f64>) -> String {
    x.map_or("-".into(), |v| format!("{v:.2}s"))
}

impl MismatchReport {
    /// The terminal table, line by line.
    pub fn table(&self) -> Vec<String> {
        let mut lines = vec![
            format!(
                "synthesized estimate vs dynamometer on mismatched drives (depth step, force control off, seed {})",
                self.seed
            ),
            format!(
                "{:<34} {:>9} {:>7} | {:>7} {:>6} {:>6} {:>8} {:>6} | {:>6} {:>6} {:>6} {:>6}",
                "drive",
                "nominal %",
                "fast %",
                "ident %",
                "sd %",
                "lag",
                "peak",
                "fast %",
                "k_slip",
                "Δ_th",
                "f0",
                "g0"
            ),
        ];
        for r in &self.rows {
            let (w, id) = match (&r.with_identified, &r.identified) {
                (Some(w), Some(id)) => (w, id),
                _ => {
                    lines.push(format!(
                        "{:<34} {:>8.2}% {:>7.0} | identification failed",
                        r.drive, r.nominal.mean_error_pct, r.nominal.fast_share_pct
                    ));
                    continue;
                }
            };
            lines.push(format!(
                "{:<34} {:>8.2}% {:>7.0} | {:>6.2}% {:>5.2}% {:>6} {:>6.1} N {:>6.0} | {:>6.3} {:>6.3} {:>6.3} {:>6.4}",
                r.drive,
                r.nominal.mean_error_pct,
                r.nominal.fast_share_pct,
                w.mean_error_pct,
                w.sd_error_pct,
                lag(w.lag_s),
                w.peak_error_n,
                w.fast_share_pct,
                id.slip_gain,
                id.switch_threshold,
                id.friction_f[0],
                id.friction_g[0],
            ));
        }
        lines
    }

    /// One CSV line per drive: its constants and both settings' figures (absent empty).
    pub fn csv(&self) -> Result<String, csv::Error> {
        #[derive(Serialize)]
        struct Flat<'a> {
            drive: &'a str,
            current_angle_rated_deg: f64,
            current_angle_no_load_deg: f64,
            stator_resistance: f64,
            delta: bool,
            inertia: f64,
            slip_stiffness: f64,
            nominal_mean_error_pct: f64,
            nominal_fast_share_pct: f64,
            identified_mean_error_pct: Option<f64>,
            identified_sd_error_pct: Option<f64>,
            identified_lag_s: Option<f64>,
            identified_peak_error_n: Option<f64>,
            identified_fast_share_pct: Option<f64>,
            slip_gain: Option<f64>,
            switch_threshold: Option<f64>,
            f0: Option<f64>,
            f1: Option<f64>,
            g0: Option<f64>,
            g1: Option<f64>,
        }
        let mut w = csv::Writer::from_writer(Vec::new());
        for r in &self.rows {
            let wi = r.with_identified.as_ref();
            let id = r.identified.as_ref();
            w.serialize(Flat {
                drive: r.drive,
                current_angle_rated_deg: r.current_angle_rated_deg,
                current_angle_no_load_deg: r.current_angle_no_load_deg,
                stator_resistance: r.stator_resistance,
                delta: r.delta,
                inertia: r.inertia,
                slip_stiffness: r.slip_stiffness,
                nominal_mean_error_pct: r.nominal.mean_error_pct,
                nominal_fast_share_pct: r.nominal.fast_share_pct,
                identified_mean_error_pct: wi.map(|x| x.mean_error_pct),
                identified_sd_error_pct: wi.map(|x| x.sd_error_pct),
                identified_lag_s: wi.and_then(|x| x.lag_s),
                identified_peak_error_n: wi.map(|x| x.peak_error_n),
                identified_fast_share_pct: wi.map(|x| x.fast_share_pct),
                slip_gain: id.map(|x| x.slip_gain),
                switch_threshold: id.map(|x| x.switch_threshold),
                f0: id.map(|x| x.friction_f[0]),
                f1: id.map(|x| x.friction_f[1]),
                g0: id.map(|x| x.friction_g[0]),
                g1: id.map(|x| x.friction_g[1]),
            })?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| csv::Error::from(e.into_error()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// The report as pretty JSON (with the identification's points).
    pub fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string_pretty(self)
    }
}
