//! The inputs of a counterexample, clock by clock from power-on: what ABC's trace gives
//! ([`super::counterexample::read_cex`]) and both replays read. A leaf module, so the replays
//! use it without importing each other.

use tooltouch_model::measure::frontend::Pins;
use tooltouch_plant::stimulus::Stimulus;

/// The inputs of a difference, clock by clock from power-on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Counterexample {
    /// Pins sampled by clock `k` (bits as [`pin`]), `k = 0 … clocks − 1`; the designs'
    /// outputs registered after the last clock differ.
    pub pins: Vec<u8>,
    /// The MCU address at each frame `0 … clocks` (the last one is the address read when
    /// the difference shows).
    pub mcu_addr: Vec<u32>,
    /// `rst` at each frame `0 … clocks` (high at frame `k`: clock `k` resets).
    pub rst: Vec<bool>,
}

impl Counterexample {
    /// Clocks of the trace.
    pub fn clocks(&self) -> usize {
        self.pins.len()
    }

    /// Whether a clock of the trace resets.
    pub fn resets(&self) -> bool {
        self.rst.iter().take(self.clocks()).any(|&r| r)
    }

    /// The pins as a stimulus at `clock_hz`.
    pub fn stimulus(&self, clock_hz: u32) -> Stimulus {
        let mut s = Stimulus::new(clock_hz);
        for &p in &self.pins {
            s.push(Pins(p), 1);
        }
        s
    }
}
