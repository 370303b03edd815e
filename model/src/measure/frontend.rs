//! Cycle level (RTL semantics): `clock(pins)` once per FPGA clock, exactly what the
//! generated Verilog does on each rising edge.
//!
//! Per input pin: a 2-flip-flop synchronizer, a glitch filter, and edge detection against
//! the previous filtered level; the detected edges drive the [`Measurement`] kernel in
//! [`MeasureEvent::CANONICAL_ORDER`]. The kernel's state registers are the outputs.
//!
//! Latency (documented contract, checked by tests): a pin level sampled at clock `k` and
//! held for at least `glitch_cycles + 1` clocks is visible in the outputs after clock
//! `k + 3 + glitch_cycles` — sync 1 at `k`, sync 2 at `k+1`, the filtered register at
//! `k+2+glitch_cycles`, the kernel update on the detected edge one clock later. See
//! [`MeasureConfig::latency_cycles`].
//!
//! Every register is updated from the values of the previous clock (non-blocking
//! assignment semantics); the order of statements in [`FrontEnd::clock`] mirrors that.

use crate::measure::config::MeasureConfig;
use crate::measure::events::MeasureEvent;
use crate::measure::kernel::Measurement;
use crate::measure::outputs::MeasureOutputs;

/// Bit positions of the input pins in [`Pins`].
pub mod pin {
    /// CNC arm (measurement-cycle start; low = abort / end).
    pub const ARM: u8 = 1 << 0;
    /// Tool–workpiece contact.
    pub const CONTACT: u8 = 1 << 1;
    /// Spindle index pulse.
    pub const INDEX: u8 = 1 << 2;
    /// Spindle FES encoder pulse.
    pub const FES: u8 = 1 << 3;
    /// Linear scale line A.
    pub const SCALE_A: u8 = 1 << 4;
    /// Linear scale line B.
    pub const SCALE_B: u8 = 1 << 5;
    /// Number of input pins.
    pub const COUNT: usize = 6;
    /// All input pin bits.
    pub const ALL: u8 = 0x3f;
    /// Pin names, by bit position, as in VCD files and the Verilog ports.
    pub const NAMES: [&str; COUNT] = ["arm", "contact", "index", "fes", "scale_a", "scale_b"];
}

/// Levels of the six input pins, one bit each (see [`pin`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Pins(pub u8);

impl Pins {
    /// Level of the pin bit `bit`.
    pub fn get(self, bit: u8) -> bool {
        self.0 & bit != 0
    }
    /// These pins with pin bit `bit` set to `level`.
    pub fn with(self, bit: u8, level: bool) -> Pins {
        if level {
            Pins(self.0 | bit)
        } else {
            Pins(self.0 & !bit)
        }
    }
}

/// Edges detected in one clock: which filtered levels changed, and the new levels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Edges {
    /// Pin bits whose filtered level changed.
    pub changed: u8,
    /// Filtered levels after the change.
    pub levels: u8,
}

impl Edges {
    /// Whether nothing changed.
    pub fn is_empty(&self) -> bool {
        self.changed == 0
    }

    /// Calls `f` with the events these edges make, in canonical order. Falling edges of
    /// index and FES make no event.
    pub fn for_each_event(&self, mut f: impl FnMut(MeasureEvent)) {
        let (changed, levels) = (self.changed, self.levels);
        if changed & pin::ARM != 0 {
            f(MeasureEvent::Arm(levels & pin::ARM != 0));
        }
        if changed & pin::CONTACT != 0 {
            f(MeasureEvent::Contact(levels & pin::CONTACT != 0));
        }
        if changed & levels & pin::INDEX != 0 {
            f(MeasureEvent::Index);
        }
        if changed & levels & pin::FES != 0 {
            f(MeasureEvent::Fes);
        }
        if changed & (pin::SCALE_A | pin::SCALE_B) != 0 {
            f(MeasureEvent::Scale {
                a: levels & pin::SCALE_A != 0,
                b: levels & pin::SCALE_B != 0,
            });
        }
    }
}

/// The cycle-level front end: synchronizers, glitch filters, edge detection, kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FrontEnd {
    glitch_cycles: u8,
    /// First synchronizer stage, one bit per pin.
    sync1: u8,
    /// Second synchronizer stage.
    sync2: u8,
    /// Glitch-filtered levels.
    filtered: u8,
    /// Filtered levels one clock earlier (edge detection).
    previous: u8,
    /// Per pin: clocks `sync2` has differed from `filtered`, `0..=glitch_cycles`.
    stable: [u8; pin::COUNT],
    /// Clocks done since reset: the next clock is clock number `clocks` (from 0), the
    /// time of the events it applies and of the kernel's FES watchdog.
    clocks: u64,
    measurement: Measurement,
}

impl FrontEnd {
    /// Reset state: every register 0.
    pub fn new(config: &MeasureConfig) -> Self {
        FrontEnd {
            glitch_cycles: config.settings().glitch_cycles,
            sync1: 0,
            sync2: 0,
            filtered: 0,
            previous: 0,
            stable: [0; pin::COUNT],
            clocks: 0,
            measurement: Measurement::new(config),
        }
    }

    /// One rising clock edge with the input pins `pins`. Returns the edges the kernel
    /// acted on in this clock.
    #[inline]
    pub fn clock(&mut self, pins: Pins) -> Edges {
        let edges = Edges {
            changed: self.filtered ^ self.previous,
            levels: self.filtered,
        };
        let now = self.clocks;
        self.clocks = now + 1;
        if edges.changed != 0 {
            let m = &mut self.measurement;
            m.observe(now);
            edges.for_each_event(|e| m.apply(e));
        }
        self.previous = self.filtered;
        let differ = self.sync2 ^ self.filtered;
        if differ != 0 || self.stable != [0; pin::COUNT] {
            self.filter(differ);
        }
        self.sync2 = self.sync1;
        self.sync1 = pins.0 & pin::ALL;
        edges
    }

    /// Glitch filter step: a differing bit is taken once it has differed for
    /// `glitch_cycles` earlier clocks too; a bit that agrees resets its counter.
    fn filter(&mut self, differ: u8) {
        for (i, stable) in self.stable.iter_mut().enumerate() {
            let bit = 1u8 << i;
            if differ & bit == 0 {
                *stable = 0;
            } else if *stable >= self.glitch_cycles {
                self.filtered ^= bit;
                *stable = 0;
            } else {
                *stable += 1;
            }
        }
    }

    /// `cycles` clocks with `pins` held, calling `on_edges(k, edges)` for the `k`-th of
    /// them (from 0) whenever the kernel acted on edges. Exact fast-forward: once the front
    /// end [is settled](Self::is_settled) no later clock can change a register, so the
    /// remaining clocks are skipped. Returns the clocks actually simulated one by one.
    #[inline]
    pub fn advance(
        &mut self,
        pins: Pins,
        cycles: u64,
        mut on_edges: impl FnMut(u64, Edges),
    ) -> u64 {
        let mut k = 0;
        while k < cycles {
            if self.is_settled(pins) {
                // Settled clocks change no register; only the time moves on.
                self.clocks += cycles - k;
                return k;
            }
            let edges = self.clock(pins);
            if !edges.is_empty() {
                on_edges(k, edges);
            }
            k += 1;
        }
        k
    }

    /// Whether clocking with `pins` held would change no register at all, so any number
    /// of such clocks may be skipped exactly.
    pub fn is_settled(&self, pins: Pins) -> bool {
        let p = pins.0 & pin::ALL;
        self.sync1 == p
            && self.sync2 == p
            && self.filtered == p
            && self.previous == p
            && self.stable == [0; pin::COUNT]
    }

    /// Every output, as registered after the last clock (clock number `clocks − 1`).
    pub fn outputs(&self) -> MeasureOutputs {
        self.measurement.outputs_at(self.clocks.saturating_sub(1))
    }

    /// Clocks done since reset.
    pub fn clocks(&self) -> u64 {
        self.clocks
    }

    /// The kernel (read-only).
    pub fn measurement(&self) -> &Measurement {
        &self.measurement
    }

    /// Glitch-filtered pin levels.
    pub fn filtered(&self) -> Pins {
        Pins(self.filtered)
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for FrontEnd {
    /// The glitch filters' counters `glitch.stable[pin]` (`u8`, `0..=glitch_cycles`), then
    /// the kernel's ([`Measurement`]'s).
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        const NAMES: [&str; pin::COUNT] = [
            "glitch.stable[arm]",
            "glitch.stable[contact]",
            "glitch.stable[index]",
            "glitch.stable[fes]",
            "glitch.stable[scale_a]",
            "glitch.stable[scale_b]",
        ];
        for (name, &stable) in NAMES.iter().zip(self.stable.iter()) {
            f(Register::new(name, Format::unsigned(8), stable.into()));
        }
        crate::internals::Internals::internals(&self.measurement, f);
    }
}

#[cfg(test)]
mod worked_examples;

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::measure::config::MeasureSettings;

    fn front_end(glitch: u8) -> FrontEnd {
        let s = MeasureSettings {
            glitch_cycles: glitch,
            ..Default::default()
        };
        FrontEnd::new(&s.validate().unwrap())
    }

    #[test]
    fn latency_is_three_plus_glitch_cycles() {
        for glitch in [0u8, 1, 4, 9] {
            let mut fe = front_end(glitch);
            let latency = 3 + u32::from(glitch);
            let mut seen = None;
            for k in 0..40u32 {
                fe.clock(Pins(pin::ARM));
                if fe.outputs().armed {
                    seen = Some(k);
                    break;
                }
            }
            // The pin was sampled at clock 0 and is visible after clock `latency`.
            assert_eq!(seen, Some(latency), "glitch {glitch}");
        }
    }

    #[test]
    fn a_level_passes_after_glitch_cycles_plus_one_clocks() {
        for (width, passes) in [(4, false), (5, true)] {
            let mut fe = front_end(4);
            let mut passed = false;
            for k in 0..30 {
                let pins = if (5..5 + width).contains(&k) {
                    Pins(pin::ARM)
                } else {
                    Pins(0)
                };
                fe.clock(pins);
                passed |= fe.outputs().armed;
            }
            assert_eq!(
                passed, passes,
                "{width}-clock pulse through a 4-cycle filter"
            );
        }
    }

    proptest::proptest! {
        #[test]
        fn advance_equals_clocking_one_by_one(
            segments in proptest::collection::vec((0u8..64, 1u64..40), 1..60),
            glitch in 0u8..6,
        ) {
            let mut plain = front_end(glitch);
            let mut fast = plain;
            let mut t = 0u64;
            for (pins, cycles) in segments {
                let pins = Pins(pins);
                let mut plain_edges = std::vec::Vec::new();
                for k in 0..cycles {
                    let e = plain.clock(pins);
                    if !e.is_empty() {
                        plain_edges.push((t + k, e));
                    }
                }
                let mut fast_edges = std::vec::Vec::new();
                fast.advance(pins, cycles, |k, e| fast_edges.push((t + k, e)));
                proptest::prop_assert_eq!(&plain_edges, &fast_edges);
                proptest::prop_assert_eq!(plain, fast);
                t += cycles;
            }
        }
    }

    #[test]
    fn settled_clocks_change_nothing() {
        let mut fe = front_end(2);
        let pins = Pins(pin::ARM | pin::SCALE_A);
        for _ in 0..10 {
            fe.clock(pins);
        }
        assert!(fe.is_settled(pins));
        let before = fe;
        fe.clock(pins);
        // Only the time moves on.
        assert_eq!(
            fe,
            FrontEnd {
                clocks: before.clocks + 1,
                ..before
            }
        );
    }
}
