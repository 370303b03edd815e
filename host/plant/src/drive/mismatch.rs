//! A spindle drive that is **not** the estimator's model (docs/estimator.md, "A plant that is
//! not the estimator"): the default [`super::Plant`] makes the currents lag exactly π/6, uses
//! the estimator's own friction functions and its winding convention, so F3 and F8 are exact
//! by construction. A [`DriveMismatch`] set on the plant replaces those three parts:
//!
//! - **Power factor.** The current angle φ between phase voltage and line current depends on
//!   the load: `φ(T_e) = φ_rated + (φ_no_load − φ_rated)·(1 − min(|T_e|/T_rated, 1))`, the
//!   shape of an induction motor's power factor, which rises with load as the magnetizing
//!   current becomes a smaller part of the stator current. The line current then satisfies
//!   the physical `√3·V·I·cos φ − P_cu(I) = P_g` (V the line-to-line voltage the channels
//!   carry), where the estimator's F3 assumes `cos φ = cos(π/6)` at every load.
//! - **Winding.** A star winding loses `3·R·I²` in copper, a delta winding of per-winding
//!   resistance R (its phase current is `I/√3`) loses `R·I²`: the estimator's F2 assumes the
//!   star form with its R_s. The phase sequence, which two phases the current sensors sit on
//!   and their direction are installation choices too; F3 and F2 use only `Σv²` and `Σi²`,
//!   which none of them changes (`tests/force/mismatch.rs` checks that).
//! - **Friction.** F8's `δT_f = f(ω)·T_c + g(ω)·T_c²` with `f(ω) = f0 + f1·ω` and
//!   `g(ω) = g0 + g1·ω` from [`DriveParams::friction_f0`], [`DriveParams::friction_g0`] and
//!   the slopes here: bearing and gear losses under load grow with speed (churning and
//!   viscous oil losses), while the estimator's defaults are constant in ω.
//!
//! The motor's own constants (R_s, J, the slip stiffness) are [`DriveParams`] fields; a
//! mismatched plant simply gives them other values than the estimator's settings
//! ([`MismatchRange`] states the ranges and where they come from).

use super::DriveParams;
use std::f64::consts::PI;

/// How the stator is connected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WindingConnection {
    /// Star: copper loss `3·R·I²` (the estimator's F2).
    Star,
    /// Delta: per-winding resistance R carries `I/√3`, copper loss `R·I²`.
    Delta,
}

/// Which two line currents the drive's current sensors measure (the third is implied).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SensedPhases {
    /// u and v (the estimator's channel names).
    UV,
    /// u and w.
    UW,
    /// v and w.
    VW,
}

/// The winding convention of the installation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Winding {
    /// Star or delta.
    pub connection: WindingConnection,
    /// Phase sequence u-w-v instead of u-v-w.
    pub negative_sequence: bool,
    /// The sensed pair of line currents.
    pub sensed: SensedPhases,
    /// Current sensors mounted the other way round (generator convention).
    pub current_reversed: bool,
}

impl Default for Winding {
    /// The estimator's convention: star, u-v-w, sensors on u and v, motor convention.
    fn default() -> Self {
        Winding {
            connection: WindingConnection::Star,
            negative_sequence: false,
            sensed: SensedPhases::UV,
            current_reversed: false,
        }
    }
}

/// The parts of the drive that differ from the estimator's model (see the module header).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriveMismatch {
    /// Current angle at rated torque and above, degrees.
    pub current_angle_rated_deg: f64,
    /// Current angle at no load, degrees.
    pub current_angle_no_load_deg: f64,
    /// Rated torque where the angle reaches its rated value, N·m.
    pub rated_torque_nm: f64,
    /// Speed slope of F8's f(ω), s/rad.
    pub friction_f1: f64,
    /// Speed slope of F8's g(ω), s/(rad·N·m).
    pub friction_g1: f64,
    /// Winding convention.
    pub winding: Winding,
}

impl Default for DriveMismatch {
    /// No mismatch: the estimator's π/6 at every load, constant friction functions, its
    /// winding convention (with [`DriveParams::default`] the plant is then the estimator's
    /// model except for the amplitude formula's rounding).
    fn default() -> Self {
        DriveMismatch {
            current_angle_rated_deg: 30.0,
            current_angle_no_load_deg: 30.0,
            rated_torque_nm: 20.0,
            friction_f1: 0.0,
            friction_g1: 0.0,
            winding: Winding::default(),
        }
    }
}

impl DriveMismatch {
    /// The current angle at motor torque `t_e`, rad.
    pub fn current_angle(&self, t_e: f64) -> f64 {
        let load = (t_e.abs() / self.rated_torque_nm.max(1e-9)).min(1.0);
        let deg = self.current_angle_rated_deg
            + (self.current_angle_no_load_deg - self.current_angle_rated_deg) * (1.0 - load);
        deg.to_radians()
    }

    /// Load-dependent friction F8 at speed `omega` (rad/s) and cutting torque `t_c` (N·m):
    /// `(f0 + f1·ω)·T_c + (g0 + g1·ω)·T_c²`, N·m.
    pub fn load_friction(&self, d: &DriveParams, omega: f64, t_c: f64) -> f64 {
        let f = d.friction_f0 + self.friction_f1 * omega;
        let g = d.friction_g0 + self.friction_g1 * omega;
        f * t_c + g * t_c * t_c
    }

    /// Copper loss per A² of line current, W/A²: `3·R` (star) or `R` (delta).
    pub fn copper_loss_per_amp_sq(&self, d: &DriveParams) -> f64 {
        match self.winding.connection {
            WindingConnection::Star => 3.0 * d.stator_resistance,
            WindingConnection::Delta => d.stator_resistance,
        }
    }

    /// Line current, A rms, for air-gap power `p_g` (W) at motor torque `t_e`: the smaller
    /// root of `k_cu·I² − √3·V·cos φ·I + P_g = 0` (clamped at the vertex when there is none).
    pub fn line_current(&self, d: &DriveParams, p_g: f64, t_e: f64) -> f64 {
        let a = 3f64.sqrt() * d.line_voltage * self.current_angle(t_e).cos();
        let k_cu = self.copper_loss_per_amp_sq(d);
        if k_cu <= 0.0 {
            return p_g / a;
        }
        let disc = (a * a - 4.0 * k_cu * p_g).max(0.0);
        (a - disc.sqrt()) / (2.0 * k_cu)
    }

    /// Instantaneous line-to-line voltages (3) and the two sensed line currents at
    /// electrical angle `theta` (rad), for line voltage `v` and line current `i` (rms).
    /// The line current of phase k lags its phase voltage by φ, which lags the line voltage
    /// k→k+1 by π/6.
    pub fn waveforms(&self, theta: f64, v: f64, i: f64, t_e: f64) -> ([f64; 3], [f64; 2]) {
        let sq2 = std::f64::consts::SQRT_2;
        let dir = if self.winding.negative_sequence {
            -1.0
        } else {
            1.0
        };
        let phase = |k: f64| theta - dir * 2.0 * PI * k / 3.0;
        let volts = [0.0, 1.0, 2.0].map(|k| sq2 * v * phase(k).sin());
        let phi = self.current_angle(t_e);
        let sign = if self.winding.current_reversed {
            -1.0
        } else {
            1.0
        };
        let line = |k: f64| sign * sq2 * i * (phase(k) - PI / 6.0 - phi).sin();
        let amps = match self.winding.sensed {
            SensedPhases::UV => [line(0.0), line(1.0)],
            SensedPhases::UW => [line(0.0), line(2.0)],
            SensedPhases::VW => [line(1.0), line(2.0)],
        };
        (volts, amps)
    }
}

/// The ranges a mismatched drive is drawn from (the property tests and the report's sweep),
/// with their sources (docs/estimator.md):
///
/// - current angle at rated load 25–40° (power factor 0.91–0.77: the range of standard
///   four-pole induction motors of a few kW at rated load; the turning-force paper's drive
///   assumes 30°), rising towards no load by 0–15° (a vector-controlled drive that keeps
///   its flux current low at light load; an induction motor fed at full flux reaches 70–80°
///   at no load, which the report shows as a row outside the range);
/// - stator resistance −10 … +40 % of the estimator's (copper's +0.39 %/K: a winding 25 K
///   colder to 100 K hotter than where it was measured);
/// - inertia ±15 % (a chuck or workpiece other than the one J was set for);
/// - slip stiffness ±30 % (rotor resistance changes with temperature as the stator's does);
/// - F8: f0 0.02–0.10 and g0 0–0.004 /(N·m) (a few to ten percent of the cutting torque
///   lost in the bearings and the belt or gears under load, the size the turning-force paper
///   leaves to be identified per lathe), slopes f1 0–2·10⁻⁴ s/rad and g1 0–10⁻⁵ s/(rad·N·m)
///   (f rising by up to a sixth between 600 and 1000 rpm);
/// - winding: star or delta with the estimator's R_s as the star equivalent, either phase
///   sequence, any sensed pair, either current direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MismatchRange {
    /// Current angle at rated load, degrees.
    pub current_angle_rated_deg: (f64, f64),
    /// Rise of the current angle from rated load to no load, degrees.
    pub current_angle_rise_deg: (f64, f64),
    /// Stator resistance, ratio to the estimator's.
    pub stator_resistance_ratio: (f64, f64),
    /// Inertia, ratio to the estimator's.
    pub inertia_ratio: (f64, f64),
    /// Slip stiffness, ratio to the default drive's.
    pub slip_stiffness_ratio: (f64, f64),
    /// F8's f0.
    pub friction_f0: (f64, f64),
    /// F8's g0, 1/(N·m).
    pub friction_g0: (f64, f64),
    /// F8's f1, s/rad.
    pub friction_f1: (f64, f64),
    /// F8's g1, s/(rad·N·m).
    pub friction_g1: (f64, f64),
}

impl Default for MismatchRange {
    fn default() -> Self {
        MismatchRange {
            current_angle_rated_deg: (25.0, 40.0),
            current_angle_rise_deg: (0.0, 15.0),
            stator_resistance_ratio: (0.9, 1.4),
            inertia_ratio: (0.85, 1.15),
            slip_stiffness_ratio: (0.7, 1.3),
            friction_f0: (0.02, 0.10),
            friction_g0: (0.0, 0.004),
            friction_f1: (0.0, 2e-4),
            friction_g1: (0.0, 1e-5),
        }
    }
}

/// A point of the range: each coordinate in `[0, 1]` from the low to the high end, in the
/// order of [`MismatchRange`]'s fields, and the winding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MismatchPoint {
    /// Position in each range, 0..=1.
    pub at: [f64; 9],
    /// Winding convention (for a delta winding R is three times the star equivalent).
    pub winding: Winding,
}

impl MismatchRange {
    /// The drive (from `nominal`, the estimator's) and its mismatch at `p`.
    pub fn drive(&self, nominal: &DriveParams, p: &MismatchPoint) -> (DriveParams, DriveMismatch) {
        let lerp = |(lo, hi): (f64, f64), x: f64| lo + (hi - lo) * x.clamp(0.0, 1.0);
        let a = p.at;
        let rated = lerp(self.current_angle_rated_deg, a[0]);
        let mut d = *nominal;
        let star_r = nominal.stator_resistance * lerp(self.stator_resistance_ratio, a[2]);
        d.stator_resistance = match p.winding.connection {
            WindingConnection::Star => star_r,
            WindingConnection::Delta => 3.0 * star_r,
        };
        d.inertia = nominal.inertia * lerp(self.inertia_ratio, a[3]);
        d.slip_stiffness = nominal.slip_stiffness * lerp(self.slip_stiffness_ratio, a[4]);
        d.friction_f0 = lerp(self.friction_f0, a[5]);
        d.friction_g0 = lerp(self.friction_g0, a[6]);
        let m = DriveMismatch {
            current_angle_rated_deg: rated,
            current_angle_no_load_deg: rated + lerp(self.current_angle_rise_deg, a[1]),
            rated_torque_nm: 20.0,
            friction_f1: lerp(self.friction_f1, a[7]),
            friction_g1: lerp(self.friction_g1, a[8]),
            winding: p.winding,
        };
        (d, m)
    }
}
