//! The measurement front end's configuration: one validated type that the model, the
//! firmware and hdl-gen all read, so a width or a threshold is never typed twice.
//!
//! Build it from [`MeasureSettings`] (plain public fields, e.g. parsed from TOML) with
//! [`MeasureSettings::validate`]; every bad field is a [`ConfigError`] naming the field and
//! its allowed range. Register widths (`*_bits`) are derived here and nowhere else. The
//! configuration's canonical bytes and its hash belong to the wire format
//! ([`crate::wire::measure_config`]).

use crate::measure::checks::MeasureChecks;
use crate::validation::{check, ConfigError};

/// Which contact bit a pulse counts with (docs/domain.md §2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum ContactRule {
    /// The contact level at the FES edge. Misses bursts shorter than one pulse period.
    Sampled,
    /// Contact was active at any time since the previous FES pulse (a bit set by contact,
    /// consumed by each FES pulse).
    Sticky,
}

/// How the digital capacitor charges and discharges once per FES pulse (docs/domain.md §2.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case", tag = "law"))]
pub enum ChargeLaw {
    /// Add `charge_step` per pulse in contact, subtract `discharge_step` per pulse without,
    /// in charge LSBs, saturating at full scale and at zero.
    Linear {
        /// Charge added per contact pulse, LSBs, `1..=full scale`.
        charge_step: u32,
        /// Charge removed per pulse without contact, LSBs, `1..=full scale`.
        discharge_step: u32,
    },
    /// RC-like: add `max(1, (full - q) >> charge_shift)` per contact pulse, subtract
    /// `max(1, q >> discharge_shift)` per pulse without (so both ends are reached exactly).
    Exponential {
        /// Time constant of charging, in pulses, as a power of two: `0..=charge_bits`.
        charge_shift: u8,
        /// Time constant of discharging, in pulses, as a power of two: `0..=charge_bits`.
        discharge_shift: u8,
    },
}

/// Which detector decides "position reached, register now" (docs/domain.md §2.1, §2.3, §2.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum DecisionMethod {
    /// The first (filtered) contact edge: measures near the largest diameter (docs/domain.md §2.1).
    /// Spelled `single-pulse`; the old `single_pulse` is read for one release (the
    /// command line warns about it).
    #[cfg_attr(feature = "serde", serde(alias = "single_pulse"))]
    SinglePulse,
    /// Device 1: the pulse counter's count exceeds `i_def` within the window (docs/domain.md §2.3).
    Counter,
    /// Device 2: the capacitor charge crosses the fire threshold upward (docs/domain.md §2.4).
    Density,
}

/// Unvalidated settings, as a user writes them. Turn them into a [`MeasureConfig`] with
/// [`MeasureSettings::validate`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MeasureSettings {
    /// FES encoder pulses per spindle revolution, `16..=16384` (docs/domain.md: 1024).
    pub pulses_per_rev: u16,
    /// Decision when the window's contact-pulse count exceeds this, `0..pulses_per_rev *
    /// window_revs` (50 % of 1024 is 512).
    pub i_def: u32,
    /// Revolutions per counting window (index pulses between resets), `1..=16`.
    pub window_revs: u8,
    /// Sampled or sticky contact bit.
    pub contact_rule: ContactRule,
    /// Width of the capacitor charge register, bits, `4..=24`; the charge is
    /// UQ0.`charge_bits` of full scale.
    pub charge_bits: u8,
    /// Charge/discharge law and its steps.
    pub charge_law: ChargeLaw,
    /// Fire when the charge reaches this from below, LSBs, `1..=full scale`.
    pub fire_threshold: u32,
    /// Re-arm once the charge falls below this, LSBs, `0..fire_threshold` (hysteresis).
    pub rearm_threshold: u32,
    /// Glitch filter: a new input level passes once seen on `glitch_cycles + 1`
    /// consecutive clocks, `0..=255`.
    pub glitch_cycles: u8,
    /// Width of the scale position counter, bits, `8..=32` (two's complement, wrapping).
    pub scale_bits: u8,
    /// Which detector drives "register now" and the decision latch.
    pub method: DecisionMethod,
    /// The measurement status's checks and their thresholds (`[measure.checks]`).
    pub checks: MeasureChecks,
}

impl Default for MeasureSettings {
    /// The papers' set-up: 1024 ppr, 50 % over one revolution, sticky contact, a 4-clock
    /// glitch filter, a 24-bit scale, and a 16-bit capacitor that charges and discharges by
    /// the same step (so it only gains charge while the density is above 50 %), firing at
    /// half of full scale — the charge of 512 net contact pulses, half a revolution — and
    /// re-arming below 1/8.
    fn default() -> Self {
        MeasureSettings {
            pulses_per_rev: 1024,
            i_def: 512,
            window_revs: 1,
            contact_rule: ContactRule::Sticky,
            charge_bits: 16,
            charge_law: ChargeLaw::Linear {
                charge_step: 64,
                discharge_step: 64,
            },
            fire_threshold: 32768,
            rearm_threshold: 8192,
            glitch_cycles: 4,
            scale_bits: 24,
            method: DecisionMethod::Counter,
            checks: MeasureChecks::default(),
        }
    }
}

/// Number of bits needed to hold every value in `0..=max`, at least 1.
pub const fn bits_for(max: u64) -> u8 {
    let bits = 64 - max.leading_zeros();
    if bits == 0 {
        1
    } else {
        bits as u8
    }
}

impl MeasureSettings {
    /// Checks every field and derives the register widths.
    ///
    /// Errors name the first field out of range and its allowed range.
    pub fn validate(&self) -> Result<MeasureConfig, ConfigError> {
        check("pulses_per_rev", self.pulses_per_rev.into(), 16, 16384)?;
        check("window_revs", self.window_revs.into(), 1, 16)?;
        let window_pulses = u32::from(self.pulses_per_rev) * u32::from(self.window_revs);
        check("i_def", self.i_def.into(), 0, u64::from(window_pulses) - 1)?;
        check("charge_bits", self.charge_bits.into(), 4, 24)?;
        let full = (1u32 << self.charge_bits) - 1;
        match self.charge_law {
            ChargeLaw::Linear {
                charge_step,
                discharge_step,
            } => {
                check("charge_step", charge_step.into(), 1, full.into())?;
                check("discharge_step", discharge_step.into(), 1, full.into())?;
            }
            ChargeLaw::Exponential {
                charge_shift,
                discharge_shift,
            } => {
                check(
                    "charge_shift",
                    charge_shift.into(),
                    0,
                    self.charge_bits.into(),
                )?;
                check(
                    "discharge_shift",
                    discharge_shift.into(),
                    0,
                    self.charge_bits.into(),
                )?;
            }
        }
        check("fire_threshold", self.fire_threshold.into(), 1, full.into())?;
        check(
            "rearm_threshold",
            self.rearm_threshold.into(),
            0,
            u64::from(self.fire_threshold) - 1,
        )?;
        check("scale_bits", self.scale_bits.into(), 8, 32)?;
        self.checks.validate(self.pulses_per_rev)?;
        Ok(MeasureConfig {
            settings: *self,
            count_bits: bits_for(window_pulses.into()),
            full_charge: full,
        })
    }
}

/// A validated configuration with its derived widths. Only [`MeasureSettings::validate`]
/// makes one, so every kernel may rely on the ranges documented there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MeasureConfig {
    settings: MeasureSettings,
    count_bits: u8,
    full_charge: u32,
}

impl Default for MeasureConfig {
    fn default() -> Self {
        // The defaults are inside every range; `defaults_are_valid` proves it.
        MeasureSettings::default()
            .validate()
            .unwrap_or_else(|_| unreachable_default())
    }
}

#[cold]
fn unreachable_default() -> MeasureConfig {
    // Never reached (see `defaults_are_valid`); kept panic-free for the firmware by
    // building the smallest valid configuration by hand.
    MeasureConfig {
        settings: MeasureSettings {
            pulses_per_rev: 16,
            i_def: 8,
            window_revs: 1,
            contact_rule: ContactRule::Sampled,
            charge_bits: 4,
            charge_law: ChargeLaw::Linear {
                charge_step: 1,
                discharge_step: 1,
            },
            fire_threshold: 8,
            rearm_threshold: 4,
            glitch_cycles: 0,
            scale_bits: 8,
            method: DecisionMethod::Counter,
            checks: MeasureChecks::OFF,
        },
        count_bits: 5,
        full_charge: 15,
    }
}

impl MeasureConfig {
    /// The settings this configuration was validated from.
    pub fn settings(&self) -> &MeasureSettings {
        &self.settings
    }
    /// FES pulses per revolution.
    pub fn pulses_per_rev(&self) -> u32 {
        self.settings.pulses_per_rev.into()
    }
    /// Pulses per counting window: `pulses_per_rev * window_revs`, the count's maximum.
    pub fn window_pulses(&self) -> u32 {
        self.pulses_per_rev() * u32::from(self.settings.window_revs)
    }
    /// Width of the pulse-count registers, bits: holds `0..=window_pulses`.
    pub fn count_bits(&self) -> u8 {
        self.count_bits
    }
    /// Full-scale capacitor charge, LSBs: `2^charge_bits - 1`.
    pub fn full_charge(&self) -> u32 {
        self.full_charge
    }
    /// Width of the glitch filter's stability counter, bits.
    pub fn glitch_bits(&self) -> u8 {
        bits_for(self.settings.glitch_cycles.into())
    }
    /// Width of the window's revolution counter, bits.
    pub fn window_rev_bits(&self) -> u8 {
        bits_for(u64::from(self.settings.window_revs) - 1)
    }
    /// Clock cycles from an input pin change to the outputs that react to it at cycle
    /// level: 2 synchronizer flip-flops, the glitch filter register plus `glitch_cycles`,
    /// and the registered kernel update: `3 + glitch_cycles`.
    pub fn latency_cycles(&self) -> u32 {
        3 + u32::from(self.settings.glitch_cycles)
    }
    /// Contact pulses a window closed after the decision must count to confirm it: one for
    /// the single-pulse method, else `confirm_percent` % of [`Self::window_pulses`]
    /// (rounded down).
    pub fn confirm_count(&self) -> u32 {
        match self.settings.method {
            DecisionMethod::SinglePulse => 1,
            _ => {
                let pct = u64::from(self.settings.checks.confirm_percent);
                (u64::from(self.window_pulses()) * pct / 100) as u32
            }
        }
    }
    /// Width of the revolution's FES pulse counter, bits: holds
    /// `0..=pulses_per_rev + pulse_tolerance + 1`.
    pub fn rev_pulse_bits(&self) -> u8 {
        let most = u64::from(self.settings.pulses_per_rev)
            + u64::from(self.settings.checks.pulse_tolerance);
        bits_for(most + 1)
    }
    /// Width of the FES watchdog's tick counter, bits: holds `0..=fes_timeout_cycles`.
    pub fn fes_idle_bits(&self) -> u8 {
        bits_for(self.settings.checks.fes_timeout_cycles.into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        let c = MeasureSettings::default().validate().unwrap();
        assert_eq!(c.count_bits(), 11);
        assert_eq!(c.full_charge(), 65535);
        assert_eq!(c.latency_cycles(), 7);
        assert_eq!(MeasureConfig::default(), c);
    }

    #[test]
    fn i_def_above_window_is_rejected_with_its_range() {
        let s = MeasureSettings {
            i_def: 1024,
            ..Default::default()
        };
        let e = s.validate().unwrap_err();
        assert_eq!(e.field, "i_def");
        assert_eq!((e.min, e.max), (0, 1023));
    }

    #[test]
    fn rearm_must_be_below_fire() {
        let s = MeasureSettings {
            rearm_threshold: 49152,
            ..Default::default()
        };
        assert_eq!(s.validate().unwrap_err().field, "rearm_threshold");
    }

    /// The re-arm level may come as close as one LSB below the fire level, no closer
    /// (docs/domain.md §2.4: the hysteresis needs two distinct levels).
    #[test]
    fn rearm_may_be_one_below_fire_and_no_closer() {
        let fire = MeasureSettings::default().fire_threshold;
        let with_rearm = |rearm_threshold| MeasureSettings {
            rearm_threshold,
            ..Default::default()
        };
        assert!(with_rearm(fire - 1).validate().is_ok());
        let e = with_rearm(fire).validate().unwrap_err();
        assert_eq!(e.field, "rearm_threshold");
        assert_eq!((e.min, e.max), (0, u64::from(fire) - 1));
    }

    /// The panic-free fallback of `Default` is itself a valid configuration.
    #[test]
    fn the_unreachable_fallback_is_valid() {
        let c = unreachable_default();
        assert_eq!(c.settings().validate(), Ok(c));
    }

    #[test]
    fn zero_step_is_rejected() {
        let s = MeasureSettings {
            charge_law: ChargeLaw::Linear {
                charge_step: 0,
                discharge_step: 1,
            },
            ..Default::default()
        };
        assert_eq!(s.validate().unwrap_err().field, "charge_step");
    }

    /// Register widths worked out by hand: a stability counter holding 0..=glitch_cycles,
    /// a revolution counter holding 0..=window_revs − 1.
    #[test]
    fn counter_widths_hold_their_ranges() {
        let config = |glitch_cycles, window_revs| {
            MeasureSettings {
                glitch_cycles,
                window_revs,
                ..Default::default()
            }
            .validate()
            .unwrap()
        };
        // 0 cycles still needs a 1-bit register; 2 → 2 bits (10b); 255 → 8 bits.
        assert_eq!(config(0, 1).glitch_bits(), 1);
        assert_eq!(config(2, 1).glitch_bits(), 2);
        assert_eq!(config(255, 1).glitch_bits(), 8);
        // window of 1 revolution: the counter only holds 0 (1 bit); 3 → 0..=2, 2 bits;
        // 4 → 0..=3, 2 bits; 5 → 0..=4, 3 bits.
        assert_eq!(config(0, 1).window_rev_bits(), 1);
        assert_eq!(config(0, 3).window_rev_bits(), 2);
        assert_eq!(config(0, 4).window_rev_bits(), 2);
        assert_eq!(config(0, 5).window_rev_bits(), 3);
    }

    #[test]
    fn bits_for_counts() {
        assert_eq!(bits_for(0), 1);
        assert_eq!(bits_for(1), 1);
        assert_eq!(bits_for(1024), 11);
        assert_eq!(bits_for(1023), 10);
    }
}
