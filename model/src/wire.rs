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
//!
//! The force configuration's canonical encoding (up to [`FORCE_CONFIG_MAX`] bytes) does not
//! fit one record: an events stream with a non-zero `force_hash` carries it as
//! [`force_kind::FORCE_CONFIG_CHUNK`] records right after `MEASURE_CONFIG`, made by
//! [`force_config_chunks`] and put back together by [`ForceConfigAssembler`].

use crate::config::{
    ChargeLaw, ConfigError, ContactRule, DecisionMethod, MeasureConfig, MeasureSettings,
    CONFIG_FORMAT_VERSION,
};
use crate::control::fuzzy::SETS;
use crate::control::{AdaptiveSettings, ControllerSettings, FuzzySettings, PiSettings};
use crate::estimator::{AdcScales, EstimatorSettings};
use crate::events::MeasureEvent;
use crate::force::{
    ForceConfig, ForceConfigError, ForceSettings, ForceSource, Fx, FORCE_CONFIG_FORMAT_VERSION,
};
use crate::measurement::MeasureOutputs;
use crate::wear::{ConditionSet, Threshold, WearSettings, MAX_CONDITION_SETS};
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

/// Record kinds of the firmware's co-simulation (firmware/src/cosim.rs writes and reads them,
/// the host's `tooltouch::cosim` reads and writes them), from the range reserved for other
/// output traces (`0x41..=0x5f`), counted down from the top so the force path can take the
/// bottom of the range.
pub mod firmware_kind {
    /// Per force event kind (sample, tick, command): events u32 and SysTick ticks u32,
    /// 24 bytes. A tick's ticks include applying the period's queued samples.
    pub const FIRMWARE_FORCE_PROFILE: u8 = 0x5c;
    /// The input was rejected; payload: code u8, wire error u8, byte offset u64, detail u64,
    /// then for a force configuration field out of range the field's name (UTF-8, up to
    /// 30 bytes).
    pub const FIRMWARE_ERROR: u8 = 0x5d;
    /// Per event kind (arm, contact, index, FES, scale): interrupts u32 and SysTick ticks
    /// u32 spent in them (pend to return), 40 bytes. FES: the counter's compare
    /// interrupts (most FES events raise none).
    pub const FIRMWARE_PROFILE: u8 = 0x5e;
    /// Input, before the first event of a stream: which measurement events get an outputs
    /// record. Payload u8: 1 = every event (the default), 0 = every event but FES pulses,
    /// whose runs the firmware then folds into the kernel many at a time, as on a board.
    pub const FIRMWARE_OBSERVE: u8 = 0x5b;
    /// events u32, lost u32, overflowed u32, stack bytes used u32, calibration
    /// instructions u32, calibration ticks u32: 24 bytes.
    pub const FIRMWARE_STATUS: u8 = 0x5f;
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

// ---------------------------------------------------------------------------------------
// Force configuration in chunks
// ---------------------------------------------------------------------------------------

/// Largest canonical force configuration, bytes ([`ForceConfig::canonical_bytes`]' buffer).
pub const FORCE_CONFIG_MAX: usize = 512;
/// Header of a [`force_kind::FORCE_CONFIG_CHUNK`] payload: total length u16 LE, byte offset
/// u16 LE.
pub const FORCE_CHUNK_HEADER: usize = 4;
/// Most configuration bytes one chunk carries.
pub const FORCE_CHUNK_DATA: usize = MAX_PAYLOAD - FORCE_CHUNK_HEADER;

/// Force-path record kinds defined here (the others are in `force::kind`).
pub mod force_kind {
    /// One piece of the force configuration's canonical encoding
    /// ([`crate::force::ForceConfig::canonical_bytes`]); payload: total length u16 LE,
    /// byte offset u16 LE, then 1..=44 bytes of the encoding from that offset. An events
    /// stream whose header has a non-zero `force_hash` carries the chunks right after its
    /// `MEASURE_CONFIG` record, in order, starting at offset 0, without gaps or overlaps.
    pub const FORCE_CONFIG_CHUNK: u8 = 0x26;
}

/// A force configuration sent in chunks that does not reassemble to a valid configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ForceChunkError {
    /// A chunk's payload (`len` bytes) is shorter than its header plus one data byte.
    BadLength {
        /// The payload length found.
        len: usize,
    },
    /// The announced total length is 0 or more than [`FORCE_CONFIG_MAX`].
    Oversized {
        /// The announced total, bytes.
        total: usize,
    },
    /// A chunk announces another total length than the first chunk.
    TotalChanged {
        /// The first chunk's total.
        first: usize,
        /// This chunk's total.
        this: usize,
    },
    /// A chunk does not start where the previous one ended (out of order, overlapping,
    /// or leaving a gap).
    OutOfOrder {
        /// The offset expected next.
        expected: usize,
        /// The chunk's offset.
        offset: usize,
    },
    /// A chunk reaches past the announced total.
    PastEnd {
        /// The chunk's end offset.
        end: usize,
        /// The announced total.
        total: usize,
    },
    /// A chunk after the configuration was already complete.
    AfterComplete,
    /// The chunks stopped before the whole configuration arrived (or none arrived).
    Incomplete {
        /// Bytes received.
        received: usize,
        /// The announced total (0: no chunk).
        total: usize,
    },
    /// The bytes do not decode at byte `at` of the encoding: an unknown format version or
    /// enum value, too few bytes, or bytes left over.
    BadEncoding {
        /// Byte offset in the canonical encoding.
        at: usize,
    },
    /// The configuration decodes but a field is out of range (the error names it).
    Invalid(ForceConfigError),
    /// The decoded configuration's hash is not the header's `force_hash`.
    HashMismatch {
        /// The header's `force_hash`.
        header: u64,
        /// The decoded configuration's hash.
        decoded: u64,
    },
}

impl fmt::Display for ForceChunkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ForceChunkError::BadLength { len } => write!(
                f,
                "force configuration chunk of {len} bytes: needs a {FORCE_CHUNK_HEADER}-byte \
                 header and 1..={FORCE_CHUNK_DATA} data bytes"
            ),
            ForceChunkError::Oversized { total } => write!(
                f,
                "force configuration of {total} bytes: allowed 1..={FORCE_CONFIG_MAX}"
            ),
            ForceChunkError::TotalChanged { first, this } => write!(
                f,
                "force configuration chunk announces {this} bytes in all, the first said {first}"
            ),
            ForceChunkError::OutOfOrder { expected, offset } => write!(
                f,
                "force configuration chunk at offset {offset}, expected offset {expected} \
                 (chunks must come in order without gaps or overlaps)"
            ),
            ForceChunkError::PastEnd { end, total } => write!(
                f,
                "force configuration chunk ends at byte {end}, past the announced {total} bytes"
            ),
            ForceChunkError::AfterComplete => {
                write!(
                    f,
                    "force configuration chunk after the configuration was complete"
                )
            }
            ForceChunkError::Incomplete { received, total } => write!(
                f,
                "force configuration incomplete: {received} of {total} bytes received"
            ),
            ForceChunkError::BadEncoding { at } => write!(
                f,
                "force configuration does not decode at byte {at} of its encoding"
            ),
            ForceChunkError::Invalid(e) => write!(f, "{e}"),
            ForceChunkError::HashMismatch { header, decoded } => write!(
                f,
                "force configuration hash {decoded:#018x} differs from the header's force_hash \
                 {header:#018x}"
            ),
        }
    }
}

impl From<ForceConfigError> for ForceChunkError {
    fn from(e: ForceConfigError) -> Self {
        ForceChunkError::Invalid(e)
    }
}

/// One [`force_kind::FORCE_CONFIG_CHUNK`] record at `time` holding `data` (at most
/// [`FORCE_CHUNK_DATA`] bytes; longer is cut) from byte `offset` of an encoding of
/// `total` bytes. Exposed so tests can build broken chunk streams.
pub fn force_config_chunk(time: u64, total: u16, offset: u16, data: &[u8]) -> Record {
    let mut p = [0u8; MAX_PAYLOAD];
    p[0..2].copy_from_slice(&total.to_le_bytes());
    p[2..4].copy_from_slice(&offset.to_le_bytes());
    let n = data.len().min(FORCE_CHUNK_DATA);
    for (d, s) in p[FORCE_CHUNK_HEADER..].iter_mut().zip(data.iter().take(n)) {
        *d = *s;
    }
    Record::new(
        force_kind::FORCE_CONFIG_CHUNK,
        time,
        p.get(..FORCE_CHUNK_HEADER + n).unwrap_or(&[]),
    )
}

/// The chunk records of a force configuration, all at one time, in order (an iterator, no
/// allocation): [`force_config_chunks`].
#[derive(Clone, Debug)]
pub struct ForceConfigChunks {
    bytes: [u8; FORCE_CONFIG_MAX],
    len: usize,
    offset: usize,
    time: u64,
}

/// Splits `config`'s canonical encoding into [`force_kind::FORCE_CONFIG_CHUNK`] records at
/// `time`, [`FORCE_CHUNK_DATA`] bytes each (the last may be shorter).
pub fn force_config_chunks(config: &ForceConfig, time: u64) -> ForceConfigChunks {
    let (bytes, len) = config.canonical_bytes();
    ForceConfigChunks {
        bytes,
        len: len.min(FORCE_CONFIG_MAX),
        offset: 0,
        time,
    }
}

impl Iterator for ForceConfigChunks {
    type Item = Record;

    fn next(&mut self) -> Option<Record> {
        if self.offset >= self.len {
            return None;
        }
        let end = self.offset.saturating_add(FORCE_CHUNK_DATA).min(self.len);
        let data = self.bytes.get(self.offset..end)?;
        let r = force_config_chunk(
            self.time,
            u16::try_from(self.len).unwrap_or(u16::MAX),
            u16::try_from(self.offset).unwrap_or(u16::MAX),
            data,
        );
        self.offset = end;
        Some(r)
    }
}

/// Reassembles a force configuration from its chunks in a fixed buffer (`no_std`, no
/// allocation, no panic): [`Self::push`] each chunk's payload in stream order, then
/// [`Self::finish`].
#[derive(Clone, Debug)]
pub struct ForceConfigAssembler {
    buf: [u8; FORCE_CONFIG_MAX],
    total: usize,
    received: usize,
}

impl Default for ForceConfigAssembler {
    fn default() -> Self {
        Self::new()
    }
}

impl ForceConfigAssembler {
    /// An empty assembler.
    pub const fn new() -> Self {
        ForceConfigAssembler {
            buf: [0; FORCE_CONFIG_MAX],
            total: 0,
            received: 0,
        }
    }

    /// Adds one chunk's payload; `Ok(true)` once every byte has arrived.
    pub fn push(&mut self, payload: &[u8]) -> Result<bool, ForceChunkError> {
        let (Some(head), Some(data)) = (
            payload.get(..FORCE_CHUNK_HEADER),
            payload.get(FORCE_CHUNK_HEADER..),
        ) else {
            return Err(ForceChunkError::BadLength { len: payload.len() });
        };
        if data.is_empty() {
            return Err(ForceChunkError::BadLength { len: payload.len() });
        }
        let total = usize::from(u16::from_le_bytes([head[0], head[1]]));
        let offset = usize::from(u16::from_le_bytes([head[2], head[3]]));
        if total == 0 || total > FORCE_CONFIG_MAX {
            return Err(ForceChunkError::Oversized { total });
        }
        if self.total == 0 {
            self.total = total;
        } else if total != self.total {
            return Err(ForceChunkError::TotalChanged {
                first: self.total,
                this: total,
            });
        }
        if self.received >= self.total {
            return Err(ForceChunkError::AfterComplete);
        }
        if offset != self.received {
            return Err(ForceChunkError::OutOfOrder {
                expected: self.received,
                offset,
            });
        }
        let end = offset.saturating_add(data.len());
        if end > self.total {
            return Err(ForceChunkError::PastEnd {
                end,
                total: self.total,
            });
        }
        let Some(dst) = self.buf.get_mut(offset..end) else {
            return Err(ForceChunkError::PastEnd {
                end,
                total: self.total,
            });
        };
        dst.copy_from_slice(data);
        self.received = end;
        Ok(self.is_complete())
    }

    /// Every announced byte has arrived.
    pub fn is_complete(&self) -> bool {
        self.total != 0 && self.received == self.total
    }

    /// Decodes and validates the reassembled configuration and checks its hash against the
    /// header's `force_hash`.
    pub fn finish(&self, force_hash: u64) -> Result<ForceConfig, ForceChunkError> {
        if !self.is_complete() {
            return Err(ForceChunkError::Incomplete {
                received: self.received,
                total: self.total,
            });
        }
        let bytes = self.buf.get(..self.total).unwrap_or(&[]);
        let config = decode_force_settings(bytes)?.validate()?;
        let decoded = config.hash();
        if decoded != force_hash {
            return Err(ForceChunkError::HashMismatch {
                header: force_hash,
                decoded,
            });
        }
        Ok(config)
    }
}

/// Reads the canonical encoding field by field.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], ForceChunkError> {
        let bad = ForceChunkError::BadEncoding { at: self.at };
        let end = self.at.checked_add(N).ok_or(bad)?;
        let src = self.bytes.get(self.at..end).ok_or(bad)?;
        let mut out = [0u8; N];
        out.copy_from_slice(src);
        self.at = end;
        Ok(out)
    }
    fn u8(&mut self) -> Result<u8, ForceChunkError> {
        Ok(self.take::<1>()?[0])
    }
    fn u16(&mut self) -> Result<u16, ForceChunkError> {
        Ok(u16::from_le_bytes(self.take()?))
    }
    fn fx(&mut self) -> Result<Fx, ForceChunkError> {
        Ok(Fx::from_bits(i64::from_le_bytes(self.take()?)))
    }
    /// An enum tag in `0..count`; the error points at the tag byte.
    fn tag(&mut self, count: u8) -> Result<u8, ForceChunkError> {
        let at = self.at;
        let t = self.u8()?;
        if t >= count {
            return Err(ForceChunkError::BadEncoding { at });
        }
        Ok(t)
    }
}

/// Decodes [`ForceConfig::canonical_bytes`]' used part back into settings (not yet
/// validated; condition sets past `set_count` are left at their default). Every byte must
/// be used.
pub fn decode_force_settings(bytes: &[u8]) -> Result<ForceSettings, ForceChunkError> {
    let mut c = Cursor { bytes, at: 0 };
    if c.u16()? != FORCE_CONFIG_FORMAT_VERSION {
        return Err(ForceChunkError::BadEncoding { at: 0 });
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
        return Err(ForceChunkError::BadEncoding { at: set_count_at });
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
    if c.at != bytes.len() {
        return Err(ForceChunkError::BadEncoding { at: c.at });
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
        },
    })
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::control::fuzzy::{NO_RULE, STANDARD_RULES};
    use crate::force::{DEFAULT_ADAPTIVE, DEFAULT_FUZZY, DEFAULT_PI};
    use proptest::prelude::*;

    /// Valid force settings from raw words: every field inside its documented range.
    fn settings_from(kind: u8, w: &[u32]) -> ForceSettings {
        let mut i = 0;
        let mut next = || {
            i += 1;
            w.get(i - 1).copied().unwrap_or(0)
        };
        let frac = |x: u32, lo: i64, hi: i64| Fx::from_bits(lo + (i64::from(x) % (hi - lo + 1)));
        let one = 1i64 << 32;
        let mut s = ForceSettings {
            sample_hz: 500 + (next() % 1500) as u16,
            samples_per_period: 10 + (next() % 90) as u16,
            lowpass_shift: 1 + (next() % 8) as u8,
            manual_override: next() as u8,
            reference: frac(next(), one, 2000 * one),
            force_source: if next() % 2 == 0 {
                ForceSource::Estimated
            } else {
                ForceSource::Measured
            },
            ..ForceSettings::default()
        };
        s.scales.speed_per_lsb = frac(next(), 1, one);
        s.scales.force_per_lsb = frac(next(), 1, 5 * one);
        s.estimator.coulomb_nominal = frac(next(), 0, 3 * one);
        s.estimator.friction_f[1] = frac(next(), -(one / 100), one / 100);
        s.estimator.slip_hold_periods = 1 + (next() % 100) as u8;
        s.controller = match kind % 3 {
            0 => ControllerSettings::Pi(PiSettings {
                kp: frac(next(), 1, 2 * one),
                ki: frac(next(), 1, 10 * one),
                ..DEFAULT_PI
            }),
            1 => ControllerSettings::Adaptive(AdaptiveSettings {
                open_loop_gain: frac(next(), 1, 5 * one),
                gain_filter_shift: (next() % 9) as u8,
                ..DEFAULT_ADAPTIVE
            }),
            _ => {
                let mut rules = STANDARD_RULES;
                for r in rules.iter_mut().flatten() {
                    if next() % 5 == 0 {
                        *r = NO_RULE;
                    }
                }
                rules[3][3] = 0;
                ControllerSettings::Fuzzy(FuzzySettings {
                    gdu: frac(next(), 1, one),
                    rules,
                    ..DEFAULT_FUZZY
                })
            }
        };
        let count = 1 + (next() % 8) as u8;
        s.wear.set_count = count;
        for set in s.wear.sets.iter_mut().take(usize::from(count)) {
            set.mean_power_limit = frac(next(), 1, 5000 * one);
            set.idle_power = frac(next(), 0, 500 * one);
        }
        s.wear.debounce_periods = 1 + (next() % 255) as u8;
        s.wear.threshold = if next() % 2 == 0 {
            Threshold::Updating
        } else {
            Threshold::Constant(frac(next(), 1, 3000 * one))
        };
        s
    }

    /// Pushes every chunk of `records` and finishes against `hash`.
    fn reassemble(records: &[Record], hash: u64) -> Result<ForceConfig, ForceChunkError> {
        let mut a = ForceConfigAssembler::new();
        for r in records {
            assert_eq!(r.kind, force_kind::FORCE_CONFIG_CHUNK);
            a.push(r.payload())?;
        }
        a.finish(hash)
    }

    #[test]
    fn default_force_config_round_trips_through_its_chunks() {
        for controller in [
            ControllerSettings::Pi(DEFAULT_PI),
            ControllerSettings::Adaptive(DEFAULT_ADAPTIVE),
            ControllerSettings::Fuzzy(DEFAULT_FUZZY),
        ] {
            let c = ForceSettings {
                controller,
                ..Default::default()
            }
            .validate()
            .unwrap();
            let chunks: std::vec::Vec<Record> = force_config_chunks(&c, 0).collect();
            let (_, n) = c.canonical_bytes();
            assert_eq!(chunks.len(), n.div_ceil(FORCE_CHUNK_DATA));
            assert!(chunks.iter().all(|r| r.payload().len() <= MAX_PAYLOAD));
            assert!((kind::FORCE_FIRST..=kind::FORCE_LAST).contains(&chunks[0].kind));
            assert_eq!(reassemble(&chunks, c.hash()), Ok(c));
        }
    }

    #[test]
    fn broken_chunk_streams_are_named_errors() {
        let c = ForceSettings {
            controller: ControllerSettings::Fuzzy(DEFAULT_FUZZY),
            ..Default::default()
        }
        .validate()
        .unwrap();
        let h = c.hash();
        let chunks: std::vec::Vec<Record> = force_config_chunks(&c, 0).collect();
        let total = c.canonical_bytes().1;
        assert!(chunks.len() >= 3);
        // Out of order: the second chunk first.
        assert_eq!(
            reassemble(&chunks[1..], h),
            Err(ForceChunkError::OutOfOrder {
                expected: 0,
                offset: FORCE_CHUNK_DATA
            })
        );
        // Overlapping: the first chunk twice.
        let dup = [chunks[0], chunks[0]];
        assert!(matches!(
            reassemble(&dup, h),
            Err(ForceChunkError::OutOfOrder { expected, offset: 0 }) if expected == FORCE_CHUNK_DATA
        ));
        // Missing the last chunk.
        assert_eq!(
            reassemble(&chunks[..chunks.len() - 1], h),
            Err(ForceChunkError::Incomplete {
                received: (chunks.len() - 1) * FORCE_CHUNK_DATA,
                total
            })
        );
        assert_eq!(
            reassemble(&[], h),
            Err(ForceChunkError::Incomplete {
                received: 0,
                total: 0
            })
        );
        // One chunk too many.
        let mut extra = chunks.clone();
        extra.push(chunks[0]);
        assert_eq!(reassemble(&extra, h), Err(ForceChunkError::AfterComplete));
        // Oversized and empty totals, short payloads.
        let mut a = ForceConfigAssembler::new();
        assert_eq!(
            a.push(force_config_chunk(0, 600, 0, &[1; 10]).payload()),
            Err(ForceChunkError::Oversized { total: 600 })
        );
        assert_eq!(
            a.push(force_config_chunk(0, 0, 0, &[1; 10]).payload()),
            Err(ForceChunkError::Oversized { total: 0 })
        );
        assert_eq!(
            a.push(&[1, 0, 0]),
            Err(ForceChunkError::BadLength { len: 3 })
        );
        assert_eq!(
            a.push(&[1, 0, 0, 0]),
            Err(ForceChunkError::BadLength { len: 4 })
        );
        // A chunk past the announced end, and a total that changes.
        let mut a = ForceConfigAssembler::new();
        assert_eq!(
            a.push(force_config_chunk(0, 10, 0, &[0; 20]).payload()),
            Err(ForceChunkError::PastEnd { end: 20, total: 10 })
        );
        let mut a = ForceConfigAssembler::new();
        a.push(chunks[0].payload()).unwrap();
        let mut p = [0u8; MAX_PAYLOAD];
        p[..chunks[1].payload().len()].copy_from_slice(chunks[1].payload());
        p[0] = p[0].wrapping_add(1);
        assert!(matches!(
            a.push(&p[..chunks[1].payload().len()]),
            Err(ForceChunkError::TotalChanged { .. })
        ));
        // The header's hash is another configuration's.
        assert_eq!(
            reassemble(&chunks, h ^ 1),
            Err(ForceChunkError::HashMismatch {
                header: h ^ 1,
                decoded: h
            })
        );
    }

    /// Chunks of arbitrary encoded bytes (for encodings no valid configuration makes).
    fn chunks_of(bytes: &[u8]) -> std::vec::Vec<Record> {
        bytes
            .chunks(FORCE_CHUNK_DATA)
            .enumerate()
            .map(|(i, d)| {
                force_config_chunk(0, bytes.len() as u16, (i * FORCE_CHUNK_DATA) as u16, d)
            })
            .collect()
    }

    #[test]
    fn bad_encodings_and_invalid_fields_are_named() {
        let c = ForceSettings::default().validate().unwrap();
        let (bytes, n) = c.canonical_bytes();
        let good = &bytes[..n];
        // Unknown format version.
        let mut b = good.to_vec();
        b[0] = 9;
        assert_eq!(
            reassemble(&chunks_of(&b), 0),
            Err(ForceChunkError::BadEncoding { at: 0 })
        );
        // Unknown controller tag (after version 2, rates 4, shift 1, 5 scales, 12
        // estimator values, 3 bytes, reference).
        let tag_at = 2 + 4 + 1 + 5 * 8 + 12 * 8 + 3 + 8;
        assert_eq!(good[tag_at], 0, "default controller is PI");
        let mut b = good.to_vec();
        b[tag_at] = 7;
        assert_eq!(
            reassemble(&chunks_of(&b), 0),
            Err(ForceChunkError::BadEncoding { at: tag_at })
        );
        // Trailing and missing bytes.
        let mut b = good.to_vec();
        b.push(0);
        assert_eq!(
            reassemble(&chunks_of(&b), 0),
            Err(ForceChunkError::BadEncoding { at: n })
        );
        assert!(matches!(
            reassemble(&chunks_of(&good[..n - 3]), 0),
            Err(ForceChunkError::BadEncoding { .. })
        ));
        // A field out of range is named: K_p = 0 (the first fx after the tag).
        let mut b = good.to_vec();
        b[tag_at + 1..tag_at + 9].fill(0);
        match reassemble(&chunks_of(&b), 0) {
            Err(ForceChunkError::Invalid(e)) => assert_eq!(e.field, "pi.kp"),
            other => panic!("expected pi.kp to be rejected, got {other:?}"),
        }
    }

    proptest! {
        #[test]
        fn random_force_configs_round_trip(kind in 0u8..3, w in proptest::collection::vec(any::<u32>(), 80)) {
            let s = settings_from(kind, &w);
            let c = s.validate().map_err(|e| TestCaseError::fail(std::format!("{e}")))?;
            let chunks: std::vec::Vec<Record> = force_config_chunks(&c, 42).collect();
            prop_assert!(chunks.iter().all(|r| r.time == 42));
            let (bytes, n) = c.canonical_bytes();
            prop_assert_eq!(decode_force_settings(&bytes[..n]), Ok(s));
            prop_assert_eq!(reassemble(&chunks, c.hash()), Ok(c));
        }

        #[test]
        fn any_flipped_bit_in_a_chunk_stream_is_an_error(kind in 0u8..3, w in proptest::collection::vec(any::<u32>(), 80), pick in any::<u32>(), bit in 0u8..8) {
            let c = settings_from(kind, &w).validate().map_err(|e| TestCaseError::fail(std::format!("{e}")))?;
            let mut chunks: std::vec::Vec<Record> = force_config_chunks(&c, 0).collect();
            let sizes: std::vec::Vec<usize> = chunks.iter().map(|r| r.payload().len()).collect();
            let mut k = pick as usize % sizes.iter().sum::<usize>();
            let mut i = 0;
            while k >= sizes[i] {
                k -= sizes[i];
                i += 1;
            }
            let mut p = [0u8; MAX_PAYLOAD];
            p[..sizes[i]].copy_from_slice(chunks[i].payload());
            p[k] ^= 1 << bit;
            chunks[i] = Record::new(chunks[i].kind, 0, &p[..sizes[i]]);
            prop_assert!(reassemble(&chunks, c.hash()).is_err());
        }
    }

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
    fn firmware_kinds_are_distinct_and_inside_the_output_trace_range() {
        use firmware_kind::*;
        let kinds = [
            FIRMWARE_OBSERVE,
            FIRMWARE_FORCE_PROFILE,
            FIRMWARE_ERROR,
            FIRMWARE_PROFILE,
            FIRMWARE_STATUS,
        ];
        for (i, k) in kinds.iter().enumerate() {
            assert!(
                (kind::OUTPUT_FIRST..=kind::OUTPUT_LAST).contains(k),
                "{k:#x}"
            );
            assert!(!kinds[..i].contains(k), "{k:#x} twice");
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
