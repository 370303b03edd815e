//! PI force controller with anti-windup (docs/domain.md §3, controller 1).
//!
//! Position form, evaluated once per period h:
//! `u(i) = K_p·e(i) + I(i)`, `e = F_r − F̂_c`, then
//! `I(i+1) = clamp(I(i) + K_i·h·e(i), I_min, I_max)` — except while the demand is saturated
//! and the error would push it further out (conditional integration). Both guards are
//! used: the clamp bounds the integrator whatever happens, conditional integration stops
//! it from sitting at the clamp during a long saturation, so the controller leaves
//! saturation as soon as the error changes sign. The gains come from Ziegler–Nichols on the
//! nominal process F10 (designed on the host: `tooltouch::reference::design`).
//!
//! Formats: gains and state I32F32 (`K_p` in %/N, `K_i` in %/(N·s), I in %); every product
//! and sum saturates; `K_i·h` is computed once at construction.

use super::interface::{
    clamp_override, quantize, ControlOutput, ForceController, Percent, OVERRIDE_MAX_FX,
};
use crate::units::{Fx, Newtons};
use crate::validation::{check_range, positive, ForceConfigError};

/// PI settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PiSettings {
    /// Proportional gain K_p, %/N, `(0, 100]`.
    pub kp: Fx,
    /// Integral gain K_i, %/(N·s), `(0, 1000]`.
    pub ki: Fx,
    /// Integrator lower clamp, %, `[0, 255)`.
    pub integrator_min: Percent,
    /// Integrator upper clamp, %, `(integrator_min, 255]`.
    pub integrator_max: Percent,
}

impl PiSettings {
    /// Checks every field (`pi.<field>`).
    pub fn validate(&self) -> Result<(), ForceConfigError> {
        positive("pi.kp", self.kp, Fx::const_from_int(100))?;
        positive("pi.ki", self.ki, Fx::const_from_int(1000))?;
        check_range(
            "pi.integrator_min",
            self.integrator_min,
            Fx::ZERO,
            OVERRIDE_MAX_FX - Fx::ONE,
        )?;
        check_range(
            "pi.integrator_max",
            self.integrator_max,
            self.integrator_min.saturating_add(Fx::DELTA),
            OVERRIDE_MAX_FX,
        )
    }
}

/// Default PI: Ziegler–Nichols (reaction curve) on the default nominal process of
/// `tooltouch::drive` (K = 6 N/%, τ_p = 0.08 s, dead time 0.075 s):
/// `K_p = 0.9τ/(K·L) = 0.16 %/N`, `T_i = 3.33·L = 0.25 s`, `K_i = K_p/T_i = 0.64 %/(N·s)`.
pub const DEFAULT_PI: PiSettings = PiSettings {
    kp: Fx::lit("0.16"),
    ki: Fx::lit("0.64"),
    integrator_min: Fx::ZERO,
    integrator_max: Fx::const_from_int(255),
};

/// The PI kernel's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Pi {
    kp: Fx,
    ki_h: Fx,
    i_min: Percent,
    i_max: Percent,
    integral: Percent,
}

impl Pi {
    /// A PI for validated `s`, period `h` (s), integrator starting at `override_pct`.
    pub fn new(s: &PiSettings, h: Fx, override_pct: u8) -> Pi {
        let mut pi = Pi {
            kp: s.kp,
            ki_h: s.ki.saturating_mul(h),
            i_min: s.integrator_min,
            i_max: s.integrator_max,
            integral: Fx::ZERO,
        };
        pi.reset(override_pct);
        pi
    }

    /// The integrator, %.
    pub fn integral(&self) -> Percent {
        self.integral
    }
}

impl ForceController for Pi {
    /// `u = K_p·e + I`, saturating; integrates unless saturated in the error's direction.
    fn step(&mut self, reference: Newtons, force: Newtons) -> ControlOutput {
        let e = reference.saturating_sub(force);
        let demand = self.kp.saturating_mul(e).saturating_add(self.integral);
        let (u, saturated) = clamp_override(demand);
        let winding_up =
            (demand > OVERRIDE_MAX_FX && e > Fx::ZERO) || (demand < Fx::ZERO && e < Fx::ZERO);
        if !winding_up {
            self.integral = self
                .integral
                .saturating_add(self.ki_h.saturating_mul(e))
                .max(self.i_min)
                .min(self.i_max);
        }
        ControlOutput {
            override_pct: quantize(u),
            saturated,
        }
    }

    /// Integrator to `override_pct` (clamped), so the first output with zero error is it.
    fn reset(&mut self, override_pct: u8) {
        self.integral = Fx::from_num(override_pct).max(self.i_min).min(self.i_max);
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for Pi {
    /// `pi.integral`: I32F32, clamped to `integrator_min..=integrator_max`.
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        let clamp =
            Format::I32F32.clamped(self.i_min.to_bits().into(), self.i_max.to_bits().into());
        f(Register::fx("pi.integral", clamp, self.integral));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pi() -> Pi {
        Pi::new(
            &PiSettings {
                kp: Fx::lit("0.1"),
                ki: Fx::const_from_int(1),
                integrator_min: Fx::ZERO,
                integrator_max: OVERRIDE_MAX_FX,
            },
            Fx::lit("0.05"),
            100,
        )
    }

    #[test]
    fn zero_error_holds_the_override() {
        let mut c = pi();
        let f = Fx::const_from_int(500);
        assert_eq!(c.step(f, f).override_pct, 100);
    }

    #[test]
    fn integrator_stops_while_saturated() {
        let mut c = pi();
        for _ in 0..1000 {
            let o = c.step(Fx::const_from_int(5000), Fx::ZERO);
            assert!(o.saturated);
            assert_eq!(o.override_pct, 255);
        }
        // proportional part alone saturates: the integrator stayed where it was
        assert_eq!(c.integral(), Fx::const_from_int(100));
    }

    /// Anti-windup holds the integrator only when the demand is *beyond* the override's
    /// range: a demand of exactly 255 % (or exactly 0 %) is not saturated, so the period
    /// integrates even though the error pushes outwards. K_p = 0.5 %/N, K_i = 1 %/(N·s),
    /// h = 0.5 s (all exact in I32F32), so K_i·h = 0.5 %/N:
    /// - I = 250 %, e = +10 N: demand = 0.5·10 + 250 = 255 %, I becomes 250 + 0.5·10 = 255 %;
    /// - I = 5 %, e = −10 N: demand = 0.5·(−10) + 5 = 0 %, I becomes 5 − 0.5·10 = 0 %.
    #[test]
    fn a_demand_exactly_at_the_range_ends_still_integrates() {
        let settings = PiSettings {
            kp: Fx::lit("0.5"),
            ki: Fx::const_from_int(1),
            integrator_min: Fx::ZERO,
            integrator_max: OVERRIDE_MAX_FX,
        };
        let half = Fx::lit("0.5");
        let f = |n: i64| Fx::const_from_int(n);

        let mut top = Pi::new(&settings, half, 250);
        let o = top.step(f(510), f(500));
        assert_eq!((o.override_pct, o.saturated), (255, false));
        assert_eq!(top.integral(), f(255));

        let mut bottom = Pi::new(&settings, half, 5);
        let o = bottom.step(f(490), f(500));
        assert_eq!((o.override_pct, o.saturated), (0, false));
        assert_eq!(bottom.integral(), Fx::ZERO);
    }

    /// The integrator's lower clamp lies in 0..=254 % (one override step below the
    /// 255 % top), the upper one above it up to 255 %.
    #[test]
    fn the_integrator_clamps_are_checked_against_their_ranges() {
        let field = |min: i32, max: i32| {
            PiSettings {
                integrator_min: Fx::from_num(min),
                integrator_max: Fx::from_num(max),
                ..DEFAULT_PI
            }
            .validate()
            .map_err(|e| e.field)
        };
        assert_eq!(field(254, 255), Ok(()));
        assert_eq!(field(255, 255), Err("pi.integrator_min"));
        assert_eq!(field(-1, 255), Err("pi.integrator_min"));
        assert_eq!(field(10, 10), Err("pi.integrator_max"));
        assert_eq!(field(10, 256), Err("pi.integrator_max"));
    }
}
