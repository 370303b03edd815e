//! The compact binary vector format shared by the host tools and the firmware: a header
//! carrying the configuration's hash, then length-prefixed timestamped records.
//!
//! ```text
//! header (28 bytes): magic "TTVX" | version u16 | stream u16 | tick_hz u32
//!                    | measure config hash u64 | force config hash u64
//! record:            kind u8 | payload length u8 | time u64 | payload
//! ```
//! All integers little-endian. Kinds `0x01..=0x1f` are measurement records (this module),
//! `0x20..=0x3f` belong to the force path, `0x40..=0x5f` are output traces, `0x7f` ends a
//! stream. Decoding never panics: a short, unknown or malformed record is a [`WireError`].

use crate::config::{
    ChargeLaw, ConfigError, ContactRule, DecisionMethod, MeasureConfig, MeasureSettings,
    CONFIG_FORMAT_VERSION,
};
use crate::events::MeasureEvent;
use crate::measurement::MeasureOutputs;
use core::fmt;

/// File magic.
pub const MAGIC: [u8; 4] = *b"TTVX";
/// Format version written and accepted.
pub const FORMAT_VERSION: u16 = 1;
/// Header length, bytes.
pub const HEADER_LEN: usize = 28;
/// Record header length (kind, length, time), bytes.
pub const RECORD_HEADER_LEN: usize = 10;
/// Largest payload, bytes.
pub const MAX_PAYLOAD: usize = 48;

/// Record kinds.
pub mod kind {
    /// The measurement configuration's canonical bytes (starts an event stream).
    pub const MEASURE_CONFIG: u8 = 0x01;
    /// Arm line changed; payload: level (1 byte).
    pub const ARM: u8 = 0x02;
    /// Contact line changed; payload: level (1 byte).
    pub const CONTACT: u8 = 0x03;
    /// Index pulse; no payload.
    pub const INDEX: u8 = 0x04;
    /// FES pulse; no payload.
    pub const FES: u8 = 0x05;
    /// Scale lines changed; payload: bit 0 = A, bit 1 = B.
    pub const SCALE: u8 = 0x06;
    /// Test event: preset the FES pulse count; payload: the count (u32).
    pub const PRESET_PULSES: u8 = 0x07;
    /// First kind reserved for the force path.
    pub const FORCE_FIRST: u8 = 0x20;
    /// Last kind reserved for the force path.
    pub const FORCE_LAST: u8 = 0x3f;
    /// Measurement outputs after an event (32 bytes, see `encode_outputs`).
    pub const MEASURE_OUTPUTS: u8 = 0x40;
    /// First kind reserved for other output traces.
    pub const OUTPUT_FIRST: u8 = 0x41;
    /// Last kind reserved for other output traces.
    pub const OUTPUT_LAST: u8 = 0x5f;
    /// End of stream; no payload.
    pub const END: u8 = 0x7f;
}

/// What a stream holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum StreamKind {
    /// Input events (stimulus).
    Events = 1,
    /// Output trace (expected or device response).
    Outputs = 2,
}

/// A malformed vector file or record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WireError {
    /// Fewer bytes than needed at `offset`: `needed` more.
    Truncated {
        /// Byte offset of the incomplete item.
        offset: usize,
        /// Bytes needed from `offset`.
        needed: usize,
    },
    /// The file does not start with [`MAGIC`].
    BadMagic([u8; 4]),
    /// Unsupported format version.
    BadVersion(u16),
    /// Unknown stream kind in the header.
    BadStream(u16),
    /// Unknown record kind at `offset`.
    UnknownKind {
        /// The kind byte.
        kind: u8,
        /// Byte offset of the record.
        offset: usize,
    },
    /// A record's payload length does not fit its kind.
    BadLength {
        /// The kind byte.
        kind: u8,
        /// The length found.
        len: u8,
        /// Byte offset of the record.
        offset: usize,
    },
    /// A record's time is earlier than the previous record's.
    NonMonotonicTime {
        /// Byte offset of the record.
        offset: usize,
        /// Previous record's time.
        previous: u64,
        /// This record's time.
        time: u64,
    },
    /// A configuration record does not decode to a valid configuration.
    Config(ConfigError),
    /// A configuration record of an unknown encoding version or enum value.
    BadConfigEncoding,
}

impl fmt::Display for WireError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WireError::Truncated { offset, needed } => {
                write!(f, "truncated at byte {offset}: {needed} more bytes needed")
            }
            WireError::BadMagic(m) => write!(f, "wrong magic {m:02x?}, expected \"TTVX\""),
            WireError::BadVersion(v) => {
                write!(
                    f,
                    "unsupported format version {v}, expected {FORMAT_VERSION}"
                )
            }
            WireError::BadStream(s) => write!(f, "unknown stream kind {s}, expected 1 or 2"),
            WireError::UnknownKind { kind, offset } => {
                write!(f, "unknown record kind 0x{kind:02x} at byte {offset}")
            }
            WireError::BadLength { kind, len, offset } => write!(
                f,
                "record kind 0x{kind:02x} at byte {offset} has a bad payload length {len}"
            ),
            WireError::NonMonotonicTime {
                offset,
                previous,
                time,
            } => write!(
                f,
                "time goes backwards at byte {offset}: {time} after {previous}"
            ),
            WireError::Config(e) => write!(f, "bad configuration record: {e}"),
            WireError::BadConfigEncoding => {
                write!(f, "configuration record has an unknown encoding")
            }
        }
    }
}

impl From<ConfigError> for WireError {
    fn from(e: ConfigError) -> Self {
        WireError::Config(e)
    }
}

/// The stream header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header {
    /// What the stream holds.
    pub stream: StreamKind,
    /// Ticks per second of the record times (the FPGA clock for cycle-level streams).
    pub tick_hz: u32,
    /// [`MeasureConfig::hash`] of the configuration the stream was made with.
    pub measure_hash: u64,
    /// Hash of the force-path configuration (0 when none).
    pub force_hash: u64,
}

impl Header {
    /// Encodes into 28 bytes.
    pub fn encode(&self) -> [u8; HEADER_LEN] {
        let mut out = [0u8; HEADER_LEN];
        out[0..4].copy_from_slice(&MAGIC);
        out[4..6].copy_from_slice(&FORMAT_VERSION.to_le_bytes());
        out[6..8].copy_from_slice(&(self.stream as u16).to_le_bytes());
        out[8..12].copy_from_slice(&self.tick_hz.to_le_bytes());
        out[12..20].copy_from_slice(&self.measure_hash.to_le_bytes());
        out[20..28].copy_from_slice(&self.force_hash.to_le_bytes());
        out
    }

    /// Decodes the first 28 bytes of `bytes`.
    pub fn decode(bytes: &[u8]) -> Result<Header, WireError> {
        let Some(h) = bytes.get(..HEADER_LEN) else {
            return Err(WireError::Truncated {
                offset: 0,
                needed: HEADER_LEN,
            });
        };
        let magic = [h[0], h[1], h[2], h[3]];
        if magic != MAGIC {
            return Err(WireError::BadMagic(magic));
        }
        let version = u16::from_le_bytes([h[4], h[5]]);
        if version != FORMAT_VERSION {
            return Err(WireError::BadVersion(version));
        }
        let stream = match u16::from_le_bytes([h[6], h[7]]) {
            1 => StreamKind::Events,
            2 => StreamKind::Outputs,
            other => return Err(WireError::BadStream(other)),
        };
        Ok(Header {
            stream,
            tick_hz: u32::from_le_bytes([h[8], h[9], h[10], h[11]]),
            measure_hash: le_u64(&h[12..20]),
            force_hash: le_u64(&h[20..28]),
        })
    }
}

fn le_u64(b: &[u8]) -> u64 {
    let mut a = [0u8; 8];
    for (d, s) in a.iter_mut().zip(b) {
        *d = *s;
    }
    u64::from_le_bytes(a)
}

fn le_u32(b: &[u8]) -> u32 {
    let mut a = [0u8; 4];
    for (d, s) in a.iter_mut().zip(b) {
        *d = *s;
    }
    u32::from_le_bytes(a)
}

/// One record: kind, time and up to [`MAX_PAYLOAD`] payload bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Record {
    /// Record kind (see [`kind`]).
    pub kind: u8,
    /// Time, ticks of the header's `tick_hz`.
    pub time: u64,
    len: u8,
    payload: [u8; MAX_PAYLOAD],
}

impl Record {
    /// A record with `payload` (at most [`MAX_PAYLOAD`] bytes; longer is cut, which no
    /// encoder in this crate does).
    pub fn new(kind: u8, time: u64, payload: &[u8]) -> Record {
        let len = payload.len().min(MAX_PAYLOAD);
        let mut p = [0u8; MAX_PAYLOAD];
        p[..len].copy_from_slice(&payload[..len]);
        Record {
            kind,
            time,
            len: len as u8,
            payload: p,
        }
    }

    /// The payload bytes.
    pub fn payload(&self) -> &[u8] {
        // `len <= MAX_PAYLOAD` by construction; `get` keeps the firmware free of a panic
        // path the optimiser cannot see through.
        self.payload.get(..usize::from(self.len)).unwrap_or(&[])
    }

    /// Encoded length, bytes.
    pub fn encoded_len(&self) -> usize {
        RECORD_HEADER_LEN + usize::from(self.len)
    }

    /// Writes the record into `out`; returns the bytes written, or `None` if `out` is too
    /// short.
    pub fn encode(&self, out: &mut [u8]) -> Option<usize> {
        let n = self.encoded_len();
        let out = out.get_mut(..n)?;
        out[0] = self.kind;
        out[1] = self.len;
        out[2..10].copy_from_slice(&self.time.to_le_bytes());
        out[10..].copy_from_slice(self.payload());
        Some(n)
    }

    /// Decodes one record from the start of `bytes` (found at byte `offset` of the file,
    /// for error messages); returns it and the bytes consumed.
    pub fn decode(bytes: &[u8], offset: usize) -> Result<(Record, usize), WireError> {
        if bytes.len() < RECORD_HEADER_LEN {
            return Err(WireError::Truncated {
                offset,
                needed: RECORD_HEADER_LEN,
            });
        }
        let kind = bytes[0];
        let len = bytes[1];
        if usize::from(len) > MAX_PAYLOAD {
            return Err(WireError::BadLength { kind, len, offset });
        }
        let n = RECORD_HEADER_LEN + usize::from(len);
        let Some(payload) = bytes.get(RECORD_HEADER_LEN..n) else {
            return Err(WireError::Truncated { offset, needed: n });
        };
        Ok((Record::new(kind, le_u64(&bytes[2..10]), payload), n))
    }
}

/// Iterates over the records of a whole stream held in memory, after its header,
/// checking that time never goes backwards. Stops after an error or an END record.
pub struct Records<'a> {
    bytes: &'a [u8],
    offset: usize,
    previous: u64,
    done: bool,
}

impl<'a> Records<'a> {
    /// Reads the header of `bytes` and iterates over the records after it.
    pub fn new(bytes: &'a [u8]) -> Result<(Header, Records<'a>), WireError> {
        let header = Header::decode(bytes)?;
        Ok((
            header,
            Records {
                bytes,
                offset: HEADER_LEN,
                previous: 0,
                done: false,
            },
        ))
    }
}

impl Iterator for Records<'_> {
    type Item = Result<Record, WireError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done || self.offset >= self.bytes.len() {
            return None;
        }
        let rest = self.bytes.get(self.offset..).unwrap_or(&[]);
        let item = Record::decode(rest, self.offset).and_then(|(record, n)| {
            if record.time < self.previous {
                return Err(WireError::NonMonotonicTime {
                    offset: self.offset,
                    previous: self.previous,
                    time: record.time,
                });
            }
            self.previous = record.time;
            self.offset += n;
            Ok(record)
        });
        if item.is_err() || matches!(item, Ok(r) if r.kind == kind::END) {
            self.done = true;
        }
        Some(item)
    }
}

/// Encodes a measurement event as a record at `time`.
pub fn encode_event(time: u64, event: MeasureEvent) -> Record {
    match event {
        MeasureEvent::Arm(level) => Record::new(kind::ARM, time, &[level as u8]),
        MeasureEvent::Contact(level) => Record::new(kind::CONTACT, time, &[level as u8]),
        MeasureEvent::Index => Record::new(kind::INDEX, time, &[]),
        MeasureEvent::Fes => Record::new(kind::FES, time, &[]),
        MeasureEvent::Scale { a, b } => {
            Record::new(kind::SCALE, time, &[(a as u8) | ((b as u8) << 1)])
        }
        MeasureEvent::PresetPulses(n) => Record::new(kind::PRESET_PULSES, time, &n.to_le_bytes()),
    }
}

/// Decodes a measurement-event record; `Ok(None)` for a record of another kind.
pub fn decode_event(record: &Record, offset: usize) -> Result<Option<MeasureEvent>, WireError> {
    let p = record.payload();
    let bad = WireError::BadLength {
        kind: record.kind,
        len: record.len,
        offset,
    };
    let level = || match p {
        [b] if *b <= 1 => Ok(*b == 1),
        _ => Err(bad),
    };
    Ok(Some(match record.kind {
        kind::ARM => MeasureEvent::Arm(level()?),
        kind::CONTACT => MeasureEvent::Contact(level()?),
        kind::INDEX if p.is_empty() => MeasureEvent::Index,
        kind::FES if p.is_empty() => MeasureEvent::Fes,
        kind::SCALE => match p {
            [b] if *b <= 3 => MeasureEvent::Scale {
                a: b & 1 != 0,
                b: b & 2 != 0,
            },
            _ => return Err(bad),
        },
        kind::PRESET_PULSES => match p {
            [a, b, c, d] => MeasureEvent::PresetPulses(u32::from_le_bytes([*a, *b, *c, *d])),
            _ => return Err(bad),
        },
        kind::INDEX | kind::FES => return Err(bad),
        _ => return Ok(None),
    }))
}

/// Encoded length of [`MeasureOutputs`], bytes.
pub const OUTPUTS_LEN: usize = 32;

/// Encodes every measurement output: flags u8 (armed, contact, register_now,
/// first_contact, density_armed, density_fired from bit 0), decision_position i32,
/// first_contact_position i32, position i32, scale_errors u8, count u32,
/// last_window_count u32, charge u32, revolutions u16, pulses u32.
pub fn encode_outputs(o: &MeasureOutputs) -> [u8; OUTPUTS_LEN] {
    let mut out = [0u8; OUTPUTS_LEN];
    out[0] = (o.armed as u8)
        | (o.contact as u8) << 1
        | (o.register_now as u8) << 2
        | (o.first_contact as u8) << 3
        | (o.density_armed as u8) << 4
        | (o.density_fired as u8) << 5;
    out[1..5].copy_from_slice(&o.decision_position.to_le_bytes());
    out[5..9].copy_from_slice(&o.first_contact_position.to_le_bytes());
    out[9..13].copy_from_slice(&o.position.to_le_bytes());
    out[13] = o.scale_errors;
    out[14..18].copy_from_slice(&o.count.to_le_bytes());
    out[18..22].copy_from_slice(&o.last_window_count.to_le_bytes());
    out[22..26].copy_from_slice(&o.charge.to_le_bytes());
    out[26..28].copy_from_slice(&o.revolutions.to_le_bytes());
    out[28..32].copy_from_slice(&o.pulses.to_le_bytes());
    out
}

/// Decodes [`encode_outputs`]' bytes; `None` if `p` is not [`OUTPUTS_LEN`] long.
pub fn decode_outputs(p: &[u8]) -> Option<MeasureOutputs> {
    if p.len() != OUTPUTS_LEN {
        return None;
    }
    let f = p[0];
    Some(MeasureOutputs {
        armed: f & 1 != 0,
        contact: f & 2 != 0,
        register_now: f & 4 != 0,
        first_contact: f & 8 != 0,
        density_armed: f & 16 != 0,
        density_fired: f & 32 != 0,
        decision_position: le_u32(&p[1..5]) as i32,
        first_contact_position: le_u32(&p[5..9]) as i32,
        position: le_u32(&p[9..13]) as i32,
        scale_errors: p[13],
        count: le_u32(&p[14..18]),
        last_window_count: le_u32(&p[18..22]),
        charge: le_u32(&p[22..26]),
        revolutions: u16::from_le_bytes([p[26], p[27]]),
        pulses: le_u32(&p[28..32]),
    })
}

/// Length of [`MeasureConfig::canonical_bytes`]' used part, bytes.
pub const CANONICAL_CONFIG_LEN: usize = 31;

/// A configuration record at time 0.
pub fn encode_config(config: &MeasureConfig) -> Record {
    let (bytes, n) = config.canonical_bytes();
    Record::new(kind::MEASURE_CONFIG, 0, &bytes[..n])
}

/// Decodes a configuration record's payload and validates it.
pub fn decode_config(p: &[u8]) -> Result<MeasureConfig, WireError> {
    let bad = WireError::BadConfigEncoding;
    if p.len() != CANONICAL_CONFIG_LEN || u16::from_le_bytes([p[0], p[1]]) != CONFIG_FORMAT_VERSION
    {
        return Err(bad);
    }
    let contact_rule = match p[9] {
        0 => ContactRule::Sampled,
        1 => ContactRule::Sticky,
        _ => return Err(bad),
    };
    let charge_law = match p[11] {
        0 => ChargeLaw::Linear {
            charge_step: le_u32(&p[12..16]),
            discharge_step: le_u32(&p[16..20]),
        },
        1 => ChargeLaw::Exponential {
            charge_shift: p[12],
            discharge_shift: p[13],
        },
        _ => return Err(bad),
    };
    let method = match p[30] {
        0 => DecisionMethod::SinglePulse,
        1 => DecisionMethod::Counter,
        2 => DecisionMethod::Density,
        _ => return Err(bad),
    };
    let settings = MeasureSettings {
        pulses_per_rev: u16::from_le_bytes([p[2], p[3]]),
        i_def: le_u32(&p[4..8]),
        window_revs: p[8],
        contact_rule,
        charge_bits: p[10],
        charge_law,
        fire_threshold: le_u32(&p[20..24]),
        rearm_threshold: le_u32(&p[24..28]),
        glitch_cycles: p[28],
        scale_bits: p[29],
        method,
    };
    Ok(settings.validate()?)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn outputs_round_trip() {
        let o = MeasureOutputs {
            armed: true,
            register_now: true,
            decision_position: -5,
            position: 1 << 20,
            charge: 65535,
            pulses: u32::MAX,
            density_fired: true,
            ..Default::default()
        };
        assert_eq!(decode_outputs(&encode_outputs(&o)), Some(o));
    }

    #[test]
    fn stream_errors_name_what_is_wrong() {
        let h = Header {
            stream: StreamKind::Events,
            tick_hz: 50_000_000,
            measure_hash: 1,
            force_hash: 0,
        };
        let mut buf = [0u8; 64];
        buf[..HEADER_LEN].copy_from_slice(&h.encode());
        let n1 = encode_event(10, MeasureEvent::Fes)
            .encode(&mut buf[HEADER_LEN..])
            .unwrap();
        let n2 = encode_event(5, MeasureEvent::Index)
            .encode(&mut buf[HEADER_LEN + n1..])
            .unwrap();
        let total = HEADER_LEN + n1 + n2;
        let (hd, mut it) = Records::new(&buf[..total]).unwrap();
        assert_eq!(hd, h);
        assert!(it.next().unwrap().is_ok());
        assert!(matches!(
            it.next().unwrap(),
            Err(WireError::NonMonotonicTime {
                previous: 10,
                time: 5,
                ..
            })
        ));
        let (_, mut it) = Records::new(&buf[..total - 3 - n2]).unwrap();
        assert!(matches!(
            it.next().unwrap(),
            Err(WireError::Truncated { .. })
        ));
        let mut bad = buf;
        bad[0] = b'X';
        assert!(matches!(Records::new(&bad), Err(WireError::BadMagic(_))));
    }
}
