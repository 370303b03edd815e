//! Machine faults on the pins (`[lathe.faults]`): what a lathe on a shop floor does to the
//! controller's inputs that a clean simulation never does.
//!
//! | fault | on the machine | on the pins |
//! | --- | --- | --- |
//! | chips | a chip caught between tool and part (or a burr on the surface) closes the circuit for a while | contact bursts of `chips.length_revs` revolutions at `chips.rate_hz` |
//! | coolant bridge | a film of coolant or a wet chip bridges tool and part before the tool touches | contact closed from the arm for `coolant_bridge.length_ms`, with probability `coolant_bridge.probability` per approach |
//! | EMI | a spindle drive or a contactor switching near the cables | spikes of `emi.length_cycles` clocks on a line: `emi.contact_hz`, `emi.fes_hz`, `emi.index_hz`; on the scale `emi.scale_hz` flips both lines at once (an illegal quadrature transition) |
//! | FES lost / doubled | a dirty encoder disc, a loose connector, ringing on a long cable | each FES pulse dropped with probability `fes_lost`, or followed by an extra pulse in its gap with probability `fes_doubled` |
//! | index lost / doubled | the same on the index track | each index pulse dropped with probability `index_lost`, or repeated half a revolution later with probability `index_doubled` |
//! | broken wire | a cut cable | from `broken_after_s` on, the line `broken_wire` (contact, fes, index, scale) held low |
//!
//! Every draw is a hash of the seed and the fault's absolute time or pulse number, never a
//! running random stream, so a span of clocks asked for twice (the driver cuts spans where
//! the CNC acts) gets the same faults. With the defaults (all zero) no pin changes, and the
//! lathe's pins are bit for bit those without this module.

use super::electrics::{self, ContactElectrics, Intervals};
use super::surface::{mix, unit};
use super::{check, ScenarioError, Spindle};
use crate::stimulus::{Segment, Stimulus};
use serde::{Deserialize, Serialize};
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::Pins;

/// Contact bursts of chips.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Chips {
    /// Mean bursts per second, `0..=1000`.
    pub rate_hz: f64,
    /// Length of a burst, revolutions, `0..=100`.
    pub length_revs: f64,
}

/// Contact closed at the arm.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CoolantBridge {
    /// Probability per approach, `0..=1`.
    pub probability: f64,
    /// How long the bridge holds after the arm, ms, `0..=10000`.
    pub length_ms: f64,
}

/// Interference spikes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Emi {
    /// Spikes per second on the contact line, `0..=1e6`.
    pub contact_hz: f64,
    /// Spikes per second on the FES line, `0..=1e6`.
    pub fes_hz: f64,
    /// Spikes per second on the index line, `0..=1e6`.
    pub index_hz: f64,
    /// Spikes per second on both scale lines at once, `0..=1e6`.
    pub scale_hz: f64,
    /// Longest spike, clocks, `0..=10000` (longer than the glitch filter: it passes).
    pub length_cycles: u32,
}

/// A line whose wire breaks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BrokenWire {
    /// Every wire holds.
    #[default]
    None,
    /// The contact circuit's wire.
    Contact,
    /// The FES encoder track.
    Fes,
    /// The index track.
    Index,
    /// The linear scale's cable (both lines).
    Scale,
}

/// Every fault of the simulated lathe; the default has none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LatheFaults {
    /// Contact bursts.
    pub chips: Chips,
    /// Contact closed at the arm.
    pub coolant_bridge: CoolantBridge,
    /// Interference spikes.
    pub emi: Emi,
    /// Probability that an FES pulse is lost, `0..=1`.
    pub fes_lost: f64,
    /// Probability that an FES pulse is doubled, `0..=1`.
    pub fes_doubled: f64,
    /// Probability that an index pulse is lost, `0..=1`.
    pub index_lost: f64,
    /// Probability that an index pulse is doubled, `0..=1`.
    pub index_doubled: f64,
    /// The wire that breaks.
    pub broken_wire: BrokenWire,
    /// When it breaks, seconds from power-on, `0..=1e6`.
    pub broken_after_s: f64,
}

/// Hash tags of the fault streams (distinct from the lathe's other streams).
mod tag {
    pub const CHIPS: u64 = 0xfa_0001;
    pub const BRIDGE: u64 = 0xfa_0002;
    pub const FES_LOST: u64 = 0xfa_0003;
    pub const FES_DOUBLED: u64 = 0xfa_0004;
    pub const INDEX_LOST: u64 = 0xfa_0005;
    pub const INDEX_DOUBLED: u64 = 0xfa_0006;
    pub const EMI: u64 = 0xfa_0100;
}

/// A uniform number in `[0, 1)` from a hash.
fn uniform(h: u64) -> f64 {
    0.5 * (unit(h) + 1.0)
}

impl LatheFaults {
    /// Whether no fault is configured (the pins are left as they are).
    pub fn is_none(&self) -> bool {
        *self == LatheFaults::default()
    }

    /// Checks every field; errors name it as `faults.…`.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        check("faults.chips.rate_hz", self.chips.rate_hz, 0.0, 1000.0)?;
        check(
            "faults.chips.length_revs",
            self.chips.length_revs,
            0.0,
            100.0,
        )?;
        let b = &self.coolant_bridge;
        check("faults.coolant_bridge.probability", b.probability, 0.0, 1.0)?;
        check(
            "faults.coolant_bridge.length_ms",
            b.length_ms,
            0.0,
            10_000.0,
        )?;
        let e = &self.emi;
        for (name, rate) in [
            ("faults.emi.contact_hz", e.contact_hz),
            ("faults.emi.fes_hz", e.fes_hz),
            ("faults.emi.index_hz", e.index_hz),
            ("faults.emi.scale_hz", e.scale_hz),
        ] {
            check(name, rate, 0.0, 1e6)?;
        }
        check(
            "faults.emi.length_cycles",
            e.length_cycles.into(),
            0.0,
            10_000.0,
        )?;
        for (name, p) in [
            ("faults.fes_lost", self.fes_lost),
            ("faults.fes_doubled", self.fes_doubled),
            ("faults.index_lost", self.index_lost),
            ("faults.index_doubled", self.index_doubled),
        ] {
            check(name, p, 0.0, 1.0)?;
        }
        check("faults.broken_after_s", self.broken_after_s, 0.0, 1e6)?;
        Ok(())
    }
}

/// What [`inject`] needs to know about the lathe.
pub struct Context<'a> {
    /// The spindle's timing.
    pub spindle: &'a Spindle,
    /// FPGA clock, Hz.
    pub clock_hz: u32,
    /// Seed of every random stream.
    pub seed: u64,
    /// The clock at which the arm rose for the current approach, if it is high.
    pub arm_rise: Option<u64>,
}

/// The pins of clocks `[k_a, k_b)` (`segments`, run-length encoded) with `faults` applied.
pub fn inject(faults: &LatheFaults, segments: &[Segment], k_a: u64, ctx: &Context) -> Vec<Segment> {
    if faults.is_none() {
        return segments.to_vec();
    }
    let k_b = k_a + segments.iter().map(|s| u64::from(s.cycles)).sum::<u64>();
    let mut lines = split(segments, k_a);
    let clip = |v: Intervals| {
        v.into_iter()
            .map(|(s, e)| (s.max(k_a), e.min(k_b)))
            .filter(|&(s, e)| s < e)
            .collect::<Intervals>()
    };
    let mut extra = chips(faults, k_a, k_b, ctx);
    if let Some(bridge) = coolant_bridge(faults, ctx) {
        extra.push(bridge);
        // The bridge is there before the arm: the arm rises one clock after it (an arm
        // and a contact rising in the same clock would reach the kernel arm first).
        if ctx.arm_rise == Some(k_a) {
            let arm = &mut lines[bit_index(pin::ARM)];
            *arm = minus(arm, &[(k_a, k_a + 1)]);
        }
    }
    let contact = &mut lines[bit_index(pin::CONTACT)];
    *contact = clip(electrics::normalize(
        contact.iter().copied().chain(extra).collect(),
    ));
    pulse_faults(faults, &mut lines, k_a, k_b, ctx, &clip);
    emi(faults, &mut lines, k_a, k_b, ctx);
    if faults.broken_wire != BrokenWire::None {
        let at = (faults.broken_after_s * f64::from(ctx.clock_hz)).round() as u64;
        let dead = [(at.max(k_a), k_b.max(at))];
        let bits: &[u8] = match faults.broken_wire {
            BrokenWire::None => &[],
            BrokenWire::Contact => &[pin::CONTACT],
            BrokenWire::Fes => &[pin::FES],
            BrokenWire::Index => &[pin::INDEX],
            BrokenWire::Scale => &[pin::SCALE_A, pin::SCALE_B],
        };
        for &bit in bits {
            let line = &mut lines[bit_index(bit)];
            *line = minus(line, &dead);
        }
    }
    join(&lines, k_a, k_b, ctx.clock_hz)
}

/// Contact bursts in `[k_a, k_b)`: time cut in slots one burst long, a burst in a slot
/// with probability `1 − exp(−rate · length)` at a hashed offset.
fn chips(faults: &LatheFaults, k_a: u64, k_b: u64, ctx: &Context) -> Intervals {
    let c = &faults.chips;
    let len = (c.length_revs * ctx.spindle.cycles_per_rev).round() as u64;
    if c.rate_hz <= 0.0 || len == 0 {
        return Intervals::new();
    }
    let p = 1.0 - (-c.rate_hz * len as f64 / f64::from(ctx.clock_hz)).exp();
    let mut out = Intervals::new();
    for slot in (k_a / len).saturating_sub(1)..=(k_b.saturating_sub(1) / len) {
        let h = mix(ctx.seed, tag::CHIPS, slot);
        if uniform(h) < p {
            let start = slot * len + mix(ctx.seed, tag::CHIPS + 0x10, slot) % len;
            out.push((start, start + len));
        }
    }
    out
}

/// The contact closed from the arm's rise, if this approach draws a bridge.
fn coolant_bridge(faults: &LatheFaults, ctx: &Context) -> Option<(u64, u64)> {
    let b = &faults.coolant_bridge;
    let rise = ctx.arm_rise?;
    let len = (b.length_ms * 1e-3 * f64::from(ctx.clock_hz)).round() as u64;
    (len > 0 && uniform(mix(ctx.seed, tag::BRIDGE, rise)) < b.probability)
        .then_some((rise, rise + len))
}

/// FES and index pulses lost or doubled, decided per pulse number.
fn pulse_faults(
    faults: &LatheFaults,
    lines: &mut [Intervals; pin::COUNT],
    k_a: u64,
    k_b: u64,
    ctx: &Context,
    clip: &dyn Fn(Intervals) -> Intervals,
) {
    let s = ctx.spindle;
    let ppr = u64::from(s.pulses_per_rev);
    let period = s.fes_period();
    let first = ((k_a as f64 / period).floor() as u64).saturating_sub(1);
    let last = (k_b as f64 / period).ceil() as u64 + 1;
    if faults.fes_lost > 0.0 || faults.fes_doubled > 0.0 {
        let (mut lost, mut added) = (Intervals::new(), Intervals::new());
        for j in first..=last {
            let (rise, fall, next) = (s.fes_rise(j), s.fes_fall(j), s.fes_rise(j + 1));
            if uniform(mix(ctx.seed, tag::FES_LOST, j)) < faults.fes_lost {
                lost.push((rise, fall));
            } else if uniform(mix(ctx.seed, tag::FES_DOUBLED, j)) < faults.fes_doubled {
                let gap = next - fall;
                added.push((fall + gap / 4, fall + 3 * gap / 4));
            }
        }
        let fes = &mut lines[bit_index(pin::FES)];
        let kept = minus(fes, &electrics::normalize(lost));
        *fes = clip(electrics::normalize(
            kept.into_iter().chain(added).collect(),
        ));
    }
    if faults.index_lost > 0.0 || faults.index_doubled > 0.0 {
        let (mut lost, mut added) = (Intervals::new(), Intervals::new());
        for r in (first / ppr).saturating_sub(1)..=last / ppr + 1 {
            let j = r * ppr;
            let (rise, fall) = (s.fes_rise(j), s.fes_rise(j + 1));
            if uniform(mix(ctx.seed, tag::INDEX_LOST, r)) < faults.index_lost {
                lost.push((rise, fall));
            } else if uniform(mix(ctx.seed, tag::INDEX_DOUBLED, r)) < faults.index_doubled {
                let half = j + ppr / 2;
                added.push((s.fes_rise(half), s.fes_rise(half + 1)));
            }
        }
        let index = &mut lines[bit_index(pin::INDEX)];
        let kept = minus(index, &electrics::normalize(lost));
        *index = clip(electrics::normalize(
            kept.into_iter().chain(added).collect(),
        ));
    }
}

/// Interference spikes, XORed onto their lines (the scale's onto both at once).
fn emi(
    faults: &LatheFaults,
    lines: &mut [Intervals; pin::COUNT],
    k_a: u64,
    k_b: u64,
    ctx: &Context,
) {
    let e = &faults.emi;
    if e.length_cycles == 0 {
        return;
    }
    let streams: [(f64, &[u8]); 4] = [
        (e.contact_hz, &[pin::CONTACT]),
        (e.fes_hz, &[pin::FES]),
        (e.index_hz, &[pin::INDEX]),
        (e.scale_hz, &[pin::SCALE_A, pin::SCALE_B]),
    ];
    for (n, (rate, bits)) in streams.into_iter().enumerate() {
        if rate <= 0.0 {
            continue;
        }
        let spikes = ContactElectrics {
            spike_rate_hz: rate,
            ..ContactElectrics::default()
        }
        .spikes(
            k_a,
            k_b,
            e.length_cycles,
            ctx.clock_hz,
            mix(ctx.seed, tag::EMI, n as u64),
        );
        for &bit in bits {
            let line = &mut lines[bit_index(bit)];
            *line = electrics::xor(line, &spikes);
        }
    }
}

/// `a` without the clocks of `b` (both sorted and disjoint), in one pass over both.
fn minus(a: &[(u64, u64)], b: &[(u64, u64)]) -> Intervals {
    let mut out = Intervals::new();
    let mut j = 0;
    for &(s, e) in a {
        let mut start = s;
        while j < b.len() && b[j].1 <= start {
            j += 1;
        }
        let mut i = j;
        while i < b.len() && b[i].0 < e {
            if b[i].0 > start {
                out.push((start, b[i].0));
            }
            start = start.max(b[i].1);
            i += 1;
        }
        if start < e {
            out.push((start, e));
        }
    }
    out
}

/// The pin number of a pin bit.
fn bit_index(bit: u8) -> usize {
    bit.trailing_zeros() as usize
}

/// Each pin's high intervals over the segments starting at clock `k_a`.
fn split(segments: &[Segment], k_a: u64) -> [Intervals; pin::COUNT] {
    let mut lines: [Intervals; pin::COUNT] = Default::default();
    let mut k = k_a;
    for s in segments {
        let end = k + u64::from(s.cycles);
        for (i, line) in lines.iter_mut().enumerate() {
            if s.pins.0 & (1 << i) != 0 {
                match line.last_mut() {
                    Some(last) if last.1 == k => last.1 = end,
                    _ => line.push((k, end)),
                }
            }
        }
        k = end;
    }
    lines
}

/// The segments of `[k_a, k_b)` from each pin's high intervals.
fn join(lines: &[Intervals; pin::COUNT], k_a: u64, k_b: u64, clock_hz: u32) -> Vec<Segment> {
    let mut changes: Vec<(u64, usize, bool)> = Vec::new();
    let mut pins = Pins(0);
    for (i, line) in lines.iter().enumerate() {
        for &(s, e) in line {
            if s <= k_a {
                pins = pins.with(1 << i, true);
            } else {
                changes.push((s, i, true));
            }
            if e < k_b {
                changes.push((e, i, false));
            }
        }
    }
    changes.sort_unstable_by_key(|c| c.0);
    let mut stimulus = Stimulus::new(clock_hz);
    let mut k = k_a;
    for (clock, i, level) in changes {
        stimulus.push(pins, clock - k);
        k = clock;
        pins = pins.with(1 << i, level);
    }
    stimulus.push(pins, k_b - k);
    stimulus.segments
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod minus_tests {
    use super::*;

    /// Random interval lists (hashed, 2 000 cases) against the lathe's quadratic subtract.
    #[test]
    fn minus_equals_the_lathe_s_subtract() {
        let draw = |case: u64, which: u64| {
            let n = mix(7, which, case) % 12;
            let v = (0..n)
                .map(|i| {
                    let h = mix(case, which, i);
                    let s = h % 200;
                    (s, s + 1 + (h >> 32) % 20)
                })
                .collect();
            electrics::normalize(v)
        };
        for case in 0..2000 {
            let (a, b) = (draw(case, 1), draw(case, 2));
            assert_eq!(minus(&a, &b), electrics::subtract(&a, &b), "{a:?} − {b:?}");
        }
    }
}
