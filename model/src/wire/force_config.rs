//! The force configuration's canonical bytes: the input of [`ForceConfig::hash`] (the
//! `force_hash` of vector headers) and the data that [`crate::wire::force_chunks`] carries
//! in [`crate::wire::kind::FORCE_CONFIG_CHUNK`] records; its encoder and its decoder.
//!
//! Every setting in declaration order, little-endian, fixed-point values as the raw bits of
//! their I32F32 (i64), enums as a tag byte followed by their variant's fields:
//!
//! ```text
//! version u16 | sample_hz u16 | samples_per_period u16 | lowpass_shift u8
//! scales: speed, power, force, volts, amps per LSB (5 × fx)
//! estimator: R_s, J, B, T_fco, f0, f1, g0, g1, min_speed, Δ_th, k_slip, radius (12 × fx)
//! slip_hold_periods u8 | force_source u8 | manual_override u8 | reference fx
//! controller tag u8 (CONTROLLER_TAG_AT), then
//!   0 PI:       kp, ki, integrator_min, integrator_max (4 × fx)
//!   1 adaptive: open_loop_gain, gain_min, gain_max, initial_gain, min_override,
//!               min_force (6 × fx), gain_filter_shift u8
//!   2 fuzzy:    ge, gde, gdu (3 × fx), rules 7 × 7 i8 (row e, column Δe)
//! wear: set_count u8 | lowpass_shift u8 | debounce_periods u8 | efficiency fx
//!       set_count × (mean_power_limit fx, idle_power fx)
//!       threshold tag u8: 0 updating | 1 constant, then its power fx
//!       settle_periods u8 (version 2)
//!       power_lag_gain tag u8: 0 none | 1 some, then its gain fx (version 3)
//! ```
//! A new field is appended to both [`ForceConfig::canonical_bytes`] and
//! [`decode_force_settings`] with a new [`FORCE_CONFIG_FORMAT_VERSION`].

use crate::fnv::fnv1a;
use crate::force::config::{ForceConfig, ForceSettings, ForceSource};
use crate::force::control::fuzzy::SETS;
use crate::force::control::{AdaptiveSettings, ControllerSettings, FuzzySettings, PiSettings};
use crate::force::estimator::settings::EstimatorSettings;
use crate::force::sampling::AdcScales;
use crate::force::wear::{ConditionSet, Threshold, WearSettings, MAX_CONDITION_SETS};
use crate::units::Fx;

/// Version of the force configuration's canonical encoding; part of [`ForceConfig::hash`].
pub const FORCE_CONFIG_FORMAT_VERSION: u16 = 3;

/// Largest canonical force configuration, bytes ([`ForceConfig::canonical_bytes`]' buffer).
pub const FORCE_CONFIG_MAX: usize = 512;

/// Bytes of one fixed-point value (the i64 of its I32F32 bits).
const FX_LEN: usize = 8;

/// Byte offset of the controller tag: after the version (2), the rates (2 × 2), the
/// low-pass shift (1), 5 scales, 12 estimator values, 3 bytes and the reference.
pub const CONTROLLER_TAG_AT: usize = 2 + 2 * 2 + 1 + 5 * FX_LEN + 12 * FX_LEN + 3 + FX_LEN;

/// The canonical bytes do not decode at byte `at`: an unknown format version or enum
/// value, too few bytes, or bytes left over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ForceEncodingError {
    /// Byte offset in the canonical encoding.
    pub at: usize,
}

impl ForceConfig {
    /// Canonical little-endian encoding of every setting (fixed-point values as their raw
    /// bits), fed to [`Self::hash`]. Returns the buffer and the bytes used.
    pub fn canonical_bytes(&self) -> ([u8; FORCE_CONFIG_MAX], usize) {
        let mut w = Writer {
            buf: [0; FORCE_CONFIG_MAX],
            n: 0,
        };
        let s = self.settings();
        w.put(&FORCE_CONFIG_FORMAT_VERSION.to_le_bytes());
        w.put(&s.sample_hz.to_le_bytes());
        w.put(&s.samples_per_period.to_le_bytes());
        w.put(&[s.lowpass_shift]);
        let c = &s.scales;
        for v in [
            c.speed_per_lsb,
            c.power_per_lsb,
            c.force_per_lsb,
            c.volts_per_lsb,
            c.amps_per_lsb,
        ] {
            w.fx(v);
        }
        let e = &s.estimator;
        for v in [
            e.stator_resistance,
            e.inertia,
            e.viscous_nominal,
            e.coulomb_nominal,
            e.friction_f[0],
            e.friction_f[1],
            e.friction_g[0],
            e.friction_g[1],
            e.min_speed,
            e.switch_threshold,
            e.slip_gain,
            e.workpiece_radius,
        ] {
            w.fx(v);
        }
        w.put(&[e.slip_hold_periods, s.force_source as u8, s.manual_override]);
        w.fx(s.reference);
        match &s.controller {
            ControllerSettings::Pi(p) => {
                w.put(&[0]);
                for v in [p.kp, p.ki, p.integrator_min, p.integrator_max] {
                    w.fx(v);
                }
            }
            ControllerSettings::Adaptive(a) => {
                w.put(&[1]);
                for v in [
                    a.open_loop_gain,
                    a.gain_min,
                    a.gain_max,
                    a.initial_gain,
                    a.min_override,
                    a.min_force,
                ] {
                    w.fx(v);
                }
                w.put(&[a.gain_filter_shift]);
            }
            ControllerSettings::Fuzzy(f) => {
                w.put(&[2]);
                for v in [f.ge, f.gde, f.gdu] {
                    w.fx(v);
                }
                for row in &f.rules {
                    for &r in row {
                        w.put(&r.to_le_bytes());
                    }
                }
            }
        }
        let wr = &s.wear;
        w.put(&[wr.set_count, wr.lowpass_shift, wr.debounce_periods]);
        w.fx(wr.efficiency);
        for set in wr.sets.iter().take(usize::from(wr.set_count)) {
            w.fx(set.mean_power_limit);
            w.fx(set.idle_power);
        }
        match wr.threshold {
            Threshold::Updating => w.put(&[0]),
            Threshold::Constant(p) => {
                w.put(&[1]);
                w.fx(p);
            }
        }
        w.put(&[wr.settle_periods]);
        match wr.power_lag_gain {
            None => w.put(&[0]),
            Some(g) => {
                w.put(&[1]);
                w.fx(g);
            }
        }
        (w.buf, w.n)
    }

    /// 64-bit FNV-1a of [`Self::canonical_bytes`]: the `force_hash` of vector headers.
    pub fn hash(&self) -> u64 {
        let (bytes, n) = self.canonical_bytes();
        fnv1a(bytes.get(..n).unwrap_or(&bytes))
    }
}

/// Appends fields to the canonical encoding (a fixed buffer; bytes past its end are
/// dropped, which no valid configuration reaches).
struct Writer {
    buf: [u8; FORCE_CONFIG_MAX],
    n: usize,
}

impl Writer {
    fn put(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if let Some(slot) = self.buf.get_mut(self.n) {
                *slot = b;
                self.n = self.n.saturating_add(1);
            }
        }
    }
    fn fx(&mut self, v: Fx) {
        self.put(&v.to_bits().to_le_bytes());
    }
}

/// Reads the canonical encoding field by field.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], ForceEncodingError> {
        let bad = ForceEncodingError { at: self.at };
        let end = self.at.checked_add(N).ok_or(bad)?;
        let src = self.bytes.get(self.at..end).ok_or(bad)?;
        let mut out = [0u8; N];
        out.copy_from_slice(src);
        self.at = end;
        Ok(out)
    }
    fn u8(&mut self) -> Result<u8, ForceEncodingError> {
        Ok(self.take::<1>()?[0])
    }
    fn u16(&mut self) -> Result<u16, ForceEncodingError> {
        Ok(u16::from_le_bytes(self.take()?))
    }
    fn fx(&mut self) -> Result<Fx, ForceEncodingError> {
        Ok(Fx::from_bits(i64::from_le_bytes(self.take()?)))
    }
    /// An enum tag in `0..count`; the error points at the tag byte.
    fn tag(&mut self, count: u8) -> Result<u8, ForceEncodingError> {
        let at = self.at;
        let t = self.u8()?;
        if t >= count {
            return Err(ForceEncodingError { at });
        }
        Ok(t)
    }
}

/// Decodes [`ForceConfig::canonical_bytes`]' used part back into settings (not yet
/// validated; condition sets past `set_count` are left at their default). Every byte must
/// be used.
pub fn decode_force_settings(bytes: &[u8]) -> Result<ForceSettings, ForceEncodingError> {
    let mut c = Cursor { bytes, at: 0 };
    if c.u16()? != FORCE_CONFIG_FORMAT_VERSION {
        return Err(ForceEncodingError { at: 0 });
    }
    let sample_hz = c.u16()?;
    let samples_per_period = c.u16()?;
    let lowpass_shift = c.u8()?;
    let scales = AdcScales {
        speed_per_lsb: c.fx()?,
        power_per_lsb: c.fx()?,
        force_per_lsb: c.fx()?,
        volts_per_lsb: c.fx()?,
        amps_per_lsb: c.fx()?,
    };
    let mut e = [Fx::ZERO; 12];
    for v in e.iter_mut() {
        *v = c.fx()?;
    }
    let [stator_resistance, inertia, viscous_nominal, coulomb_nominal, f0, f1, g0, g1, min_speed, switch_threshold, slip_gain, workpiece_radius] =
        e;
    let slip_hold_periods = c.u8()?;
    let force_source = match c.tag(2)? {
        0 => ForceSource::Estimated,
        _ => ForceSource::Measured,
    };
    let manual_override = c.u8()?;
    let reference = c.fx()?;
    let controller = match c.tag(3)? {
        0 => ControllerSettings::Pi(PiSettings {
            kp: c.fx()?,
            ki: c.fx()?,
            integrator_min: c.fx()?,
            integrator_max: c.fx()?,
        }),
        1 => ControllerSettings::Adaptive(AdaptiveSettings {
            open_loop_gain: c.fx()?,
            gain_min: c.fx()?,
            gain_max: c.fx()?,
            initial_gain: c.fx()?,
            min_override: c.fx()?,
            min_force: c.fx()?,
            gain_filter_shift: c.u8()?,
        }),
        _ => {
            let (ge, gde, gdu) = (c.fx()?, c.fx()?, c.fx()?);
            let mut rules = [[0i8; SETS]; SETS];
            for r in rules.iter_mut().flatten() {
                *r = i8::from_le_bytes(c.take()?);
            }
            ControllerSettings::Fuzzy(FuzzySettings {
                ge,
                gde,
                gdu,
                rules,
            })
        }
    };
    let set_count_at = c.at;
    let set_count = c.u8()?;
    let wear_lowpass = c.u8()?;
    let debounce_periods = c.u8()?;
    let efficiency = c.fx()?;
    if usize::from(set_count) > MAX_CONDITION_SETS {
        return Err(ForceEncodingError { at: set_count_at });
    }
    let mut sets = [ConditionSet::default(); MAX_CONDITION_SETS];
    for set in sets.iter_mut().take(usize::from(set_count)) {
        set.mean_power_limit = c.fx()?;
        set.idle_power = c.fx()?;
    }
    let threshold = match c.tag(2)? {
        0 => Threshold::Updating,
        _ => Threshold::Constant(c.fx()?),
    };
    let settle_periods = c.u8()?;
    let power_lag_gain = match c.tag(2)? {
        0 => None,
        _ => Some(c.fx()?),
    };
    if c.at != bytes.len() {
        return Err(ForceEncodingError { at: c.at });
    }
    Ok(ForceSettings {
        sample_hz,
        samples_per_period,
        lowpass_shift,
        scales,
        estimator: EstimatorSettings {
            stator_resistance,
            inertia,
            viscous_nominal,
            coulomb_nominal,
            friction_f: [f0, f1],
            friction_g: [g0, g1],
            min_speed,
            switch_threshold,
            slip_gain,
            slip_hold_periods,
            workpiece_radius,
        },
        force_source,
        reference,
        manual_override,
        controller,
        wear: WearSettings {
            sets,
            set_count,
            efficiency,
            lowpass_shift: wear_lowpass,
            debounce_periods,
            threshold,
            settle_periods,
            power_lag_gain,
        },
    })
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::testing::force::force_settings;
    use proptest::prelude::*;

    #[test]
    fn defaults_are_valid_and_hash_is_stable() {
        let c = ForceSettings::default().validate().unwrap();
        assert!((c.period() - Fx::lit("0.05")).abs() <= Fx::DELTA);
        assert_eq!(c.hash(), c.hash());
        let s = ForceSettings {
            reference: Fx::const_from_int(400),
            ..Default::default()
        };
        assert_ne!(s.validate().unwrap().hash(), c.hash());
    }

    #[test]
    fn the_controller_tag_is_where_the_layout_says() {
        let c = ForceSettings {
            controller: ControllerSettings::Adaptive(
                crate::force::control::adaptive::DEFAULT_ADAPTIVE,
            ),
            ..Default::default()
        }
        .validate()
        .unwrap();
        assert_eq!(c.canonical_bytes().0[CONTROLLER_TAG_AT], 1);
    }

    proptest! {
        #[test]
        fn random_force_settings_round_trip(s in force_settings()) {
                        let c = s.validate().map_err(|e| TestCaseError::fail(std::format!("{e}")))?;
            let (bytes, n) = c.canonical_bytes();
            prop_assert!(n <= FORCE_CONFIG_MAX);
            prop_assert_eq!(decode_force_settings(&bytes[..n]), Ok(s));
            prop_assert!(decode_force_settings(&bytes[..n - 1]).is_err());
        }
    }
}
