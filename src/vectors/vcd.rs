//! Value change dump files, per the VCD contract (docs/CONTRACT.md): the golden
//! writer (inputs and outputs of the measurement front end at `k·P` ns, closed by a
//! `tooltouch end cycles=<n>` comment so a cut file is told from a whole one), and a
//! streaming reader that takes any tool's dump (Verilator, Icarus) for `tooltouch check`
//! and `tooltouch vectors` in constant memory, with [`Dump`] on top of it for callers that
//! want the whole file in memory.

use super::clock_through;
use crate::stimulus::Stimulus;
use std::collections::HashMap;
use std::io::{self, Write};
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_model::{FrontEnd, MeasureConfig, MeasureOutputs};

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

    let total = stimulus.total_cycles();
    let end = end.unwrap_or(total).min(total);
    let mut last_pins: Option<Pins> = None;
    let mut last_out: Option<[u64; 15]> = None;
    let mut buffer = String::new();
    let mut error = None;
    // Pin changes at segment starts and output changes at clocked clocks, merged by
    // clock: `clock_through` visits every clock at which an output can change, and pin
    // levels only change at segment starts, which it always clocks (a changed pin is
    // never settled).
    let mut stopped = false;
    let mut last_time = None;
    // Every signal's value at time 0, even when nothing happens at clock 0 (a settled
    // start is skipped by `clock_through`): the pins of the first segment and the reset
    // outputs, which are the outputs after clock 0 (no edge can be detected at clock 0).
    if let (true, Some(first)) = (end > 0, stimulus.segments.first()) {
        for (i, _) in pin::NAMES.iter().enumerate() {
            let bit = 1u8 << i;
            buffer.push_str(&value_text(first.pins.get(bit).into(), 1, &id_code(i)));
        }
        let values = output_values(&FrontEnd::new(config).outputs(), config);
        for (i, (_, width)) in outputs.iter().enumerate() {
            buffer.push_str(&value_text(values[i], *width, &id_code(pin::COUNT + i)));
        }
        write!(w, "#0\n$dumpvars\n{buffer}$end\n")?;
        last_pins = Some(first.pins);
        last_out = Some(values);
        last_time = Some(0);
    }
    clock_through(stimulus, config, |k, pins, fe, edges| {
        if stopped || error.is_some() {
            return;
        }
        if k >= end {
            stopped = true;
            return;
        }
        buffer.clear();
        if last_pins != Some(pins) {
            for (i, _) in pin::NAMES.iter().enumerate() {
                let bit = 1u8 << i;
                if last_pins.is_none_or(|l| l.get(bit) != pins.get(bit)) {
                    buffer.push_str(&value_text(pins.get(bit).into(), 1, &id_code(i)));
                }
            }
            last_pins = Some(pins);
        }
        if last_out.is_none() || !edges.is_empty() {
            let values = output_values(&fe.outputs(), config);
            for (i, (_, width)) in outputs.iter().enumerate() {
                if last_out.is_none_or(|l| l[i] != values[i]) {
                    buffer.push_str(&value_text(values[i], *width, &id_code(pin::COUNT + i)));
                }
            }
            last_out = Some(values);
        }
        if !buffer.is_empty() {
            let r = if k == 0 {
                write!(w, "#0\n$dumpvars\n{buffer}$end\n")
            } else {
                write!(w, "#{}\n{buffer}", k * p)
            };
            last_time = Some(k * p);
            if let Err(e) = r {
                error = Some(e);
            }
        }
    });
    if let Some(e) = error {
        return Err(e);
    }
    // Mark the end of the covered time so a reader knows the last clock.
    if end > 0 && last_time != Some((end - 1) * p) {
        writeln!(w, "#{}", (end - 1) * p)?;
    }
    writeln!(w, "$comment {END_COMMENT} cycles={end} $end")?;
    Ok(end)
}

/// The `$comment` text a golden file ends with: `tooltouch end cycles=<n>`, so a reader
/// can tell a whole golden file from one cut short.
pub const END_COMMENT: &str = "tooltouch end";

/// A value in a dump: bits, and whether any bit was x or z.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Value {
    /// The bits (x/z read as 0), low 64 bits of the vector.
    pub bits: u64,
    /// Some bit was x or z.
    pub unknown: bool,
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
#[error("{file}: line {line}: {message}")]
pub struct VcdError {
    /// File name (as given).
    pub file: String,
    /// Line number, from 1.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

#[cfg(test)]
fn parse_value(text: &str, width: u32) -> Value {
    let (bits, unknown, pad) = parse_bits(text.as_bytes());
    Value {
        bits,
        unknown: unknown || (pad && (text.len() as u32) < width),
    }
}

/// Bits of a binary value text, whether some digit was x/z, and whether it left-extends
/// with x/z (its first digit is x or z).
fn parse_bits(text: &[u8]) -> (u64, bool, bool) {
    let mut bits = 0u64;
    let mut unknown = false;
    for &c in text {
        bits = bits.wrapping_shl(1);
        match c {
            b'1' => bits |= 1,
            b'0' => {}
            _ => unknown = true,
        }
    }
    let pad = matches!(text.first(), Some(b'x' | b'X' | b'z' | b'Z'));
    (bits, unknown, pad)
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
    index: HashMap<String, usize>,
    /// Dense index + 1 of the one- and two-character codes (the common ones), by
    /// [`short_code_slot`]; 0 = none. Spares the body's hot loop a string hash.
    short: Vec<u32>,
}

/// A decimal number of ASCII digits (no sign, at least one digit), or `None`.
fn parse_decimal(digits: &[u8]) -> Option<u64> {
    if digits.is_empty() {
        return None;
    }
    digits.iter().try_fold(0u64, |n, &d| {
        d.is_ascii_digit()
            .then(|| n.checked_mul(10)?.checked_add(u64::from(d - b'0')))
            .flatten()
    })
}

/// Printable code characters `'!'..='~'`.
const CODE_CHARS: usize = 94;

/// The slot of a one- or two-character code in [`Declarations::short`].
fn short_code_slot(id: &[u8]) -> Option<usize> {
    let c = |b: u8| (33..=126).contains(&b).then(|| usize::from(b - 33));
    match *id {
        [a] => c(a),
        [a, b] => Some(CODE_CHARS + c(a)? * CODE_CHARS + c(b)?),
        _ => None,
    }
}

impl Declarations {
    fn add(&mut self, signal: Signal) {
        if !self.index.contains_key(&signal.id) {
            if let Some(slot) = short_code_slot(signal.id.as_bytes()) {
                if self.short.is_empty() {
                    self.short = vec![0; CODE_CHARS + CODE_CHARS * CODE_CHARS];
                }
                self.short[slot] = self.codes.len() as u32 + 1;
            }
            self.index.insert(signal.id.clone(), self.codes.len());
            self.codes.push(signal.id.clone());
            self.widths.push(signal.width);
        }
        self.signals.push(signal);
    }

    /// The dense index of identifier code `id`.
    pub fn code_index(&self, id: &str) -> Option<usize> {
        self.code_index_bytes(id.as_bytes())
    }

    /// [`Declarations::code_index`] of a code given as bytes.
    fn code_index_bytes(&self, id: &[u8]) -> Option<usize> {
        match short_code_slot(id) {
            Some(slot) => match self.short.get(slot) {
                Some(&n) if n > 0 => Some(n as usize - 1),
                _ => None,
            },
            None => std::str::from_utf8(id)
                .ok()
                .and_then(|id| self.index.get(id).copied()),
        }
    }

    /// Identifier codes by dense index.
    pub fn codes(&self) -> &[String] {
        &self.codes
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
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Item {
    /// A `#` time, femtoseconds.
    Time(u64),
    /// A value change of the identifier code with this dense index, at the current time.
    Change(usize, Value),
}

/// Reads a dump as a stream: the declarations first ([`VcdReader::new`]), then the body
/// item by item, so that a file of any length is read in constant memory. Any tool's
/// dump is accepted (scopes, `$timescale`, several codes per line, reals and strings
/// skipped); errors name the file and line.
pub struct VcdReader<R> {
    src: R,
    file: String,
    buf: Vec<u8>,
    pos: usize,
    line: usize,
    declarations: Declarations,
    time_fs: u64,
    late_comments: Vec<String>,
}

impl<R: std::io::BufRead> VcdReader<R> {
    /// Reads the declarations of `src` (up to `$enddefinitions`); `file` names it in
    /// errors.
    pub fn new(src: R, file: &str) -> Result<Self, VcdError> {
        let mut r = VcdReader {
            src,
            file: file.to_string(),
            buf: Vec::with_capacity(256),
            pos: 0,
            line: 0,
            declarations: Declarations {
                timescale_fs: 1_000_000,
                ..Default::default()
            },
            time_fs: 0,
            late_comments: Vec::new(),
        };
        r.read_declarations()?;
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

    /// The byte range of the next whitespace-separated token in `self.buf`, reading lines
    /// as needed; `None` at the end of the file.
    fn next_token(&mut self) -> Result<Option<(usize, usize)>, VcdError> {
        loop {
            let b = &self.buf;
            let mut i = self.pos;
            while i < b.len() && b[i].is_ascii_whitespace() {
                i += 1;
            }
            if i < b.len() {
                let start = i;
                while i < b.len() && !b[i].is_ascii_whitespace() {
                    i += 1;
                }
                self.pos = i;
                return Ok(Some((start, i)));
            }
            self.buf.clear();
            self.pos = 0;
            let n = self
                .src
                .read_until(b'\n', &mut self.buf)
                .map_err(|e| self.error(format!("cannot read: {e}")))?;
            if n == 0 {
                return Ok(None);
            }
            self.line += 1;
        }
    }

    fn token_text(&self, (a, b): (usize, usize)) -> String {
        String::from_utf8_lossy(&self.buf[a..b]).into_owned()
    }

    /// The tokens up to `$end` (not included); `what` names the command in the error.
    fn until_end(&mut self, what: &str) -> Result<Vec<String>, VcdError> {
        let start = self.line;
        let mut v = Vec::new();
        while let Some(t) = self.next_token()? {
            if &self.buf[t.0..t.1] == b"$end" {
                return Ok(v);
            }
            v.push(self.token_text(t));
        }
        Err(VcdError {
            file: self.file.clone(),
            line: start,
            message: format!("{what} without $end"),
        })
    }

    fn read_declarations(&mut self) -> Result<(), VcdError> {
        let mut scope: Vec<String> = Vec::new();
        loop {
            let Some(t) = self.next_token()? else {
                return Err(self.error("no $enddefinitions".into()));
            };
            let tok = self.token_text(t);
            let line = self.line;
            match tok.as_str() {
                "$scope" => {
                    let v = self.until_end("$scope")?;
                    scope.push(v.get(1).cloned().unwrap_or_default());
                }
                "$upscope" => {
                    self.until_end("$upscope")?;
                    scope.pop();
                }
                "$var" => {
                    let v = self.until_end("$var")?;
                    if v.len() < 4 {
                        return Err(VcdError {
                            file: self.file.clone(),
                            line,
                            message: format!("malformed $var: {}", v.join(" ")),
                        });
                    }
                    let width: u32 = v[1].parse().map_err(|_| VcdError {
                        file: self.file.clone(),
                        line,
                        message: format!("bad $var width `{}`", v[1]),
                    })?;
                    let name = v[3].split('[').next().unwrap_or("").to_string();
                    self.declarations.add(Signal {
                        scope: scope.clone(),
                        name,
                        width,
                        id: v[2].clone(),
                        line,
                    });
                }
                "$timescale" => {
                    let v = self.until_end("$timescale")?.concat();
                    let digits: String = v.chars().take_while(|c| c.is_ascii_digit()).collect();
                    let unit = &v[digits.len()..];
                    let bad = |message: String| VcdError {
                        file: self.file.clone(),
                        line,
                        message,
                    };
                    let n: u64 = digits
                        .parse()
                        .map_err(|_| bad(format!("bad $timescale `{v}`")))?;
                    let per: u64 = match unit {
                        "s" => 1_000_000_000_000_000,
                        "ms" => 1_000_000_000_000,
                        "us" => 1_000_000_000,
                        "ns" => 1_000_000,
                        "ps" => 1_000,
                        "fs" => 1,
                        _ => return Err(bad(format!("bad $timescale unit `{unit}`"))),
                    };
                    self.declarations.timescale_fs = n * per;
                }
                "$comment" => {
                    let v = self.until_end("$comment")?;
                    self.declarations.comments.push(v.join(" "));
                }
                "$enddefinitions" => {
                    self.until_end("$enddefinitions")?;
                    return Ok(());
                }
                "$dumpvars" | "$dumpall" | "$dumpon" | "$dumpoff" | "$end" => {}
                t if t.starts_with('$') => {
                    self.until_end(t)?;
                }
                t => {
                    return Err(self.error(format!("unexpected `{t}` before $enddefinitions")));
                }
            }
        }
    }

    /// The next time or value change of the body; `None` at the end of the file.
    /// Comments are kept ([`VcdReader::late_comments`]); times must not go backwards.
    pub fn next_item(&mut self) -> Result<Option<Item>, VcdError> {
        loop {
            let Some((a, b)) = self.next_token()? else {
                return Ok(None);
            };
            match self.buf[a] {
                b'#' => {
                    let n = parse_decimal(&self.buf[a + 1..b]).ok_or_else(|| {
                        self.error(format!("bad time `{}`", self.token_text((a, b))))
                    })?;
                    let fs = n
                        .checked_mul(self.declarations.timescale_fs)
                        .ok_or_else(|| {
                            self.error(format!("time `{}` overflows", self.token_text((a, b))))
                        })?;
                    if fs < self.time_fs {
                        return Err(
                            self.error(format!("time goes backwards: {}", self.token_text((a, b))))
                        );
                    }
                    self.time_fs = fs;
                    return Ok(Some(Item::Time(fs)));
                }
                b'0' | b'1' | b'x' | b'X' | b'z' | b'Z' if b - a > 1 => {
                    let (bits, unknown, _) = parse_bits(&self.buf[a..a + 1]);
                    let Some(index) = self.declarations.code_index_bytes(&self.buf[a + 1..b])
                    else {
                        let id = self.token_text((a + 1, b));
                        return Err(self.error(format!("unknown identifier `{id}`")));
                    };
                    return Ok(Some(Item::Change(index, Value { bits, unknown })));
                }
                b'b' | b'B' => {
                    let (bits, unknown, pad) = parse_bits(&self.buf[a + 1..b]);
                    let digits = (b - a - 1) as u32;
                    let Some(t) = self.next_token()? else {
                        return Err(self.error("vector value without identifier".into()));
                    };
                    let Some(index) = self.declarations.code_index_bytes(&self.buf[t.0..t.1])
                    else {
                        let id = self.token_text(t);
                        return Err(self.error(format!("unknown identifier `{id}`")));
                    };
                    let width = self.declarations.widths[index];
                    let unknown = unknown || (pad && digits < width);
                    return Ok(Some(Item::Change(index, Value { bits, unknown })));
                }
                b'r' | b'R' | b's' | b'S' => {
                    // Real and string values: not compared; skip the identifier.
                    self.next_token()?;
                }
                b'$' => {
                    let tok = self.token_text((a, b));
                    match tok.as_str() {
                        "$comment" => {
                            let v = self.until_end("$comment")?;
                            self.late_comments.push(v.join(" "));
                        }
                        "$dumpvars" | "$dumpall" | "$dumpon" | "$dumpoff" | "$end" => {}
                        t => {
                            self.until_end(t)?;
                        }
                    }
                }
                _ => {
                    return Err(self.error(format!("unexpected `{}`", self.token_text((a, b)))));
                }
            }
        }
    }
}

/// A source of value changes in time order, for [`crate::vectors::check`]: a streamed
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
}

impl<R: std::io::BufRead> Changes for VcdReader<R> {
    fn next_change(&mut self) -> Result<Option<(u64, usize, Value)>, VcdError> {
        loop {
            match self.next_item()? {
                None => return Ok(None),
                Some(Item::Time(_)) => {}
                Some(Item::Change(i, v)) => return Ok(Some((self.time_fs, i, v))),
            }
        }
    }
    fn end_fs(&self) -> u64 {
        self.time_fs
    }
    fn line(&self) -> usize {
        self.line
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
            for &(t, v) in self.changes.get(code).into_iter().flatten() {
                all.push((t, i, v));
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
        (i > 0).then(|| ch[i - 1].1)
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
        assert_eq!(
            parse_value("101", 8),
            Value {
                bits: 5,
                unknown: false
            }
        );
        assert!(parse_value("x", 8).unknown);
        assert!(parse_value("1z", 2).unknown);
    }
}
