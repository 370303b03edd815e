//! The spindle-drive and turning-process plant of the force-control scenario (docs/domain.md §3),
//! in float, integrated at 10 kHz and sampled at the ADC rate into 12-bit codes.
//!
//! - Induction motor under a V/f drive with an integrating speed loop: the drive sets the
//!   synchronous speed ω_s; in the linear slip region `T_e = k_slip·(ω_s − ω_M)`; the shaft
//!   obeys F5 `J dω/dt + Bω = T_e − T_t` with `T_t = T_fco + δT_f + T_c`, δT_f as F8.
//!   The spindle is driven directly (motor speed = spindle speed; our choice).
//! - Electrical signals consistent with F2–F3: air-gap power `P_g = T_e·ω_s`, line
//!   voltage V constant, line current from `(3/2)·V·I − 3·R_s·I² = P_g`, phase
//!   voltages/currents balanced sinusoids at the electrical angle (pole pairs × ω_s),
//!   currents lagging by φ = π/6.
//! - Measured power P_o: the shaft power `T_e·ω_M` through a first-order lag of 0.3 s
//!   (the drive's smooth, late power signal).
//! - Turning process F10 `τ_p dF/dt = K_s·a·f − F` with f = programmed feed × override/100,
//!   K_s and τ_p drifting linearly in time (relative rates per second), a small random
//!   force ripple, and the depth-of-cut profile `a(t)` (default 1 mm stepping to 1.5 mm).
//! - Dynamometer: a piezoelectric force sensor with a charge amplifier reads the cutting
//!   force the tool sees (F10's force with its ripple) through a first-order low-pass of
//!   [`DYNAMOMETER_BANDWIDTH_HZ`] — far above the 20 Hz control rate, so after the model's
//!   100 Hz low-pass and 20 Hz average it is as fast as any channel can be.
//! - Speed reference: [`Plant::set_speed`] before each sample; it moves linearly over the
//!   sample's integration substeps (a drive's ramp generator is continuous, and a reference
//!   stepped at the ADC rate would leave a 1 kHz torque sawtooth that the ADC, sampling
//!   always at the same phase of it, would alias into a bias of the torque during a ramp).
//! - ADC: Gaussian noise of [`DriveParams::adc_noise`] LSB rms on every channel, rounded and
//!   clamped to 0..=4095, with the scales of the model's [`AdcScales`]
//!   (docs/estimator.md states what each channel models and its noise).

pub mod estimator_report;
pub mod identify;
pub mod kienzle;
pub mod mismatch;
pub mod mismatch_report;
pub mod scenario;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, StandardNormal};
use std::f64::consts::PI;
use tooltouch_model::force::sampling::AdcScales;
use tooltouch_model::force::sampling::{AdcCodes, ADC_MAX, ADC_MID};

/// Integration steps per ADC sample.
pub const SUBSTEPS: u32 = 10;

/// −3 dB bandwidth of the dynamometer (piezo sensor and charge amplifier), Hz.
pub const DYNAMOMETER_BANDWIDTH_HZ: f64 = 2000.0;

/// Spindle-drive parameters (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriveParams {
    /// Inertia J, kg·m².
    pub inertia: f64,
    /// Viscous friction B, N·m·s/rad.
    pub viscous: f64,
    /// Coulomb friction T_fco, N·m.
    pub coulomb: f64,
    /// Load-dependent friction f0 (δT_f = f0·T_c + g0·T_c²).
    pub friction_f0: f64,
    /// Load-dependent friction g0, 1/(N·m).
    pub friction_g0: f64,
    /// Slip stiffness, N·m per rad/s of slip.
    pub slip_stiffness: f64,
    /// Speed-loop integral gain, 1/s.
    pub speed_ki: f64,
    /// Stator resistance per phase, Ω.
    pub stator_resistance: f64,
    /// Line voltage, V rms.
    pub line_voltage: f64,
    /// Pole pairs.
    pub pole_pairs: f64,
    /// Lag of the measured power, s.
    pub power_lag: f64,
    /// ADC noise, LSB rms.
    pub adc_noise: f64,
}

impl Default for DriveParams {
    fn default() -> Self {
        DriveParams {
            inertia: 0.05,
            viscous: 0.005,
            coulomb: 1.0,
            friction_f0: 0.05,
            friction_g0: 0.002,
            slip_stiffness: 5.0,
            speed_ki: 5.0,
            stator_resistance: 0.5,
            line_voltage: 200.0,
            pole_pairs: 2.0,
            power_lag: 0.3,
            adc_noise: 1.5,
        }
    }
}

/// Turning process F10 parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProcessParams {
    /// Specific cutting force K_s at t = 0, N/mm².
    pub ks: f64,
    /// Relative drift of K_s, 1/s (K_s(t) = K_s·(1 + drift·t)).
    pub ks_drift: f64,
    /// Time constant τ_p at t = 0, s.
    pub tau_p: f64,
    /// Relative drift of τ_p, 1/s.
    pub tau_drift: f64,
    /// Programmed feed at 100 % override, mm/rev.
    pub feed_mm_per_rev: f64,
    /// Workpiece radius, m.
    pub radius: f64,
    /// Random force ripple, relative rms.
    pub ripple: f64,
}

impl Default for ProcessParams {
    fn default() -> Self {
        ProcessParams {
            ks: 2000.0,
            ks_drift: 0.01,
            tau_p: 0.08,
            tau_drift: 0.0,
            feed_mm_per_rev: 0.3,
            radius: 0.02,
            ripple: 0.01,
        }
    }
}

/// Depth of cut over time: `before` mm until `step_at`, then `after` mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthProfile {
    /// Depth before the step, mm.
    pub before: f64,
    /// Depth after the step, mm.
    pub after: f64,
    /// Time of the step, s.
    pub step_at: f64,
}

/// The true state of the plant at a sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlantState {
    /// Time, s.
    pub t: f64,
    /// Motor speed, rad/s.
    pub omega: f64,
    /// Synchronous speed, rad/s.
    pub omega_s: f64,
    /// Motor torque, N·m.
    pub t_e: f64,
    /// Cutting force, N (F10's state, without the ripple).
    pub force: f64,
    /// Dynamometer reading before the ADC, N (the force with its ripple, low-passed at
    /// [`DYNAMOMETER_BANDWIDTH_HZ`]).
    pub dynamometer: f64,
    /// Depth of cut, mm.
    pub depth: f64,
    /// Air-gap power, W.
    pub p_g: f64,
    /// Measured (lagged) power, W.
    pub p_o: f64,
}

/// The drive + process plant.
pub struct Plant {
    /// Drive parameters.
    pub drive: DriveParams,
    /// Process parameters.
    pub process: ProcessParams,
    /// Depth profile.
    pub depth: DepthProfile,
    scales: [f64; 5],
    dt: f64,
    state: PlantState,
    /// Speed reference at the end of the next sample period, rad/s.
    speed_ref: f64,
    /// Speed reference at the end of the last sample period, rad/s: the reference moves
    /// linearly between the two over the integration substeps.
    speed_ref_prev: f64,
    integ: f64,
    theta: f64,
    ripple: f64,
    /// Tool in the cut (force builds up only then).
    pub engaged: bool,
    /// Override applied by the CNC, %.
    pub override_pct: u8,
    rng: ChaCha8Rng,
    noise: Normal<f64>,
    /// A drive that is not the estimator's model (power factor, winding, friction
    /// functions; [`mismatch`]); `None`: the estimator's own model, as documented above.
    pub mismatch: Option<mismatch::DriveMismatch>,
    /// A nonlinear, time-varying process law ([`kienzle`]); `None`: the linear F10.
    pub kienzle: Option<kienzle::KienzleProcess>,
}

impl Plant {
    /// A plant at `speed` rad/s in steady state, no cut, sampled at `sample_hz`.
    pub fn new(
        drive: DriveParams,
        process: ProcessParams,
        depth: DepthProfile,
        scales: &AdcScales,
        sample_hz: f64,
        speed: f64,
        seed: u64,
    ) -> Plant {
        let f = |x: tooltouch_model::units::Fx| x.to_num::<f64>();
        let load = drive.coulomb + drive.viscous * speed;
        let slip = load / drive.slip_stiffness;
        let mut p = Plant {
            drive,
            process,
            depth,
            scales: [
                f(scales.speed_per_lsb),
                f(scales.power_per_lsb),
                f(scales.force_per_lsb),
                f(scales.volts_per_lsb),
                f(scales.amps_per_lsb),
            ],
            dt: 1.0 / (sample_hz * f64::from(SUBSTEPS)),
            state: PlantState {
                omega: speed,
                omega_s: speed + slip,
                t_e: load,
                depth: depth.before,
                ..PlantState::default()
            },
            speed_ref: speed,
            speed_ref_prev: speed,
            integ: slip,
            theta: 0.0,
            ripple: 0.0,
            engaged: false,
            override_pct: 100,
            rng: ChaCha8Rng::seed_from_u64(seed),
            noise: Normal::new(0.0, drive.adc_noise.max(1e-12)).expect("positive sigma"),
            mismatch: None,
            kienzle: None,
        };
        p.state.p_g = p.state.t_e * p.state.omega_s;
        p.state.p_o = p.state.t_e * speed;
        p
    }

    /// Sets the speed reference, rad/s.
    pub fn set_speed(&mut self, speed: f64) {
        self.speed_ref = speed;
    }

    /// The true state.
    pub fn state(&self) -> PlantState {
        self.state
    }

    /// Advances one ADC sample period and returns the sampled codes.
    pub fn sample(&mut self) -> AdcCodes {
        let d = self.drive;
        let pr = self.process;
        // exact discretization of the dynamometer's first-order lag over one substep
        let dyn_alpha = 1.0 - (-2.0 * PI * DYNAMOMETER_BANDWIDTH_HZ * self.dt).exp();
        for j in 1..=SUBSTEPS {
            let speed_ref = self.speed_ref_prev
                + (self.speed_ref - self.speed_ref_prev) * f64::from(j) / f64::from(SUBSTEPS);
            let s = &mut self.state;
            s.t += self.dt;
            s.depth = if s.t >= self.depth.step_at {
                self.depth.after
            } else {
                self.depth.before
            };
            // process F10
            let ks = pr.ks * (1.0 + pr.ks_drift * s.t);
            let tau = (pr.tau_p * (1.0 + pr.tau_drift * s.t)).max(1e-3);
            let feed = pr.feed_mm_per_rev * f64::from(self.override_pct) / 100.0;
            let target = if !self.engaged {
                0.0
            } else if let Some(k) = &self.kienzle {
                k.steady_force(ks, s.depth, feed, s.t)
            } else {
                ks * s.depth * feed
            };
            s.force += (target - s.force) * self.dt / tau;
            if !self.engaged {
                s.force = s.force.max(0.0) * (1.0 - self.dt / 0.005);
            }
            let cutting = s.force * (1.0 + self.ripple);
            s.dynamometer += (cutting - s.dynamometer) * dyn_alpha;
            // drive
            let t_c = cutting * pr.radius;
            let t_load = match &self.mismatch {
                None => d.coulomb + d.friction_f0 * t_c + d.friction_g0 * t_c * t_c + t_c,
                Some(m) => d.coulomb + m.load_friction(&d, s.omega, t_c) + t_c,
            };
            self.integ += d.speed_ki * (speed_ref - s.omega) * self.dt;
            s.omega_s = speed_ref + self.integ;
            s.t_e = d.slip_stiffness * (s.omega_s - s.omega);
            s.omega += (s.t_e - d.viscous * s.omega - t_load) / d.inertia * self.dt;
            s.p_g = s.t_e * s.omega_s;
            s.p_o += (s.t_e * s.omega - s.p_o) * self.dt / d.power_lag;
            self.theta = (self.theta + d.pole_pairs * s.omega_s * self.dt) % (2.0 * PI);
        }
        self.speed_ref_prev = self.speed_ref;
        // slowly varying force ripple (first-order noise, ~20 ms)
        let n: f64 = self.rng.sample(StandardNormal);
        self.ripple += (self.process.ripple * n * 3.0 - self.ripple) * 0.05;
        let s = self.state;
        let (volts, amps) = match &self.mismatch {
            None => Self::nominal_waveforms(&d, &s, self.theta),
            Some(m) => {
                let i = m.line_current(&d, s.p_g, s.t_e);
                m.waveforms(self.theta, d.line_voltage, i, s.t_e)
            }
        };
        let [ks, kp, kf, kv, ka] = self.scales;
        let mut code = |x: f64, scale: f64, mid: f64| -> u16 {
            let c = (x / scale + mid + self.noise.sample(&mut self.rng)).round();
            c.clamp(0.0, f64::from(ADC_MAX)) as u16
        };
        let mid = f64::from(ADC_MID);
        AdcCodes {
            speed: code(s.omega, ks, 0.0),
            power: code(s.p_o, kp, 0.0),
            force: code(s.dynamometer, kf, mid),
            volts: volts.map(|x| code(x, kv, mid)),
            amps: amps.map(|x| code(x, ka, mid)),
        }
    }

    /// The estimator's own electrics: line voltage V, currents lagging π/6 with
    /// `(3/2)·V·I − 3·R_s·I² = P_g`.
    fn nominal_waveforms(d: &DriveParams, s: &PlantState, theta: f64) -> ([f64; 3], [f64; 2]) {
        let v = d.line_voltage;
        let a = 1.5 * v;
        let rs = d.stator_resistance;
        let disc = (a * a - 12.0 * rs * s.p_g).max(0.0);
        let i = if rs > 0.0 {
            (a - disc.sqrt()) / (6.0 * rs)
        } else {
            s.p_g / a
        };
        let phase = |k: f64| theta - 2.0 * PI * k / 3.0;
        let sq2 = std::f64::consts::SQRT_2;
        let volts = [0.0, 1.0, 2.0].map(|k| sq2 * v * phase(k).sin());
        let amps = [0.0, 1.0].map(|k| sq2 * i * (phase(k) - PI / 6.0).sin());
        (volts, amps)
    }
}
