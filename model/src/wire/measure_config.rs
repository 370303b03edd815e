//! The measurement configuration's canonical bytes: the payload of the
//! [`kind::MEASURE_CONFIG`] record that starts every event stream, and the input of
//! [`MeasureConfig::hash`], the configuration's identity in vector headers and generated
//! Verilog.
//!
//! ```text
//! 0..2   format version u16 (CONFIG_FORMAT_VERSION)   2..4   pulses_per_rev u16
//! 4..8   i_def u32                                    8      window_revs u8
//! 9      contact_rule u8 (0 sampled, 1 sticky)        10     charge_bits u8
//! 11     charge law u8 (0 linear, 1 exponential)
//! 12..20 linear: charge_step u32, discharge_step u32
//!        exponential: charge_shift u8, discharge_shift u8, 6 zero bytes
//! 20..24 fire_threshold u32                           24..28 rearm_threshold u32
//! 28     glitch_cycles u8                             29     scale_bits u8
//! 30     method u8 (0 single pulse, 1 counter, 2 density)
//! 31     checks: flags u8 (bit 0 contact_at_arm, 1 revolutions, 2 scale_errors)
//! 32..34 checks.pulse_tolerance u16                   34..36 checks.probe_revs u16
//! 36..40 checks.fes_timeout_cycles u32                40     checks.confirm_windows u8
//! 41     checks.confirm_percent u8
//! ```
//! All little-endian, [`CANONICAL_CONFIG_LEN`] bytes. A new field is appended here (both
//! the encoder and the decoder below) with a new format version.

use crate::fnv::fnv1a;
use crate::measure::checks::MeasureChecks;
use crate::measure::config::{
    ChargeLaw, ContactRule, DecisionMethod, MeasureConfig, MeasureSettings,
};
use crate::wire::{kind, le_u16, le_u32, Record, WireError};
use core::ops::Range;

/// Version of the configuration's canonical encoding; part of [`MeasureConfig::hash`].
pub const CONFIG_FORMAT_VERSION: u16 = 2;

/// Length of [`MeasureConfig::canonical_bytes`]' used part, bytes.
pub const CANONICAL_CONFIG_LEN: usize = 42;

/// Where each field is.
mod at {
    use super::Range;
    pub const VERSION: Range<usize> = 0..2;
    pub const PULSES_PER_REV: Range<usize> = 2..4;
    pub const I_DEF: Range<usize> = 4..8;
    pub const WINDOW_REVS: usize = 8;
    pub const CONTACT_RULE: usize = 9;
    pub const CHARGE_BITS: usize = 10;
    pub const CHARGE_LAW: usize = 11;
    /// Linear law: `charge_step` u32; exponential: `charge_shift` u8 at its first byte.
    pub const LAW_CHARGE: Range<usize> = 12..16;
    /// Linear law: `discharge_step` u32; exponential: `discharge_shift` u8 at byte 13.
    pub const LAW_DISCHARGE: Range<usize> = 16..20;
    pub const EXPONENTIAL_DISCHARGE_SHIFT: usize = 13;
    pub const FIRE_THRESHOLD: Range<usize> = 20..24;
    pub const REARM_THRESHOLD: Range<usize> = 24..28;
    pub const GLITCH_CYCLES: usize = 28;
    pub const SCALE_BITS: usize = 29;
    pub const METHOD: usize = 30;
    pub const CHECK_FLAGS: usize = 31;
    pub const PULSE_TOLERANCE: Range<usize> = 32..34;
    pub const PROBE_REVS: Range<usize> = 34..36;
    pub const FES_TIMEOUT_CYCLES: Range<usize> = 36..40;
    pub const CONFIRM_WINDOWS: usize = 40;
    pub const CONFIRM_PERCENT: usize = 41;
}

/// Bits of the checks' flags byte.
mod check_flag {
    pub const CONTACT_AT_ARM: u8 = 1 << 0;
    pub const REVOLUTIONS: u8 = 1 << 1;
    pub const SCALE_ERRORS: u8 = 1 << 2;
    pub const ALL: u8 = 0x07;
}

/// [`ChargeLaw`] tags.
const LAW_LINEAR: u8 = 0;
const LAW_EXPONENTIAL: u8 = 1;

impl MeasureConfig {
    /// Canonical little-endian encoding of the configuration (layout in the module header),
    /// fed to [`Self::hash`]. Returns the buffer and the number of bytes used.
    pub fn canonical_bytes(&self) -> ([u8; 48], usize) {
        let s = self.settings();
        let mut out = [0u8; 48];
        out[at::VERSION].copy_from_slice(&CONFIG_FORMAT_VERSION.to_le_bytes());
        out[at::PULSES_PER_REV].copy_from_slice(&s.pulses_per_rev.to_le_bytes());
        out[at::I_DEF].copy_from_slice(&s.i_def.to_le_bytes());
        out[at::WINDOW_REVS] = s.window_revs;
        out[at::CONTACT_RULE] = s.contact_rule as u8;
        out[at::CHARGE_BITS] = s.charge_bits;
        match s.charge_law {
            ChargeLaw::Linear {
                charge_step,
                discharge_step,
            } => {
                out[at::CHARGE_LAW] = LAW_LINEAR;
                out[at::LAW_CHARGE].copy_from_slice(&charge_step.to_le_bytes());
                out[at::LAW_DISCHARGE].copy_from_slice(&discharge_step.to_le_bytes());
            }
            ChargeLaw::Exponential {
                charge_shift,
                discharge_shift,
            } => {
                out[at::CHARGE_LAW] = LAW_EXPONENTIAL;
                out[at::LAW_CHARGE.start] = charge_shift;
                out[at::EXPONENTIAL_DISCHARGE_SHIFT] = discharge_shift;
            }
        }
        out[at::FIRE_THRESHOLD].copy_from_slice(&s.fire_threshold.to_le_bytes());
        out[at::REARM_THRESHOLD].copy_from_slice(&s.rearm_threshold.to_le_bytes());
        out[at::GLITCH_CYCLES] = s.glitch_cycles;
        out[at::SCALE_BITS] = s.scale_bits;
        out[at::METHOD] = s.method as u8;
        let c = &s.checks;
        let flag = |on: bool, bit: u8| if on { bit } else { 0 };
        out[at::CHECK_FLAGS] = flag(c.contact_at_arm, check_flag::CONTACT_AT_ARM)
            | flag(c.revolutions, check_flag::REVOLUTIONS)
            | flag(c.scale_errors, check_flag::SCALE_ERRORS);
        out[at::PULSE_TOLERANCE].copy_from_slice(&c.pulse_tolerance.to_le_bytes());
        out[at::PROBE_REVS].copy_from_slice(&c.probe_revs.to_le_bytes());
        out[at::FES_TIMEOUT_CYCLES].copy_from_slice(&c.fes_timeout_cycles.to_le_bytes());
        out[at::CONFIRM_WINDOWS] = c.confirm_windows;
        out[at::CONFIRM_PERCENT] = c.confirm_percent;
        (out, CANONICAL_CONFIG_LEN)
    }

    /// 64-bit FNV-1a hash of [`Self::canonical_bytes`]: stamped into every vector file and
    /// every generated Verilog header, so a configuration mismatch is an error, not a diff.
    pub fn hash(&self) -> u64 {
        let (bytes, n) = self.canonical_bytes();
        fnv1a(&bytes[..n])
    }
}

/// A configuration record at time 0.
pub fn encode_config(config: &MeasureConfig) -> Record {
    let (bytes, n) = config.canonical_bytes();
    Record::new(kind::MEASURE_CONFIG, 0, &bytes[..n])
}

/// Decodes a configuration record's payload and validates it.
pub fn decode_config(p: &[u8]) -> Result<MeasureConfig, WireError> {
    let bad = WireError::BadConfigEncoding;
    if p.len() != CANONICAL_CONFIG_LEN || le_u16(&p[at::VERSION]) != CONFIG_FORMAT_VERSION {
        return Err(bad);
    }
    let contact_rule = match p[at::CONTACT_RULE] {
        0 => ContactRule::Sampled,
        1 => ContactRule::Sticky,
        _ => return Err(bad),
    };
    let charge_law = match p[at::CHARGE_LAW] {
        LAW_LINEAR => ChargeLaw::Linear {
            charge_step: le_u32(&p[at::LAW_CHARGE]),
            discharge_step: le_u32(&p[at::LAW_DISCHARGE]),
        },
        LAW_EXPONENTIAL => ChargeLaw::Exponential {
            charge_shift: p[at::LAW_CHARGE.start],
            discharge_shift: p[at::EXPONENTIAL_DISCHARGE_SHIFT],
        },
        _ => return Err(bad),
    };
    let method = match p[at::METHOD] {
        0 => DecisionMethod::SinglePulse,
        1 => DecisionMethod::Counter,
        2 => DecisionMethod::Density,
        _ => return Err(bad),
    };
    let flags = p[at::CHECK_FLAGS];
    if flags & !check_flag::ALL != 0 {
        return Err(bad);
    }
    let checks = MeasureChecks {
        contact_at_arm: flags & check_flag::CONTACT_AT_ARM != 0,
        revolutions: flags & check_flag::REVOLUTIONS != 0,
        pulse_tolerance: le_u16(&p[at::PULSE_TOLERANCE]),
        scale_errors: flags & check_flag::SCALE_ERRORS != 0,
        probe_revs: le_u16(&p[at::PROBE_REVS]),
        fes_timeout_cycles: le_u32(&p[at::FES_TIMEOUT_CYCLES]),
        confirm_windows: p[at::CONFIRM_WINDOWS],
        confirm_percent: p[at::CONFIRM_PERCENT],
    };
    let settings = MeasureSettings {
        pulses_per_rev: le_u16(&p[at::PULSES_PER_REV]),
        i_def: le_u32(&p[at::I_DEF]),
        window_revs: p[at::WINDOW_REVS],
        contact_rule,
        charge_bits: p[at::CHARGE_BITS],
        charge_law,
        fire_threshold: le_u32(&p[at::FIRE_THRESHOLD]),
        rearm_threshold: le_u32(&p[at::REARM_THRESHOLD]),
        glitch_cycles: p[at::GLITCH_CYCLES],
        scale_bits: p[at::SCALE_BITS],
        method,
        checks,
    };
    Ok(settings.validate()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn config_round_trips_through_its_record() {
        let mut s = MeasureSettings::default();
        for method in [
            DecisionMethod::SinglePulse,
            DecisionMethod::Counter,
            DecisionMethod::Density,
        ] {
            s.method = method;
            s.charge_law = ChargeLaw::Exponential {
                charge_shift: 3,
                discharge_shift: 5,
            };
            let c = s.validate().unwrap();
            let r = encode_config(&c);
            assert_eq!(decode_config(r.payload()).unwrap(), c);
        }
    }

    #[test]
    fn a_threshold_of_the_checks_out_of_range_is_rejected() {
        // A tolerance of 5 pulses is over a quarter of the 16-pulse revolution.
        let mut b = EXPONENTIAL_BYTES;
        b[32] = 5;
        assert!(matches!(
            decode_config(&b),
            Err(WireError::Config(e)) if e.field == "checks.pulse_tolerance"
        ));
    }

    #[test]
    fn hash_changes_with_the_checks() {
        let a = MeasureConfig::default();
        let mut s = MeasureSettings::default();
        s.checks.fes_timeout_cycles += 1;
        assert_ne!(a.hash(), s.validate().unwrap().hash());
    }

    #[test]
    fn hash_changes_with_any_field() {
        let a = MeasureConfig::default();
        let b = MeasureSettings {
            glitch_cycles: 5,
            ..Default::default()
        }
        .validate()
        .unwrap();
        assert_ne!(a.hash(), b.hash());
    }

    #[test]
    fn the_default_encoding_is_pinned() {
        // Vector files and generated Verilog carry this hash: a change here is a format change.
        let (bytes, n) = MeasureConfig::default().canonical_bytes();
        assert_eq!(
            &bytes[..n],
            &[
                2, 0, 0, 4, 0, 2, 0, 0, 1, 1, 16, 0, 64, 0, 0, 0, 64, 0, 0, 0, 0, 128, 0, 0, 0, 32,
                0, 0, 4, 24, 1, 7, 2, 0, 100, 0, 0, 0, 1, 0, 3, 25
            ]
        );
    }

    #[test]
    fn the_default_hash_is_fnv1a_of_those_bytes() {
        // FNV-1a 64 of the 42 bytes above, evaluated outside this crate.
        assert_eq!(MeasureConfig::default().hash(), 0x016a_d816_02b8_b588);
    }

    /// Sampled contact, an 8-bit exponential capacitor, density method.
    fn exponential() -> MeasureSettings {
        MeasureSettings {
            pulses_per_rev: 16,
            i_def: 7,
            window_revs: 2,
            contact_rule: ContactRule::Sampled,
            charge_bits: 8,
            charge_law: ChargeLaw::Exponential {
                charge_shift: 3,
                discharge_shift: 5,
            },
            fire_threshold: 200,
            rearm_threshold: 10,
            glitch_cycles: 0,
            scale_bits: 32,
            method: DecisionMethod::Density,
            checks: MeasureChecks::OFF,
        }
    }

    const EXPONENTIAL_BYTES: [u8; CANONICAL_CONFIG_LEN] = [
        2, 0, 16, 0, 7, 0, 0, 0, 2, 0, 8, 1, 3, 5, 0, 0, 0, 0, 0, 0, 200, 0, 0, 0, 10, 0, 0, 0, 0,
        32, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 100,
    ];

    #[test]
    fn an_exponential_encoding_by_hand() {
        let c = exponential().validate().unwrap();
        let (bytes, n) = c.canonical_bytes();
        assert_eq!(bytes[..n], EXPONENTIAL_BYTES);
        assert_eq!(decode_config(&EXPONENTIAL_BYTES), Ok(c));
        let r = encode_config(&c);
        assert_eq!(
            (r.kind, r.time, r.payload()),
            (0x01, 0, &EXPONENTIAL_BYTES[..])
        );
    }

    #[test]
    fn unknown_tags_and_invalid_fields_are_rejected() {
        // Unknown tags, a version-1 encoding and an unknown checks flag.
        for (at, value) in [(9, 2u8), (11, 2), (30, 3), (1, 1), (0, 1), (31, 0x08)] {
            let mut b = EXPONENTIAL_BYTES;
            b[at] = value;
            assert_eq!(
                decode_config(&b),
                Err(WireError::BadConfigEncoding),
                "byte {at}"
            );
        }
        // i_def = 32 is not below the 32-pulse window.
        let mut b = EXPONENTIAL_BYTES;
        b[4] = 32;
        assert!(matches!(
            decode_config(&b),
            Err(WireError::Config(e)) if e.field == "i_def"
        ));
        let mut long = [0u8; CANONICAL_CONFIG_LEN + 1];
        long[..CANONICAL_CONFIG_LEN].copy_from_slice(&EXPONENTIAL_BYTES);
        assert_eq!(decode_config(&long), Err(WireError::BadConfigEncoding));
    }

    /// Any valid settings (the test kit's full profile: every field across its valid range).
    fn any_settings() -> impl Strategy<Value = MeasureSettings> {
        crate::testing::measure_settings(&crate::testing::MeasureProfile::FULL)
    }

    proptest! {
        #[test]
        fn any_config_round_trips(s in any_settings()) {
            let c = s.validate().unwrap();
            let r = encode_config(&c);
            prop_assert_eq!(r.kind, kind::MEASURE_CONFIG);
            prop_assert_eq!(r.payload().len(), CANONICAL_CONFIG_LEN);
            prop_assert_eq!(decode_config(r.payload()), Ok(c));
        }

        #[test]
        fn a_wrong_length_or_version_is_rejected(s in any_settings(), cut in 1usize..CANONICAL_CONFIG_LEN) {
            let (mut bytes, n) = s.validate().unwrap().canonical_bytes();
            prop_assert_eq!(decode_config(&bytes[..n - cut]), Err(WireError::BadConfigEncoding));
            bytes[0] ^= 0x80;
            prop_assert_eq!(decode_config(&bytes[..n]), Err(WireError::BadConfigEncoding));
        }
    }
}
