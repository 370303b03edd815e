//! The interface every force controller kernel implements: the feed override's format and
//! range, one period's output, and the [`ForceController`] trait.
//!
//! A leaf of the control room: the kernels import it, so none of them needs the module that
//! selects among them.

use crate::units::{Fx, Newtons};

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
