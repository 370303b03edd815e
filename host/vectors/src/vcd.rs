//! Value change dump files, per the VCD contract (docs/CONTRACT.md): the golden
//! writer (inputs and outputs of the measurement front end at `k·P` ns, closed by a
//! `tooltouch end cycles=<n>` comment so a cut file is told from a whole one), and a
//! streaming reader that takes any tool's dump (Verilator, Icarus) for `tooltouch check`
//! and `tooltouch vectors` in constant memory, with [`Dump`] on top of it for callers that
//! want the whole file in memory.

use super::{clock_through, watchdog_expires_at};
use bitvec::prelude::*;
use std::collections::HashMap;
use std::hash::BuildHasherDefault;
use std::io::{self, Write};

mod body;
use body::{Body, LastByte, Step};
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_model::{FrontEnd, MeasureConfig, MeasureOutputs};
use tooltouch_plant::stimulus::Stimulus;

/// Names and widths of the [`MeasureOutputs`] fields in VCD files and Verilog ports, in
/// declaration order ([`MeasureOutputs::widths`]: widths from the configuration, never typed
/// twice).
pub fn output_signals(config: &MeasureConfig) -> Vec<(&'static str, u32)> {
    MeasureOutputs::widths(config).to_vec()
}

/// The values of [`output_signals`], in the same order, as unsigned bit vectors of their
/// widths (two's-complement positions masked to `scale_bits`).
pub fn output_values(
    o: &MeasureOutputs,
    config: &MeasureConfig,
) -> [u64; MeasureOutputs::FIELD_COUNT] {
    o.register_bits(config)
}

/// Clock period, ns, for `clock_hz` (must divide 1e9; the scenario checks it).
pub fn period_ns(clock_hz: u32) -> u64 {
    1_000_000_000 / u64::from(clock_hz.max(1))
}

fn id_code(mut n: usize) -> String {
    // Printable identifier codes '!'..='~', little-endian base 94.
    let mut s = String::new();
    loop {
        s.push(char::from(b'!' + (n % 94) as u8));
        n /= 94;
        if n == 0 {
            return s;
        }
    }
}

fn value_text(value: u64, width: u32, id: &str) -> String {
    if width == 1 {
        format!("{}{id}\n", value & 1)
    } else {
        format!("b{value:b} {id}\n")
    }
}

/// Writes the golden VCD of `stimulus` clocks `[0, end)` (all of it when `end` is
/// `None`): inputs sampled at clock `k` and outputs registered after clock `k`, both at
/// time `k·P` ns, changes only, then the time of the last clock and the closing
/// `$comment tooltouch end cycles=<n> $end`. Returns the number of clocks covered.
pub fn write_golden<W: Write>(
    w: &mut W,
    stimulus: &Stimulus,
    config: &MeasureConfig,
    end: Option<u64>,
) -> io::Result<u64> {
    let p = period_ns(stimulus.clock_hz);
    let outputs = output_signals(config);
    writeln!(w, "$date tooltouch golden model $end")?;
    writeln!(w, "$version tooltouch {} $end", env!("CARGO_PKG_VERSION"))?;
    writeln!(
        w,
        "$comment tooltouch measure_hash={:016x} clock_hz={} $end",
        config.hash(),
        stimulus.clock_hz
    )?;
    writeln!(w, "$timescale 1ns $end")?;
    writeln!(w, "$scope module tooltouch $end")?;
    writeln!(w, "$scope module inputs $end")?;
    for (i, name) in pin::NAMES.iter().enumerate() {
        writeln!(w, "$var wire 1 {} {name} $end", id_code(i))?;
    }
    writeln!(w, "$upscope $end")?;
    writeln!(w, "$scope module outputs $end")?;
    for (i, (name, width)) in outputs.iter().enumerate() {
        let range = if *width > 1 {
            format!(" [{}:0]", width - 1)
        } else {
            String::new()
        };
        writeln!(
            w,
            "$var wire {width} {} {name}{range} $end",
            id_code(pin::COUNT + i)
        )?;
    }
    writeln!(w, "$upscope $end")?;
    writeln!(w, "$upscope $end")?;
    writeln!(w, "$enddefinitions $end")?;

    let width_of = |i: usize| {
        if i < pin::COUNT {
            1
        } else {
            outputs[i - pin::COUNT].1
        }
    };
    let mut buffer = String::new();
    let (end, last_time) = golden_changes(stimulus, config, end, &mut |k, changes| {
        buffer.clear();
        for &(i, value) in changes {
            buffer.push_str(&value_text(value, width_of(i), &id_code(i)));
        }
        if k == 0 {
            write!(w, "#0\n$dumpvars\n{buffer}$end\n")
        } else {
            write!(w, "#{}\n{buffer}", k * p)
        }
    })?;
    // Mark the end of the covered time so a reader knows the last clock.
    if end > 0 && last_time != Some(end - 1) {
        writeln!(w, "#{}", (end - 1) * p)?;
    }
    writeln!(w, "$comment {END_COMMENT} cycles={end} $end")?;
    Ok(end)
}

/// One clock's changes of a golden trace: `(signal, value)`, signals numbered as
/// declared (the [`pin::NAMES`] first, then [`output_signals`]).
pub(crate) type GoldenChanges<'a> = &'a [(usize, u64)];

/// The changes of the golden trace of `stimulus` clocks `[0, end)` (all of it when `end`
/// is `None`), clock by clock: `emit(k, changes)` for clock 0 with every signal's value
/// (when `end > 0`), then for each clock `k` at which a pin or an output changed — inputs
/// sampled at clock `k`, outputs registered after it. Returns the number of clocks
/// covered and the last clock emitted.
pub(crate) fn golden_changes(
    stimulus: &Stimulus,
    config: &MeasureConfig,
    end: Option<u64>,
    emit: &mut dyn FnMut(u64, GoldenChanges) -> io::Result<()>,
) -> io::Result<(u64, Option<u64>)> {
    let total = stimulus.total_cycles();
    let end = end.unwrap_or(total).min(total);
    let mut last_pins: Option<Pins> = None;
    let mut last_out: Option<[u64; MeasureOutputs::FIELD_COUNT]> = None;
    let mut changes: Vec<(usize, u64)> = Vec::new();
    let mut error = None;
    // Pin changes at segment starts and output changes at clocked clocks, merged by
    // clock: `clock_through` visits every clock at which an output can change (an edge the
    // kernel acts on, or the FES watchdog expiring), and pin levels only change at segment
    // starts, which it always clocks (a changed pin is never settled).
    let mut stopped = false;
    let mut last_clock = None;
    // Every signal's value at time 0, even when nothing happens at clock 0 (a settled
    // start is skipped by `clock_through`): the pins of the first segment and the reset
    // outputs, which are the outputs after clock 0 (no edge can be detected at clock 0).
    if let (true, Some(first)) = (end > 0, stimulus.segments.first()) {
        for (i, level) in first.pins.0.view_bits::<Lsb0>()[..pin::COUNT]
            .iter()
            .enumerate()
        {
            changes.push((i, (*level).into()));
        }
        let values = output_values(&FrontEnd::new(config).outputs(), config);
        for (i, v) in values.iter().enumerate() {
            changes.push((pin::COUNT + i, *v));
        }
        emit(0, &changes)?;
        last_pins = Some(first.pins);
        last_out = Some(values);
        last_clock = Some(0);
    }
    clock_through(stimulus, config, |k, pins, fe, edges| {
        if stopped || error.is_some() {
            return;
        }
        if k >= end {
            stopped = true;
            return;
        }
        changes.clear();
        if last_pins != Some(pins) {
            let levels = &pins.0.view_bits::<Lsb0>()[..pin::COUNT];
            let before = last_pins.map(|l| l.0);
            for (i, level) in levels.iter().enumerate() {
                if before.is_none_or(|b| b.view_bits::<Lsb0>()[i] != *level) {
                    changes.push((i, (*level).into()));
                }
            }
            last_pins = Some(pins);
        }
        if last_out.is_none() || !edges.is_empty() || watchdog_expires_at(fe, k) {
            let values = output_values(&fe.outputs(), config);
            for (i, v) in values.iter().enumerate() {
                if last_out.is_none_or(|l| l[i] != *v) {
                    changes.push((pin::COUNT + i, *v));
                }
            }
            last_out = Some(values);
        }
        if !changes.is_empty() {
            last_clock = Some(k);
            if let Err(e) = emit(k, &changes) {
                error = Some(e);
            }
        }
    });
    match error {
        Some(e) => Err(e),
        None => Ok((end, last_clock)),
    }
}

/// The `$comment` text a golden file ends with: `tooltouch end cycles=<n>`, so a reader
/// can tell a whole golden file from one cut short.
pub const END_COMMENT: &str = "tooltouch end";

/// A value in a dump, of any width: its bits exactly, and whether any bit was x or z.
///
/// The bits are kept without their high zeros, so two values are equal exactly when their
/// numbers are, whatever widths they were written at (a DUT may declare a wider port than
/// the golden signal).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Value {
    /// The bits, least significant first, x and z read as 0, no zero above the highest 1.
    pub bits: BitVec<u64, Lsb0>,
    /// Some bit was x or z.
    pub unknown: bool,
}

impl Value {
    /// A known value.
    pub fn known(number: u64) -> Value {
        Value::from_bits(number.view_bits::<Lsb0>().to_bitvec(), false)
    }

    /// A value of `bits` (least significant first), high zeros dropped.
    pub(crate) fn from_bits(mut bits: BitVec<u64, Lsb0>, unknown: bool) -> Value {
        bits.truncate(bits.last_one().map_or(0, |top| top + 1));
        Value { bits, unknown }
    }

    /// The number when it fits 64 bits (x and z read as 0).
    pub fn to_u64(&self) -> Option<u64> {
        match self.bits.len() {
            0 => Some(0),
            1..=64 => Some(self.bits.load_le()),
            _ => None,
        }
    }

    /// Bit `index` (x and z read as 0).
    pub fn bit(&self, index: usize) -> bool {
        self.bits.get(index).is_some_and(|b| *b)
    }

    /// Hexadecimal digits of the number, most significant first, no leading zeros (`0` for
    /// zero); x and z read as 0.
    pub fn hex_digits(&self) -> String {
        if self.bits.is_empty() {
            return "0".into();
        }
        let digits: Vec<char> = self
            .bits
            .chunks(4)
            .map(|d| char::from_digit(d.load_le::<u32>(), 16).unwrap_or('0'))
            .collect();
        digits.into_iter().rev().collect()
    }
}

/// One variable of a dump.
#[derive(Clone, Debug, PartialEq)]
pub struct Signal {
    /// Scope path, e.g. `["tooltouch", "outputs"]`.
    pub scope: Vec<String>,
    /// Leaf name (without a bit range).
    pub name: String,
    /// Width, bits.
    pub width: u32,
    /// Identifier code.
    pub id: String,
    /// Line of its `$var`, from 1.
    pub line: usize,
}

/// A malformed dump.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {}{message}", if *line > 0 { format!("line {line}: ") } else { String::new() })]
pub struct VcdError {
    /// File name (as given).
    pub file: String,
    /// Line number, from 1 (0: no line, e.g. an FST file).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

#[cfg(test)]
fn parse_value(text: &str, width: u32) -> Value {
    let digits: Vec<vcd::Value> = text
        .chars()
        .map(|c| c.to_string().parse().unwrap_or(vcd::Value::X))
        .collect();
    vector_value(&digits, width)
}

/// The value of a vector change's digits (most significant first) for a signal `width`
/// bits wide: fewer digits than the width extend to the left with 0, or with x when the
/// first digit is x or z (the VCD rule).
fn vector_value(digits: &[vcd::Value], width: u32) -> Value {
    let bits: BitVec<u64, Lsb0> = digits.iter().rev().map(|d| *d == vcd::Value::V1).collect();
    let some_unknown = digits
        .iter()
        .any(|d| matches!(d, vcd::Value::X | vcd::Value::Z));
    let pads_unknown = matches!(digits.first(), Some(vcd::Value::X | vcd::Value::Z));
    let extends_unknown = pads_unknown && (digits.len() as u64) < u64::from(width);
    Value::from_bits(bits, some_unknown || extends_unknown)
}

/// The declarations of a dump: timescale, variables, the comments before
/// `$enddefinitions`, and a dense index per identifier code (several variables may share
/// a code: the same net seen in several scopes).
#[derive(Clone, Debug, Default)]
pub struct Declarations {
    /// Femtoseconds per time unit of the file's `$timescale`.
    pub timescale_fs: u64,
    /// Every `$var`, in file order.
    pub signals: Vec<Signal>,
    /// `$comment` texts of the declarations.
    pub comments: Vec<String>,
    codes: Vec<String>,
    widths: Vec<u32>,
    /// The first signal of each code, index into `signals` (named in messages).
    first_signal: Vec<usize>,
    index: HashMap<vcd::IdCode, usize, BuildHasherDefault<IdCodeHasher>>,
}

/// Hashes an [`vcd::IdCode`] as the number it is (a code is a base-94 number: hashing it
/// again would only cost time in the body's hot loop).
#[derive(Default)]
struct IdCodeHasher(u64);

impl std::hash::Hasher for IdCodeHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = self.0.rotate_left(8) ^ u64::from(b);
        }
    }
    fn write_u64(&mut self, n: u64) {
        self.0 = n;
    }
}

impl Declarations {
    pub(crate) fn add(&mut self, signal: Signal) {
        if let Ok(code) = signal.id.parse::<vcd::IdCode>() {
            if !self.index.contains_key(&code) {
                self.index.insert(code, self.codes.len());
                self.codes.push(signal.id.clone());
                self.widths.push(signal.width);
                self.first_signal.push(self.signals.len());
            }
        }
        self.signals.push(signal);
    }

    /// The dense index of identifier code `id`.
    pub fn code_index(&self, id: &str) -> Option<usize> {
        self.index.get(&id.parse().ok()?).copied()
    }

    /// Identifier codes by dense index.
    pub fn codes(&self) -> &[String] {
        &self.codes
    }

    /// The first signal declared with the code of dense index `index`.
    fn signal_of(&self, index: usize) -> &Signal {
        &self.signals[self.first_signal[index]]
    }

    /// The signal named `name` in the scope path ending with `scope_suffix`.
    pub fn find_in_scope(&self, scope_suffix: &str, name: &str) -> Option<&Signal> {
        find_in_scope(&self.signals, scope_suffix, name)
    }

    /// The signal compared with golden output `name` (see [`Dump::find_shallowest`]).
    pub fn find_shallowest(&self, name: &str) -> Option<&Signal> {
        find_shallowest(&self.signals, name)
    }

    /// `(measure_hash, clock_hz)` from a golden file's `$comment`.
    pub fn golden_stamp(&self) -> Option<(u64, u32)> {
        golden_stamp(&self.comments)
    }
}

fn in_scope(s: &Signal, scope: &str) -> bool {
    s.scope.last().is_some_and(|l| l == scope)
}

fn find_in_scope<'a>(signals: &'a [Signal], scope_suffix: &str, name: &str) -> Option<&'a Signal> {
    signals
        .iter()
        .find(|s| s.name == name && in_scope(s, scope_suffix))
}

fn find_shallowest<'a>(signals: &'a [Signal], name: &str) -> Option<&'a Signal> {
    let named = || signals.iter().filter(move |s| s.name == name);
    named()
        .filter(|s| in_scope(s, "outputs"))
        .min_by_key(|s| s.scope.len())
        .or_else(|| {
            named()
                .filter(|s| !in_scope(s, "inputs"))
                .min_by_key(|s| s.scope.len())
        })
        .or_else(|| named().min_by_key(|s| s.scope.len()))
}

/// `(measure_hash, clock_hz)` from the `tooltouch measure_hash=… clock_hz=…` comment.
pub fn golden_stamp(comments: &[String]) -> Option<(u64, u32)> {
    comments.iter().find_map(|c| {
        let rest = c.strip_prefix("tooltouch ")?;
        let mut hash = None;
        let mut hz = None;
        for kv in rest.split_whitespace() {
            if let Some(v) = kv.strip_prefix("measure_hash=") {
                hash = u64::from_str_radix(v, 16).ok();
            }
            if let Some(v) = kv.strip_prefix("clock_hz=") {
                hz = v.parse().ok();
            }
        }
        Some((hash?, hz?))
    })
}

/// The clock count of a golden file's closing `tooltouch end cycles=<n>` comment.
pub fn golden_end(comments: &[String]) -> Option<u64> {
    comments.iter().find_map(|c| {
        c.strip_prefix(END_COMMENT)?
            .trim()
            .strip_prefix("cycles=")?
            .parse()
            .ok()
    })
}

/// One step of a dump's body.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Item {
    /// A `#` time, femtoseconds.
    Time(u64),
    /// A value change of the identifier code with this dense index, at the current time.
    Change(usize, Value),
}

/// Reads a dump as a stream: the declarations first ([`VcdReader::new`]), then the body
/// item by item, so that a file of any length is read in constant memory. The declarations
/// are the `vcd` crate's ([`vcd::Parser`], which reads command by command from a
/// `BufRead`); the body is scanned from a large buffer of the file (times, scalar and
/// vector changes, `$end`), everything else handed to the crate's parser command by
/// command, so both accept and reject exactly the same text. This layer resolves
/// identifier codes, scales times to femtoseconds and checks what the crate leaves to its
/// user: times that go backwards, unknown codes, a value with more digits than its
/// signal's width. Scopes, `$timescale`, reals and strings (skipped) of any tool's dump
/// are accepted; errors name the file and line.
pub struct VcdReader<R> {
    /// The file, and one newline after its end: the crate needs whitespace after the last
    /// token, which a dump whose last line has no newline lacks.
    parser: vcd::Parser<LastByte<std::io::Chain<R, &'static [u8]>>>,
    file: String,
    line: usize,
    declarations: Declarations,
    time_fs: u64,
    late_comments: Vec<String>,
    /// The body's buffer and position.
    body: Body,
    /// A `$dumpvars`/`$dumpon`/`$dumpoff`/`$dumpall` is open (its `$end` closes it; any
    /// other `$end` is an error, as the crate's parser has it).
    simulation_open: bool,
    /// Dense index of each short identifier code by its number (`u32::MAX`: none); longer
    /// codes are looked up in [`Declarations`]' map.
    short_codes: Vec<u32>,
    /// Per dense index, whether [`Changes::next_change`] gives its changes (all when
    /// `None`).
    selected: Option<Vec<bool>>,
}

/// A time for messages: whole nanoseconds as `… ns`, else femtoseconds.
fn time_text(fs: u64) -> String {
    if fs.is_multiple_of(1_000_000) {
        format!("{} ns", fs / 1_000_000)
    } else {
        format!("{fs} fs")
    }
}

/// A `$comment` text as a list of words joined by single spaces (the form the golden
/// stamp and end comments are matched in).
fn comment_words(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

impl<R: std::io::BufRead> VcdReader<R> {
    /// Reads the declarations of `src` (up to `$enddefinitions`); `file` names it in
    /// errors.
    pub fn new(src: R, file: &str) -> Result<Self, VcdError> {
        let mut r = VcdReader {
            parser: vcd::Parser::new(LastByte::new(src.chain(&b"\n"[..]))),
            file: file.to_string(),
            line: 0,
            declarations: Declarations {
                timescale_fs: 1_000_000,
                ..Default::default()
            },
            time_fs: 0,
            late_comments: Vec::new(),
            body: Body::default(),
            simulation_open: false,
            short_codes: Vec::new(),
            selected: None,
        };
        r.read_declarations()?;
        r.start_body();
        Ok(r)
    }

    /// The declarations.
    pub fn declarations(&self) -> &Declarations {
        &self.declarations
    }

    /// The file name given to [`VcdReader::new`].
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The line of the last token read, from 1.
    pub fn line(&self) -> usize {
        self.line
    }

    /// The current time (the last `#` read), femtoseconds; the file's last time once
    /// [`VcdReader::next_item`] returned `None`.
    pub fn time_fs(&self) -> u64 {
        self.time_fs
    }

    /// `$comment` texts after the declarations read so far (a golden file's closing
    /// [`END_COMMENT`]).
    pub fn late_comments(&self) -> &[String] {
        &self.late_comments
    }

    fn error(&self, message: String) -> VcdError {
        VcdError {
            file: self.file.clone(),
            line: self.line,
            message,
        }
    }

    /// The next command of the declarations, `None` at the end of the file; a parse error
    /// names its line.
    fn command(&mut self) -> Result<Option<vcd::Command>, VcdError> {
        let next = self.parser.next();
        self.line = usize::try_from(self.parser.line()).unwrap_or(usize::MAX);
        self.parsed(next, 0)
    }

    /// The result of the crate's parser, its lines `line_offset` after the file's.
    fn parsed(
        &self,
        next: Option<io::Result<vcd::Command>>,
        line_offset: usize,
    ) -> Result<Option<vcd::Command>, VcdError> {
        match next {
            None => Ok(None),
            Some(Ok(c)) => Ok(Some(c)),
            Some(Err(e)) => {
                let parse = e
                    .get_ref()
                    .and_then(|i| i.downcast_ref::<vcd::ParseError>());
                Err(match parse {
                    Some(p) => VcdError {
                        file: self.file.clone(),
                        line: usize::try_from(p.line())
                            .unwrap_or(usize::MAX)
                            .saturating_add(line_offset),
                        message: p.kind().to_string(),
                    },
                    None if e.kind() == std::io::ErrorKind::UnexpectedEof => {
                        self.error("ends inside a command (cut short?)".into())
                    }
                    None => self.error(format!("cannot read: {e}")),
                })
            }
        }
    }

    fn read_declarations(&mut self) -> Result<(), VcdError> {
        use vcd::Command as C;
        let mut scope: Vec<String> = Vec::new();
        let mut any = false;
        loop {
            let Some(command) = self.command()? else {
                return Err(if any {
                    self.error("ends before $enddefinitions (cut short?)".into())
                } else {
                    VcdError {
                        file: self.file.clone(),
                        line: 0,
                        message: "empty: no VCD declarations ($var … $enddefinitions)".into(),
                    }
                });
            };
            any = true;
            match command {
                C::ScopeDef(_, name) => scope.push(name),
                C::Upscope => {
                    scope.pop();
                }
                C::VarDef(_, width, code, reference, _) => {
                    let name = reference.split('[').next().unwrap_or("").to_string();
                    let line = self.line;
                    self.declarations.add(Signal {
                        scope: scope.clone(),
                        name,
                        width,
                        id: code.to_string(),
                        line,
                    });
                }
                C::Timescale(n, unit) => {
                    let per: u64 = match unit {
                        vcd::TimescaleUnit::S => 1_000_000_000_000_000,
                        vcd::TimescaleUnit::MS => 1_000_000_000_000,
                        vcd::TimescaleUnit::US => 1_000_000_000,
                        vcd::TimescaleUnit::NS => 1_000_000,
                        vcd::TimescaleUnit::PS => 1_000,
                        vcd::TimescaleUnit::FS => 1,
                    };
                    self.declarations.timescale_fs = u64::from(n)
                        .checked_mul(per)
                        .filter(|&fs| fs > 0)
                        .ok_or_else(|| self.error(format!("bad $timescale `{n}{unit}`")))?;
                }
                C::Comment(text) => self.declarations.comments.push(comment_words(&text)),
                C::Begin(_) => self.simulation_open = true,
                C::End(_) => self.simulation_open = false,
                C::Enddefinitions => return Ok(()),
                C::Timestamp(t) => {
                    return Err(self.error(format!("unexpected `#{t}` before $enddefinitions")))
                }
                C::ChangeScalar(..)
                | C::ChangeVector(..)
                | C::ChangeReal(..)
                | C::ChangeString(..) => {
                    return Err(self.error("a value change before $enddefinitions".into()))
                }
                _ => {}
            }
        }
    }

    /// The next time or value change of the body; `None` at the end of the file.
    /// Comments are kept ([`VcdReader::late_comments`]); times must not go backwards; a
    /// vector value must not have more digits than its signal is wide.
    pub fn next_item(&mut self) -> Result<Option<Item>, VcdError> {
        loop {
            match self.next_step(true)? {
                Step::End => return Ok(None),
                Step::Time(fs) => return Ok(Some(Item::Time(fs))),
                Step::Change(index, Some(value)) => return Ok(Some(Item::Change(index, value))),
                Step::Change(_, None) => {}
            }
        }
    }
}

/// A source of value changes in time order, for [`crate::check`]: a streamed
/// file ([`VcdReader`]) or a parsed [`Dump`].
pub trait Changes {
    /// The next change `(time fs, code index, value)`; `None` when none is left.
    fn next_change(&mut self) -> Result<Option<(u64, usize, Value)>, VcdError>;
    /// The file's last time, femtoseconds (final once `next_change` returned `None`).
    fn end_fs(&self) -> u64;
    /// The line reached, for messages (0 when unknown).
    fn line(&self) -> usize {
        0
    }
    /// Only the changes of these code indexes are needed from now on (a source may skip
    /// the others: an FST reader then decodes only their blocks); before the first
    /// [`Changes::next_change`]. By default every change is still given.
    fn select(&mut self, _codes: &[usize]) {}
    /// `$comment` texts read after the declarations (a golden file's closing comment),
    /// complete once `next_change` returned `None`.
    fn late_comments(&self) -> Vec<String> {
        Vec::new()
    }
}

impl<R: std::io::BufRead> Changes for VcdReader<R> {
    fn next_change(&mut self) -> Result<Option<(u64, usize, Value)>, VcdError> {
        loop {
            match self.next_step(false)? {
                Step::End => return Ok(None),
                Step::Time(_) | Step::Change(_, None) => {}
                Step::Change(i, Some(v)) => return Ok(Some((self.time_fs, i, v))),
            }
        }
    }
    fn select(&mut self, codes: &[usize]) {
        let mut wanted = vec![false; self.declarations.codes.len()];
        for &c in codes {
            if let Some(w) = wanted.get_mut(c) {
                *w = true;
            }
        }
        self.selected = Some(wanted);
    }
    fn end_fs(&self) -> u64 {
        self.time_fs
    }
    fn line(&self) -> usize {
        self.line
    }
    fn late_comments(&self) -> Vec<String> {
        self.late_comments.clone()
    }
}

/// A parsed dump: signals and, per identifier code, its changes `(time fs, value)`.
/// Holds the whole file in memory: for tests and small files; `tooltouch check` streams
/// with [`VcdReader`].
#[derive(Clone, Debug, Default)]
pub struct Dump {
    /// Femtoseconds per time unit of the file's `$timescale`.
    pub timescale_fs: u64,
    /// Every `$var`.
    pub signals: Vec<Signal>,
    /// Changes per identifier code, in time order.
    pub changes: HashMap<String, Vec<(u64, Value)>>,
    /// `$comment` texts, declarations and body.
    pub comments: Vec<String>,
    /// Largest time seen, fs.
    pub last_time_fs: u64,
}

impl Dump {
    /// Parses a VCD text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Dump, VcdError> {
        let mut r = VcdReader::new(text.as_bytes(), file)?;
        let mut changes: HashMap<String, Vec<(u64, Value)>> = HashMap::new();
        while let Some(item) = r.next_item()? {
            if let Item::Change(i, v) = item {
                let code = &r.declarations.codes[i];
                match changes.get_mut(code) {
                    Some(list) => list.push((r.time_fs, v)),
                    None => {
                        changes.insert(code.clone(), vec![(r.time_fs, v)]);
                    }
                }
            }
        }
        let VcdReader {
            declarations,
            late_comments,
            time_fs,
            ..
        } = r;
        let mut comments = declarations.comments;
        comments.extend(late_comments);
        Ok(Dump {
            timescale_fs: declarations.timescale_fs,
            signals: declarations.signals,
            changes,
            comments,
            last_time_fs: time_fs,
        })
    }

    /// The declarations of this dump (its signals and comments, codes indexed in
    /// declaration order), as [`VcdReader::declarations`] would give them.
    pub fn declarations(&self) -> Declarations {
        let mut d = Declarations {
            timescale_fs: self.timescale_fs,
            comments: self.comments.clone(),
            ..Default::default()
        };
        for s in &self.signals {
            d.add(s.clone());
        }
        d
    }

    /// Every change in time order, code indexes as in [`Dump::declarations`].
    pub fn timeline(&self) -> DumpTimeline {
        let d = self.declarations();
        let mut all: Vec<(u64, usize, Value)> = Vec::new();
        for (i, code) in d.codes.iter().enumerate() {
            for (t, v) in self.changes.get(code).into_iter().flatten() {
                all.push((*t, i, v.clone()));
            }
        }
        // Stable: one code's changes at one time keep their order (the last one holds).
        all.sort_by_key(|c| c.0);
        DumpTimeline {
            changes: all.into_iter(),
            end_fs: self.last_time_fs,
        }
    }

    /// The value of identifier `id` at time `fs` (the last change at or before it);
    /// `None` before its first change.
    pub fn value_at(&self, id: &str, fs: u64) -> Option<Value> {
        let ch = self.changes.get(id)?;
        let i = ch.partition_point(|&(t, _)| t <= fs);
        (i > 0).then(|| ch[i - 1].1.clone())
    }

    /// The signal named `name` in the scope path ending with `scope_suffix`.
    pub fn find_in_scope(&self, scope_suffix: &str, name: &str) -> Option<&Signal> {
        find_in_scope(&self.signals, scope_suffix, name)
    }

    /// The DUT signal compared with golden output `name`: one in a scope named `outputs`
    /// if there is one, else the shallowest not in a scope named `inputs` (the input pin
    /// `contact` and the output `contact` share a leaf name), else the shallowest.
    pub fn find_shallowest(&self, name: &str) -> Option<&Signal> {
        find_shallowest(&self.signals, name)
    }

    /// `(measure_hash, clock_hz)` from a golden file's `$comment`.
    pub fn golden_stamp(&self) -> Option<(u64, u32)> {
        golden_stamp(&self.comments)
    }
}

/// A [`Dump`]'s changes in time order ([`Dump::timeline`]).
pub struct DumpTimeline {
    changes: std::vec::IntoIter<(u64, usize, Value)>,
    end_fs: u64,
}

impl Changes for DumpTimeline {
    fn next_change(&mut self) -> Result<Option<(u64, usize, Value)>, VcdError> {
        Ok(self.changes.next())
    }
    fn end_fs(&self) -> u64 {
        self.end_fs
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn id_codes_are_unique_and_printable() {
        let ids: Vec<String> = (0..200).map(id_code).collect();
        let set: std::collections::HashSet<_> = ids.iter().collect();
        assert_eq!(set.len(), 200);
        assert!(ids
            .iter()
            .all(|s| s.chars().all(|c| ('!'..='~').contains(&c))));
    }

    #[test]
    fn values_parse_with_extension() {
        assert_eq!(parse_value("101", 8), Value::known(5));
        assert!(parse_value("x", 8).unknown);
        assert!(parse_value("1z", 2).unknown);
    }

    #[test]
    fn values_wider_than_64_bits_are_kept_exactly() {
        let low = format!("1{}", "0".repeat(63));
        assert_eq!(parse_value(&low, 100), Value::known(1 << 63));
        let above = format!("1{}", "0".repeat(64));
        let v = parse_value(&above, 100);
        assert!(v.bit(64) && v.bits.count_ones() == 1 && !v.unknown, "{v:?}");
        assert_eq!(v.to_u64(), None);
        assert_eq!(v.hex_digits(), format!("1{}", "0".repeat(16)));
        let wide = format!("11{}", "01".repeat(49));
        let v = parse_value(&wide, 100);
        assert_eq!(v.bits.len(), 100);
        assert_eq!(v.hex_digits(), format!("d{}", "5".repeat(24)));
        let zeros = format!("{}101", "0".repeat(90));
        assert_eq!(parse_value(&zeros, 100), Value::known(5));
    }

    #[test]
    fn a_value_wider_than_its_signal_names_signal_line_and_time() {
        let text = "$scope module top $end\n$var wire 4 ! q [3:0] $end\n$upscope $end\n\
                    $enddefinitions $end\n#0\nb101 !\n#7\nb10101 !\n";
        let mut r = VcdReader::new(text.as_bytes(), "w.vcd").unwrap();
        let e = loop {
            match r.next_item() {
                Ok(Some(_)) => {}
                Ok(None) => panic!("read without error"),
                Err(e) => break e.to_string(),
            }
        };
        assert!(
            e.contains("w.vcd: line 8:")
                && e.contains("5 bits for `top.q`")
                && e.contains("4 bits wide")
                && e.contains("time 7 ns"),
            "{e}"
        );
    }

    #[test]
    fn a_last_line_without_a_newline_is_read() {
        let text = "$var wire 1 ! a $end\n$enddefinitions $end\n#0\n1!\n#5";
        let mut r = VcdReader::new(text.as_bytes(), "n.vcd").unwrap();
        while r.next_item().unwrap().is_some() {}
        assert_eq!(r.time_fs(), 5_000_000);
    }

    #[test]
    fn an_empty_file_is_named_empty() {
        let e = VcdReader::new(&b""[..], "e.vcd").err().unwrap().to_string();
        assert!(e.contains("e.vcd") && e.contains("empty"), "{e}");
    }
}
