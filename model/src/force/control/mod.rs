//! Force controllers (docs/domain.md §3): one interface, three kernels — [`pi`], [`adaptive`] (F11)
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

//!
//! Layout: the interface every kernel implements (the override's format and range, the
//! trait) is a private leaf that the kernels import; this module selects one kernel by
//! settings and re-exports the interface and the kernels' types, and no kernel imports it.

pub mod adaptive;
pub mod fuzzy;
mod interface;
pub mod pi;

use crate::units::{Fx, Newtons};
pub use adaptive::{Adaptive, AdaptiveSettings};
pub use fuzzy::{Fuzzy, FuzzySettings};
pub use interface::{
    clamp_override, quantize, ControlOutput, ForceController, Percent, OVERRIDE_MAX,
    OVERRIDE_MAX_FX,
};
pub use pi::{Pi, PiSettings};

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

#[cfg(feature = "internals")]
impl crate::internals::Internals for Controller {
    /// The selected kernel's ([`Pi`], [`Adaptive`] or [`Fuzzy`]).
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        match self {
            Controller::Pi(c) => c.internals(f),
            Controller::Adaptive(c) => c.internals(f),
            Controller::Fuzzy(c) => c.internals(f),
        }
    }
}

#[cfg(test)]
mod worked_examples;
