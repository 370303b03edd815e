//! The co-simulation driver: replays binary event streams (model::wire) through the
//! firmware's interrupts and writes the output trace the host compares with the golden
//! model.
//!
//! Input: one or more concatenated streams, each `Header{stream: Events}`, a
//! `MEASURE_CONFIG` record (the firmware configures itself from it and checks it against
//! the header's hash), then — when the header's `force_hash` is not 0 — the force
//! configuration in `FORCE_CONFIG_CHUNK` records (model::wire: reassembled in a fixed
//! buffer, decoded, validated and checked against `force_hash` before any event; a stream
//! with `force_hash` 0 holds no force event and the force path idles in
//! [`ForceSettings::default`]), measurement and force event records, `END`. Output, per input
//! stream: `Header{stream: Outputs}` with the same hashes, one `MEASURE_OUTPUTS` record
//! after every measurement event (but FES pulses, when the stream's
//! [`kind::FIRMWARE_OBSERVE`] record says so), followed by a [`kind::FIRMWARE_DECISION`]
//! record (the decision position corrected by the baked calibration,
//! [`crate::handlers::ReportedDecision`]) when "register now" rose since the previous
//! outputs record, and one force `OUTPUTS` record after every force event
//! except a sample (model::force's convention), each at its event's time; then
//! [`kind::FIRMWARE_PROFILE`], [`kind::FIRMWARE_FORCE_PROFILE`] and
//! [`kind::FIRMWARE_STATUS`] records (`wire::firmware_status`: the status ends with the
//! hashes of the configuration baked into the image, [`crate::baked`]) and `END`. A bad
//! input ends the trace with a [`kind::FIRMWARE_ERROR`] record and `END`, and [`run`]
//! returns the error.
//!
//! Board-independent: the board supplies the file [`Port`] and the [`Target`] that
//! delivers an event through its interrupt.

use crate::handlers::{Counters, ReportedDecision};
use tooltouch_model::force::config::{ForceConfig, ForceSettings};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceOutputs;
use tooltouch_model::wire::firmware_status::FirmwareStatus;
use tooltouch_model::wire::force_chunks::{ForceChunkError, ForceConfigAssembler};
use tooltouch_model::wire::force_event::decode_force_event;
use tooltouch_model::wire::measure_config::decode_config;
use tooltouch_model::wire::measure_event::decode_event;
use tooltouch_model::wire::measure_outputs::encode_outputs;
use tooltouch_model::wire::{
    self, Header, Record, StreamKind, WireError, HEADER_LEN, MAX_PAYLOAD, RECORD_HEADER_LEN,
};
use tooltouch_model::{MeasureConfig, MeasureEvent, MeasureOutputs};

/// Record kinds of the co-simulation: the firmware's trace records and its input option
/// (defined in model::wire, which the host reads them with too).
pub use tooltouch_model::wire::kind;

/// A file transfer failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IoError;

/// The host files: input events, output trace.
pub trait Port {
    /// Reads up to `buf.len()` bytes of the input; 0 at its end.
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, IoError>;
    /// Appends `bytes` to the output.
    fn write(&mut self, bytes: &[u8]) -> Result<(), IoError>;
}

/// One input event of either path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// A measurement event.
    Measure(MeasureEvent),
    /// A force-path event.
    Force(ForceEvent),
}

/// The firmware under test, as the driver sees it.
pub trait Target {
    /// Power-on state with `config` and `force`: fresh kernels, all input pins low, empty
    /// sample queue.
    fn configure(&mut self, config: &MeasureConfig, force: &ForceConfig);
    /// The stream's clock reaches `time` (ticks, never less than before; the clock starts
    /// at 0 with each [`Target::configure`]): every alarm of the board's clock due by then
    /// fires first, at its own time, as a timer's compare match would.
    fn advance(&mut self, time: u64);
    /// Drives the event's pins (or ADC / command registers) and pends its interrupt (with
    /// the barriers that make the pend take effect at once); returns SysTick ticks from
    /// the pend to the return, or `None` when the event raised no interrupt (an FES pulse
    /// the counter only counts).
    fn inject(&mut self, event: Input) -> Option<u32>;
    /// Snapshot of the measurement kernel's outputs.
    fn outputs(&mut self) -> MeasureOutputs;
    /// Snapshot of the force kernel's outputs.
    fn force_outputs(&mut self) -> ForceOutputs;
    /// Lost / overflowed counters since [`Target::configure`].
    fn counters(&mut self) -> Counters;
    /// A known instruction count and the SysTick ticks it took (converts ticks to
    /// instructions under `-icount`).
    fn calibration(&self) -> (u32, u32);
    /// Stack bytes used so far.
    fn stack_used(&self) -> u32;
}

/// Why a run stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// Reading the input or writing the output failed.
    Io,
    /// A malformed stream at `offset`.
    Wire(WireError, u64),
    /// A header at `offset` is not an event stream.
    NotEvents(u64),
    /// The stream at `offset` does not start with a `MEASURE_CONFIG` record.
    MissingConfig(u64),
    /// The configuration record's hash differs from the header's (stream at `offset`).
    HashMismatch(u64),
    /// A record of a kind an event stream may not hold here (`kind`, at `offset`).
    UnexpectedKind(u8, u64),
    /// The input holds no stream.
    Empty,
    /// The force configuration chunks after the record at `offset` do not reassemble to
    /// the valid configuration the header's `force_hash` names.
    ForceConfig(ForceChunkError, u64),
}

impl Error {
    /// `(code, wire error, offset, detail)` as written in a [`kind::FIRMWARE_ERROR`] record.
    pub fn code(&self) -> (u8, u8, u64, u64) {
        match *self {
            Error::Io => (1, 0, 0, 0),
            Error::Wire(e, offset) => {
                let (w, detail) = match e {
                    WireError::Truncated { needed, .. } => (1, needed as u64),
                    WireError::BadMagic(m) => (2, u64::from(u32::from_le_bytes(m))),
                    WireError::BadVersion(v) => (3, v.into()),
                    WireError::BadStream(s) => (4, s.into()),
                    WireError::UnknownKind { kind, .. } => (5, kind.into()),
                    WireError::BadLength { kind, len, .. } => {
                        (6, u64::from(kind) << 8 | u64::from(len))
                    }
                    WireError::NonMonotonicTime { time, .. } => (7, time),
                    WireError::Config(c) => (8, c.value),
                    WireError::BadConfigEncoding => (9, 0),
                };
                (2, w, offset, detail)
            }
            Error::NotEvents(offset) => (3, 0, offset, 0),
            Error::MissingConfig(offset) => (4, 0, offset, 0),
            Error::HashMismatch(offset) => (5, 0, offset, 0),
            Error::UnexpectedKind(k, offset) => (6, 0, offset, k.into()),
            Error::Empty => (7, 0, 0, 0),
            Error::ForceConfig(e, offset) => {
                let pair = |a: usize, b: usize| (a as u64) << 16 | b as u64;
                let (w, detail) = match e {
                    ForceChunkError::BadLength { len } => (1, len as u64),
                    ForceChunkError::Oversized { total } => (2, total as u64),
                    ForceChunkError::TotalChanged { first, this } => (3, pair(first, this)),
                    ForceChunkError::OutOfOrder { expected, offset } => (4, pair(expected, offset)),
                    ForceChunkError::PastEnd { end, total } => (5, pair(end, total)),
                    ForceChunkError::AfterComplete => (6, 0),
                    ForceChunkError::Incomplete { received, total } => (7, pair(received, total)),
                    ForceChunkError::BadEncoding { at } => (8, at as u64),
                    ForceChunkError::Invalid(f) => (9, f.value.to_bits() as u64),
                    ForceChunkError::HashMismatch { decoded, .. } => (10, decoded),
                };
                (8, w, offset, detail)
            }
        }
    }

    /// The force configuration field an error names (empty for other errors).
    pub fn field(&self) -> &'static str {
        match self {
            Error::ForceConfig(ForceChunkError::Invalid(f), _) => f.field,
            _ => "",
        }
    }
}

const READ_BUF: usize = 2048;
const WRITE_BUF: usize = 2048;
const MAX_RECORD: usize = RECORD_HEADER_LEN + MAX_PAYLOAD;

/// Buffered reader over the input port; `pos` is the file offset of the first unread byte.
struct Reader {
    buf: [u8; READ_BUF],
    start: usize,
    end: usize,
    pos: u64,
    eof: bool,
}

impl Reader {
    fn new() -> Self {
        Reader {
            buf: [0; READ_BUF],
            start: 0,
            end: 0,
            pos: 0,
            eof: false,
        }
    }

    fn available(&self) -> &[u8] {
        self.buf.get(self.start..self.end).unwrap_or(&[])
    }

    /// Makes at least `want` bytes available unless the input ends first.
    fn fill<P: Port>(&mut self, port: &mut P, want: usize) -> Result<(), Error> {
        if self.end.saturating_sub(self.start) >= want || self.eof {
            return Ok(());
        }
        // Move the unread tail to the front (no slicing that could panic).
        let n = self.end.saturating_sub(self.start);
        for i in 0..n {
            let b = self
                .buf
                .get(self.start.wrapping_add(i))
                .copied()
                .unwrap_or(0);
            if let Some(d) = self.buf.get_mut(i) {
                *d = b;
            }
        }
        self.start = 0;
        self.end = n;
        while self.end < want && !self.eof {
            let room = self.buf.get_mut(self.end..).unwrap_or(&mut []);
            if room.is_empty() {
                break;
            }
            let got = port.read(room).map_err(|_| Error::Io)?;
            if got == 0 {
                self.eof = true;
            }
            self.end = self.end.saturating_add(got).min(READ_BUF);
        }
        Ok(())
    }

    fn consume(&mut self, n: usize) {
        let n = n.min(self.end.saturating_sub(self.start));
        self.start = self.start.saturating_add(n);
        self.pos = self.pos.wrapping_add(n as u64);
    }

    /// The next record and its file offset.
    fn record<P: Port>(&mut self, port: &mut P) -> Result<(Record, u64), Error> {
        self.fill(port, MAX_RECORD)?;
        let at = self.pos;
        let (record, n) =
            Record::decode(self.available(), at as usize).map_err(|e| Error::Wire(e, at))?;
        self.consume(n);
        Ok((record, at))
    }
}

/// Buffered writer over the output port.
struct Writer {
    buf: [u8; WRITE_BUF],
    len: usize,
}

impl Writer {
    fn new() -> Self {
        Writer {
            buf: [0; WRITE_BUF],
            len: 0,
        }
    }

    fn put<P: Port>(&mut self, port: &mut P, bytes: &[u8]) -> Result<(), Error> {
        if self.len.saturating_add(bytes.len()) > WRITE_BUF {
            self.flush(port)?;
        }
        for (d, s) in self.buf.iter_mut().skip(self.len).zip(bytes) {
            *d = *s;
        }
        self.len = self.len.saturating_add(bytes.len()).min(WRITE_BUF);
        Ok(())
    }

    fn record<P: Port>(&mut self, port: &mut P, record: &Record) -> Result<(), Error> {
        let mut tmp = [0u8; MAX_RECORD];
        let n = record.encode(&mut tmp).unwrap_or(0);
        self.put(port, tmp.get(..n).unwrap_or(&[]))
    }

    fn flush<P: Port>(&mut self, port: &mut P) -> Result<(), Error> {
        let pending = self.buf.get(..self.len).unwrap_or(&[]);
        if !pending.is_empty() {
            port.write(pending).map_err(|_| Error::Io)?;
        }
        self.len = 0;
        Ok(())
    }
}

/// Interrupts and SysTick ticks per event kind: arm, contact, index, FES (compare), scale, then force
/// sample, tick, command.
#[derive(Default)]
struct Profile {
    slots: [(u32, u32); 8],
}

impl Profile {
    fn slot(input: &Input) -> usize {
        match input {
            // The test event is not profiled (no slot).
            Input::Measure(MeasureEvent::PresetPulses(_)) => usize::MAX,
            Input::Measure(e) => e.kind() as usize,
            Input::Force(ForceEvent::Sample(_)) => 5,
            Input::Force(ForceEvent::Tick) => 6,
            Input::Force(_) => 7,
        }
    }

    fn add(&mut self, input: &Input, ticks: u32) {
        if let Some((n, t)) = self.slots.get_mut(Self::slot(input)) {
            *n = n.saturating_add(1);
            *t = t.saturating_add(ticks);
        }
    }

    /// Encodes slots `from..to` as (events u32, ticks u32) pairs; returns the bytes used.
    fn encode(&self, from: usize, to: usize) -> ([u8; 40], usize) {
        let mut out = [0u8; 40];
        let slots = self.slots.get(from..to).unwrap_or(&[]);
        for (chunk, (n, t)) in out.chunks_exact_mut(8).zip(slots.iter()) {
            for (d, s) in chunk
                .iter_mut()
                .zip(n.to_le_bytes().iter().chain(&t.to_le_bytes()))
            {
                *d = *s;
            }
        }
        (out, slots.len().saturating_mul(8).min(40))
    }
}

fn put_u32s(out: &mut [u8], values: &[u32]) {
    for (chunk, v) in out.chunks_exact_mut(4).zip(values) {
        for (d, s) in chunk.iter_mut().zip(v.to_le_bytes()) {
            *d = s;
        }
    }
}

/// Replays every stream of the input through `target`, writing the output trace. Returns
/// the number of streams; on an error the trace ends with a [`kind::FIRMWARE_ERROR`]
/// record.
pub fn run<P: Port, T: Target>(port: &mut P, target: &mut T) -> Result<u32, Error> {
    let mut reader = Reader::new();
    let mut writer = Writer::new();
    let result = run_streams(port, target, &mut reader, &mut writer);
    if let Err(e) = result {
        let (code, wire_code, offset, detail) = e.code();
        let mut p = [0u8; 48];
        p[0] = code;
        p[1] = wire_code;
        for (d, s) in p
            .iter_mut()
            .skip(2)
            .zip(offset.to_le_bytes().iter().chain(&detail.to_le_bytes()))
        {
            *d = *s;
        }
        let name = e.field().as_bytes();
        let name_len = name.len().min(30);
        for (d, s) in p.iter_mut().skip(18).zip(name.iter().take(name_len)) {
            *d = *s;
        }
        let p = p.get(..18usize.saturating_add(name_len)).unwrap_or(&[]);
        // Best effort: the error is returned whether or not it reaches the host.
        let _ = writer.record(port, &Record::new(kind::FIRMWARE_ERROR, 0, p));
        let _ = writer.record(port, &Record::new(wire::kind::END, 0, &[]));
    }
    writer.flush(port)?;
    result
}

fn run_streams<P: Port, T: Target>(
    port: &mut P,
    target: &mut T,
    reader: &mut Reader,
    writer: &mut Writer,
) -> Result<u32, Error> {
    let idle_force = ForceSettings::default()
        .validate()
        .map_err(|_| Error::Wire(WireError::BadConfigEncoding, 0))?;
    let mut streams: u32 = 0;
    loop {
        reader.fill(port, HEADER_LEN)?;
        if reader.available().is_empty() {
            break;
        }
        let at = reader.pos;
        let header = Header::decode(reader.available()).map_err(|e| Error::Wire(e, at))?;
        if header.stream != StreamKind::Events {
            return Err(Error::NotEvents(at));
        }
        reader.consume(HEADER_LEN);
        let (first, offset) = reader.record(port)?;
        if first.kind != wire::kind::MEASURE_CONFIG {
            return Err(Error::MissingConfig(offset));
        }
        let config = decode_config(first.payload()).map_err(|e| Error::Wire(e, offset))?;
        if config.hash() != header.measure_hash {
            return Err(Error::HashMismatch(at));
        }
        let force = if header.force_hash != 0 {
            read_force_config(port, reader, header.force_hash, offset)?
        } else {
            idle_force
        };
        let report = crate::baked::reported_decision(&config);
        target.configure(&config, &force);
        let out_header = Header {
            stream: StreamKind::Outputs,
            ..header
        };
        writer.put(port, &out_header.encode())?;
        replay(
            port,
            target,
            reader,
            writer,
            first.time,
            header.force_hash != 0,
            &report,
        )?;
        streams = streams.saturating_add(1);
    }
    if streams == 0 {
        return Err(Error::Empty);
    }
    Ok(streams)
}

/// Reads the `FORCE_CONFIG_CHUNK` records that follow the configuration record at
/// `config_offset` until the force configuration is complete, and decodes it.
fn read_force_config<P: Port>(
    port: &mut P,
    reader: &mut Reader,
    force_hash: u64,
    config_offset: u64,
) -> Result<ForceConfig, Error> {
    let mut assembler = ForceConfigAssembler::new();
    let mut last = config_offset;
    while !assembler.is_complete() {
        let (record, offset) = reader.record(port)?;
        if record.kind != kind::FORCE_CONFIG_CHUNK {
            // A stream that names a force configuration must carry all of it first.
            let e = match assembler.finish(force_hash) {
                Err(e) => e,
                Ok(_) => ForceChunkError::AfterComplete,
            };
            return Err(Error::ForceConfig(e, offset));
        }
        assembler
            .push(record.payload())
            .map_err(|e| Error::ForceConfig(e, offset))?;
        last = offset;
    }
    assembler
        .finish(force_hash)
        .map_err(|e| Error::ForceConfig(e, last))
}

/// Replays one stream's events up to its END record.
fn replay<P: Port, T: Target>(
    port: &mut P,
    target: &mut T,
    reader: &mut Reader,
    writer: &mut Writer,
    start: u64,
    force_enabled: bool,
    report: &ReportedDecision,
) -> Result<(), Error> {
    let mut previous = start;
    // "Register now" in the last outputs record: a decision record follows the first
    // outputs record that shows it raised.
    let mut reported = false;
    let mut profile = Profile::default();
    let mut events: u32 = 0;
    let mut observe_fes = true;
    loop {
        let (record, offset) = reader.record(port)?;
        if record.time < previous {
            return Err(Error::Wire(
                WireError::NonMonotonicTime {
                    offset: offset as usize,
                    previous,
                    time: record.time,
                },
                offset,
            ));
        }
        previous = record.time;
        if record.kind == wire::kind::END {
            break;
        }
        if record.kind == kind::FIRMWARE_OBSERVE {
            observe_fes = record.payload().first().is_none_or(|&b| b != 0);
            continue;
        }
        let input = match decode_event(&record, offset as usize) {
            Ok(Some(event)) => Input::Measure(event),
            Ok(None) if force_enabled => match decode_force_event(&record, offset as usize) {
                Ok(Some(event)) => Input::Force(event),
                Ok(None) => return Err(Error::UnexpectedKind(record.kind, offset)),
                Err(e) => return Err(Error::Wire(e, offset)),
            },
            Ok(None) => return Err(Error::UnexpectedKind(record.kind, offset)),
            Err(e) => return Err(Error::Wire(e, offset)),
        };
        target.advance(record.time);
        if let Some(ticks) = target.inject(input) {
            profile.add(&input, ticks);
        }
        events = events.saturating_add(1);
        match input {
            Input::Measure(MeasureEvent::Fes) if !observe_fes => {}
            Input::Measure(_) => {
                let o = target.outputs();
                writer.record(
                    port,
                    &Record::new(
                        wire::kind::MEASURE_OUTPUTS,
                        record.time,
                        &encode_outputs(&o),
                    ),
                )?;
                if o.register_now && !reported {
                    let mut p = [0u8; 8];
                    put_u32s(
                        &mut p,
                        &[report.position(&o) as u32, report.offset() as u32],
                    );
                    writer.record(port, &Record::new(kind::FIRMWARE_DECISION, record.time, &p))?;
                }
                reported = o.register_now;
            }
            // A sample changes no output (model::force): no record, as the model writes.
            Input::Force(ForceEvent::Sample(_)) => {}
            Input::Force(_) => {
                let o = target.force_outputs();
                writer.record(port, &wire::force_outputs::outputs_record(record.time, &o))?;
            }
        }
    }
    let counters = target.counters();
    let (cal_instructions, cal_ticks) = target.calibration();
    let status = FirmwareStatus {
        events,
        lost: counters.lost,
        overflowed: counters.overflowed,
        stack_bytes: target.stack_used(),
        calibration_instructions: cal_instructions,
        calibration_ticks: cal_ticks,
        // The image's own configuration (the one it was built with), so a trace tells
        // which image made it.
        image_hashes: Some((crate::baked::MEASURE_HASH, crate::baked::FORCE_HASH)),
    };
    let (p, n) = profile.encode(0, 5);
    writer.record(
        port,
        &Record::new(kind::FIRMWARE_PROFILE, previous, p.get(..n).unwrap_or(&[])),
    )?;
    let (p, n) = profile.encode(5, 8);
    writer.record(
        port,
        &Record::new(
            kind::FIRMWARE_FORCE_PROFILE,
            previous,
            p.get(..n).unwrap_or(&[]),
        ),
    )?;
    let (p, n) = status.encode();
    writer.record(
        port,
        &Record::new(kind::FIRMWARE_STATUS, previous, p.get(..n).unwrap_or(&[])),
    )?;
    writer.record(port, &Record::new(wire::kind::END, previous, &[]))?;
    Ok(())
}
