//! Binary vector files over `tooltouch_model::wire`: an **Events** stream (header, the
//! configuration record first, one record per event, END) for the firmware under QEMU,
//! and an **Outputs** stream (header, one `MEASURE_OUTPUTS` record after each event, END)
//! for `tooltouch check`. Reading checks everything the header and records promise and
//! names the file in every error.

use std::path::Path;
use tooltouch_model::wire::{self, Header, Record, Records, StreamKind, WireError};
use tooltouch_model::{MeasureConfig, MeasureOutputs, TimedEvent};

/// A bad binary vector file.
#[derive(Debug, thiserror::Error)]
pub enum BinaryError {
    /// The file could not be read or written.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The stream is malformed.
    #[error("{file}: {problem}")]
    Wire {
        /// The file.
        file: String,
        /// What is wrong (truncated, wrong magic or version, time going backwards, ...).
        problem: WireError,
    },
    /// The stream holds another kind of stream than expected.
    #[error("{file}: holds a {found:?} stream, expected {expected:?}")]
    WrongStream {
        /// The file.
        file: String,
        /// Found.
        found: StreamKind,
        /// Expected.
        expected: StreamKind,
    },
    /// The configuration differs from the expected one.
    #[error("{file}: configuration hash {found:016x} does not match the expected {expected:016x} (made with another configuration)")]
    ConfigMismatch {
        /// The file.
        file: String,
        /// Hash found.
        found: u64,
        /// Hash expected.
        expected: u64,
    },
    /// A record is not what the stream may hold at that place.
    #[error("{file}: record {index} (kind 0x{kind:02x}): {message}")]
    BadRecord {
        /// The file.
        file: String,
        /// Record number, from 0.
        index: usize,
        /// Its kind.
        kind: u8,
        /// What is wrong.
        message: String,
    },
    /// The stream ends without an END record.
    #[error("{file}: stream ends without an END record (truncated?)")]
    NoEnd {
        /// The file.
        file: String,
    },
}

fn push(out: &mut Vec<u8>, r: &Record) {
    let mut buf = [0u8; wire::RECORD_HEADER_LEN + wire::MAX_PAYLOAD];
    // `encode` only fails on a short buffer; this one holds the largest record.
    let n = r.encode(&mut buf).unwrap_or(0);
    out.extend_from_slice(&buf[..n]);
}

/// Encodes an Events stream: header (`tick_hz`, the configuration's hash), the
/// configuration record at time 0, one record per event, END at the last event's time.
pub fn encode_events(events: &[TimedEvent], config: &MeasureConfig, tick_hz: u32) -> Vec<u8> {
    let header = Header {
        stream: StreamKind::Events,
        tick_hz,
        measure_hash: config.hash(),
        force_hash: 0,
    };
    let mut out = Vec::with_capacity(wire::HEADER_LEN + 16 * events.len() + 64);
    out.extend_from_slice(&header.encode());
    push(&mut out, &wire::measure_config::encode_config(config));
    for e in events {
        push(
            &mut out,
            &wire::measure_event::encode_event(e.time, e.event),
        );
    }
    let end = events.last().map_or(0, |e| e.time);
    push(&mut out, &Record::new(wire::kind::END, end, &[]));
    out
}

/// Encodes an Outputs stream: one `MEASURE_OUTPUTS` record per `(time, outputs)`.
pub fn encode_outputs(
    outputs: &[(u64, MeasureOutputs)],
    config: &MeasureConfig,
    tick_hz: u32,
) -> Vec<u8> {
    let header = Header {
        stream: StreamKind::Outputs,
        tick_hz,
        measure_hash: config.hash(),
        force_hash: 0,
    };
    let mut out = Vec::with_capacity(wire::HEADER_LEN + 42 * outputs.len() + 16);
    out.extend_from_slice(&header.encode());
    for (t, o) in outputs {
        push(
            &mut out,
            &Record::new(
                wire::kind::MEASURE_OUTPUTS,
                *t,
                &wire::measure_outputs::encode_outputs(o),
            ),
        );
    }
    let end = outputs.last().map_or(0, |o| o.0);
    push(&mut out, &Record::new(wire::kind::END, end, &[]));
    out
}

/// A decoded Events stream.
#[derive(Clone, Debug, PartialEq)]
pub struct EventStream {
    /// Its header.
    pub header: Header,
    /// The configuration from its first record (its hash matches the header's).
    pub config: MeasureConfig,
    /// The events.
    pub events: Vec<TimedEvent>,
}

/// Decodes an Events stream; `file` names it in errors. The first record must be the
/// configuration and its hash must match the header's (and `expected_hash` when given).
pub fn decode_events(
    bytes: &[u8],
    file: &str,
    expected_hash: Option<u64>,
) -> Result<EventStream, BinaryError> {
    let wire_err = |problem| BinaryError::Wire {
        file: file.to_string(),
        problem,
    };
    let (header, records) = Records::new(bytes).map_err(wire_err)?;
    expect_stream(file, header, StreamKind::Events, expected_hash)?;
    let mut config = None;
    let mut events = Vec::new();
    let mut ended = false;
    let mut offset = wire::HEADER_LEN;
    for (index, r) in records.enumerate() {
        let r = r.map_err(wire_err)?;
        let bad = |message: String| BinaryError::BadRecord {
            file: file.to_string(),
            index,
            kind: r.kind,
            message,
        };
        if index == 0 {
            if r.kind != wire::kind::MEASURE_CONFIG {
                return Err(bad("the first record must be the configuration".into()));
            }
            let c = wire::measure_config::decode_config(r.payload()).map_err(wire_err)?;
            if c.hash() != header.measure_hash {
                return Err(BinaryError::ConfigMismatch {
                    file: file.to_string(),
                    found: c.hash(),
                    expected: header.measure_hash,
                });
            }
            config = Some(c);
        } else if r.kind == wire::kind::END {
            ended = true;
        } else {
            match wire::measure_event::decode_event(&r, offset).map_err(wire_err)? {
                Some(event) => events.push(TimedEvent {
                    time: r.time,
                    event,
                }),
                None => return Err(bad("not a measurement event".into())),
            }
        }
        offset += r.encoded_len();
    }
    if !ended {
        return Err(BinaryError::NoEnd {
            file: file.to_string(),
        });
    }
    let config = config.ok_or_else(|| BinaryError::NoEnd {
        file: file.to_string(),
    })?;
    Ok(EventStream {
        header,
        config,
        events,
    })
}

fn expect_stream(
    file: &str,
    header: Header,
    expected: StreamKind,
    expected_hash: Option<u64>,
) -> Result<(), BinaryError> {
    if header.stream != expected {
        return Err(BinaryError::WrongStream {
            file: file.to_string(),
            found: header.stream,
            expected,
        });
    }
    if let Some(h) = expected_hash {
        if h != header.measure_hash {
            return Err(BinaryError::ConfigMismatch {
                file: file.to_string(),
                found: header.measure_hash,
                expected: h,
            });
        }
    }
    Ok(())
}

/// Decodes an Outputs stream: its header and `(time, outputs)` per record.
pub fn decode_outputs(
    bytes: &[u8],
    file: &str,
    expected_hash: Option<u64>,
) -> Result<(Header, Vec<(u64, MeasureOutputs)>), BinaryError> {
    let wire_err = |problem| BinaryError::Wire {
        file: file.to_string(),
        problem,
    };
    let (header, records) = Records::new(bytes).map_err(wire_err)?;
    expect_stream(file, header, StreamKind::Outputs, expected_hash)?;
    let mut out = Vec::new();
    let mut ended = false;
    for (index, r) in records.enumerate() {
        let r = r.map_err(wire_err)?;
        match r.kind {
            wire::kind::END => ended = true,
            wire::kind::MEASURE_OUTPUTS => match wire::measure_outputs::decode_outputs(r.payload())
            {
                Some(o) => out.push((r.time, o)),
                None => {
                    return Err(BinaryError::BadRecord {
                        file: file.to_string(),
                        index,
                        kind: r.kind,
                        message: format!(
                            "payload of {} bytes, expected {}",
                            r.payload().len(),
                            wire::measure_outputs::OUTPUTS_LEN
                        ),
                    })
                }
            },
            k => {
                return Err(BinaryError::BadRecord {
                    file: file.to_string(),
                    index,
                    kind: k,
                    message: "not a measurement-outputs record".into(),
                })
            }
        }
    }
    if !ended {
        return Err(BinaryError::NoEnd {
            file: file.to_string(),
        });
    }
    Ok((header, out))
}

/// Reads a whole file, naming it in the error.
pub fn read_file(path: &Path) -> Result<Vec<u8>, BinaryError> {
    std::fs::read(path).map_err(|source| BinaryError::Io {
        file: path.display().to_string(),
        source,
    })
}

/// Names of the [`MeasureOutputs`] fields with their values as unsigned numbers (signed
/// positions as their two's-complement `i32` bits), for record-by-record comparison.
pub fn output_fields(o: &MeasureOutputs) -> [(&'static str, u64); MeasureOutputs::FIELD_COUNT] {
    // Every field fits 32 bits: keep the low 32 bits (two's complement for positions).
    o.fields()
        .map(|(name, value)| (name, u64::from(value as u32)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::MeasureEvent;

    #[test]
    fn events_round_trip() {
        let c = MeasureConfig::default();
        let ev = vec![
            TimedEvent {
                time: 3,
                event: MeasureEvent::Arm(true),
            },
            TimedEvent {
                time: 3,
                event: MeasureEvent::Scale { a: true, b: false },
            },
        ];
        let bytes = encode_events(&ev, &c, 50_000_000);
        let s = decode_events(&bytes, "x", Some(c.hash())).unwrap();
        assert_eq!(s.events, ev);
        assert_eq!(s.config, c);
    }
}
