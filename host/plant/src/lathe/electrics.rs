//! The tool–workpiece contact circuit (docs/domain.md §2.6): the geometric contact turned into the
//! electric contact signal, with a bounce at first touch, a short non-conduction after it,
//! and noise spikes shorter than the front end's glitch filter.
//!
//! Signals here are sets of clocks at which the contact line is high, as sorted, disjoint,
//! half-open intervals `[start, end)`.

use super::surface::{mix, unit};
use serde::{Deserialize, Serialize};

/// Sorted, disjoint, half-open clock intervals `[start, end)` during which a line is high.
pub type Intervals = Vec<(u64, u64)>;

/// Electrical effects on the contact line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ContactElectrics {
    /// Conducting pulses of the bounce at the first touch of each approach, `0..=100`.
    pub bounce_pulses: u32,
    /// Length of each bounce pulse, µs, `0..=10000`.
    pub bounce_on_us: f64,
    /// Gap after each bounce pulse, µs, `0..=10000`.
    pub bounce_off_us: f64,
    /// No conduction after the bounce (oxide film, coolant), µs, `0..=100000`.
    pub non_conduction_us: f64,
    /// Mean rate of noise spikes on the contact line, per second, `0..=1e6`.
    pub spike_rate_hz: f64,
    /// Longest noise spike, clocks, `0..=255`; spikes are drawn `1..=min(this,
    /// glitch_cycles)` clocks long, so the glitch filter must reject all of them.
    pub spike_max_cycles: u32,
}

impl Default for ContactElectrics {
    /// Three 2 µs bounce pulses 3 µs apart, 40 µs of non-conduction, 400 spikes/s of up
    /// to 4 clocks.
    fn default() -> Self {
        ContactElectrics {
            bounce_pulses: 3,
            bounce_on_us: 2.0,
            bounce_off_us: 3.0,
            non_conduction_us: 40.0,
            spike_rate_hz: 400.0,
            spike_max_cycles: 4,
        }
    }
}

impl ContactElectrics {
    /// Replaces `signal` inside the first-touch window that starts at clock `touch` by the
    /// bounce pattern followed by non-conduction. `cycles_per_us` converts times.
    pub fn apply_first_touch(
        &self,
        signal: &Intervals,
        touch: u64,
        cycles_per_us: f64,
    ) -> Intervals {
        let on = (self.bounce_on_us * cycles_per_us).round() as u64;
        let off = (self.bounce_off_us * cycles_per_us).round() as u64;
        let quiet = (self.non_conduction_us * cycles_per_us).round() as u64;
        let mut pattern = Intervals::new();
        let mut k = touch;
        for _ in 0..self.bounce_pulses {
            if on > 0 {
                pattern.push((k, k + on));
            }
            k += on + off;
        }
        let window_end = k + quiet;
        if window_end == touch {
            return signal.clone();
        }
        let mut out = subtract(signal, &[(touch, window_end)]);
        out.extend(pattern);
        normalize(out)
    }

    /// The noise spikes in clocks `[k_a, k_b)`: a Poisson process of rate `spike_rate_hz`,
    /// widths `1..=max_width` clocks, reproducible from `seed` whatever the window (drawn
    /// per block of 2^20 clocks).
    pub fn spikes(
        &self,
        k_a: u64,
        k_b: u64,
        max_width: u32,
        clock_hz: u32,
        seed: u64,
    ) -> Intervals {
        let mut out = Intervals::new();
        if max_width == 0 || self.spike_rate_hz <= 0.0 || k_b <= k_a {
            return out;
        }
        const BLOCK: u64 = 1 << 20;
        let per_block = self.spike_rate_hz * BLOCK as f64 / f64::from(clock_hz);
        let mut raw: Vec<(u64, u64)> = Vec::new();
        // The block before the window too, so the spacing rule below sees the same
        // neighbours whatever the window.
        for block in (k_a / BLOCK).saturating_sub(1)..=(k_b - 1) / BLOCK {
            // Poisson count by inversion from one uniform; positions and widths uniform.
            let mut n = 0u64;
            let mut p = (-per_block).exp();
            let mut cumulative = p;
            let u = 0.5 * (unit(mix(seed, 0x5b_0000, block)) + 1.0);
            while u > cumulative && n < 100_000 {
                n += 1;
                p *= per_block / n as f64;
                cumulative += p;
            }
            for i in 0..n {
                let h = mix(seed, 0x5b_0001 + i, block);
                let start = block * BLOCK + (h >> 44) % BLOCK;
                let width = 1 + (h & 0xffff) % u64::from(max_width);
                raw.push((start, start + width));
            }
        }
        raw.sort_unstable();
        // Keep spikes at least `max_width + 2` clocks apart, so two of them never merge
        // into one pulse long enough to pass the glitch filter.
        let mut last_end: Option<u64> = None;
        for (s, e) in raw {
            if let Some(le) = last_end {
                if s < le + u64::from(max_width) + 2 {
                    continue;
                }
            }
            last_end = Some(e);
            let (s, e) = (s.max(k_a), e.min(k_b));
            if s < e {
                out.push((s, e));
            }
        }
        normalize(out)
    }
}

/// Sorts and merges overlapping or touching intervals; drops empty ones.
pub fn normalize(mut v: Intervals) -> Intervals {
    v.retain(|&(s, e)| s < e);
    v.sort_unstable();
    let mut out: Intervals = Vec::with_capacity(v.len());
    for (s, e) in v {
        match out.last_mut() {
            Some(last) if s <= last.1 => last.1 = last.1.max(e),
            _ => out.push((s, e)),
        }
    }
    out
}

/// `a` without the clocks of `b` (both normalized).
pub fn subtract(a: &[(u64, u64)], b: &[(u64, u64)]) -> Intervals {
    let mut out = Intervals::new();
    for &(s, e) in a {
        let mut pieces = vec![(s, e)];
        for &(bs, be) in b {
            let mut next = Vec::new();
            for (ps, pe) in pieces {
                if be <= ps || bs >= pe {
                    next.push((ps, pe));
                } else {
                    if ps < bs {
                        next.push((ps, bs));
                    }
                    if be < pe {
                        next.push((be, pe));
                    }
                }
            }
            pieces = next;
        }
        out.extend(pieces);
    }
    normalize(out)
}

/// Symmetric difference: the line `a` with every clock of `b` inverted (noise spikes).
pub fn xor(a: &[(u64, u64)], b: &[(u64, u64)]) -> Intervals {
    let mut points: Vec<u64> = Vec::with_capacity(2 * (a.len() + b.len()));
    for &(s, e) in a.iter().chain(b) {
        points.push(s);
        points.push(e);
    }
    points.sort_unstable();
    // Each boundary toggles the level; equal boundaries cancel in pairs.
    let mut out = Intervals::new();
    let mut i = 0;
    let mut high = false;
    let mut start = 0;
    while i < points.len() {
        let p = points[i];
        let mut n = 0;
        while i < points.len() && points[i] == p {
            n += 1;
            i += 1;
        }
        if n % 2 == 1 {
            if high {
                out.push((start, p));
            } else {
                start = p;
            }
            high = !high;
        }
    }
    normalize(out)
}

/// Clocks covered by `v` inside `[k_a, k_b)`.
pub fn covered(v: &[(u64, u64)], k_a: u64, k_b: u64) -> u64 {
    v.iter()
        .map(|&(s, e)| e.min(k_b).saturating_sub(s.max(k_a)))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interval_algebra() {
        let a = vec![(0, 10), (20, 30)];
        assert_eq!(subtract(&a, &[(5, 25)]), vec![(0, 5), (25, 30)]);
        assert_eq!(xor(&a, &[(8, 12)]), vec![(0, 8), (10, 12), (20, 30)]);
        assert_eq!(xor(&a, &[(10, 20)]), vec![(0, 30)]);
        assert_eq!(covered(&a, 5, 25), 10);
        assert_eq!(normalize(vec![(3, 4), (0, 3), (7, 7)]), vec![(0, 4)]);
    }

    #[test]
    fn first_touch_is_bounce_then_quiet() {
        let e = ContactElectrics {
            bounce_pulses: 2,
            bounce_on_us: 1.0,
            bounce_off_us: 1.0,
            non_conduction_us: 2.0,
            ..Default::default()
        };
        let out = e.apply_first_touch(&vec![(100, 1000)], 100, 50.0);
        assert_eq!(out, vec![(100, 150), (200, 250), (400, 1000)]);
    }

    #[test]
    fn spikes_are_reproducible_short_and_windowed() {
        let e = ContactElectrics {
            spike_rate_hz: 50_000.0,
            ..Default::default()
        };
        let all = e.spikes(0, 4_000_000, 3, 50_000_000, 9);
        assert!(all.len() > 1000);
        assert!(all.iter().all(|&(s, e)| e - s <= 3));
        assert!(all.windows(2).all(|w| w[1].0 >= w[0].1 + 5));
        let part = e.spikes(1_000_000, 2_000_000, 3, 50_000_000, 9);
        let expect: Intervals = all
            .iter()
            .filter_map(|&(s, e)| {
                let (s, e) = (s.max(1_000_000), e.min(2_000_000));
                (s < e).then_some((s, e))
            })
            .collect();
        assert_eq!(part, expect);
    }
}
