//! Identification of the estimator's parameters on a drive (docs/estimator.md, "Identifying
//! f(ω) and g(ω)"): steady runs at several spindle speeds, each at no load and at a few known
//! cutting loads (the dynamometer's reading — a set-up with a force sensor, or a brake, done
//! once per lathe), read through the model's own sampling chain (the 20 Hz period averages the
//! estimator sees), then three least-squares fits:
//!
//! 1. **no load** at every speed: `P_o/ω = B·ω + T_fco` (F5 at steady speed) → B, T_fco;
//! 2. **under load**: with `c = P_o/ω − B·ω − T_fco` the torque F7 leaves for the cut and its
//!    friction and `T_c = F·r` the known cutting torque, `c − T_c = f0·T_c + f1·ω·T_c +
//!    g0·T_c² + g1·ω·T_c²` (F8 with `f(ω) = f0 + f1·ω`, `g(ω) = g0 + g1·ω`, the estimator's
//!    forms) → f0, f1, g0, g1;
//! 3. **electrical**, the loaded points: `P_o = k·P̂_g` with F2–F3's `P̂_g = (3/2)·V·I −
//!    R_s·Σi²` (the settings' R_s) → the slip gain k of F9's fast estimate, which then absorbs
//!    what the fixed π/6 of F3 and the winding's copper-loss form get wrong at those loads as
//!    well as the slip; and F9's threshold Δ_th raised, if needed, to 5 points above the
//!    largest steady `(P̂_g − P_o)/P_o` seen, so that a steady bias of P̂_g does not hold the
//!    switch on the noisy fast estimate. R_s itself is not fitted: the slip loss
//!    `P_g − P_o = T_e²/k_slip-stiffness` grows with the square of the current just as the copper loss
//!    does, so P_o cannot tell them apart (a fit of both found R_s = 0.02 Ω on the drive
//!    that has 0.5 Ω).
//!
//! The result is an [`EstimatorSettings`] with those values (B and T_fco as its nominal ones);
//! the scenario that uses it turns the kernel's own no-load identification off, because that
//! one fits P_g, which a power factor other than F3's biases.

use super::mismatch::DriveMismatch;
use super::scenario::{scenario_settings, ClosedLoop, ControllerKind};
use super::{DepthProfile, DriveParams, Plant, ProcessParams};
use serde::Serialize;
use std::f64::consts::PI;
use tooltouch_model::force::config::ForceSource;
use tooltouch_model::force::estimator::settings::EstimatorSettings;
use tooltouch_model::units::Fx;

/// Speeds and loads of the identification runs.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentificationPlan {
    /// Spindle speeds, rpm (at least two).
    pub speeds_rpm: Vec<f64>,
    /// Cutting forces at each speed, N (0 included: the no-load point).
    pub loads_n: Vec<f64>,
    /// Time each point is held before it is averaged, s.
    pub settle_s: f64,
    /// Averaging time of each point, s.
    pub average_s: f64,
}

impl Default for IdentificationPlan {
    /// 600, 800 and 1000 rpm; 0, 300, 600 and 900 N; 2.4 s to settle (eight times P_o's
    /// 0.3 s lag: with 1.2 s the lag's remainder biased f0 by −30 %), 0.8 s averaged.
    fn default() -> Self {
        IdentificationPlan {
            speeds_rpm: vec![600.0, 800.0, 1000.0],
            loads_n: vec![0.0, 300.0, 600.0, 900.0],
            settle_s: 2.4,
            average_s: 0.8,
        }
    }
}

/// One steady point's averages.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LoadPoint {
    /// Speed, rad/s.
    pub omega: f64,
    /// Dynamometer force, N.
    pub force_n: f64,
    /// Measured power P_o, W.
    pub p_o: f64,
    /// `(3/2)·V·I`, W.
    pub vi: f64,
    /// Σi², A².
    pub amps_sq: f64,
}

/// What the identification found.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Identified {
    /// Viscous friction B, N·m·s/rad.
    pub viscous: f64,
    /// Coulomb friction T_fco, N·m.
    pub coulomb: f64,
    /// F8's f(ω) = f0 + f1·ω: `[f0, f1]`.
    pub friction_f: [f64; 2],
    /// F8's g(ω) = g0 + g1·ω: `[g0, g1]`.
    pub friction_g: [f64; 2],
    /// F9's slip gain.
    pub slip_gain: f64,
    /// F9's switch threshold Δ_th.
    pub switch_threshold: f64,
    /// Largest steady `(P̂_g − P_o)/P_o` of the loaded points.
    pub steady_power_bias: f64,
    /// Rms residual of the load fit, N·m.
    pub load_fit_rms_nm: f64,
    /// The averaged points.
    pub points: Vec<LoadPoint>,
}

impl Identified {
    /// `base` with the identified values (each clamped into the settings' range).
    pub fn settings(&self, base: &EstimatorSettings) -> EstimatorSettings {
        let fx = |x: f64, lo: f64, hi: f64| Fx::from_num(x.clamp(lo, hi));
        EstimatorSettings {
            switch_threshold: fx(self.switch_threshold, 0.001, 10.0),
            viscous_nominal: fx(self.viscous, 0.0, 1.0),
            coulomb_nominal: fx(self.coulomb, 0.0, 1000.0),
            friction_f: [
                fx(self.friction_f[0], -0.5, 1.0),
                fx(self.friction_f[1], -0.01, 0.01),
            ],
            friction_g: [
                fx(self.friction_g[0], -1.0, 1.0),
                fx(self.friction_g[1], -0.01, 0.01),
            ],
            slip_gain: fx(self.slip_gain, 0.01, 2.0),
            ..*base
        }
    }
}

/// Solves the normal equations `AᵀA·x = Aᵀy` of `rows` (each `(a, y)`) by Gaussian
/// elimination with partial pivoting; `None` if they are singular. At most 4 unknowns
/// here, so the normal equations' squared condition number is harmless and a linear-algebra
/// crate would be a dependency for twenty lines.
pub fn least_squares<const N: usize>(rows: &[([f64; N], f64)]) -> Option<[f64; N]> {
    let mut m = [[0.0; N]; N];
    let mut v = [0.0; N];
    for (a, y) in rows {
        for i in 0..N {
            v[i] += a[i] * y;
            for j in 0..N {
                m[i][j] += a[i] * a[j];
            }
        }
    }
    let scale = (0..N).map(|i| m[i][i].abs()).fold(0.0, f64::max);
    for c in 0..N {
        let p = (c..N).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))?;
        if m[p][c].abs() <= 1e-12 * scale.max(1e-300) {
            return None;
        }
        m.swap(c, p);
        v.swap(c, p);
        for r in c + 1..N {
            let k = m[r][c] / m[c][c];
            let (upper, lower) = m.split_at_mut(r);
            for (x, p) in lower[0][c..].iter_mut().zip(&upper[c][c..]) {
                *x -= k * p;
            }
            v[r] -= k * v[c];
        }
    }
    let mut x = [0.0; N];
    for c in (0..N).rev() {
        let s: f64 = (c + 1..N).map(|j| m[c][j] * x[j]).sum();
        x[c] = (v[c] - s) / m[c][c];
    }
    Some(x)
}

/// Averages of one speed's points: the plant held at `rpm`, idle then at each load.
fn run_speed(
    drive: &DriveParams,
    mismatch: Option<&DriveMismatch>,
    plan: &IdentificationPlan,
    rpm: f64,
    seed: u64,
) -> Vec<LoadPoint> {
    let config = scenario_settings(ControllerKind::Pi, ForceSource::Measured)
        .validate()
        .expect("the scenario's default settings are valid");
    let s = config.settings();
    let fs = f64::from(s.sample_hz);
    let spp = usize::from(s.samples_per_period);
    let omega = rpm * 2.0 * PI / 60.0;
    let process = ProcessParams {
        ks_drift: 0.0,
        ..ProcessParams::default()
    };
    let depth = DepthProfile {
        before: 1.0,
        after: 1.0,
        step_at: f64::INFINITY,
    };
    let mut plant = Plant::new(*drive, process, depth, &s.scales, fs, omega, seed);
    plant.mismatch = mismatch.copied();
    let mut lp = ClosedLoop::new(&config, plant);
    let settle = (plan.settle_s * fs).round() as usize;
    let average = ((plan.average_s * fs).round() as usize).max(spp);
    let mut points = Vec::new();
    for &load in &plan.loads_n {
        let feed = process.feed_mm_per_rev;
        lp.plant.engaged = load > 0.0;
        let d = load / (process.ks * feed);
        lp.plant.depth = DepthProfile {
            before: d,
            after: d,
            step_at: f64::INFINITY,
        };
        let mut acc = [0.0f64; 5];
        let mut n = 0.0;
        for k in 0..settle + average {
            lp.plant.set_speed(omega);
            lp.step(|c| c);
            if k >= settle && (lp.samples() as usize).is_multiple_of(spp) {
                let sig = lp.kernel().estimate().signals;
                let f = |x: Fx| x.to_num::<f64>();
                acc[0] += f(sig.omega);
                acc[1] += f(sig.force_measured);
                acc[2] += f(sig.p_o);
                acc[3] += 1.5 * f(sig.v_line) * f(sig.i_line);
                acc[4] += f(sig.amps_sq);
                n += 1.0;
            }
        }
        let n = if n > 0.0 { n } else { 1.0 };
        points.push(LoadPoint {
            omega: acc[0] / n,
            force_n: acc[1] / n,
            p_o: acc[2] / n,
            vi: acc[3] / n,
            amps_sq: acc[4] / n,
        });
    }
    points
}

/// Runs `plan` on the drive (`mismatch` as [`Plant::mismatch`]) with noise `seed` and fits
/// the parameters (module header) for an estimator set up as `base` (its R_s, Δ_th and
/// workpiece radius are used). `None` if a fit is singular (fewer than two speeds, or no
/// load above 0).
pub fn identify(
    drive: &DriveParams,
    mismatch: Option<&DriveMismatch>,
    plan: &IdentificationPlan,
    base: &EstimatorSettings,
    seed: u64,
) -> Option<Identified> {
    let radius = base.workpiece_radius.to_num::<f64>();
    let r_s = base.stator_resistance.to_num::<f64>();
    let mut points = Vec::new();
    for (i, &rpm) in plan.speeds_rpm.iter().enumerate() {
        points.extend(run_speed(
            drive,
            mismatch,
            plan,
            rpm,
            seed.wrapping_add(i as u64),
        ));
    }
    let idle: Vec<([f64; 2], f64)> = points
        .iter()
        .filter(|p| p.force_n.abs() < 20.0)
        .map(|p| ([p.omega, 1.0], p.p_o / p.omega))
        .collect();
    let [viscous, coulomb] = least_squares(&idle)?;
    let loaded: Vec<([f64; 4], f64)> = points
        .iter()
        .filter(|p| p.force_n.abs() >= 20.0)
        .map(|p| {
            let t_c = p.force_n * radius;
            let c = p.p_o / p.omega - viscous * p.omega - coulomb;
            (
                [t_c, p.omega * t_c, t_c * t_c, p.omega * t_c * t_c],
                c - t_c,
            )
        })
        .collect();
    let [f0, f1, g0, g1] = least_squares(&loaded)?;
    let residual = (loaded
        .iter()
        .map(|(a, y)| (y - (f0 * a[0] + f1 * a[1] + g0 * a[2] + g1 * a[3])).powi(2))
        .sum::<f64>()
        / loaded.len().max(1) as f64)
        .sqrt();
    let loaded_points = || points.iter().filter(|p| p.force_n.abs() >= 20.0);
    let p_g = |p: &LoadPoint| p.vi - r_s * p.amps_sq;
    let electrical: Vec<([f64; 1], f64)> = loaded_points().map(|p| ([p_g(p)], p.p_o)).collect();
    let [k] = least_squares(&electrical)?;
    let bias = loaded_points()
        .map(|p| (p_g(p) - p.p_o) / p.p_o)
        .fold(f64::MIN, f64::max);
    let default_threshold = base.switch_threshold.to_num::<f64>();
    Some(Identified {
        viscous,
        coulomb,
        friction_f: [f0, f1],
        friction_g: [g0, g1],
        slip_gain: k,
        switch_threshold: default_threshold.max(bias + 0.05),
        steady_power_bias: bias,
        load_fit_rms_nm: residual,
        points,
    })
}
