//! The force configuration in chunks: its canonical bytes ([`crate::wire::force_config`],
//! up to [`FORCE_CONFIG_MAX`] bytes) do not fit one record, so an events stream with a
//! non-zero `force_hash` carries them as [`kind::FORCE_CONFIG_CHUNK`] records right after
//! `MEASURE_CONFIG`, made by [`force_config_chunks`] and put back together, checked and
//! validated by [`ForceConfigAssembler`].
//!
//! ```text
//! chunk payload: total length u16 | byte offset u16 | 1..=44 bytes of the encoding
//! ```

use crate::force::config::ForceConfig;
use crate::validation::ForceConfigError;
use crate::wire::force_config::{decode_force_settings, ForceEncodingError, FORCE_CONFIG_MAX};
use crate::wire::{kind, le_u16, Record, MAX_PAYLOAD};
use core::fmt;

/// Header of a [`kind::FORCE_CONFIG_CHUNK`] payload: total length u16 LE, byte offset
/// u16 LE.
pub const FORCE_CHUNK_HEADER: usize = 4;

/// Where a chunk header's fields are.
mod chunk_at {
    use core::ops::Range;
    pub const TOTAL: Range<usize> = 0..2;
    pub const OFFSET: Range<usize> = 2..4;
}
/// Most configuration bytes one chunk carries.
pub const FORCE_CHUNK_DATA: usize = MAX_PAYLOAD - FORCE_CHUNK_HEADER;

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

impl From<ForceEncodingError> for ForceChunkError {
    fn from(e: ForceEncodingError) -> Self {
        ForceChunkError::BadEncoding { at: e.at }
    }
}

/// One [`kind::FORCE_CONFIG_CHUNK`] record at `time` holding `data` (at most
/// [`FORCE_CHUNK_DATA`] bytes; longer is cut) from byte `offset` of an encoding of
/// `total` bytes. Exposed so tests can build broken chunk streams.
pub fn force_config_chunk(time: u64, total: u16, offset: u16, data: &[u8]) -> Record {
    let mut p = [0u8; MAX_PAYLOAD];
    p[chunk_at::TOTAL].copy_from_slice(&total.to_le_bytes());
    p[chunk_at::OFFSET].copy_from_slice(&offset.to_le_bytes());
    let n = data.len().min(FORCE_CHUNK_DATA);
    for (d, s) in p[FORCE_CHUNK_HEADER..].iter_mut().zip(data.iter().take(n)) {
        *d = *s;
    }
    Record::new(
        kind::FORCE_CONFIG_CHUNK,
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

/// Splits `config`'s canonical encoding into [`kind::FORCE_CONFIG_CHUNK`] records at
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
        let total = usize::from(le_u16(&head[chunk_at::TOTAL]));
        let offset = usize::from(le_u16(&head[chunk_at::OFFSET]));
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

#[cfg(test)]
mod tests;
