//! Range checks of configuration fields and the errors that name a bad field.
//!
//! A leaf below both paths: the measurement configuration checks integer fields
//! ([`ConfigError`]), every part of the force path checks its fixed-point fields with
//! `check_range` and `positive` ([`ForceConfigError`]), so a controller's settings need
//! neither the estimator nor the force kernel to validate themselves.

use crate::units::Fx;
use core::fmt;

/// A measurement configuration field outside its allowed range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConfigError {
    /// The field's name as in [`crate::measure::config::MeasureSettings`].
    pub field: &'static str,
    /// The rejected value.
    pub value: u64,
    /// Smallest allowed value.
    pub min: u64,
    /// Largest allowed value.
    pub max: u64,
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "configuration field `{}` = {} is out of range: allowed {}..={}",
            self.field, self.value, self.min, self.max
        )
    }
}

/// `value` must be in `min..=max`, else a [`ConfigError`] naming `field`.
pub(crate) fn check(
    field: &'static str,
    value: u64,
    min: u64,
    max: u64,
) -> Result<(), ConfigError> {
    if value < min || value > max {
        Err(ConfigError {
            field,
            value,
            min,
            max,
        })
    } else {
        Ok(())
    }
}

/// A force-path configuration field outside its allowed range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ForceConfigError {
    /// The field's path, e.g. `pi.kp`, `wear.efficiency`, `fuzzy.rules`.
    pub field: &'static str,
    /// The rejected value (a count for `fuzzy.rules`' emptiness).
    pub value: Fx,
    /// Smallest allowed value.
    pub min: Fx,
    /// Largest allowed value.
    pub max: Fx,
}

impl fmt::Display for ForceConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "force configuration field `{}` = {} is out of range: allowed {}..={}",
            self.field, self.value, self.min, self.max
        )
    }
}

/// `v` must be in `min..=max`, else a [`ForceConfigError`] naming `field`.
pub(crate) fn check_range(
    field: &'static str,
    v: Fx,
    min: Fx,
    max: Fx,
) -> Result<(), ForceConfigError> {
    if v < min || v > max {
        Err(ForceConfigError {
            field,
            value: v,
            min,
            max,
        })
    } else {
        Ok(())
    }
}

/// `v` must be in `(0, max]`: reported with the smallest positive value as the minimum.
pub(crate) fn positive(field: &'static str, v: Fx, max: Fx) -> Result<(), ForceConfigError> {
    check_range(field, v, Fx::DELTA, max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_field_and_its_range() {
        let e = check("i_def", 9, 0, 8).unwrap_err();
        assert_eq!((e.field, e.value, e.min, e.max), ("i_def", 9, 0, 8));
        assert!(check("i_def", 8, 0, 8).is_ok());
        let e = positive("pi.kp", Fx::ZERO, Fx::ONE).unwrap_err();
        assert_eq!((e.field, e.min, e.max), ("pi.kp", Fx::DELTA, Fx::ONE));
        assert!(check_range("x", Fx::ONE, Fx::ZERO, Fx::ONE).is_ok());
    }
}
