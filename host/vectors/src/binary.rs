//! Binary vector files over `tooltouch_model::wire`: an **Events** stream (header, the
//! configuration record first, one record per event, END) for the firmware under QEMU,
//! and an **Outputs** stream (header, one `MEASURE_OUTPUTS` record after each event, END)
//! for `tooltouch check`. Reading checks everything the header and records promise and
//! names the file in every error.
//!
//! A file holds exactly one stream: bytes after its END record (a second stream, or
//! anything else) are an error, so a file glued from two runs is not read as the first.
//!
//! Three layers, one API each way:
//! - the framing, any record kind: [`RecordReader`] reads a stream record by record from
//!   any [`Read`] (constant memory), [`RecordWriter`] writes one into any [`Write`];
//! - input streams: [`read_event_stream`] / [`decode_event_stream`] read every input
//!   stream — measurement events, force events with their configuration chunks, or both —
//!   into an [`InputStream`], [`encode_event_stream`] writes one;
//! - output streams: [`OutputReader`] / [`decode_output_stream`] read every output stream
//!   a device emits — measurement outputs, force outputs (`tooltouch control --out`), and
//!   the firmware's own trace with its profile and status ([`FirmwareStatus`]) records —
//!   and [`encode_output_stream`] writes one.

use std::borrow::Borrow;
use std::io::{Read, Write};
use std::path::Path;
use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceOutputs;
pub use tooltouch_model::wire::firmware_status::FirmwareStatus;
use tooltouch_model::wire::force_chunks::ForceConfigAssembler;
use tooltouch_model::wire::force_event::decode_force_event;
use tooltouch_model::wire::force_outputs::decode_force_outputs;
use tooltouch_model::wire::{self, kind, Header, Record, StreamKind, WireError};
use tooltouch_model::{MeasureConfig, MeasureEvent, MeasureOutputs, TimedEvent};

/// A wire problem as told to a user: an older stream format version names what changed
/// and how to make the file again.
fn explain_wire(problem: &WireError) -> String {
    match problem {
        WireError::BadVersion(v) if *v < wire::FORMAT_VERSION => format!(
            "{problem}: written by an older tooltouch (stream format version {v}; version 2 \
             added the measurement status: outputs `confirmed` and `faults`, configuration \
             format 2). Regenerate it with the command that made it: `tooltouch vectors` or \
             `tooltouch measure` for golden streams, `tooltouch control` for force streams, \
             the device's run again for a trace"
        ),
        _ => problem.to_string(),
    }
}

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
    #[error("{file}: {}", explain_wire(problem))]
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
    /// Bytes follow the END record.
    #[error("{file}: {what} after the END record at byte {offset} (one stream per file)")]
    AfterEnd {
        /// The file.
        file: String,
        /// Byte offset just past the END record.
        offset: usize,
        /// What follows: a second stream, or a count of bytes.
        what: String,
    },
    /// The force configuration chunks are broken.
    #[error("{file}: record {index}: {problem}")]
    ForceConfig {
        /// The file.
        file: String,
        /// Record number, from 0.
        index: usize,
        /// What is wrong.
        problem: wire::force_chunks::ForceChunkError,
    },
    /// A record written with a time before the previous record's.
    #[error("{file}: time {time} is before the previous record's {previous}")]
    TimeBeforePrevious {
        /// The file.
        file: String,
        /// The record's time.
        time: u64,
        /// The previous record's time.
        previous: u64,
    },
    /// The trace holds the firmware's error record: it rejected its input.
    #[error("{file}: the firmware rejected its input: {what}")]
    Firmware {
        /// The file.
        file: String,
        /// The error record, explained.
        what: String,
    },
}

fn push(out: &mut Vec<u8>, r: &Record) {
    let mut buf = [0u8; wire::RECORD_HEADER_LEN + wire::MAX_PAYLOAD];
    // `encode` only fails on a short buffer; this one holds the largest record.
    let n = r.encode(&mut buf).unwrap_or(0);
    out.extend_from_slice(&buf[..n]);
}

fn expect_stream(file: &str, header: Header, expected: StreamKind) -> Result<(), BinaryError> {
    if header.stream != expected {
        return Err(BinaryError::WrongStream {
            file: file.to_string(),
            found: header.stream,
            expected,
        });
    }
    Ok(())
}

/// One input event of either path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Input {
    /// A measurement event.
    Measure(MeasureEvent),
    /// A force-path event (ADC sample, control tick, CNC command).
    Force(ForceEvent),
}

/// A decoded input stream of the measurement path, the force path, or both.
#[derive(Clone, Debug, PartialEq)]
pub struct InputStream {
    /// Its header.
    pub header: Header,
    /// The measurement configuration (when the header's `measure_hash` is not 0).
    pub measure: Option<MeasureConfig>,
    /// The force configuration from its chunks (when the header's `force_hash` is not 0).
    pub force: Option<ForceConfig>,
    /// Whether the device writes an outputs record after FES events (the
    /// `FIRMWARE_OBSERVE` record; absent = yes).
    pub observe_fes: bool,
    /// Every event, time in ticks, in stream order.
    pub events: Vec<(u64, Input)>,
    /// Byte offset of each event's record, for messages.
    pub offsets: Vec<usize>,
    /// The END record's time.
    pub end_time: u64,
}

impl InputStream {
    /// The input stream of measurement `events` made under `config` alone: its header
    /// (`tick_hz`, the configuration's hash, no force configuration), every event, END at
    /// the last event's time.
    pub fn of_measure_events(
        config: &MeasureConfig,
        tick_hz: u32,
        events: &[TimedEvent],
    ) -> InputStream {
        InputStream {
            header: Header {
                stream: StreamKind::Events,
                tick_hz,
                measure_hash: config.hash(),
                force_hash: 0,
            },
            measure: Some(*config),
            force: None,
            observe_fes: true,
            events: events
                .iter()
                .map(|e| (e.time, Input::Measure(e.event)))
                .collect(),
            offsets: Vec::new(),
            end_time: events.last().map_or(0, |e| e.time),
        }
    }

    /// Fails unless the stream was made with the measurement configuration of hash
    /// `expected` (its header's, which its configuration record matches); `file` names it.
    pub fn expect_measure_hash(&self, file: &str, expected: u64) -> Result<(), BinaryError> {
        if self.header.measure_hash != expected {
            return Err(BinaryError::ConfigMismatch {
                file: file.to_string(),
                found: self.header.measure_hash,
                expected,
            });
        }
        Ok(())
    }

    /// The measurement events, timed.
    pub fn measure_events(&self) -> Vec<TimedEvent> {
        self.events
            .iter()
            .filter_map(|&(time, e)| match e {
                Input::Measure(event) => Some(TimedEvent { time, event }),
                Input::Force(_) => None,
            })
            .collect()
    }
}

/// Decodes an input stream of either path or both; `file` names it in errors. A
/// measurement configuration record comes first when the header's `measure_hash` is not
/// 0 (its hash must match), then the force configuration chunks when `force_hash` is not
/// 0 (reassembled, validated, hash checked), then an optional `FIRMWARE_OBSERVE`, the
/// events and END, and nothing after it.
pub fn decode_event_stream(bytes: &[u8], file: &str) -> Result<InputStream, BinaryError> {
    read_event_stream(bytes, file)
}

/// [`decode_event_stream`] reading `src` record by record (a `BufReader` over the file:
/// the events are kept, the file is not).
pub fn read_event_stream<R: Read>(src: R, file: &str) -> Result<InputStream, BinaryError> {
    let wire_err = |problem| BinaryError::Wire {
        file: file.to_string(),
        problem,
    };
    let mut records = RecordReader::new(src, file)?;
    let header = records.header();
    expect_stream(file, header, StreamKind::Events)?;
    let mut stream = InputStream {
        header,
        measure: None,
        force: None,
        observe_fes: true,
        events: Vec::new(),
        offsets: Vec::new(),
        end_time: 0,
    };
    let mut assembler = (header.force_hash != 0).then(ForceConfigAssembler::new);
    let mut ended = false;
    let mut index = 0;
    while let Some((r, offset)) = records.next_record()? {
        let bad = |message: String| BinaryError::BadRecord {
            file: file.to_string(),
            index,
            kind: r.kind,
            message,
        };
        if index == 0 && header.measure_hash != 0 {
            if r.kind != wire::kind::MEASURE_CONFIG {
                return Err(bad(format!(
                    "the header names measure_hash {:016x}: the first record must be the configuration",
                    header.measure_hash
                )));
            }
            let c = wire::measure_config::decode_config(r.payload()).map_err(wire_err)?;
            if c.hash() != header.measure_hash {
                return Err(BinaryError::ConfigMismatch {
                    file: file.to_string(),
                    found: c.hash(),
                    expected: header.measure_hash,
                });
            }
            stream.measure = Some(c);
        } else if let Some(a) = assembler.as_mut() {
            let problem = if r.kind == kind::FORCE_CONFIG_CHUNK {
                a.push(r.payload()).err()
            } else {
                Some(
                    a.finish(header.force_hash)
                        .err()
                        .unwrap_or(wire::force_chunks::ForceChunkError::AfterComplete),
                )
            };
            if let Some(problem) = problem {
                return Err(BinaryError::ForceConfig {
                    file: file.to_string(),
                    index,
                    problem,
                });
            }
            if a.is_complete() {
                let config =
                    a.finish(header.force_hash)
                        .map_err(|problem| BinaryError::ForceConfig {
                            file: file.to_string(),
                            index,
                            problem,
                        })?;
                stream.force = Some(config);
                assembler = None;
            }
        } else if r.kind == wire::kind::END {
            ended = true;
            stream.end_time = r.time;
        } else if r.kind == kind::FIRMWARE_OBSERVE {
            if !stream.events.is_empty() {
                return Err(bad("FIRMWARE_OBSERVE after the first event".into()));
            }
            stream.observe_fes = r.payload().first().is_none_or(|&b| b != 0);
        } else {
            let measure = wire::measure_event::decode_event(&r, offset).map_err(wire_err)?;
            let input = match measure {
                Some(e) if stream.measure.is_some() => Input::Measure(e),
                Some(_) => {
                    return Err(bad(
                        "a measurement event in a stream without a measurement configuration (measure_hash 0)".into(),
                    ))
                }
                None => match decode_force_event(&r, offset).map_err(wire_err)? {
                    Some(e) if stream.force.is_some() => Input::Force(e),
                    Some(_) => {
                        return Err(bad(
                            "a force event in a stream without a force configuration (force_hash 0)".into(),
                        ))
                    }
                    None => return Err(bad("not an input event".into())),
                },
            };
            stream.events.push((r.time, input));
            stream.offsets.push(offset);
        }
        index += 1;
    }
    if let Some(a) = &assembler {
        let problem = a
            .finish(header.force_hash)
            .err()
            .unwrap_or(wire::force_chunks::ForceChunkError::AfterComplete);
        return Err(BinaryError::ForceConfig {
            file: file.to_string(),
            index: 0,
            problem,
        });
    }
    if !ended {
        return Err(BinaryError::NoEnd {
            file: file.to_string(),
        });
    }
    records.nothing_after_end()?;
    if header.measure_hash == 0 && header.force_hash == 0 {
        return Err(BinaryError::BadRecord {
            file: file.to_string(),
            index: 0,
            kind: 0,
            message: "the header names no configuration (both hashes 0)".into(),
        });
    }
    Ok(stream)
}

/// Encodes an input stream: header, the measurement configuration, the force
/// configuration chunks and the `FIRMWARE_OBSERVE` record (when the stream has them, all
/// at time 0), the events, END at `end_time`.
pub fn encode_event_stream(stream: &InputStream) -> Vec<u8> {
    let mut out = Vec::with_capacity(wire::HEADER_LEN + 16 * stream.events.len() + 64);
    out.extend_from_slice(&stream.header.encode());
    if let Some(c) = &stream.measure {
        push(&mut out, &wire::measure_config::encode_config(c));
    }
    if let Some(f) = &stream.force {
        for r in wire::force_chunks::force_config_chunks(f, 0) {
            push(&mut out, &r);
        }
    }
    if !stream.observe_fes {
        push(&mut out, &Record::new(kind::FIRMWARE_OBSERVE, 0, &[0]));
    }
    for &(time, e) in &stream.events {
        let r = match e {
            Input::Measure(e) => wire::measure_event::encode_event(time, e),
            Input::Force(e) => tooltouch_model::wire::force_event::encode_force_event(time, &e),
        };
        push(&mut out, &r);
    }
    push(
        &mut out,
        &Record::new(wire::kind::END, stream.end_time, &[]),
    );
    out
}

/// One output record of either path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Output {
    /// Measurement outputs after a measurement event.
    Measure(MeasureOutputs),
    /// Force outputs after a force event other than a sample.
    Force(ForceOutputs),
}

/// Encodes an Outputs stream of either path or both: header (`tick_hz` and both hashes
/// from `header`), one record per output `(time, output)` in order (a slice of them, or
/// an iterator), END at the last record's time.
pub fn encode_output_stream<I>(header: Header, outputs: I) -> Vec<u8>
where
    I: IntoIterator,
    I::Item: Borrow<(u64, Output)>,
{
    let header = Header {
        stream: StreamKind::Outputs,
        ..header
    };
    let outputs = outputs.into_iter();
    let mut out = Vec::with_capacity(wire::HEADER_LEN + 54 * outputs.size_hint().0 + 16);
    out.extend_from_slice(&header.encode());
    let mut end = 0;
    for output in outputs {
        let &(t, o) = output.borrow();
        end = t;
        let r = match o {
            Output::Measure(o) => Record::new(
                wire::kind::MEASURE_OUTPUTS,
                t,
                &wire::measure_outputs::encode_outputs(&o),
            ),
            Output::Force(o) => tooltouch_model::wire::force_outputs::outputs_record(t, &o),
        };
        push(&mut out, &r);
    }
    push(&mut out, &Record::new(wire::kind::END, end, &[]));
    out
}

/// A decoded Outputs stream of any device: measurement and force outputs in stream
/// order, and the firmware's status when the stream is a firmware trace.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputStream {
    /// Its header.
    pub header: Header,
    /// Measurement outputs with their times.
    pub measure: Vec<(u64, MeasureOutputs)>,
    /// Force outputs with their times.
    pub force: Vec<(u64, ForceOutputs)>,
    /// The firmware's status record, if any.
    pub status: Option<FirmwareStatus>,
}

/// The part of the firmware's status a trace must hold: its events, lost and overflowed
/// counters (the ones `check` reports), bytes.
const STATUS_COUNTERS_LEN: usize = 12;

/// One output record of a device's Outputs stream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OutputRecord {
    /// Measurement outputs and their time.
    Measure(u64, MeasureOutputs),
    /// Force outputs and their time.
    Force(u64, ForceOutputs),
}

/// Reads an Outputs stream of any device record by record ([`RecordReader`]): the
/// records [`decode_output_stream`] keeps, one per [`OutputReader::next_output`], the
/// firmware's status kept aside, and every error of [`decode_output_stream`] at the same
/// place (a missing END and bytes after it when the records are exhausted).
pub struct OutputReader<R> {
    records: RecordReader<R>,
    file: String,
    index: usize,
    status: Option<FirmwareStatus>,
    ended: bool,
    finished: bool,
}

impl<R: Read> OutputReader<R> {
    /// Reads the header of `src` (an Outputs stream); `file` names it in errors.
    pub fn new(src: R, file: &str) -> Result<Self, BinaryError> {
        let records = RecordReader::new(src, file)?;
        expect_stream(file, records.header(), StreamKind::Outputs)?;
        Ok(OutputReader {
            records,
            file: file.to_string(),
            index: 0,
            status: None,
            ended: false,
            finished: false,
        })
    }

    /// The stream's header.
    pub fn header(&self) -> Header {
        self.records.header()
    }

    /// The firmware's status record, once read.
    pub fn status(&self) -> Option<FirmwareStatus> {
        self.status
    }

    /// The next output record; `None` once the stream is read to its END and nothing
    /// follows it.
    pub fn next_output(&mut self) -> Result<Option<OutputRecord>, BinaryError> {
        loop {
            if self.finished {
                return Ok(None);
            }
            let Some((r, _)) = self.records.next_record()? else {
                self.finished = true;
                if !self.ended {
                    return Err(BinaryError::NoEnd {
                        file: self.file.clone(),
                    });
                }
                self.records.nothing_after_end()?;
                return Ok(None);
            };
            let index = self.index;
            self.index += 1;
            let p = r.payload();
            let bad = |message: String| BinaryError::BadRecord {
                file: self.file.clone(),
                index,
                kind: r.kind,
                message,
            };
            match r.kind {
                wire::kind::END => self.ended = true,
                wire::kind::MEASURE_OUTPUTS => match wire::measure_outputs::decode_outputs(p) {
                    Some(o) => return Ok(Some(OutputRecord::Measure(r.time, o))),
                    None => {
                        return Err(bad(format!(
                            "payload of {} bytes, expected {}",
                            p.len(),
                            wire::measure_outputs::OUTPUTS_LEN
                        )))
                    }
                },
                tooltouch_model::wire::kind::FORCE_OUTPUTS => match decode_force_outputs(p) {
                    Some(o) => return Ok(Some(OutputRecord::Force(r.time, o))),
                    None => {
                        return Err(bad(format!(
                            "force outputs payload of {} bytes, expected {}",
                            p.len(),
                            tooltouch_model::wire::force_outputs::FORCE_OUTPUTS_LEN
                        )))
                    }
                },
                // The firmware's profile and its calibrated decision reports
                // (`tooltouch cosim` checks those against the golden model).
                kind::FIRMWARE_PROFILE | kind::FIRMWARE_FORCE_PROFILE | kind::FIRMWARE_DECISION => {
                }
                kind::FIRMWARE_STATUS => {
                    if p.len() < STATUS_COUNTERS_LEN {
                        return Err(bad(format!("status payload of {} bytes", p.len())));
                    }
                    self.status = Some(FirmwareStatus::decode(p));
                }
                kind::FIRMWARE_ERROR => {
                    return Err(BinaryError::Firmware {
                        file: self.file.clone(),
                        what: crate::firmware_error::describe_firmware_error(p),
                    })
                }
                _ => return Err(bad("not an output record".into())),
            }
        }
    }
}

/// Decodes an Outputs stream of any device: `MEASURE_OUTPUTS` and force `OUTPUTS`
/// records, the firmware's profile and decision records (skipped) and status record (kept), END, and
/// nothing after it. A firmware error record is [`BinaryError::Firmware`]. Holds every
/// record: `tooltouch check` streams with [`OutputReader`] instead.
pub fn decode_output_stream(bytes: &[u8], file: &str) -> Result<OutputStream, BinaryError> {
    let mut reader = OutputReader::new(bytes, file)?;
    let mut s = OutputStream {
        header: reader.header(),
        measure: Vec::new(),
        force: Vec::new(),
        status: None,
    };
    while let Some(r) = reader.next_output()? {
        match r {
            OutputRecord::Measure(t, o) => s.measure.push((t, o)),
            OutputRecord::Force(t, o) => s.force.push((t, o)),
        }
    }
    s.status = reader.status();
    Ok(s)
}

/// Reads as many bytes as `buf` holds, fewer only at the end of `src`; returns the count.
fn fill<R: Read>(src: &mut R, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match src.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

/// Reads a stream record by record from any [`Read`] (a `BufReader` over the file), so
/// that a file of any length is read in constant memory: the header first
/// ([`RecordReader::new`]), then one record per [`RecordReader::next_record`], with the
/// same checks and messages as [`wire::Records`] over the whole file in memory (truncation, bad
/// payload lengths, time going backwards, each at its byte offset).
pub struct RecordReader<R> {
    src: R,
    file: String,
    header: Header,
    /// Byte offset of the next record.
    offset: usize,
    previous: u64,
    /// After an END record or an error.
    done: bool,
}

impl<R: Read> RecordReader<R> {
    /// Reads the header of `src`; `file` names it in errors.
    pub fn new(mut src: R, file: &str) -> Result<Self, BinaryError> {
        let mut h = [0u8; wire::HEADER_LEN];
        let n = fill(&mut src, &mut h).map_err(|source| BinaryError::Io {
            file: file.to_string(),
            source,
        })?;
        let header = Header::decode(&h[..n]).map_err(|problem| BinaryError::Wire {
            file: file.to_string(),
            problem,
        })?;
        Ok(RecordReader {
            src,
            file: file.to_string(),
            header,
            offset: wire::HEADER_LEN,
            previous: 0,
            done: false,
        })
    }

    /// The stream's header.
    pub fn header(&self) -> Header {
        self.header
    }

    /// The byte offset of the next record (just past the END record once it was read).
    pub fn offset(&self) -> usize {
        self.offset
    }

    fn wire_error(&mut self, problem: WireError) -> BinaryError {
        self.done = true;
        BinaryError::Wire {
            file: self.file.clone(),
            problem,
        }
    }

    fn io_error(&mut self, source: std::io::Error) -> BinaryError {
        self.done = true;
        BinaryError::Io {
            file: self.file.clone(),
            source,
        }
    }

    /// The next record and its byte offset; `None` at the end of the file and after the
    /// END record.
    pub fn next_record(&mut self) -> Result<Option<(Record, usize)>, BinaryError> {
        if self.done {
            return Ok(None);
        }
        let offset = self.offset;
        let mut buf = [0u8; wire::RECORD_HEADER_LEN + wire::MAX_PAYLOAD];
        let n = fill(&mut self.src, &mut buf[..wire::RECORD_HEADER_LEN])
            .map_err(|e| self.io_error(e))?;
        if n == 0 {
            self.done = true;
            return Ok(None);
        }
        if n == wire::RECORD_HEADER_LEN {
            let len = usize::from(buf[1]).min(wire::MAX_PAYLOAD);
            let end = wire::RECORD_HEADER_LEN + len;
            let got = fill(&mut self.src, &mut buf[wire::RECORD_HEADER_LEN..end])
                .map_err(|e| self.io_error(e))?;
            let total = wire::RECORD_HEADER_LEN + got;
            let decoded = Record::decode(&buf[..total], offset);
            return match decoded {
                Err(problem) => Err(self.wire_error(problem)),
                Ok((record, size)) => {
                    if record.time < self.previous {
                        let problem = WireError::NonMonotonicTime {
                            offset,
                            previous: self.previous,
                            time: record.time,
                        };
                        return Err(self.wire_error(problem));
                    }
                    self.previous = record.time;
                    self.offset += size;
                    self.done = record.kind == kind::END;
                    Ok(Some((record, offset)))
                }
            };
        }
        Err(self.wire_error(WireError::Truncated {
            offset,
            needed: wire::RECORD_HEADER_LEN,
        }))
    }

    /// After the END record: fails when bytes follow it (one stream per file), naming a
    /// second stream or counting the bytes.
    pub fn nothing_after_end(&mut self) -> Result<(), BinaryError> {
        let mut head = [0u8; 4];
        let n = fill(&mut self.src, &mut head).map_err(|e| self.io_error(e))?;
        if n == 0 {
            return Ok(());
        }
        let what = if head[..n].starts_with(&wire::MAGIC) {
            "a second stream (magic \"TTVX\")".to_string()
        } else {
            let more =
                std::io::copy(&mut self.src, &mut std::io::sink()).map_err(|e| self.io_error(e))?;
            format!("{} more bytes", n as u64 + more)
        };
        Err(BinaryError::AfterEnd {
            file: self.file.clone(),
            offset: self.offset,
            what,
        })
    }
}

/// Writes a stream record by record into any [`Write`] (a `BufWriter` over the file), the
/// framing [`RecordReader`] reads back: the header first ([`RecordWriter::new`]), then one
/// record per [`RecordWriter::write`], time never going backwards, and the END record at
/// the last record's time ([`RecordWriter::finish`]).
pub struct RecordWriter<W: Write> {
    sink: W,
    file: String,
    last_time: u64,
    /// Records written, END excluded.
    written: usize,
}

impl<W: Write> RecordWriter<W> {
    /// Writes `header` into `sink`; `file` names it in errors.
    pub fn new(mut sink: W, header: Header, file: &str) -> Result<Self, BinaryError> {
        sink.write_all(&header.encode())
            .map_err(|source| BinaryError::Io {
                file: file.to_string(),
                source,
            })?;
        Ok(RecordWriter {
            sink,
            file: file.to_string(),
            last_time: 0,
            written: 0,
        })
    }

    /// The last record's time (0 before the first).
    pub fn last_time(&self) -> u64 {
        self.last_time
    }

    /// Writes `record`: not before the previous record's time, and not END (which
    /// [`RecordWriter::finish`] writes).
    pub fn write(&mut self, record: &Record) -> Result<(), BinaryError> {
        if record.kind == kind::END {
            return Err(BinaryError::BadRecord {
                file: self.file.clone(),
                index: self.written,
                kind: record.kind,
                message: "END is written when the stream is finished".into(),
            });
        }
        self.put(record)?;
        self.written += 1;
        Ok(())
    }

    fn put(&mut self, record: &Record) -> Result<(), BinaryError> {
        if record.time < self.last_time {
            return Err(BinaryError::TimeBeforePrevious {
                file: self.file.clone(),
                time: record.time,
                previous: self.last_time,
            });
        }
        let mut buf = [0u8; wire::RECORD_HEADER_LEN + wire::MAX_PAYLOAD];
        // `encode` only fails on a short buffer; this one holds the largest record.
        let n = record.encode(&mut buf).unwrap_or(0);
        self.sink
            .write_all(&buf[..n])
            .map_err(|source| BinaryError::Io {
                file: self.file.clone(),
                source,
            })?;
        self.last_time = record.time;
        Ok(())
    }

    /// Writes the END record at the last record's time, flushes the sink and returns it.
    pub fn finish(mut self) -> Result<W, BinaryError> {
        self.put(&Record::new(kind::END, self.last_time, &[]))?;
        self.sink.flush().map_err(|source| BinaryError::Io {
            file: self.file.clone(),
            source,
        })?;
        Ok(self.sink)
    }
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

    fn events() -> Vec<TimedEvent> {
        vec![
            TimedEvent {
                time: 3,
                event: MeasureEvent::Arm(true),
            },
            TimedEvent {
                time: 3,
                event: MeasureEvent::Scale { a: true, b: false },
            },
        ]
    }

    #[test]
    fn events_round_trip() {
        let c = MeasureConfig::default();
        let ev = events();
        let bytes = encode_event_stream(&InputStream::of_measure_events(&c, 50_000_000, &ev));
        let s = decode_event_stream(&bytes, "x").unwrap();
        s.expect_measure_hash("x", c.hash()).unwrap();
        assert_eq!(s.measure_events(), ev);
        assert_eq!(s.measure, Some(c));
        assert_eq!(s.end_time, 3);
        let e = s.expect_measure_hash("x", c.hash() ^ 1).unwrap_err();
        assert!(e.to_string().contains("does not match"), "{e}");
    }

    #[test]
    fn the_record_writer_writes_what_the_encoders_write() {
        let c = MeasureConfig::default();
        let stream = InputStream::of_measure_events(&c, 1000, &events());
        let mut w = RecordWriter::new(Vec::new(), stream.header, "w.ttv").unwrap();
        w.write(&wire::measure_config::encode_config(&c)).unwrap();
        for &(time, e) in &stream.events {
            let Input::Measure(e) = e else { unreachable!() };
            w.write(&wire::measure_event::encode_event(time, e))
                .unwrap();
        }
        assert_eq!(w.last_time(), 3);
        let e = w.write(&Record::new(kind::FES, 2, &[])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "w.ttv: time 2 is before the previous record's 3"
        );
        let e = w.write(&Record::new(kind::END, 9, &[])).unwrap_err();
        assert!(e.to_string().contains("record 3 (kind 0x7f)"), "{e}");
        assert_eq!(w.finish().unwrap(), encode_event_stream(&stream));
    }

    #[test]
    fn a_stream_of_format_version_1_names_its_version_and_how_to_regenerate_it() {
        let c = MeasureConfig::default();
        let mut bytes = encode_event_stream(&InputStream::of_measure_events(&c, 1000, &events()));
        bytes[4..6].copy_from_slice(&1u16.to_le_bytes());
        let e = decode_event_stream(&bytes, "old.ttv")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "old.ttv: unsupported format version 1, expected 2: written by an older tooltouch"
            ) && e.contains("`confirmed` and `faults`")
                && e.contains("Regenerate it with the command that made it: `tooltouch vectors`"),
            "{e}"
        );
        let header = InputStream::of_measure_events(&c, 1000, &events()).header;
        let mut old = encode_output_stream::<[(u64, Output); 0]>(header, []);
        old[4..6].copy_from_slice(&1u16.to_le_bytes());
        let e = decode_output_stream(&old, "old.ttv")
            .unwrap_err()
            .to_string();
        assert!(e.contains("stream format version 1"), "{e}");
    }
}
