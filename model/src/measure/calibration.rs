//! The calibration as a controller applies it (docs/accuracy.md "Calibration on a reference
//! part"): the FPGA latches the raw scale position at the decision (`decision_position`);
//! the firmware reports that position corrected by the offset a reference-part calibration
//! found, `decision_position − offset`, in scale counts.
//!
//! The offset is the mean of (decided − known) on the reference, converted from µm on the
//! diameter to scale counts on the cross slide (one count moves the radius by the scale's
//! resolution, so the diameter by twice it): `offset_counts = round(offset_um / (2 ·
//! resolution_um))`, to the nearest count, halves away from zero. It is signed and fits
//! in the configuration's `scale_bits` (|offset| < 2^(scale_bits − 1), checked when it is
//! baked, [`CalibrationRecord::check_for`]).
//!
//! The corrected position **wraps** in `scale_bits` two's complement, as the scale's
//! position counter does ([`crate::measure::quadrature`]): the host unwraps both the same
//! way, and a saturating subtraction would make the corrected position disagree with the
//! raw one by more than the offset near the wrap.
//!
//! A calibration is made with one configuration (its method and contact rule among the
//! rest: [`crate::MeasureConfig::hash`]) at one feed and speed. The firmware applies it to
//! that configuration only ([`CalibrationRecord::offset_for`]): under QEMU a stream in
//! another configuration reports its raw position (offset 0). Without a calibration the
//! offset is 0 and the corrected position is the raw one.

use crate::fnv::fnv1a;
use crate::MeasureConfig;

/// Length of [`CalibrationRecord::canonical_bytes`].
pub const CALIBRATION_LEN: usize = 21;
/// The encoding's version, its first byte.
pub const CALIBRATION_ENCODING: u8 = 1;

/// A reference-part calibration baked into a firmware image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CalibrationRecord {
    /// [`MeasureConfig::hash`] of the configuration it was made with.
    pub measure_hash: u64,
    /// The offset, scale counts (signed; see the module documentation for the rounding).
    pub offset_counts: i32,
    /// The approach feed it was made at, nm per revolution (rounded to the nearest).
    pub feed_nm_per_rev: u32,
    /// The spindle speed it was made at, milli-rpm (rounded to the nearest).
    pub speed_milli_rpm: u32,
}

/// A calibration record that does not decode or does not fit its configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CalibrationError {
    /// Not [`CALIBRATION_LEN`] bytes.
    Length(usize),
    /// An unknown encoding version (the first byte).
    Encoding(u8),
    /// Made with another configuration: (the record's hash, the configuration's).
    OtherConfiguration(u64, u64),
    /// The offset does not fit the configuration's `scale_bits`: (offset, scale_bits).
    OffsetRange(i32, u8),
}

impl core::fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            CalibrationError::Length(n) => {
                write!(
                    f,
                    "a calibration record of {n} bytes, expected {CALIBRATION_LEN}"
                )
            }
            CalibrationError::Encoding(v) => write!(
                f,
                "calibration record encoding {v}, expected {CALIBRATION_ENCODING}"
            ),
            CalibrationError::OtherConfiguration(record, config) => write!(
                f,
                "the calibration was made with configuration measure_hash={record:016x}, the \
                 image is built with measure_hash={config:016x}: recalibrate with these settings"
            ),
            CalibrationError::OffsetRange(offset, bits) => write!(
                f,
                "the calibration offset {offset} counts does not fit a {bits}-bit scale position"
            ),
        }
    }
}

impl CalibrationRecord {
    /// Encoding version u8, `measure_hash` u64, `offset_counts` i32, `feed_nm_per_rev`
    /// u32, `speed_milli_rpm` u32, little-endian: [`CALIBRATION_LEN`] bytes.
    pub fn canonical_bytes(&self) -> [u8; CALIBRATION_LEN] {
        let mut out = [0u8; CALIBRATION_LEN];
        let fields = self
            .measure_hash
            .to_le_bytes()
            .into_iter()
            .chain(self.offset_counts.to_le_bytes())
            .chain(self.feed_nm_per_rev.to_le_bytes())
            .chain(self.speed_milli_rpm.to_le_bytes());
        let header = [CALIBRATION_ENCODING].into_iter();
        for (d, s) in out.iter_mut().zip(header.chain(fields)) {
            *d = s;
        }
        out
    }

    /// Decodes [`Self::canonical_bytes`].
    pub fn decode(bytes: &[u8]) -> Result<Self, CalibrationError> {
        if bytes.len() != CALIBRATION_LEN {
            return Err(CalibrationError::Length(bytes.len()));
        }
        let short = CalibrationError::Length(bytes.len());
        let (&[version], rest) = bytes.split_first_chunk::<1>().ok_or(short)?;
        if version != CALIBRATION_ENCODING {
            return Err(CalibrationError::Encoding(version));
        }
        let (hash, rest) = rest.split_first_chunk::<8>().ok_or(short)?;
        let (offset, rest) = rest.split_first_chunk::<4>().ok_or(short)?;
        let (feed, rest) = rest.split_first_chunk::<4>().ok_or(short)?;
        let (speed, _) = rest.split_first_chunk::<4>().ok_or(short)?;
        Ok(CalibrationRecord {
            measure_hash: u64::from_le_bytes(*hash),
            offset_counts: i32::from_le_bytes(*offset),
            feed_nm_per_rev: u32::from_le_bytes(*feed),
            speed_milli_rpm: u32::from_le_bytes(*speed),
        })
    }

    /// FNV-1a of [`Self::canonical_bytes`]: the calibration's part of a firmware image's
    /// identity (not of the FPGA's configuration hash: the FPGA latches the raw position).
    pub fn hash(&self) -> u64 {
        fnv1a(&self.canonical_bytes())
    }

    /// Whether the record may be baked with `config`: made with it, and its offset fits
    /// the configuration's `scale_bits`.
    pub fn check_for(&self, config: &MeasureConfig) -> Result<(), CalibrationError> {
        if self.measure_hash != config.hash() {
            return Err(CalibrationError::OtherConfiguration(
                self.measure_hash,
                config.hash(),
            ));
        }
        let bits = config.settings().scale_bits;
        let limit = 1i64 << (bits.clamp(1, 32) - 1);
        if i64::from(self.offset_counts).abs() >= limit {
            return Err(CalibrationError::OffsetRange(self.offset_counts, bits));
        }
        Ok(())
    }

    /// The offset the firmware applies to a run in `config`: the record's for the
    /// configuration it was made with, 0 for any other.
    pub fn offset_for(&self, config: &MeasureConfig) -> i32 {
        if self.measure_hash == config.hash() {
            self.offset_counts
        } else {
            0
        }
    }
}

/// The offset applied to a run in `config` with the optional `calibration` baked: 0 without
/// one (see [`CalibrationRecord::offset_for`]).
pub fn applied_offset(calibration: Option<&CalibrationRecord>, config: &MeasureConfig) -> i32 {
    calibration.map_or(0, |c| c.offset_for(config))
}

/// The corrected decision position, `raw − offset` wrapped to `scale_bits` two's complement
/// (sign-extended), as the scale's counter wraps. `scale_bits` is clamped to `1..=32`
/// (validated configurations hold `8..=32`).
pub fn corrected_position(raw: i32, offset: i32, scale_bits: u8) -> i32 {
    let bits = u32::from(scale_bits.clamp(1, 32));
    let shift = 32u32.wrapping_sub(bits);
    // Wrapping subtraction in 32 bits, then the low `bits` bits sign-extended.
    raw.wrapping_sub(offset)
        .wrapping_shl(shift)
        .wrapping_shr(shift)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MeasureSettings;

    fn config(bits: u8) -> MeasureConfig {
        MeasureSettings {
            scale_bits: bits,
            ..MeasureSettings::default()
        }
        .validate()
        .unwrap()
    }

    #[test]
    fn a_zero_offset_gives_the_raw_position() {
        for bits in [8u8, 16, 24, 32] {
            let max = ((1i64 << (bits - 1)) - 1) as i32;
            let min = (-(1i64 << (bits - 1))) as i32;
            for raw in [0, 1, -1, 1234 % max.max(2), max, min] {
                assert_eq!(corrected_position(raw, 0, bits), raw, "{bits} bits, {raw}");
            }
        }
    }

    #[test]
    fn the_offset_is_subtracted_within_the_range() {
        assert_eq!(corrected_position(1000, 27, 24), 973);
        assert_eq!(corrected_position(1000, -27, 24), 1027);
        assert_eq!(corrected_position(-5, 10, 8), -15);
    }

    #[test]
    fn the_corrected_position_wraps_at_scale_bits_as_the_scale_does() {
        // 8 bits: -128..=127.
        assert_eq!(corrected_position(-128, 1, 8), 127, "-128 - 1 wraps to 127");
        assert_eq!(
            corrected_position(127, -1, 8),
            -128,
            "127 + 1 wraps to -128"
        );
        assert_eq!(corrected_position(-100, 100, 8), 56, "-200 wraps to 56");
        // 24 bits.
        let max24 = (1 << 23) - 1;
        assert_eq!(corrected_position(max24, -1, 24), -(1 << 23));
        assert_eq!(corrected_position(-(1 << 23), 3, 24), max24 - 2);
        // 32 bits: i32 wrapping.
        assert_eq!(corrected_position(i32::MIN, 1, 32), i32::MAX);
        assert_eq!(corrected_position(i32::MAX, -1, 32), i32::MIN);
        // Wrapping, not saturating: unwrapped, the difference is the offset exactly.
        for bits in [8u8, 12, 24, 32] {
            let m = 1i64 << bits;
            for (raw, offset) in [(-128, 7), (127, -7), (5, 100), (-3, -100)] {
                let c = i64::from(corrected_position(raw, offset, bits));
                assert_eq!(
                    (i64::from(raw) - i64::from(offset) - c).rem_euclid(m),
                    0,
                    "{bits} bits, {raw} - {offset} = {c}"
                );
                assert!((-(m / 2)..m / 2).contains(&c), "{c} outside {bits} bits");
            }
        }
    }

    #[test]
    fn the_record_round_trips_and_its_hash_names_every_field() {
        let c = config(24);
        let r = CalibrationRecord {
            measure_hash: c.hash(),
            offset_counts: -13,
            feed_nm_per_rev: 1000,
            speed_milli_rpm: 800_000,
        };
        let bytes = r.canonical_bytes();
        assert_eq!(CalibrationRecord::decode(&bytes), Ok(r));
        assert_eq!(
            CalibrationRecord::decode(&bytes[..20]),
            Err(CalibrationError::Length(20))
        );
        let mut bad = bytes;
        bad[0] = 2;
        assert_eq!(
            CalibrationRecord::decode(&bad),
            Err(CalibrationError::Encoding(2))
        );
        for other in [
            CalibrationRecord {
                offset_counts: -12,
                ..r
            },
            CalibrationRecord {
                feed_nm_per_rev: 500,
                ..r
            },
            CalibrationRecord {
                speed_milli_rpm: 600_000,
                ..r
            },
            CalibrationRecord {
                measure_hash: r.measure_hash ^ 1,
                ..r
            },
        ] {
            assert_ne!(other.hash(), r.hash(), "{other:?}");
        }
    }

    #[test]
    fn it_applies_to_its_own_configuration_only_and_must_fit_the_scale() {
        let c = config(24);
        let other = config(16);
        let r = CalibrationRecord {
            measure_hash: c.hash(),
            offset_counts: -13,
            feed_nm_per_rev: 1000,
            speed_milli_rpm: 800_000,
        };
        assert_eq!(r.offset_for(&c), -13);
        assert_eq!(r.offset_for(&other), 0);
        assert_eq!(applied_offset(Some(&r), &c), -13);
        assert_eq!(applied_offset(None, &c), 0);
        assert_eq!(r.check_for(&c), Ok(()));
        assert_eq!(
            r.check_for(&other),
            Err(CalibrationError::OtherConfiguration(c.hash(), other.hash()))
        );
        let c8 = config(8);
        let edge = |offset_counts| CalibrationRecord {
            measure_hash: c8.hash(),
            offset_counts,
            ..r
        };
        assert_eq!(edge(127).check_for(&c8), Ok(()));
        assert_eq!(edge(-127).check_for(&c8), Ok(()));
        assert_eq!(
            edge(128).check_for(&c8),
            Err(CalibrationError::OffsetRange(128, 8))
        );
        assert_eq!(
            edge(-128).check_for(&c8),
            Err(CalibrationError::OffsetRange(-128, 8))
        );
    }
}
