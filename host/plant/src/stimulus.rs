//! Cycle-level pin stimulus, run-length encoded: a scenario of millions of FPGA clocks is
//! a few thousand segments, one per pin change, not one struct per cycle.

use tooltouch_model::measure::frontend::Pins;

/// `cycles` consecutive FPGA clocks with the input pins held at `pins`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    /// Pin levels during the segment.
    pub pins: Pins,
    /// Clocks in the segment, at least 1.
    pub cycles: u32,
}

/// A run-length-encoded pin stimulus at a given clock frequency.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Stimulus {
    /// FPGA clock, Hz.
    pub clock_hz: u32,
    /// Consecutive segments; adjacent segments may hold equal pins.
    pub segments: Vec<Segment>,
}

impl Stimulus {
    /// An empty stimulus at `clock_hz`.
    pub fn new(clock_hz: u32) -> Self {
        Stimulus {
            clock_hz,
            segments: Vec::new(),
        }
    }

    /// Appends `cycles` clocks of `pins`, merging with the last segment when equal.
    /// Zero cycles append nothing.
    pub fn push(&mut self, pins: Pins, cycles: u64) {
        let mut left = cycles;
        while left > 0 {
            if let Some(last) = self.segments.last_mut() {
                if last.pins == pins && last.cycles < u32::MAX {
                    let add = left.min(u64::from(u32::MAX - last.cycles));
                    last.cycles += add as u32;
                    left -= add;
                    continue;
                }
            }
            let add = left.min(u64::from(u32::MAX));
            self.segments.push(Segment {
                pins,
                cycles: add as u32,
            });
            left -= add;
        }
    }

    /// Total clocks.
    pub fn total_cycles(&self) -> u64 {
        self.segments.iter().map(|s| u64::from(s.cycles)).sum()
    }

    /// Every clock's pins in order (for simulators that step one clock at a time).
    pub fn cycles(&self) -> impl Iterator<Item = Pins> + '_ {
        self.segments
            .iter()
            .flat_map(|s| std::iter::repeat_n(s.pins, s.cycles as usize))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_merges_equal_pins_and_counts_cycles() {
        let mut s = Stimulus::new(50_000_000);
        s.push(Pins(1), 3);
        s.push(Pins(1), 2);
        s.push(Pins(0), 0);
        s.push(Pins(2), 1);
        assert_eq!(s.segments.len(), 2);
        assert_eq!(s.total_cycles(), 6);
        assert_eq!(s.cycles().count(), 6);
    }
}
