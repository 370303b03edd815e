//! The workpiece surface as the tool sees it during measurement (docs/domain.md §2.6): nominal
//! radius, the polyharmonic form error left by machining, a random roughness, and the spindle
//! errors that repeat every revolution.
//!
//! The surface is tabulated at [`SAMPLES_PER_REV`] angles and read with linear
//! interpolation, so the contact model and the "true" diameters (mean and largest) are
//! computed from exactly the same piecewise-linear shape.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Angular samples per revolution of the tabulated surface (≈ 229 clocks apart at 800 rpm
/// and 50 MHz; contact edges between samples are found by linear interpolation).
pub const SAMPLES_PER_REV: usize = 16384;

/// Roughness cells per revolution: the random error is drawn once per cell and linearly
/// interpolated between cells (hardness scatter and cutting-force variation vary along the
/// circumference on this scale, not from sample to sample).
pub const ROUGHNESS_CELLS_PER_REV: usize = 2048;

/// One harmonic of a radius error: `amplitude_um · cos(order·φ + phase_rad)`, µm.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Harmonic {
    /// Undulations per revolution, `1..=512`.
    pub order: u32,
    /// Amplitude, µm (radius), `0..=1000`.
    pub amplitude_um: f64,
    /// Phase at the index pulse, rad.
    #[serde(default)]
    pub phase_rad: f64,
}

impl Harmonic {
    /// The harmonic's radius error at spindle angle `phi` (rad), µm.
    pub fn at(&self, phi: f64) -> f64 {
        self.amplitude_um * (f64::from(self.order) * phi + self.phase_rad).cos()
    }
}

/// The tabulated surface of one axial (Z) position.
#[derive(Clone, Debug)]
pub struct Surface {
    /// Radius seen by the tool at angle `i / SAMPLES_PER_REV` of a turn, µm, without the
    /// spindle errors of period longer than one revolution (those depend on time).
    seen_um: Vec<f64>,
    /// Radius of the workpiece in its own (machining) frame, µm: what an ideal gauge reads.
    true_um: Vec<f64>,
}

impl Surface {
    /// The surface at axial position number `z_index` of a workpiece of nominal radius
    /// `radius_um`: `profile` (docs/domain.md §2.6 polyharmonic form error, the same at every Z),
    /// roughness of standard deviation `random_um` (drawn per Z from `seed`), and the
    /// per-revolution spindle errors `repeating`, of which the fraction `mismatch`
    /// (`0..=1`) does not cancel between machining and measuring.
    pub fn new(
        radius_um: f64,
        profile: &[Harmonic],
        repeating: &[Harmonic],
        mismatch: f64,
        random_um: f64,
        seed: u64,
        z_index: u64,
    ) -> Surface {
        let mut rng = ChaCha8Rng::seed_from_u64(mix(seed, 0x5a5a_0001, z_index));
        let cells: Vec<f64> = match Normal::new(0.0, random_um.max(0.0)) {
            Ok(normal) if random_um > 0.0 => (0..ROUGHNESS_CELLS_PER_REV)
                .map(|_| normal.sample(&mut rng))
                .collect(),
            _ => vec![0.0; ROUGHNESS_CELLS_PER_REV],
        };
        let per_cell = SAMPLES_PER_REV / ROUGHNESS_CELLS_PER_REV;
        let mut seen_um = Vec::with_capacity(SAMPLES_PER_REV);
        let mut true_um = Vec::with_capacity(SAMPLES_PER_REV);
        for i in 0..SAMPLES_PER_REV {
            let phi = TAU * i as f64 / SAMPLES_PER_REV as f64;
            let cell = i / per_cell;
            let frac = (i % per_cell) as f64 / per_cell as f64;
            let rough = cells[cell] * (1.0 - frac) + cells[(cell + 1) % cells.len()] * frac;
            let form: f64 = profile.iter().map(|h| h.at(phi)).sum();
            let rep: f64 = repeating.iter().map(|h| h.at(phi)).sum();
            // Machining cut the surface along the spindle's repeating error path: relative
            // to the tool the cut surface is R0 + form + rough - rep; measuring on the same
            // path adds rep back. Only the mismatch fraction survives (docs/domain.md §2.6).
            let machined = radius_um + form + rough - rep;
            let seen = machined + rep * (1.0 - mismatch);
            true_um.push(radius_um + form + rough);
            seen_um.push(seen);
        }
        Surface { seen_um, true_um }
    }

    /// The surface as the tool sees it when the spindle's measuring path differs from its
    /// machining path by `d` (docs/domain.md §2.6, [`super::SpindlePath`]): the seen radius
    /// only changes, the true one is the part's. No change when the paths coincide.
    pub fn with_path_difference(mut self, d: &super::PathDifference) -> Surface {
        if !d.is_zero() {
            let n = self.seen_um.len();
            for (i, r) in self.seen_um.iter_mut().enumerate() {
                *r += d.at(TAU * i as f64 / n as f64);
            }
        }
        self
    }

    /// Radius seen by the tool at `turn` (fraction of a revolution from the index, any
    /// real; only the fractional part matters), µm, linearly interpolated.
    #[inline]
    pub fn seen_at(&self, turn: f64) -> f64 {
        let x = turn.rem_euclid(1.0) * SAMPLES_PER_REV as f64;
        let i = (x as usize).min(SAMPLES_PER_REV - 1);
        let frac = x - i as f64;
        let a = self.seen_um[i];
        let b = self.seen_um[(i + 1) % SAMPLES_PER_REV];
        a + (b - a) * frac
    }

    /// Radius seen by the tool at sample `i` (angle `i / SAMPLES_PER_REV` of a turn), µm.
    #[inline]
    pub fn seen_sample(&self, i: usize) -> f64 {
        self.seen_um[i % SAMPLES_PER_REV]
    }

    /// True mean radius of the workpiece at this Z, µm.
    pub fn mean_radius_um(&self) -> f64 {
        self.true_um.iter().sum::<f64>() / self.true_um.len() as f64
    }

    /// True largest radius of the workpiece at this Z, µm.
    pub fn largest_radius_um(&self) -> f64 {
        self.true_um.iter().copied().fold(f64::MIN, f64::max)
    }

    /// Largest radius the tool sees without the slow spindle errors, µm.
    pub fn largest_seen_um(&self) -> f64 {
        self.seen_um.iter().copied().fold(f64::MIN, f64::max)
    }

    /// Smallest radius the tool sees without the slow spindle errors, µm.
    pub fn smallest_seen_um(&self) -> f64 {
        self.seen_um.iter().copied().fold(f64::MAX, f64::min)
    }
}

/// Mixes a seed with a stream tag and an index into a new 64-bit seed (SplitMix64 finaliser),
/// so every random stream (roughness per Z, slow-error jitter per revolution, noise spikes
/// per revolution) is reproducible on its own, whatever order it is asked for in.
pub fn mix(seed: u64, tag: u64, index: u64) -> u64 {
    let mut z = seed
        .wrapping_add(tag.wrapping_mul(0x9e37_79b9_7f4a_7c15))
        .wrapping_add(index.wrapping_mul(0xd1b5_4a32_d192_ed03));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A uniform number in `[-1, 1)` from a 64-bit hash.
pub fn unit(hash: u64) -> f64 {
    (hash >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeating_errors_cancel_without_mismatch() {
        let profile = [Harmonic {
            order: 2,
            amplitude_um: 2.0,
            phase_rad: 0.0,
        }];
        let rep = [Harmonic {
            order: 1,
            amplitude_um: 5.0,
            phase_rad: 0.3,
        }];
        let with = Surface::new(20_000.0, &profile, &rep, 0.0, 0.0, 1, 0);
        let without = Surface::new(20_000.0, &profile, &[], 0.0, 0.0, 1, 0);
        for i in 0..SAMPLES_PER_REV {
            assert!((with.seen_sample(i) - without.seen_sample(i)).abs() < 1e-9);
        }
        let half = Surface::new(20_000.0, &profile, &rep, 0.5, 0.0, 1, 0);
        assert!((half.largest_seen_um() - without.largest_seen_um()).abs() > 1.0);
        assert!((without.largest_radius_um() - 20_002.0).abs() < 1e-6);
        assert!((without.mean_radius_um() - 20_000.0).abs() < 1e-6);
    }

    #[test]
    fn roughness_is_reproducible_per_z_and_differs_between_z() {
        let a = Surface::new(100.0, &[], &[], 0.0, 0.5, 7, 3);
        let b = Surface::new(100.0, &[], &[], 0.0, 0.5, 7, 3);
        let c = Surface::new(100.0, &[], &[], 0.0, 0.5, 7, 4);
        assert_eq!(a.seen_sample(100), b.seen_sample(100));
        assert_ne!(a.seen_sample(100), c.seen_sample(100));
    }
}
