//! Variable-gain adaptive force controller, Lin & Masory form (docs/domain.md §3, eq. F11).
//!
//! `f(i) = f(i−1) + K̄_c(i−1)·h·(F_r − F̂_c(i))` — an integral controller on the feed
//! override f (percent) whose gain is re-tuned every period so that the open-loop gain
//! `K̄_c·K̂` stays at `open_loop_gain` (1/s): `K̄_c = open_loop_gain / K̂`, where `K̂` is the
//! estimated static process gain `F̂_c(i) / f(i−1)` (N per %, i.e. F10's `K_s·a` per percent
//! of programmed feed), low-passed by `2^-gain_filter_shift`.
//!
//! Guards against division by ~0: K̂ is only re-estimated while `f(i−1) ≥ min_override` and
//! `F̂_c ≥ min_force` (otherwise the last estimate is held — e.g. in air or at feed hold),
//! and it is clamped to `[gain_min, gain_max]` with `gain_min > 0` before `K̄_c` divides by
//! it. The override state is clamped to `[0, 255]` (anti-windup of the integral form).
//!
//! Formats: I32F32 throughout (K̂ in N/%, K̄_c in %/(N·s), f in %), saturating.

use super::interface::{
    clamp_override, quantize, ControlOutput, ForceController, Percent, OVERRIDE_MAX_FX,
};
use crate::units::{Fx, Newtons};
use crate::validation::{check_range, positive, ForceConfigError};

/// Adaptive-controller settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AdaptiveSettings {
    /// Desired open-loop gain K̄_c·K̂, 1/s, `(0, 1/h]` (`K·h ≤ 1` keeps the loop stable on
    /// a static process).
    pub open_loop_gain: Fx,
    /// Smallest process-gain estimate, N/%, `(0, 10000]`.
    pub gain_min: Fx,
    /// Largest process-gain estimate, N/%, `[gain_min, 10000]`.
    pub gain_max: Fx,
    /// Process-gain estimate before the first update, N/%, `[gain_min, gain_max]`.
    pub initial_gain: Fx,
    /// Low-pass of the estimate, `K̂ += (raw − K̂) >> shift`, `0..=8` (0 = none).
    pub gain_filter_shift: u8,
    /// Re-estimate only while the previous override is at least this, %, `(0, 255]`.
    pub min_override: Percent,
    /// Re-estimate only while the force feedback is at least this, N, `(0, 100000]`.
    pub min_force: Newtons,
}

impl AdaptiveSettings {
    /// Checks every field (`adaptive.<field>`); `h` is the control period, s.
    pub fn validate(&self, h: Fx) -> Result<(), ForceConfigError> {
        let k_max = Fx::ONE.checked_div(h).unwrap_or(Fx::ZERO);
        positive("adaptive.open_loop_gain", self.open_loop_gain, k_max)?;
        let g_max = Fx::const_from_int(10000);
        positive("adaptive.gain_min", self.gain_min, g_max)?;
        check_range("adaptive.gain_max", self.gain_max, self.gain_min, g_max)?;
        check_range(
            "adaptive.initial_gain",
            self.initial_gain,
            self.gain_min,
            self.gain_max,
        )?;
        check_range(
            "adaptive.gain_filter_shift",
            Fx::from_num(self.gain_filter_shift),
            Fx::ZERO,
            Fx::const_from_int(8),
        )?;
        positive("adaptive.min_override", self.min_override, OVERRIDE_MAX_FX)?;
        positive(
            "adaptive.min_force",
            self.min_force,
            Fx::const_from_int(100_000),
        )
    }
}

/// Default adaptive controller: open-loop gain 4 /s (K·h = 0.2), K̂ in 0.5..=100 N/%.
pub const DEFAULT_ADAPTIVE: AdaptiveSettings = AdaptiveSettings {
    open_loop_gain: Fx::const_from_int(4),
    gain_min: Fx::lit("0.5"),
    gain_max: Fx::const_from_int(100),
    initial_gain: Fx::const_from_int(6),
    gain_filter_shift: 2,
    min_override: Fx::const_from_int(5),
    min_force: Fx::const_from_int(50),
};

/// The adaptive kernel's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Adaptive {
    s: AdaptiveSettings,
    h: Fx,
    feed: Percent,
    gain_estimate: Fx,
    controller_gain: Fx,
}

impl Adaptive {
    /// A controller for validated `s`, period `h` (s), starting at `override_pct`.
    pub fn new(s: &AdaptiveSettings, h: Fx, override_pct: u8) -> Adaptive {
        let mut a = Adaptive {
            s: *s,
            h,
            feed: Fx::ZERO,
            gain_estimate: s.initial_gain,
            controller_gain: Fx::ZERO,
        };
        a.controller_gain = a.gain_for(s.initial_gain);
        a.reset(override_pct);
        a
    }

    fn gain_for(&self, k_hat: Fx) -> Fx {
        let k_hat = k_hat.max(self.s.gain_min).min(self.s.gain_max);
        self.s.open_loop_gain.checked_div(k_hat).unwrap_or(Fx::ZERO)
    }

    /// The estimated static process gain K̂, N/%.
    pub fn gain_estimate(&self) -> Fx {
        self.gain_estimate
    }

    /// The controller gain K̄_c in use for the next period, %/(N·s).
    pub fn controller_gain(&self) -> Fx {
        self.controller_gain
    }

    /// The override state f (the last period's clamped demand, before rounding), %, I32F32.
    pub fn override_state(&self) -> Percent {
        self.feed
    }
}

impl ForceController for Adaptive {
    /// F11 with the previous period's gain, then the gain re-tuned from F̂_c / f(i−1).
    fn step(&mut self, reference: Newtons, force: Newtons) -> ControlOutput {
        let e = reference.saturating_sub(force);
        let demand = self.feed.saturating_add(
            self.controller_gain
                .saturating_mul(self.h)
                .saturating_mul(e),
        );
        let (u, saturated) = clamp_override(demand);
        if self.feed >= self.s.min_override && force >= self.s.min_force {
            if let Some(raw) = force.checked_div(self.feed) {
                let raw = raw.max(self.s.gain_min).min(self.s.gain_max);
                let delta =
                    raw.saturating_sub(self.gain_estimate) >> u32::from(self.s.gain_filter_shift);
                self.gain_estimate = self
                    .gain_estimate
                    .saturating_add(delta)
                    .max(self.s.gain_min)
                    .min(self.s.gain_max);
            }
        }
        self.controller_gain = self.gain_for(self.gain_estimate);
        self.feed = u;
        ControlOutput {
            override_pct: quantize(u),
            saturated,
        }
    }

    /// Override state to `override_pct`; the gain estimate is kept.
    fn reset(&mut self, override_pct: u8) {
        self.feed = Fx::from_num(override_pct);
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for Adaptive {
    /// The override state `adaptive.feed` (I32F32 clamped to `0..=255`), the process-gain
    /// estimate `adaptive.gain_estimate` (clamped to `gain_min..=gain_max`) and the
    /// controller gain `adaptive.controller_gain` (I32F32).
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        let bits = |v: Fx| i128::from(v.to_bits());
        let feed = Format::I32F32.clamped(0, bits(OVERRIDE_MAX_FX));
        f(Register::fx("adaptive.feed", feed, self.feed));
        let gain = Format::I32F32.clamped(bits(self.s.gain_min), bits(self.s.gain_max));
        f(Register::fx(
            "adaptive.gain_estimate",
            gain,
            self.gain_estimate,
        ));
        f(Register::fx(
            "adaptive.controller_gain",
            Format::I32F32,
            self.controller_gain,
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_field_is_checked_against_its_range() {
        let h = Fx::lit("0.0625");
        assert_eq!(DEFAULT_ADAPTIVE.validate(h), Ok(()));
        let field = |s: AdaptiveSettings| s.validate(h).map_err(|e| e.field);
        let d = DEFAULT_ADAPTIVE;
        // K·h ≤ 1: at most 16 /s at h = 1/16 s.
        let at_limit = AdaptiveSettings {
            open_loop_gain: Fx::const_from_int(16),
            ..d
        };
        assert_eq!(field(at_limit), Ok(()));
        let cases = [
            (
                AdaptiveSettings {
                    open_loop_gain: Fx::const_from_int(16) + Fx::DELTA,
                    ..d
                },
                "adaptive.open_loop_gain",
            ),
            (
                AdaptiveSettings {
                    gain_min: Fx::ZERO,
                    ..d
                },
                "adaptive.gain_min",
            ),
            (
                AdaptiveSettings {
                    gain_max: Fx::lit("0.25"),
                    ..d
                },
                "adaptive.gain_max",
            ),
            (
                AdaptiveSettings {
                    initial_gain: Fx::const_from_int(101),
                    ..d
                },
                "adaptive.initial_gain",
            ),
            (
                AdaptiveSettings {
                    gain_filter_shift: 9,
                    ..d
                },
                "adaptive.gain_filter_shift",
            ),
            (
                AdaptiveSettings {
                    min_override: Fx::ZERO,
                    ..d
                },
                "adaptive.min_override",
            ),
            (
                AdaptiveSettings {
                    min_force: Fx::const_from_int(100_001),
                    ..d
                },
                "adaptive.min_force",
            ),
        ];
        for (s, name) in cases {
            assert_eq!(field(s), Err(name));
        }
    }

    #[test]
    fn gain_tracks_a_static_process() {
        let s = AdaptiveSettings {
            open_loop_gain: Fx::const_from_int(4),
            gain_min: Fx::lit("0.1"),
            gain_max: Fx::const_from_int(100),
            initial_gain: Fx::const_from_int(1),
            gain_filter_shift: 0,
            min_override: Fx::const_from_int(5),
            min_force: Fx::const_from_int(10),
        };
        let mut c = Adaptive::new(&s, Fx::lit("0.05"), 100);
        // static process: F = 6 N/% · f
        let mut f = Fx::const_from_int(100);
        for _ in 0..100 {
            let force = f.saturating_mul(Fx::const_from_int(6));
            let o = c.step(Fx::const_from_int(500), force);
            f = Fx::from_num(o.override_pct);
        }
        assert_eq!(c.gain_estimate().round(), Fx::const_from_int(6));
        // 500 N / 6 N/% = 83.3 %
        assert_eq!(f, Fx::const_from_int(83));
    }
}
