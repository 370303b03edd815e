//! The spindle: its angle as a function of the FPGA clock, and its axis errors whose period
//! is longer than one revolution (docs/domain.md §2.6, eq. E: Δ_1; belt-drive loading).
//!
//! The spindle turns at a constant speed from clock 0, where the index pulse and FES pulse
//! 0 begin. Times are in FPGA clocks (real numbers inside, whole clocks at the pins).

use super::surface::{mix, unit};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// A spindle axis error with a period longer than one revolution, µm (radius): the error
/// a part of the spindle unit that turns at its own speed makes (a rolling bearing's cage
/// and its rolling elements, a belt whose pulleys' ratio is not whole):
/// `a_r · cos(2π·τ/(T_n·T_rev) + ψ_n)`, τ the time since approach `n` began.
///
/// - The amplitude `a_r` is `amplitude_um · (1 + amplitude_jitter · u_r)`, `u_r` uniform in
///   `[-1, 1)` drawn per revolution `r` and interpolated linearly across it.
/// - The period `T_n` is `period_revs · (1 + period_scatter · u_n)`, drawn per approach:
///   the cause's speed relative to the spindle is not a fixed ratio (a cage slips, more at
///   light load; a belt creeps 1–2 % with the torque it carries).
/// - The phase `ψ_n` is `phase_rad` plus a phase drawn uniform in `[0, 2π)` per approach:
///   nothing synchronises the cause to the index or to the cycle, and between two
///   measurements it has turned, slipping, for many periods.
///
/// Because the period is not a whole number of revolutions, the phase relative to the
/// spindle angle changes every revolution too; these errors do not cancel and make the
/// 50 % method's scatter (eq. S10, docs/domain.md). Everything is drawn from the
/// scenario's seed: the same seed gives the same errors.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlowHarmonic {
    /// Mean amplitude, µm, `0..=1000`.
    pub amplitude_um: f64,
    /// Mean period in revolutions, `> 1` (`1.0001..=1000`).
    pub period_revs: f64,
    /// Added to the phase drawn for every approach, rad (another realisation of the same
    /// errors without another seed).
    #[serde(default)]
    pub phase_rad: f64,
    /// Relative amplitude change from revolution to revolution, `0..=1`.
    #[serde(default)]
    pub amplitude_jitter: f64,
    /// Relative change of the period from approach to approach (half-range of a uniform
    /// draw), `0..=0.2`: the cause's slip or creep.
    #[serde(default)]
    pub period_scatter: f64,
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

/// The spindle's errors with a period longer than one revolution, as [`SlowHarmonic`]
/// describes them: the current approach's phases and periods.
#[derive(Clone, Debug)]
pub struct SlowErrors {
    harmonics: Vec<SlowHarmonic>,
    seed: u64,
    cycles_per_rev: f64,
    /// Clock at which the current approach began.
    epoch: f64,
    /// Per harmonic: its phase at `epoch`, rad, and its period, clocks.
    drawn: Vec<(f64, f64)>,
}

/// Stream tags of the slow errors' draws (see [`mix`]).
const JITTER_STREAM: u64 = 0x51_0000;
const PHASE_STREAM: u64 = 0x52_0000;
const PERIOD_STREAM: u64 = 0x53_0000;

impl SlowErrors {
    /// The errors `harmonics` for a spindle with `cycles_per_rev`, drawn from `seed`;
    /// approach 0 begins at clock 0.
    pub fn new(harmonics: &[SlowHarmonic], seed: u64, cycles_per_rev: f64) -> SlowErrors {
        let mut errors = SlowErrors {
            harmonics: harmonics
                .iter()
                .copied()
                .filter(|h| h.amplitude_um != 0.0)
                .collect(),
            seed,
            cycles_per_rev,
            epoch: 0.0,
            drawn: Vec::new(),
        };
        errors.start_approach(0, 0.0);
        errors
    }

    /// Draws the phases and periods of approach number `approach`, which begins at (real)
    /// clock `epoch`.
    pub fn start_approach(&mut self, approach: u64, epoch: f64) {
        self.epoch = epoch;
        self.drawn = self
            .harmonics
            .iter()
            .enumerate()
            .map(|(i, h)| {
                let i = i as u64;
                let u_phase = unit(mix(self.seed, PHASE_STREAM + i, approach));
                let u_period = unit(mix(self.seed, PERIOD_STREAM + i, approach));
                let period = h.period_revs * (1.0 + h.period_scatter * u_period);
                (
                    h.phase_rad + PI * (u_phase + 1.0),
                    period * self.cycles_per_rev,
                )
            })
            .collect();
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
        let since = t - self.epoch;
        let mut sum = 0.0;
        for (i, (h, &(phase, period))) in self.harmonics.iter().zip(&self.drawn).enumerate() {
            let u0 = unit(mix(self.seed, JITTER_STREAM + i as u64, r));
            let u1 = unit(mix(self.seed, JITTER_STREAM + i as u64, r + 1));
            let u = u0 + (u1 - u0) * frac;
            let amplitude = h.amplitude_um * (1.0 + h.amplitude_jitter * u);
            sum += amplitude * (TAU * since / period + phase).cos();
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
            period_scatter: 0.02,
        }];
        let e = SlowErrors::new(&h, 1, 1000.0);
        let at_index: Vec<f64> = (0..10).map(|r| e.at(r as f64 * 1000.0)).collect();
        assert!(at_index.iter().all(|v| v.abs() <= e.bound_um()));
        assert!(at_index.windows(2).any(|w| (w[0] - w[1]).abs() > 0.1));
    }

    #[test]
    fn every_approach_draws_its_own_phase_and_period_reproducibly() {
        let h = [SlowHarmonic {
            amplitude_um: 1.0,
            period_revs: 2.7,
            phase_rad: 0.0,
            amplitude_jitter: 0.0,
            period_scatter: 0.03,
        }];
        let start = |seed: u64, approach: u64| {
            let mut e = SlowErrors::new(&h, seed, 1000.0);
            e.start_approach(approach, 5000.0);
            e
        };
        // Same seed and approach: the same error; at the approach's start it is cos ψ_n.
        assert_eq!(start(3, 7).at(5123.0), start(3, 7).at(5123.0));
        let at_start: Vec<f64> = (0..400).map(|n| start(3, n).at(5000.0)).collect();
        // cos of a uniform phase: mean 0, mean square 1/2 (400 draws: ±0.1 at 3σ).
        let mean = at_start.iter().sum::<f64>() / 400.0;
        let mean_sq = at_start.iter().map(|v| v * v).sum::<f64>() / 400.0;
        assert!(mean.abs() < 0.11, "{mean}");
        assert!((mean_sq - 0.5).abs() < 0.08, "{mean_sq}");
        // The periods differ between approaches within ±3 %: the zero crossings move.
        let crossing = |e: &SlowErrors| {
            (5000..20_000)
                .find(|&k| e.at(k as f64) <= 0.0 && e.at(k as f64 + 1.0) > 0.0)
                .unwrap()
        };
        let periods: Vec<f64> = (0..20)
            .map(|n| {
                let e = start(3, n);
                let first = crossing(&e);
                let next = (first + 1000..first + 5000)
                    .find(|&k| e.at(k as f64) <= 0.0 && e.at(k as f64 + 1.0) > 0.0)
                    .unwrap();
                (next - first) as f64 / 1000.0
            })
            .collect();
        assert!(periods
            .iter()
            .all(|&p| (p - 2.7).abs() <= 2.7 * 0.03 + 0.002));
        let spread = periods.iter().copied().fold(f64::MIN, f64::max)
            - periods.iter().copied().fold(f64::MAX, f64::min);
        assert!(spread > 0.05, "{periods:?}");
    }
}
