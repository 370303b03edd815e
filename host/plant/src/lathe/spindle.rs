//! The spindle: its angle as a function of the FPGA clock, and its axis errors whose period
//! is longer than one revolution (docs/domain.md §2.6, eq. E: Δ_1; belt-drive loading).
//!
//! The spindle turns at a constant speed from clock 0, where the index pulse and FES pulse
//! 0 begin. Times are in FPGA clocks (real numbers inside, whole clocks at the pins).

use super::surface::{mix, unit};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// A spindle axis error with a period longer than one revolution, µm (radius):
/// `a_r · cos(2π·t/(period_revs·T_rev) + phase_rad)`, where the amplitude `a_r` is
/// `amplitude_um · (1 + amplitude_jitter · u_r)` with `u_r` uniform in `[-1, 1)` drawn
/// per revolution `r` and interpolated linearly across the revolution. Because the period
/// is not a whole number of revolutions, its phase relative to the spindle angle changes
/// every revolution too; these errors do not cancel and make the 50 % method's scatter
/// (eq. S10, docs/domain.md).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlowHarmonic {
    /// Mean amplitude, µm, `0..=1000`.
    pub amplitude_um: f64,
    /// Period in revolutions, `> 1` (`1.0001..=1000`).
    pub period_revs: f64,
    /// Phase at clock 0, rad.
    #[serde(default)]
    pub phase_rad: f64,
    /// Relative amplitude change from revolution to revolution, `0..=1`.
    #[serde(default)]
    pub amplitude_jitter: f64,
}

/// Spindle timing at a given clock and speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spindle {
    /// FPGA clocks per revolution.
    pub cycles_per_rev: f64,
    /// FES pulses per revolution.
    pub pulses_per_rev: u32,
}

impl Spindle {
    /// A spindle at `rpm` with a `pulses_per_rev` encoder, clocked at `clock_hz`.
    pub fn new(clock_hz: u32, rpm: f64, pulses_per_rev: u32) -> Spindle {
        Spindle {
            cycles_per_rev: f64::from(clock_hz) * 60.0 / rpm,
            pulses_per_rev,
        }
    }

    /// FPGA clocks per FES period.
    pub fn fes_period(&self) -> f64 {
        self.cycles_per_rev / f64::from(self.pulses_per_rev)
    }

    /// Revolutions turned at (real) clock `t`.
    #[inline]
    pub fn turns(&self, t: f64) -> f64 {
        t / self.cycles_per_rev
    }

    /// Clock at which FES pulse `j` (counted from clock 0) rises: `round(j · T_fes)`.
    pub fn fes_rise(&self, j: u64) -> u64 {
        (j as f64 * self.fes_period()).round() as u64
    }

    /// Clock at which FES pulse `j` falls: half a period after it rose (50 % duty).
    pub fn fes_fall(&self, j: u64) -> u64 {
        ((j as f64 + 0.5) * self.fes_period()).round() as u64
    }

    /// Clock at which revolution `r` begins: the index pulse rises with FES pulse
    /// `r · pulses_per_rev` and falls with the next FES pulse's rise (one FES period wide).
    pub fn index_rise(&self, r: u64) -> u64 {
        self.fes_rise(r * u64::from(self.pulses_per_rev))
    }

    /// The first revolution whose index rises at or after clock `k`.
    pub fn next_revolution(&self, k: u64) -> u64 {
        let mut r = (k as f64 / self.cycles_per_rev).floor().max(0.0) as u64;
        while self.index_rise(r) < k {
            r += 1;
        }
        r
    }

    /// Levels of FES and index at clock `k`.
    pub fn levels_at(&self, k: u64) -> (bool, bool) {
        let mut j = (k as f64 / self.fes_period()).floor() as u64;
        while j > 0 && self.fes_rise(j) > k {
            j -= 1;
        }
        while self.fes_rise(j + 1) <= k {
            j += 1;
        }
        let fes = k < self.fes_fall(j);
        let index = j.is_multiple_of(u64::from(self.pulses_per_rev));
        (fes, index)
    }

    /// Appends the FES and index level changes in clocks `(k_a, k_b)` (exclusive of
    /// `k_a`, whose levels are [`Self::levels_at`]) as `(clock, pin bit, level)`.
    pub fn transitions(&self, k_a: u64, k_b: u64, out: &mut Vec<(u64, u8, bool)>) {
        use tooltouch_model::measure::frontend::pin;
        let ppr = u64::from(self.pulses_per_rev);
        let mut j = ((k_a as f64 / self.fes_period()).floor() as u64).saturating_sub(1);
        loop {
            let rise = self.fes_rise(j);
            if rise >= k_b {
                break;
            }
            let fall = self.fes_fall(j);
            if rise > k_a {
                out.push((rise, pin::FES, true));
                if j.is_multiple_of(ppr) {
                    out.push((rise, pin::INDEX, true));
                }
                if j % ppr == 1 {
                    out.push((rise, pin::INDEX, false));
                }
            }
            if fall > k_a && fall < k_b {
                out.push((fall, pin::FES, false));
            }
            j += 1;
        }
    }
}

/// The spindle's errors with a period longer than one revolution.
#[derive(Clone, Debug)]
pub struct SlowErrors {
    harmonics: Vec<SlowHarmonic>,
    seed: u64,
    cycles_per_rev: f64,
}

impl SlowErrors {
    /// The errors `harmonics` for a spindle with `cycles_per_rev`, jitter drawn from `seed`.
    pub fn new(harmonics: &[SlowHarmonic], seed: u64, cycles_per_rev: f64) -> SlowErrors {
        SlowErrors {
            harmonics: harmonics
                .iter()
                .copied()
                .filter(|h| h.amplitude_um != 0.0)
                .collect(),
            seed,
            cycles_per_rev,
        }
    }

    /// Radial axis error seen by the tool at (real) clock `t`, µm.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        if self.harmonics.is_empty() {
            return 0.0;
        }
        let turns = t / self.cycles_per_rev;
        let r = turns.floor().max(0.0);
        let frac = turns - r;
        let r = r as u64;
        let mut sum = 0.0;
        for (i, h) in self.harmonics.iter().enumerate() {
            let u0 = unit(mix(self.seed, 0x51_0000 + i as u64, r));
            let u1 = unit(mix(self.seed, 0x51_0000 + i as u64, r + 1));
            let u = u0 + (u1 - u0) * frac;
            let amplitude = h.amplitude_um * (1.0 + h.amplitude_jitter * u);
            sum += amplitude * (TAU * turns / h.period_revs + h.phase_rad).cos();
        }
        sum
    }

    /// Largest possible error, µm (sum of the largest amplitudes).
    pub fn bound_um(&self) -> f64 {
        self.harmonics
            .iter()
            .map(|h| h.amplitude_um.abs() * (1.0 + h.amplitude_jitter.abs()))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::measure::frontend::pin;

    #[test]
    fn fes_and_index_transitions_agree_with_levels() {
        let s = Spindle::new(50_000_000, 800.0, 1024);
        let (k_a, k_b) = (3_700_000u64, 3_800_000u64);
        let mut t = Vec::new();
        s.transitions(k_a, k_b, &mut t);
        t.sort_by_key(|x| x.0);
        let (mut fes, mut index) = s.levels_at(k_a);
        let mut it = t.iter().peekable();
        for k in k_a..k_b {
            while let Some(&&(c, bit, level)) = it.peek() {
                if c != k {
                    break;
                }
                if bit == pin::FES {
                    fes = level;
                } else {
                    index = level;
                }
                it.next();
            }
            assert_eq!((fes, index), s.levels_at(k), "clock {k}");
        }
        // One index rise in this window (revolution 1 starts at 3_750_000).
        assert_eq!(s.index_rise(1), 3_750_000);
        assert_eq!(
            t.iter()
                .filter(|x| x.1 == pin::INDEX && x.2)
                .map(|x| x.0)
                .collect::<Vec<_>>(),
            vec![3_750_000]
        );
    }

    #[test]
    fn slow_errors_are_bounded_and_vary_per_revolution() {
        let h = [SlowHarmonic {
            amplitude_um: 1.0,
            period_revs: 2.7,
            phase_rad: 0.0,
            amplitude_jitter: 0.3,
        }];
        let e = SlowErrors::new(&h, 1, 1000.0);
        let at_index: Vec<f64> = (0..10).map(|r| e.at(r as f64 * 1000.0)).collect();
        assert!(at_index.iter().all(|v| v.abs() <= e.bound_um()));
        assert!(at_index.windows(2).any(|w| (w[0] - w[1]).abs() > 0.1));
    }
}
