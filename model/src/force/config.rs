//! The force path's configuration: [`ForceSettings`] as a user writes them, validated once
//! into a [`ForceConfig`] that the kernel, the firmware and the vectors share.
//!
//! Each part validates its own settings ([`crate::force::control`], [`crate::force::wear`],
//! [`crate::force::estimator::settings`]) and owns its defaults; this module checks the
//! sampling rates and scales, derives the control period, and assembles the defaults of
//! `tooltouch control`'s plant. The canonical bytes and the hash of a configuration belong
//! to the wire format ([`crate::wire::force_config`]).

use crate::force::control::pi::DEFAULT_PI;
use crate::force::control::ControllerSettings;
use crate::force::estimator::settings::EstimatorSettings;
use crate::force::sampling::AdcScales;
use crate::force::wear::WearSettings;
use crate::units::{Fx, Newtons, Seconds};
use crate::validation::{check_range, positive, ForceConfigError};

/// Which force the controller regulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ForceSource {
    /// The estimator's F̂_c (eq. F1–F9, docs/domain.md): no dynamometer needed.
    Estimated,
    /// The dynamometer channel of the ADC (for comparison).
    Measured,
}

/// Unvalidated force-path settings; [`ForceSettings::validate`] makes a [`ForceConfig`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ForceSettings {
    /// ADC sample rate, Hz, `100..=10000` (docs/domain.md: 1000).
    pub sample_hz: u16,
    /// Samples per control period, `1..=1000` (docs/domain.md: 50, h = 0.05 s).
    pub samples_per_period: u16,
    /// Low-pass coefficient `2^-lowpass_shift`, `1..=8` (1 ≈ 110 Hz at 1 kHz).
    pub lowpass_shift: u8,
    /// ADC scales.
    pub scales: AdcScales,
    /// Estimator parameters.
    pub estimator: EstimatorSettings,
    /// Estimated or measured force feedback.
    pub force_source: ForceSource,
    /// Reference force F_r, N, `(0, 100000]` (docs/domain.md: 500).
    pub reference: Newtons,
    /// Override while force control is off, %, `0..=255`.
    pub manual_override: u8,
    /// The controller.
    pub controller: ControllerSettings,
    /// The wear monitor.
    pub wear: WearSettings,
}

impl Default for ForceSettings {
    /// The set-up of `tooltouch control`'s default plant: 1 kHz, 50 samples per period,
    /// 12-bit channels, a 0.05 kg·m² spindle, 20 mm workpiece radius, 500 N reference, PI.
    fn default() -> Self {
        ForceSettings {
            sample_hz: 1000,
            samples_per_period: 50,
            lowpass_shift: 1,
            scales: AdcScales::default(),
            estimator: EstimatorSettings::default(),
            force_source: ForceSource::Estimated,
            reference: Fx::const_from_int(500),
            manual_override: 100,
            controller: ControllerSettings::Pi(DEFAULT_PI),
            wear: WearSettings::default(),
        }
    }
}

impl ForceSettings {
    /// Checks every field; the error names the first bad field and its allowed range.
    pub fn validate(&self) -> Result<ForceConfig, ForceConfigError> {
        check_range(
            "sample_hz",
            Fx::from_num(self.sample_hz),
            Fx::const_from_int(100),
            Fx::const_from_int(10_000),
        )?;
        check_range(
            "samples_per_period",
            Fx::from_num(self.samples_per_period),
            Fx::ONE,
            Fx::const_from_int(1000),
        )?;
        check_range(
            "lowpass_shift",
            Fx::from_num(self.lowpass_shift),
            Fx::ONE,
            Fx::const_from_int(8),
        )?;
        let h = Fx::from_num(self.samples_per_period)
            .checked_div(Fx::from_num(self.sample_hz))
            .unwrap_or(Fx::ZERO);
        let s = &self.scales;
        positive("scales.speed_per_lsb", s.speed_per_lsb, Fx::ONE)?;
        positive(
            "scales.power_per_lsb",
            s.power_per_lsb,
            Fx::const_from_int(100),
        )?;
        positive(
            "scales.force_per_lsb",
            s.force_per_lsb,
            Fx::const_from_int(100),
        )?;
        positive(
            "scales.volts_per_lsb",
            s.volts_per_lsb,
            Fx::const_from_int(10),
        )?;
        positive("scales.amps_per_lsb", s.amps_per_lsb, Fx::ONE)?;
        self.estimator.validate(h)?;
        positive("reference", self.reference, Fx::const_from_int(100_000))?;
        match &self.controller {
            ControllerSettings::Pi(p) => p.validate()?,
            ControllerSettings::Adaptive(a) => a.validate(h)?,
            ControllerSettings::Fuzzy(f) => f.validate()?,
        }
        self.wear.validate()?;
        Ok(ForceConfig { settings: *self, h })
    }
}

/// A validated force-path configuration. Only [`ForceSettings::validate`] makes one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ForceConfig {
    settings: ForceSettings,
    h: Seconds,
}

impl ForceConfig {
    /// The settings this configuration was validated from.
    pub fn settings(&self) -> &ForceSettings {
        &self.settings
    }

    /// Control period h = samples_per_period / sample_hz, s.
    pub fn period(&self) -> Seconds {
        self.h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::force::control::pi::PiSettings;

    #[test]
    fn bad_fields_are_named() {
        let s = ForceSettings {
            controller: ControllerSettings::Pi(PiSettings {
                kp: Fx::ZERO,
                ..DEFAULT_PI
            }),
            ..Default::default()
        };
        assert_eq!(s.validate().unwrap_err().field, "pi.kp");
        let s = ForceSettings {
            controller: ControllerSettings::Pi(PiSettings {
                ki: Fx::const_from_int(-1),
                ..DEFAULT_PI
            }),
            ..Default::default()
        };
        assert_eq!(s.validate().unwrap_err().field, "pi.ki");
        let mut s = ForceSettings::default();
        s.estimator.workpiece_radius = Fx::ZERO;
        assert_eq!(
            s.validate().unwrap_err().field,
            "estimator.workpiece_radius"
        );
    }
}
