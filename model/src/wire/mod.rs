//! The compact binary vector format shared by the host tools and the firmware: a header
//! carrying the configurations' hashes, then length-prefixed timestamped records.
//!
//! ```text
//! header (28 bytes): magic "TTVX" | version u16 | stream u16 | tick_hz u32
//!                    | measure config hash u64 | force config hash u64
//! record:            kind u8 | payload length u8 | time u64 | payload (0..=48 bytes)
//! ```
//! All integers little-endian. This module is the framing: [`Header`], [`Record`], the
//! [`Records`] iterator and [`WireError`]. The kind bytes are registered in one place,
//! [`kind`]; each payload has one file holding both its encoder and its decoder:
//!
//! | payload | kinds | file |
//! |---|---|---|
//! | measurement configuration (canonical bytes, hash) | `MEASURE_CONFIG` | [`measure_config`] |
//! | measurement events | `ARM`..=`PRESET_PULSES` | [`measure_event`] |
//! | measurement outputs | `MEASURE_OUTPUTS` | [`measure_outputs`] |
//! | force configuration (canonical bytes, hash) | — | [`force_config`] |
//! | force configuration in chunks | `FORCE_CONFIG_CHUNK` | [`force_chunks`] |
//! | force events | `SAMPLE`..=`TOOL_CHANGED` | [`force_event`] |
//! | force outputs | `FORCE_OUTPUTS` | [`force_outputs`] |
//! | the firmware's status | `FIRMWARE_STATUS` | [`firmware_status`] |
//!
//! The firmware co-simulation's other records (`FIRMWARE_*`) are registered in [`kind`];
//! their payloads are written by the firmware and read by the host's `tooltouch::cosim`.
//!
//! Decoding never panics: a short, unknown or malformed record is a [`WireError`].
//! Dependencies point one way: the payload files import this framing and the model types
//! they encode; nothing in `measure` or `force` imports `wire`.

pub mod firmware_status;
pub mod force_chunks;
pub mod force_config;
pub mod force_event;
pub mod force_outputs;
pub mod kind;
pub mod measure_config;
pub mod measure_event;
pub mod measure_outputs;

use crate::validation::ConfigError;
use core::fmt;

/// File magic.
pub const MAGIC: [u8; 4] = *b"TTVX";
/// Format version written and accepted.
pub const FORMAT_VERSION: u16 = 2;
/// Header length, bytes.
pub const HEADER_LEN: usize = 28;
/// Record header length (kind, length, time), bytes.
pub const RECORD_HEADER_LEN: usize = 10;
/// Largest payload, bytes.
pub const MAX_PAYLOAD: usize = 48;

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
    /// [`crate::measure::config::MeasureConfig::hash`] of the configuration the stream was made
    /// with.
    pub measure_hash: u64,
    /// Hash of the force-path configuration (0 when none).
    pub force_hash: u64,
}

impl Header {
    /// Encodes into 28 bytes.
    pub fn encode(&self) -> [u8; HEADER_LEN] {
        let mut out = [0u8; HEADER_LEN];
        out[header_at::MAGIC].copy_from_slice(&MAGIC);
        out[header_at::VERSION].copy_from_slice(&FORMAT_VERSION.to_le_bytes());
        out[header_at::STREAM].copy_from_slice(&(self.stream as u16).to_le_bytes());
        out[header_at::TICK_HZ].copy_from_slice(&self.tick_hz.to_le_bytes());
        out[header_at::MEASURE_HASH].copy_from_slice(&self.measure_hash.to_le_bytes());
        out[header_at::FORCE_HASH].copy_from_slice(&self.force_hash.to_le_bytes());
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
        let magic = le_array(&h[header_at::MAGIC]);
        if magic != MAGIC {
            return Err(WireError::BadMagic(magic));
        }
        let version = le_u16(&h[header_at::VERSION]);
        if version != FORMAT_VERSION {
            return Err(WireError::BadVersion(version));
        }
        let stream = match le_u16(&h[header_at::STREAM]) {
            1 => StreamKind::Events,
            2 => StreamKind::Outputs,
            other => return Err(WireError::BadStream(other)),
        };
        Ok(Header {
            stream,
            tick_hz: le_u32(&h[header_at::TICK_HZ]),
            measure_hash: le_u64(&h[header_at::MEASURE_HASH]),
            force_hash: le_u64(&h[header_at::FORCE_HASH]),
        })
    }
}

/// Byte ranges of the header's fields.
mod header_at {
    use core::ops::Range;
    /// [`super::MAGIC`].
    pub const MAGIC: Range<usize> = 0..4;
    /// [`super::FORMAT_VERSION`], u16.
    pub const VERSION: Range<usize> = 4..6;
    /// [`super::StreamKind`], u16.
    pub const STREAM: Range<usize> = 6..8;
    /// `tick_hz`, u32.
    pub const TICK_HZ: Range<usize> = 8..12;
    /// `measure_hash`, u64.
    pub const MEASURE_HASH: Range<usize> = 12..20;
    /// `force_hash`, u64.
    pub const FORCE_HASH: Range<usize> = 20..28;
}

/// Byte positions of a record's fields.
mod record_at {
    use core::ops::Range;
    /// The kind byte.
    pub const KIND: usize = 0;
    /// The payload length byte.
    pub const LEN: usize = 1;
    /// The time, u64.
    pub const TIME: Range<usize> = 2..10;
}

/// The first `N` bytes of `b`, zero-padded when `b` is shorter (callers pass exact ranges).
pub(crate) fn le_array<const N: usize>(b: &[u8]) -> [u8; N] {
    let mut a = [0u8; N];
    for (d, s) in a.iter_mut().zip(b) {
        *d = *s;
    }
    a
}

/// A little-endian u16 from the first 2 bytes of `b`.
pub(crate) fn le_u16(b: &[u8]) -> u16 {
    u16::from_le_bytes(le_array(b))
}

/// A little-endian u32 from the first 4 bytes of `b`.
pub(crate) fn le_u32(b: &[u8]) -> u32 {
    u32::from_le_bytes(le_array(b))
}

/// A little-endian u64 from the first 8 bytes of `b`.
pub(crate) fn le_u64(b: &[u8]) -> u64 {
    u64::from_le_bytes(le_array(b))
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
        out[record_at::KIND] = self.kind;
        out[record_at::LEN] = self.len;
        out[record_at::TIME].copy_from_slice(&self.time.to_le_bytes());
        out[RECORD_HEADER_LEN..].copy_from_slice(self.payload());
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
        let kind = bytes[record_at::KIND];
        let len = bytes[record_at::LEN];
        if usize::from(len) > MAX_PAYLOAD {
            return Err(WireError::BadLength { kind, len, offset });
        }
        let n = RECORD_HEADER_LEN + usize::from(len);
        let Some(payload) = bytes.get(RECORD_HEADER_LEN..n) else {
            return Err(WireError::Truncated { offset, needed: n });
        };
        let time = le_u64(&bytes[record_at::TIME]);
        Ok((Record::new(kind, time, payload), n))
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

#[cfg(test)]
mod worked_examples;

#[cfg(test)]
mod tests {
    use super::*;

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
        let n1 = Record::new(kind::FES, 10, &[])
            .encode(&mut buf[HEADER_LEN..])
            .unwrap();
        let n2 = Record::new(kind::INDEX, 5, &[])
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
