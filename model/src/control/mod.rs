//! Force controllers (SPEC 3): one interface, three kernels — [`pi`], [`adaptive`] (F11)
//! and [`fuzzy`] (Mamdani fuzzy PI).
//!
//! Every controller is called once per control period (h = 0.05 s) with the reference
//! force F_r and the force feedback F̂_c (estimated or measured, newtons, I32F32) and returns
//! the CNC feed override: an integer percentage `0..=255` in 1 % steps (0 = feed hold) and a
//! saturated flag. Internally each keeps a continuous override (I32F32 percent) clamped to
//! `[0, 255]`; the output is that value rounded to the nearest integer (ties away from
//! zero), so it is in range for any input by construction.
//!
//! Firmware use: build a [`Controller`] once from the validated configuration, then call
//! [`ForceController::step`] from the 20 Hz control task. No allocation, no panics, no
//! division by a value that can be zero.

pub mod adaptive;
pub mod fuzzy;
pub mod pi;

use crate::force::{Fx, Newtons};
pub use adaptive::{Adaptive, AdaptiveSettings};
pub use fuzzy::{Fuzzy, FuzzySettings};
pub use pi::{Pi, PiSettings};

/// Feed override or a controller's internal override state, percent, I32F32.
pub type Percent = Fx;

/// Largest feed override, percent.
pub const OVERRIDE_MAX: u8 = 255;

/// Largest feed override as a [`Percent`].
pub const OVERRIDE_MAX_FX: Percent = Fx::const_from_int(255);

/// One control period's output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ControlOutput {
    /// Feed override, percent, `0..=255` (0 = feed hold).
    pub override_pct: u8,
    /// The controller's unclamped demand was outside `[0, 255]` this period.
    pub saturated: bool,
}

/// The interface every force controller kernel implements.
pub trait ForceController {
    /// One control period: reference `reference` and feedback `force` (N) → override.
    fn step(&mut self, reference: Newtons, force: Newtons) -> ControlOutput;
    /// Restarts the controller bumplessly from the override `override_pct` (e.g. when
    /// force control is switched on while the CNC runs at that override).
    fn reset(&mut self, override_pct: u8);
}

/// Clamps a continuous override to `[0, 255]`; returns it and whether it was outside.
pub fn clamp_override(u: Percent) -> (Percent, bool) {
    if u < Fx::ZERO {
        (Fx::ZERO, true)
    } else if u > OVERRIDE_MAX_FX {
        (OVERRIDE_MAX_FX, true)
    } else {
        (u, false)
    }
}

/// Rounds a continuous override to the nearest integer percent (ties away from zero) and
/// saturates it to `0..=255`.
pub fn quantize(u: Percent) -> u8 {
    let (u, _) = clamp_override(u);
    let r: i64 = u.saturating_round().to_bits() >> 32;
    u8::try_from(r.clamp(0, 255)).unwrap_or(OVERRIDE_MAX)
}

/// Which controller and its settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ControllerSettings {
    /// PI with anti-windup.
    Pi(PiSettings),
    /// Variable-gain adaptive (F11).
    Adaptive(AdaptiveSettings),
    /// Fuzzy PI.
    Fuzzy(FuzzySettings),
}

impl ControllerSettings {
    /// A short name: `pi`, `adaptive` or `fuzzy`.
    pub fn name(&self) -> &'static str {
        match self {
            ControllerSettings::Pi(_) => "pi",
            ControllerSettings::Adaptive(_) => "adaptive",
            ControllerSettings::Fuzzy(_) => "fuzzy",
        }
    }
}

/// One of the three controllers, behind the common interface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Controller {
    /// PI.
    Pi(Pi),
    /// Adaptive.
    Adaptive(Adaptive),
    /// Fuzzy PI.
    Fuzzy(Fuzzy),
}

impl Controller {
    /// The controller for validated `settings`, control period `h` (s), starting at
    /// `override_pct`.
    pub fn new(settings: &ControllerSettings, h: Fx, override_pct: u8) -> Controller {
        match settings {
            ControllerSettings::Pi(s) => Controller::Pi(Pi::new(s, h, override_pct)),
            ControllerSettings::Adaptive(s) => {
                Controller::Adaptive(Adaptive::new(s, h, override_pct))
            }
            ControllerSettings::Fuzzy(s) => Controller::Fuzzy(Fuzzy::new(s, override_pct)),
        }
    }
}

impl ForceController for Controller {
    fn step(&mut self, reference: Newtons, force: Newtons) -> ControlOutput {
        match self {
            Controller::Pi(c) => c.step(reference, force),
            Controller::Adaptive(c) => c.step(reference, force),
            Controller::Fuzzy(c) => c.step(reference, force),
        }
    }
    fn reset(&mut self, override_pct: u8) {
        match self {
            Controller::Pi(c) => c.reset(override_pct),
            Controller::Adaptive(c) => c.reset(override_pct),
            Controller::Fuzzy(c) => c.reset(override_pct),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantize_rounds_and_saturates() {
        assert_eq!(quantize(Fx::lit("99.5")), 100);
        assert_eq!(quantize(Fx::lit("99.49")), 99);
        assert_eq!(quantize(Fx::const_from_int(-5)), 0);
        assert_eq!(quantize(Fx::const_from_int(1000)), 255);
        assert_eq!(quantize(Fx::MAX), 255);
        assert_eq!(quantize(Fx::MIN), 0);
    }
}
