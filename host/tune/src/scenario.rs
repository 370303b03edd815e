//! Tuning scenarios: one open-loop approach of the tool toward a turning workpiece
//! (docs/domain.md §2.6), as the front end's pin [`Stimulus`] **and** the ground truth the float
//! reference needs — the clean (spike-free) contact intervals in exact clock time and the
//! tool's radial position at every instant.
//!
//! Why not the closed-loop measurement cycle: a sweep clocks thousands of configurations
//! through the same scenarios, so a scenario is generated once and must not depend on the
//! configuration under test (the encoder's pulses per revolution is fixed per sweep; the
//! arm line rises with an index pulse and stays high; the tool feeds at f_r, no retract).
//!
//! The surface seen by the tool at angle φ in revolution `r` is
//! `R(φ, r) = R0 + Σ profile + Σ slow(r) + roughness(φ) + offset` (docs/domain.md §2.6, paper E's
//! Δ_1 and Δ_2): low form harmonics with seeded phases, spindle-axis harmonics with a
//! period longer than one revolution and a per-revolution amplitude jitter, a few high
//! harmonics for roughness (so contact comes in bursts), and a seeded random offset.
//! Contact exists when the tool's radius `x(t) ≤ R` (docs/domain.md §2.6). Noise spikes shorter
//! than `spike_max_cycles` toggle the contact pin (they are not in the clean contact).

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_plant::stimulus::Stimulus;

/// What a tuning scenario is made from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ApproachSettings {
    /// FPGA clock, Hz (divides 1e9).
    pub clock_hz: u32,
    /// Spindle speed, rpm.
    pub rpm: f64,
    /// FES pulses per revolution (the encoder; equal to the configuration's).
    pub pulses_per_rev: u16,
    /// Nominal workpiece radius R0, µm.
    pub radius_um: f64,
    /// Radial feed of the approach f_r, µm per revolution.
    pub feed_um_per_rev: f64,
    /// Linear scale resolution, µm per count.
    pub scale_resolution_um: f64,
    /// Revolutions simulated after the arm.
    pub revolutions: u32,
    /// Amplitudes of the form harmonics of orders 2, 3, 5, µm (phases seeded).
    pub profile_um: [f64; 3],
    /// Amplitude of the slow spindle-axis harmonic (period 2.7 rev), µm; jittered ±30 %
    /// per revolution (eq. S10, docs/domain.md: these do not cancel).
    pub slow_um: f64,
    /// Amplitude of each of the roughness harmonics (orders 37, 61, 113), µm.
    pub roughness_um: f64,
    /// Standard deviation of the per-scenario random radius offset, µm.
    pub random_um: f64,
    /// Noise spikes on the contact line, per second (Poisson).
    pub spike_rate_hz: f64,
    /// Longest noise spike, clocks (at least 1).
    pub spike_max_cycles: u32,
}

impl Default for ApproachSettings {
    /// The papers' set-up (docs/domain.md §1): 50 MHz, 800 rpm, 1024 ppr, D = 40 mm,
    /// f_r = 1 µm/rev, 0.1 µm scale; 12 revolutions of approach; spikes of at most 3 clocks at 2 kHz.
    fn default() -> Self {
        ApproachSettings {
            clock_hz: 50_000_000,
            rpm: 800.0,
            pulses_per_rev: 1024,
            radius_um: 20_000.0,
            feed_um_per_rev: 1.0,
            scale_resolution_um: 0.1,
            revolutions: 12,
            profile_um: [2.0, 1.0, 0.4],
            slow_um: 0.8,
            roughness_um: 0.15,
            random_um: 0.15,
            spike_rate_hz: 2000.0,
            spike_max_cycles: 3,
        }
    }
}

/// One generated approach: the pins and the truth behind them.
#[derive(Clone, Debug, PartialEq)]
pub struct Approach {
    /// The six input pins, from power-on.
    pub stimulus: Stimulus,
    /// Clock at which the arm line rises (with an index pulse).
    pub arm_cycle: u64,
    /// Index rising clocks, from the arm's on (`index_cycles[0] == arm_cycle`).
    pub index_cycles: Vec<u64>,
    /// Clean contact intervals `[start, end)` in exact (fractional) clocks, sorted.
    pub contact: Vec<(f64, f64)>,
    /// Tool radius at the arm, µm (the start point; the scale count 0 is centred on it).
    pub start_um: f64,
    /// Tool feed, µm per clock (the radius decreases at this rate after the arm).
    pub feed_um_per_cycle: f64,
    /// Clocks per revolution.
    pub cycles_per_rev: f64,
    /// Scale resolution, µm per count.
    pub scale_resolution_um: f64,
    /// FES pulses per revolution.
    pub pulses_per_rev: u32,
}

impl Approach {
    /// Tool radius at (fractional) clock `t`, µm.
    pub fn tool_um(&self, t: f64) -> f64 {
        self.start_um - self.feed_um_per_cycle * (t - self.arm_cycle as f64).max(0.0)
    }
    /// Revolutions since the arm at (fractional) clock `t`.
    pub fn revs_since_arm(&self, t: f64) -> f64 {
        (t - self.arm_cycle as f64) / self.cycles_per_rev
    }
    /// The scale count the slide's position at clock `t` reads (0 at the start point).
    pub fn count_at(&self, t: f64) -> i64 {
        ((self.tool_um(t) - self.start_um) / self.scale_resolution_um + 0.5).floor() as i64
    }
}

/// Quadrature lines for scale count `c` (x4, A leads B for positive motion, 00 at 0).
fn quadrature(c: i64) -> u8 {
    match c.rem_euclid(4) {
        0 => 0,
        1 => pin::SCALE_A,
        2 => pin::SCALE_A | pin::SCALE_B,
        _ => pin::SCALE_B,
    }
}

/// Generates the approach of scenario number `seed` (every random stream is seeded by it).
pub fn approach(s: &ApproachSettings, seed: u64) -> Approach {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let clock = f64::from(s.clock_hz);
    let cpr = clock * 60.0 / s.rpm;
    let ppr = u64::from(s.pulses_per_rev);
    let cpp = cpr / ppr as f64;
    let profile: Vec<(f64, f64, f64)> = [2.0, 3.0, 5.0]
        .iter()
        .zip(s.profile_um)
        .map(|(&k, a)| (k, a, rng.random_range(0.0..TAU)))
        .collect();
    let rough: Vec<(f64, f64, f64)> = [37.0, 61.0, 113.0]
        .iter()
        .map(|&k| (k, s.roughness_um, rng.random_range(0.0..TAU)))
        .collect();
    let slow_phase = rng.random_range(0.0..TAU);
    let offset = s.random_um * rng.sample::<f64, _>(rand_distr::StandardNormal);
    let revs = u64::from(s.revolutions);
    let jitter: Vec<f64> = (0..revs + 2)
        .map(|_| 1.0 + 0.3 * rng.random_range(-1.0..1.0))
        .collect();
    let peak: f64 = s.profile_um.iter().sum::<f64>() + s.slow_um * 1.3 + 3.0 * s.roughness_um;
    // Revolution 0 starts at clock 0; the arm rises with the index of revolution 1.
    let rev_start = |r: u64| (r as f64 * cpr).floor() as u64;
    let arm = rev_start(1);
    let start_um = s.radius_um + offset + peak + s.feed_um_per_rev;
    let feed = s.feed_um_per_rev / cpr;
    let end = rev_start(revs + 1);
    let radius = |t: f64| {
        let turns = t / cpr;
        let phi = turns.fract() * TAU;
        let r = turns.floor() as usize;
        let mut x = s.radius_um + offset;
        for &(k, a, p) in profile.iter().chain(rough.iter()) {
            x += a * (k * phi + p).cos();
        }
        x + s.slow_um * jitter[r.min(jitter.len() - 1)] * (TAU * turns / 2.7 + slow_phase).cos()
    };
    let tool = |t: f64| start_um - feed * (t - arm as f64).max(0.0);
    // Clean contact: sign changes of the gap on a grid of 1/16384 rev, refined by bisection
    // to a hundredth of a clock.
    let mut contact = Vec::new();
    let step = cpr / 16384.0;
    let gap = |t: f64| radius(t) - tool(t);
    let mut t = arm as f64;
    let mut g = gap(t);
    let mut open: Option<f64> = (g >= 0.0).then_some(t);
    while t < end as f64 {
        let t2 = (t + step).min(end as f64);
        let g2 = gap(t2);
        if (g >= 0.0) != (g2 >= 0.0) {
            let (mut a, mut b) = (t, t2);
            while b - a > 0.01 {
                let m = 0.5 * (a + b);
                if (gap(m) >= 0.0) == (g >= 0.0) {
                    a = m;
                } else {
                    b = m;
                }
            }
            match open.take() {
                Some(s0) => contact.push((s0, b)),
                None => open = Some(b),
            }
        }
        t = t2;
        g = g2;
    }
    if let Some(s0) = open {
        contact.push((s0, end as f64));
    }
    // Pin toggles: (clock, bits).
    let mut toggles: Vec<(u64, u8)> = Vec::new();
    toggles.push((arm, pin::ARM));
    let mut index_cycles = Vec::new();
    for i in 0..(revs + 1) * ppr {
        let rise = (i as f64 * cpp).floor() as u64;
        let fall = ((i as f64 + 0.5) * cpp).floor() as u64;
        toggles.push((rise, pin::FES));
        toggles.push((fall, pin::FES));
        if i % ppr == 0 {
            let next = ((i + 1) as f64 * cpp).floor() as u64;
            toggles.push((rise, pin::INDEX));
            toggles.push((next, pin::INDEX));
            if rise >= arm {
                index_cycles.push(rise);
            }
        }
    }
    for &(a, b) in &contact {
        toggles.push((a.ceil() as u64, pin::CONTACT));
        toggles.push((b.ceil() as u64, pin::CONTACT));
    }
    if s.spike_rate_hz > 0.0 {
        let mean_gap = clock / s.spike_rate_hz;
        let mut t = 0.0;
        loop {
            t += -mean_gap * (1.0 - rng.random::<f64>()).ln();
            if t >= end as f64 {
                break;
            }
            let d = rng.random_range(1..=s.spike_max_cycles.max(1));
            toggles.push((t as u64, pin::CONTACT));
            toggles.push((t as u64 + u64::from(d), pin::CONTACT));
        }
    }
    // Scale: count n (negative, toward the part) is reached when the tool has moved
    // (n - 1/2) counts from the start point.
    let res = s.scale_resolution_um;
    let mut n = 1u64;
    loop {
        let t = arm as f64 + (n as f64 - 0.5) * res / feed;
        if t >= end as f64 {
            break;
        }
        let before = quadrature(-(n as i64 - 1));
        let after = quadrature(-(n as i64));
        toggles.push((t.ceil() as u64, before ^ after));
        n += 1;
    }
    toggles.sort_by_key(|&(k, _)| k);
    let mut stimulus = Stimulus::new(s.clock_hz);
    let mut level = 0u8;
    let mut k = 0u64;
    for (at, bits) in toggles {
        let at = at.min(end);
        stimulus.push(Pins(level), at - k);
        k = at;
        level ^= bits;
    }
    stimulus.push(Pins(level), end - k);
    Approach {
        stimulus,
        arm_cycle: arm,
        index_cycles,
        contact,
        start_um,
        feed_um_per_cycle: feed,
        cycles_per_rev: cpr,
        scale_resolution_um: res,
        pulses_per_rev: ppr as u32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> ApproachSettings {
        ApproachSettings {
            rpm: 6000.0,
            pulses_per_rev: 64,
            revolutions: 14,
            ..Default::default()
        }
    }

    #[test]
    fn contact_density_grows_and_the_scale_follows_the_feed() {
        let a = approach(&small(), 3);
        assert!(!a.contact.is_empty());
        let end = a.stimulus.total_cycles();
        assert_eq!(a.index_cycles.len(), 14);
        let frac = |r: usize| {
            let e = a.index_cycles.get(r + 1).copied().unwrap_or(end);
            let (s, e) = (a.index_cycles[r] as f64, e as f64);
            a.contact
                .iter()
                .map(|&(x, y)| (y.min(e) - x.max(s)).max(0.0))
                .sum::<f64>()
                / (e - s)
        };
        assert_eq!(frac(0), 0.0, "no contact in the first revolution");
        assert!(
            frac(13) > 0.99,
            "permanent contact at the end: {}",
            frac(13)
        );
        // Ten revolutions at 1 µm/rev and 0.1 µm per count: 100 counts.
        assert_eq!(a.count_at(a.index_cycles[10] as f64), -100);
        assert_eq!(end, (15.0 * a.cycles_per_rev) as u64);
    }

    #[test]
    fn same_seed_same_stimulus() {
        assert_eq!(approach(&small(), 5), approach(&small(), 5));
        assert_ne!(
            approach(&small(), 5).stimulus,
            approach(&small(), 6).stimulus
        );
    }
}
