//! A face-milling power plant with per-tooth entry and exit transients and noise: the
//! signal shape the milling-wear paper measures (docs/wear.md, "The transient plant"); its use on the cutter is in `crate::milling`
//! (`WearScenario::transients`, `cutting_trace`).
//!
//! The cutting power of W6 (`MillingParams::cutting_power`) jumps when a tooth enters the
//! cut (its force at φ_v is not zero: `sin φ_v = cos ψ_1`, plus the flank-wear term) and
//! drops when it leaves at φ_r. The paper attributes the irregular swings of its measured
//! power near those instants to the power-measuring system overshooting these load steps
//! (a positive pulse at entry, a negative one at exit). Here the measuring system is an
//! underdamped second-order system with unity gain at rest — natural frequency `natural_hz`,
//! damping ratio `damping` — so each jump rings, and white noise of `noise_w` rms is added
//! to every sample. The mean is untouched (unity DC gain, zero-mean noise), which is why the
//! mean power is predicted better than the instantaneous one.
//!
//! Integration: semi-implicit Euler in [`SUBSTEPS`] steps per sample; the cutter angle
//! advances with each substep so the jumps fall between samples as they do on the machine.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::PI;

/// Integration substeps per sample.
pub const SUBSTEPS: u32 = 20;

/// The measuring system's dynamics and noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToothTransients {
    /// Natural frequency of the power-measuring system, Hz, `(0, 1000]`.
    pub natural_hz: f64,
    /// Damping ratio ζ, `(0, 2]` (below 1: overshoot, `exp(−πζ/√(1−ζ²))` of a step).
    pub damping: f64,
    /// White noise on every sample, W rms, `[0, 10^5]`.
    pub noise_w: f64,
}

impl Default for ToothTransients {
    /// 60 Hz, ζ = 0.3 (37 % overshoot, rings for ≈ 1/(ζ·ω_n) = 9 ms), 20 W rms: our
    /// choice, shaped like the paper's measured traces (it gives no meter data).
    fn default() -> Self {
        ToothTransients {
            natural_hz: 60.0,
            damping: 0.3,
            noise_w: 20.0,
        }
    }
}

impl ToothTransients {
    /// Checks the ranges; the error names the field.
    pub fn validate(&self) -> Result<(), String> {
        let ok = |v: f64, lo: f64, hi: f64, open: bool| {
            v.is_finite() && v <= hi && if open { v > lo } else { v >= lo }
        };
        if !ok(self.natural_hz, 0.0, 1000.0, true) {
            return Err(format!(
                "natural_hz = {}: allowed (0, 1000]",
                self.natural_hz
            ));
        }
        if !ok(self.damping, 0.0, 2.0, true) {
            return Err(format!("damping = {}: allowed (0, 2]", self.damping));
        }
        if !ok(self.noise_w, 0.0, 1e5, false) {
            return Err(format!("noise_w = {}: allowed [0, 100000]", self.noise_w));
        }
        Ok(())
    }

    /// The envelope time constant 1/(ζ·ω_n) of the ringing, s (for the settling hold).
    pub fn envelope_s(&self) -> f64 {
        1.0 / (self.damping.min(1.0) * 2.0 * PI * self.natural_hz)
    }
}

/// The measuring system's state: it sees the cutter turn and reports the power.
#[derive(Clone, Debug)]
pub struct TransientMeter {
    p: ToothTransients,
    /// Output power, W.
    x: f64,
    /// Its rate, W/s.
    v: f64,
    rng: ChaCha8Rng,
    noise: Normal<f64>,
}

impl TransientMeter {
    /// At rest at `power` W; noise from `seed`.
    pub fn new(p: &ToothTransients, power: f64, seed: u64) -> TransientMeter {
        TransientMeter {
            p: *p,
            x: power,
            v: 0.0,
            rng: ChaCha8Rng::seed_from_u64(seed),
            noise: Normal::new(0.0, p.noise_w.max(1e-12)).expect("positive sigma"),
        }
    }

    /// Advances one sample of `dt` s, the load being `load(substep_fraction)` W within it
    /// (fraction in (0, 1]); returns the sampled output with noise, W.
    pub fn sample(&mut self, dt: f64, mut load: impl FnMut(f64) -> f64) -> f64 {
        let w = 2.0 * PI * self.p.natural_hz;
        let h = dt / f64::from(SUBSTEPS);
        for i in 1..=SUBSTEPS {
            let u = load(f64::from(i) / f64::from(SUBSTEPS));
            self.v += h * (w * w * (u - self.x) - 2.0 * self.p.damping * w * self.v);
            self.x += h * self.v;
        }
        self.x + self.noise.sample(&mut self.rng)
    }
}
