//! The firmware's status record ([`kind::FIRMWARE_STATUS`], [`STATUS_LEN`] bytes), the
//! last record before END of each stream of the firmware's co-simulation trace:
//! firmware/src/cosim.rs encodes it, and the host's co-simulation, `tooltouch check` and
//! the Python package decode it here.
//!
//! [`kind::FIRMWARE_STATUS`]: crate::wire::kind::FIRMWARE_STATUS
//!
//! ```text
//! 0..4   events u32                    4..8   lost u32
//! 8..12  overflowed u32                12..16 stack_bytes u32
//! 16..20 calibration_instructions u32  20..24 calibration_ticks u32
//! 24..32 measure_hash u64              32..40 force_hash u64
//! ```
//!
//! All little-endian; [`STATUS_FIELDS`] is this table. A shorter payload (an older image
//! wrote only the counters) holds the fields up to the first one it is too short for:
//! [`status_fields`] lists those, and [`FirmwareStatus::decode`] reads the counters
//! missing as 0 and the image's hashes as absent unless both are there. Decoding never
//! fails and never panics.

use crate::wire::le_u64;

/// Length of a complete status payload, bytes.
pub const STATUS_LEN: usize = 40;

/// One field of the status payload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StatusField {
    /// Its name, as in [`FirmwareStatus`] (the hashes: `measure_hash`, `force_hash`).
    pub name: &'static str,
    /// Byte offset in the payload.
    pub offset: usize,
    /// Width, bytes: 4 (a u32) or 8 (a u64), little-endian.
    pub width: usize,
}

impl StatusField {
    const fn new(name: &'static str, offset: usize, width: usize) -> StatusField {
        StatusField {
            name,
            offset,
            width,
        }
    }

    /// The byte just past the field.
    pub const fn end(&self) -> usize {
        self.offset + self.width
    }
}

/// The payload's fields in payload order, contiguous from byte 0 (layout in the module
/// header).
pub const STATUS_FIELDS: [StatusField; 8] = [
    StatusField::new("events", 0, 4),
    StatusField::new("lost", 4, 4),
    StatusField::new("overflowed", 8, 4),
    StatusField::new("stack_bytes", 12, 4),
    StatusField::new("calibration_instructions", 16, 4),
    StatusField::new("calibration_ticks", 20, 4),
    StatusField::new("measure_hash", 24, 8),
    StatusField::new("force_hash", 32, 8),
];

/// What the firmware reports about one stream it replayed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FirmwareStatus {
    /// Events replayed.
    pub events: u32,
    /// Edges lost (an interrupt still pending at the next edge).
    pub lost: u32,
    /// Samples dropped by a full queue.
    pub overflowed: u32,
    /// Stack bytes used (watermark since boot).
    pub stack_bytes: u32,
    /// Instructions of the calibration loop.
    pub calibration_instructions: u32,
    /// SysTick ticks of the calibration loop.
    pub calibration_ticks: u32,
    /// The hashes (measurement, force) of the configuration baked into the image; `None`
    /// for an image that does not report them.
    pub image_hashes: Option<(u64, u64)>,
}

impl FirmwareStatus {
    /// Encodes the status: the payload and its length, [`STATUS_LEN`] bytes, or the 24
    /// bytes of the counters without [`FirmwareStatus::image_hashes`].
    pub fn encode(&self) -> ([u8; STATUS_LEN], usize) {
        let counters = [
            self.events,
            self.lost,
            self.overflowed,
            self.stack_bytes,
            self.calibration_instructions,
            self.calibration_ticks,
        ]
        .map(u64::from);
        let mut values = [0u64; STATUS_FIELDS.len()];
        for (v, c) in values.iter_mut().zip(counters) {
            *v = c;
        }
        let held = match self.image_hashes {
            Some((measure, force)) => {
                for (v, h) in values.iter_mut().skip(counters.len()).zip([measure, force]) {
                    *v = h;
                }
                values.len()
            }
            None => counters.len(),
        };
        encode_status_fields(values.get(..held).unwrap_or(&[]))
    }

    /// Decodes a status payload of any length (see the module header): the counters it
    /// does not hold are 0, the image's hashes `None` unless it holds both.
    pub fn decode(p: &[u8]) -> FirmwareStatus {
        let mut values = [None; STATUS_FIELDS.len()];
        for (v, (_, value)) in values.iter_mut().zip(status_fields(p)) {
            *v = Some(value);
        }
        let [events, lost, overflowed, stack_bytes, instructions, ticks, measure, force] = values;
        // Each counter is a 4-byte field: its value fits a u32.
        let counter = |v: Option<u64>| v.unwrap_or(0) as u32;
        FirmwareStatus {
            events: counter(events),
            lost: counter(lost),
            overflowed: counter(overflowed),
            stack_bytes: counter(stack_bytes),
            calibration_instructions: counter(instructions),
            calibration_ticks: counter(ticks),
            image_hashes: measure.zip(force),
        }
    }
}

/// The fields the payload `p` holds, in payload order, each with its value: every field up
/// to the first one `p` is too short for.
pub fn status_fields(p: &[u8]) -> impl Iterator<Item = (&'static StatusField, u64)> + '_ {
    STATUS_FIELDS
        .iter()
        .map_while(move |f| p.get(f.offset..f.end()).map(|b| (f, le_u64(b))))
}

/// Encodes the first `values.len()` fields of [`STATUS_FIELDS`] (at most all of them),
/// each value cut to its field's width; returns the payload and its length.
pub fn encode_status_fields(values: &[u64]) -> ([u8; STATUS_LEN], usize) {
    let mut p = [0u8; STATUS_LEN];
    let mut len = 0;
    for (f, v) in STATUS_FIELDS.iter().zip(values) {
        if let Some(d) = p.get_mut(f.offset..f.end()) {
            for (d, s) in d.iter_mut().zip(v.to_le_bytes()) {
                *d = s;
            }
        }
        len = f.end();
    }
    (p, len)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    fn status() -> FirmwareStatus {
        FirmwareStatus {
            events: 1234,
            lost: 2,
            overflowed: 1,
            stack_bytes: 1800,
            calibration_instructions: 100,
            calibration_ticks: 104,
            image_hashes: Some((0x0123_4567_89ab_cdef, 0xfedc_ba98_7654_3210)),
        }
    }

    #[test]
    fn the_fields_are_contiguous_and_fill_the_payload() {
        let mut at = 0;
        for f in STATUS_FIELDS {
            assert_eq!(f.offset, at, "{}", f.name);
            assert!(f.width == 4 || f.width == 8, "{}", f.name);
            at = f.end();
        }
        assert_eq!(at, STATUS_LEN);
    }

    #[test]
    fn a_status_round_trips_with_and_without_the_image_hashes() {
        let s = status();
        let (p, n) = s.encode();
        assert_eq!(n, STATUS_LEN);
        assert_eq!(&p[..4], &1234u32.to_le_bytes());
        assert_eq!(&p[32..40], &0xfedc_ba98_7654_3210u64.to_le_bytes());
        assert_eq!(FirmwareStatus::decode(&p[..n]), s);
        let old = FirmwareStatus {
            image_hashes: None,
            ..s
        };
        let (p, n) = old.encode();
        assert_eq!(n, 24);
        assert_eq!(FirmwareStatus::decode(&p[..n]), old);
    }

    #[test]
    fn a_short_payload_holds_the_fields_up_to_the_first_cut_one() {
        let (p, _) = status().encode();
        let names = |len: usize| {
            status_fields(&p[..len])
                .map(|(f, _)| f.name)
                .collect::<Vec<_>>()
        };
        assert!(names(3).is_empty());
        assert_eq!(names(10), ["events", "lost"]);
        assert_eq!(names(39).len(), 7);
        assert_eq!(
            status_fields(&p[..12]).map(|(_, v)| v).collect::<Vec<_>>(),
            [1234, 2, 1]
        );
        let s = FirmwareStatus::decode(&p[..35]);
        assert_eq!(
            (s.events, s.calibration_ticks, s.image_hashes),
            (1234, 104, None)
        );
        let s = FirmwareStatus::decode(&p[..13]);
        assert_eq!((s.overflowed, s.stack_bytes), (1, 0));
        assert_eq!(FirmwareStatus::decode(&[]), FirmwareStatus::default());
        // Bytes past the last field are ignored.
        let mut long = p.to_vec();
        long.push(9);
        assert_eq!(FirmwareStatus::decode(&long), status());
    }

    #[test]
    fn encoding_some_fields_writes_just_those() {
        let (p, n) = encode_status_fields(&[7, u64::from(u32::MAX) + 5, 9]);
        assert_eq!(n, 12);
        assert_eq!(&p[..12], &[7, 0, 0, 0, 4, 0, 0, 0, 9, 0, 0, 0]);
        assert_eq!(encode_status_fields(&[]).1, 0);
        assert_eq!(encode_status_fields(&[1; 9]).1, STATUS_LEN);
    }
}
