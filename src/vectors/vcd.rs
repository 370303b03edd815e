//! Value change dump files, per the VCD contract (docs/CONTRACT.md): the golden
//! writer (inputs and outputs of the measurement front end at `k·P` ns) and a reader that
//! takes any tool's dump (Verilator, Icarus) for `tooltouch check`.

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
/// time `k·P` ns, changes only. Returns the number of clocks covered.
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
    Ok(end)
}

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
}

/// A parsed dump: signals and, per identifier code, its changes `(time fs, value)`.
#[derive(Clone, Debug, Default)]
pub struct Dump {
    /// Femtoseconds per time unit of the file's `$timescale`.
    pub timescale_fs: u64,
    /// Every `$var`.
    pub signals: Vec<Signal>,
    /// Changes per identifier code, in time order.
    pub changes: HashMap<String, Vec<(u64, Value)>>,
    /// `$comment` texts.
    pub comments: Vec<String>,
    /// Largest time seen, fs.
    pub last_time_fs: u64,
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

fn parse_value(text: &str, width: u32) -> Value {
    let mut bits = 0u64;
    let mut unknown = false;
    let chars: Vec<char> = text.chars().collect();
    // Left-extension: x/z extend with themselves, 0/1 with 0.
    let pad = matches!(chars.first(), Some('x' | 'X' | 'z' | 'Z'));
    if pad && (chars.len() as u32) < width {
        unknown = true;
    }
    for c in chars {
        bits = bits.wrapping_shl(1);
        match c {
            '1' => bits |= 1,
            '0' => {}
            _ => unknown = true,
        }
    }
    Value { bits, unknown }
}

impl Dump {
    /// Parses a VCD text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Dump, VcdError> {
        let err = |line: usize, message: String| VcdError {
            file: file.to_string(),
            line,
            message,
        };
        let mut dump = Dump {
            timescale_fs: 1_000_000,
            ..Default::default()
        };
        let mut widths: HashMap<String, u32> = HashMap::new();
        let mut scope: Vec<String> = Vec::new();
        let mut time = 0u64;
        let mut in_definitions = true;
        // Tokenize by whitespace, keeping line numbers.
        let mut tokens = text
            .lines()
            .enumerate()
            .flat_map(|(i, l)| l.split_whitespace().map(move |t| (i + 1, t)));
        let until_end = |tokens: &mut dyn Iterator<Item = (usize, &str)>,
                         start: usize|
         -> Result<Vec<String>, VcdError> {
            let mut v = Vec::new();
            for (_, t) in &mut *tokens {
                if t == "$end" {
                    return Ok(v);
                }
                v.push(t.to_string());
            }
            Err(err(start, "missing $end".into()))
        };
        while let Some((line, tok)) = tokens.next() {
            match tok {
                "$scope" => {
                    let v = until_end(&mut tokens, line)?;
                    scope.push(v.get(1).cloned().unwrap_or_default());
                }
                "$upscope" => {
                    until_end(&mut tokens, line)?;
                    scope.pop();
                }
                "$var" => {
                    let v = until_end(&mut tokens, line)?;
                    if v.len() < 4 {
                        return Err(err(line, format!("malformed $var: {}", v.join(" "))));
                    }
                    let width: u32 = v[1]
                        .parse()
                        .map_err(|_| err(line, format!("bad $var width `{}`", v[1])))?;
                    let name = v[3].split('[').next().unwrap_or("").to_string();
                    widths.insert(v[2].clone(), width);
                    dump.signals.push(Signal {
                        scope: scope.clone(),
                        name,
                        width,
                        id: v[2].clone(),
                    });
                }
                "$timescale" => {
                    let v = until_end(&mut tokens, line)?.concat();
                    let digits: String = v.chars().take_while(|c| c.is_ascii_digit()).collect();
                    let unit = &v[digits.len()..];
                    let n: u64 = digits
                        .parse()
                        .map_err(|_| err(line, format!("bad $timescale `{v}`")))?;
                    let per = match unit {
                        "s" => 1_000_000_000_000_000,
                        "ms" => 1_000_000_000_000,
                        "us" => 1_000_000_000,
                        "ns" => 1_000_000,
                        "ps" => 1_000,
                        "fs" => 1,
                        _ => return Err(err(line, format!("bad $timescale unit `{unit}`"))),
                    };
                    dump.timescale_fs = n * per;
                }
                "$comment" => {
                    let v = until_end(&mut tokens, line)?;
                    dump.comments.push(v.join(" "));
                }
                "$enddefinitions" => {
                    until_end(&mut tokens, line)?;
                    in_definitions = false;
                }
                "$dumpvars" | "$dumpall" | "$dumpon" | "$dumpoff" | "$end" => {}
                t if t.starts_with('$') => {
                    until_end(&mut tokens, line)?;
                }
                t if in_definitions => {
                    return Err(err(
                        line,
                        format!("unexpected `{t}` before $enddefinitions"),
                    ));
                }
                t if t.starts_with('#') => {
                    let n: u64 = t[1..]
                        .parse()
                        .map_err(|_| err(line, format!("bad time `{t}`")))?;
                    let fs = n
                        .checked_mul(dump.timescale_fs)
                        .ok_or_else(|| err(line, format!("time `{t}` overflows")))?;
                    if fs < time {
                        return Err(err(line, format!("time goes backwards: {t}")));
                    }
                    time = fs;
                    dump.last_time_fs = time;
                }
                t if t.starts_with(['b', 'B']) => {
                    let (_, id) = tokens
                        .next()
                        .ok_or_else(|| err(line, "vector value without identifier".into()))?;
                    let width = *widths
                        .get(id)
                        .ok_or_else(|| err(line, format!("unknown identifier `{id}`")))?;
                    dump.changes
                        .entry(id.to_string())
                        .or_default()
                        .push((time, parse_value(&t[1..], width)));
                }
                t if t.starts_with(['r', 'R', 's', 'S']) => {
                    // Real and string values: not compared; skip the identifier.
                    tokens.next();
                }
                t => {
                    let mut chars = t.chars();
                    let c = chars.next().unwrap_or(' ');
                    let id = chars.as_str();
                    if !matches!(c, '0' | '1' | 'x' | 'X' | 'z' | 'Z') || id.is_empty() {
                        return Err(err(line, format!("unexpected `{t}`")));
                    }
                    if !widths.contains_key(id) {
                        return Err(err(line, format!("unknown identifier `{id}`")));
                    }
                    dump.changes
                        .entry(id.to_string())
                        .or_default()
                        .push((time, parse_value(&c.to_string(), 1)));
                }
            }
        }
        if in_definitions {
            return Err(err(text.lines().count(), "no $enddefinitions".into()));
        }
        Ok(dump)
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
        self.signals
            .iter()
            .find(|s| s.name == name && s.scope.last().is_some_and(|l| l == scope_suffix))
    }

    /// The DUT signal compared with golden output `name`: one in a scope named `outputs`
    /// if there is one, else the shallowest not in a scope named `inputs` (the input pin
    /// `contact` and the output `contact` share a leaf name), else the shallowest.
    pub fn find_shallowest(&self, name: &str) -> Option<&Signal> {
        let named = || self.signals.iter().filter(move |s| s.name == name);
        let in_scope = |s: &Signal, scope: &str| s.scope.last().is_some_and(|l| l == scope);
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

    /// `(measure_hash, clock_hz)` from a golden file's `$comment`.
    pub fn golden_stamp(&self) -> Option<(u64, u32)> {
        self.comments.iter().find_map(|c| {
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
