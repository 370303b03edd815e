//! The body of a dump (after `$enddefinitions`), scanned from a large buffer: `#` times,
//! scalar changes (`0!`, `1!`, `x!`, `z!`), vector changes (`b… code`) and the `$end` of
//! a `$dumpvars`-like command, the commands that make up nearly all of a dump. Any other
//! command, and any of these written in a way the scanner does not take (a space after
//! `#`, a code longer than the crate's tokens, a file cut inside it, …), is handed to the
//! `vcd` crate's parser from the same position, so the reader accepts and rejects exactly
//! what the crate does, with the same messages and line numbers.
//!
//! Lines follow the crate's count: the line of the last byte a command consumed (its
//! closing whitespace), and after the end of the file one past the last newline.

use super::{time_text, vector_value, Value, VcdError, VcdReader};
use bitvec::prelude::*;
use std::io::{self, BufRead, Read};

/// Bytes of the body's buffer.
const BUFFER: usize = 1 << 20;

/// The buffer is refilled when fewer bytes than this are left in it, so that a command
/// shorter than this is always whole in the buffer (a longer one goes to the crate's
/// parser).
const AHEAD: usize = 64 << 10;

/// Identifier codes whose number is below this (every code of one or two characters) are
/// looked up in a table rather than a map.
const SHORT_CODES: u64 = 94 * 94 + 94;

/// The crate's token buffer for an identifier code: a longer code is an error there.
const CODE_MAX: usize = 32;

/// Digits of a `#` time the scanner reads itself (below `u64::MAX`); longer ones go to the
/// crate.
const TIME_DIGITS_MAX: usize = 19;

/// One step of the body.
pub(super) enum Step {
    /// The end of the file.
    End,
    /// A `#` time, femtoseconds.
    Time(u64),
    /// A change of a code (dense index) and its value, `None` when it is not selected.
    Change(usize, Option<Value>),
}

/// A reader that remembers the last byte it gave (`None` after the end of its input):
/// the crate's parser counts a newline only once the byte after it is read, so the line
/// reached depends on whether the last byte read was a newline.
pub(crate) struct LastByte<B> {
    inner: B,
    last: Option<u8>,
}

impl<B> LastByte<B> {
    pub(super) fn new(inner: B) -> Self {
        LastByte { inner, last: None }
    }
}

impl<B: Read> Read for LastByte<B> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        if n > 0 {
            self.last = Some(buf[n - 1]);
        } else if !buf.is_empty() {
            self.last = None;
        }
        Ok(n)
    }
}

impl<B: BufRead> BufRead for LastByte<B> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        self.inner.fill_buf()
    }
    fn consume(&mut self, amt: usize) {
        if amt > 0 {
            if let Ok(b) = self.inner.fill_buf() {
                self.last = b.get(amt - 1).copied();
            }
        }
        self.inner.consume(amt);
    }
}

/// The body's buffer: `buf[pos..end]` is read and not yet consumed.
#[derive(Default)]
pub(super) struct Body {
    buf: Vec<u8>,
    pos: usize,
    end: usize,
    /// The file has no more bytes.
    eof: bool,
    /// Newlines consumed since the start of the file.
    newlines: usize,
    /// The last byte consumed was a newline.
    last_newline: bool,
}

fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\n' | b'\r' | b'\t')
}

/// The number of an identifier code as the crate computes it (little-endian base 94 over
/// `!`..=`~`, each digit counted from 1), `None` where the crate rejects the code.
fn code_number(code: &[u8]) -> Option<u64> {
    if code.is_empty() {
        return None;
    }
    let mut n = 0u64;
    for &c in code.iter().rev() {
        if !(b'!'..=b'~').contains(&c) {
            return None;
        }
        n = n.checked_mul(94)?.checked_add(u64::from(c - b'!') + 1)?;
    }
    Some(n - 1)
}

/// The value of a vector change's digits (`0`, `1`, `x`, `z`, most significant first) for
/// a signal `width` bits wide: as [`vector_value`], without a heap digit list up to 64
/// digits.
fn digits_value(digits: &[u8], width: u32) -> Value {
    let unknown_digit = |d: &u8| matches!(d, b'x' | b'X' | b'z' | b'Z');
    if digits.len() > 64 {
        let values: Vec<vcd::Value> = digits
            .iter()
            .map(|d| match d {
                b'1' => vcd::Value::V1,
                b'0' => vcd::Value::V0,
                b'x' | b'X' => vcd::Value::X,
                _ => vcd::Value::Z,
            })
            .collect();
        return vector_value(&values, width);
    }
    let number = digits
        .iter()
        .fold(0u64, |n, &d| (n << 1) | u64::from(d == b'1'));
    let some_unknown = digits.iter().any(unknown_digit);
    let pads_unknown = digits.first().is_some_and(unknown_digit);
    let extends_unknown = pads_unknown && (digits.len() as u64) < u64::from(width);
    number_value(number, some_unknown || extends_unknown)
}

/// A value of `number` (x and z read as 0), high zeros dropped.
fn number_value(number: u64, unknown: bool) -> Value {
    let mut bits = BitVec::<u64, Lsb0>::new();
    if number != 0 {
        bits = BitVec::from_element(number);
        bits.truncate(64 - number.leading_zeros() as usize);
    }
    Value { bits, unknown }
}

/// What the scanner found at the head of the buffer.
enum Scanned<'a> {
    Time(u64),
    Scalar(u8, u64),
    Vector(&'a [u8], u64),
    SimulationEnd,
    /// For the crate's parser.
    Other,
}

/// Scans one command at the start of `b` (no whitespace before it): what it is, the bytes
/// it takes (its closing whitespace included) and the newlines among them.
fn scan(b: &[u8]) -> (Scanned<'_>, usize, usize) {
    let nl = |c: u8| usize::from(c == b'\n');
    let other = (Scanned::Other, 0, 0);
    // The token from `from` to the next whitespace, which must be in `b`.
    let token_end = |from: usize| -> Option<usize> {
        let n = b.get(from..)?.iter().position(|&c| is_space(c))?;
        Some(from + n)
    };
    match b[0] {
        b'#' => {
            let Some(end) = token_end(1) else {
                return other;
            };
            let digits = &b[1..end];
            if digits.is_empty()
                || digits.len() > TIME_DIGITS_MAX
                || !digits.iter().all(u8::is_ascii_digit)
            {
                return other;
            }
            let n = digits
                .iter()
                .fold(0u64, |n, &d| n * 10 + u64::from(d - b'0'));
            (Scanned::Time(n), end + 1, nl(b[end]))
        }
        v @ (b'0' | b'1' | b'x' | b'X' | b'z' | b'Z') => {
            let Some(end) = token_end(1) else {
                return other;
            };
            if end - 1 > CODE_MAX {
                return other;
            }
            match code_number(&b[1..end]) {
                Some(code) => (Scanned::Scalar(v, code), end + 1, nl(b[end])),
                None => other,
            }
        }
        b'b' | b'B' => {
            let Some(digits_end) = token_end(1) else {
                return other;
            };
            let digits = &b[1..digits_end];
            if digits.is_empty()
                || !digits
                    .iter()
                    .all(|d| matches!(d, b'0' | b'1' | b'x' | b'X' | b'z' | b'Z'))
            {
                return other;
            }
            let mut newlines = nl(b[digits_end]);
            let mut start = digits_end + 1;
            while start < b.len() && is_space(b[start]) {
                newlines += nl(b[start]);
                start += 1;
            }
            let Some(end) = token_end(start) else {
                return other;
            };
            if end == start || end - start > CODE_MAX {
                return other;
            }
            match code_number(&b[start..end]) {
                Some(code) => (
                    Scanned::Vector(digits, code),
                    end + 1,
                    newlines + nl(b[end]),
                ),
                None => other,
            }
        }
        b'$' => {
            if b.get(1..4) != Some(b"end") || !b.get(4).copied().is_some_and(is_space) {
                return other;
            }
            (Scanned::SimulationEnd, 5, nl(b[4]))
        }
        _ => other,
    }
}

impl<R: BufRead> VcdReader<R> {
    /// Sets the body's line count where the declarations' parser stopped.
    pub(super) fn start_body(&mut self) {
        let last_newline = self.parser.reader().last == Some(b'\n');
        let line = usize::try_from(self.parser.line()).unwrap_or(usize::MAX);
        self.body.newlines = line.saturating_sub(1) + usize::from(last_newline);
        self.body.last_newline = last_newline;
        let mut short = Vec::new();
        for (index, code) in self.declarations.codes.iter().enumerate() {
            if let Some(n) = code_number(code.as_bytes()).filter(|&n| n < SHORT_CODES) {
                let n = n as usize;
                if short.len() <= n {
                    short.resize(n + 1, u32::MAX);
                }
                short[n] = u32::try_from(index).unwrap_or(u32::MAX);
            }
        }
        self.short_codes = short;
    }

    /// Moves the unread bytes to the front of the buffer and reads the file after them.
    fn fill(&mut self) -> Result<(), VcdError> {
        let body = &mut self.body;
        if body.buf.is_empty() {
            body.buf = vec![0; BUFFER];
        }
        body.buf.copy_within(body.pos..body.end, 0);
        body.end -= body.pos;
        body.pos = 0;
        while body.end < body.buf.len() && !body.eof {
            match self.parser.reader().read(&mut body.buf[body.end..]) {
                Ok(0) => body.eof = true,
                Ok(n) => body.end += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.error(format!("cannot read: {e}"))),
            }
        }
        Ok(())
    }

    /// Consumes `n` bytes (at least one) holding `newlines` newlines.
    fn consume(&mut self, n: usize, newlines: usize) {
        let body = &mut self.body;
        body.last_newline = body.buf[body.pos + n - 1] == b'\n';
        body.pos += n;
        body.newlines += newlines;
        self.line = 1 + body.newlines - usize::from(body.last_newline);
    }

    /// The dense index of the code numbered `code`, or an error naming it.
    fn index_of(&self, code: u64) -> Result<usize, VcdError> {
        let short = usize::try_from(code)
            .ok()
            .and_then(|c| self.short_codes.get(c))
            .filter(|&&i| i != u32::MAX);
        match short {
            Some(&i) => Ok(i as usize),
            None => self
                .declarations
                .index
                .get(&vcd::IdCode::from(code))
                .copied()
                .ok_or_else(|| {
                    self.error(format!("unknown identifier `{}`", vcd::IdCode::from(code)))
                }),
        }
    }

    fn wanted(&self, index: usize, all: bool) -> bool {
        all || self.selected.as_ref().is_none_or(|s| s[index])
    }

    /// A `#n` time: scaled, and checked not to overflow or go backwards.
    fn time(&mut self, n: u64) -> Result<Step, VcdError> {
        let fs = n
            .checked_mul(self.declarations.timescale_fs)
            .ok_or_else(|| self.error(format!("time `#{n}` overflows")))?;
        if fs < self.time_fs {
            return Err(self.error(format!("time goes backwards: #{n}")));
        }
        self.time_fs = fs;
        Ok(Step::Time(fs))
    }

    /// A vector change of `index` with `digits`, checked against the signal's width.
    fn vector(&self, index: usize, digits: &[u8], all: bool) -> Result<Step, VcdError> {
        let width = self.declarations.widths[index];
        if digits.len() as u64 > u64::from(width) {
            let s = self.declarations.signal_of(index);
            return Err(self.error(format!(
                "a value of {} bits for `{}`, declared {width} bits wide (line {}), at time {}",
                digits.len(),
                s.scope
                    .iter()
                    .chain([&s.name])
                    .cloned()
                    .collect::<Vec<_>>()
                    .join("."),
                s.line,
                time_text(self.time_fs)
            )));
        }
        let value = self.wanted(index, all).then(|| digits_value(digits, width));
        Ok(Step::Change(index, value))
    }

    /// The next step of the body; every change's value built when `all`, else only those
    /// of the selected codes.
    pub(super) fn next_step(&mut self, all: bool) -> Result<Step, VcdError> {
        loop {
            if self.body.end - self.body.pos < AHEAD && !self.body.eof {
                self.fill()?;
            }
            let b = &self.body.buf[self.body.pos..self.body.end];
            let spaces = b.iter().position(|&c| !is_space(c)).unwrap_or(b.len());
            if spaces > 0 {
                let newlines = b[..spaces].iter().filter(|&&c| c == b'\n').count();
                self.consume(spaces, newlines);
                continue;
            }
            if b.is_empty() {
                // The end of the file: the crate's parser counts the last newline too.
                self.body.last_newline = false;
                self.line = 1 + self.body.newlines;
                return Ok(Step::End);
            }
            let (scanned, n, newlines) = scan(b);
            let step = match scanned {
                Scanned::Time(t) => {
                    self.consume(n, newlines);
                    self.time(t)?
                }
                Scanned::Scalar(v, code) => {
                    self.consume(n, newlines);
                    let index = self.index_of(code)?;
                    let value = self.wanted(index, all).then(|| Value {
                        bits: if v == b'1' {
                            bitvec![u64, Lsb0; 1]
                        } else {
                            BitVec::new()
                        },
                        unknown: !matches!(v, b'0' | b'1'),
                    });
                    Step::Change(index, value)
                }
                Scanned::Vector(digits, code) => {
                    // The digits stay valid: consuming only moves the position.
                    let start = digits.as_ptr() as usize - b.as_ptr() as usize;
                    let len = digits.len();
                    self.consume(n, newlines);
                    let index = self.index_of(code)?;
                    let base = self.body.pos - n;
                    let digits = &self.body.buf[base + start..base + start + len];
                    self.vector(index, digits, all)?
                }
                Scanned::SimulationEnd if self.simulation_open => {
                    self.consume(n, newlines);
                    self.simulation_open = false;
                    continue;
                }
                Scanned::SimulationEnd | Scanned::Other => match self.parse_one()? {
                    Some(step) => step,
                    None => continue,
                },
            };
            return Ok(step);
        }
    }

    /// Reads one command with the crate's parser, from the buffer's position on; `None`
    /// when it gives no step (a comment, a real or a string change, a `$dumpvars`).
    fn parse_one(&mut self) -> Result<Option<Step>, VcdError> {
        use vcd::Command as C;
        let before = self.body.newlines;
        let rest = &self.body.buf[self.body.pos..self.body.end];
        let rest_len = rest.len();
        let mut src = LastByte::new(rest.chain(self.parser.reader()));
        let (next, line) = {
            let mut parser = vcd::Parser::new(&mut src);
            let next = parser.next();
            (next, usize::try_from(parser.line()).unwrap_or(usize::MAX))
        };
        let last_newline = src.last == Some(b'\n');
        let left = src.inner.get_ref().0.len();
        self.body.pos += rest_len - left;
        self.body.last_newline = last_newline;
        self.body.newlines = before + line - 1 + usize::from(last_newline);
        self.line = before + line;
        let Some(command) = self.parsed(next, before)? else {
            self.line = 1 + self.body.newlines;
            return Ok(Some(Step::End));
        };
        Ok(match command {
            C::Timestamp(n) => Some(self.time(n)?),
            C::ChangeScalar(code, v) => {
                let index = self
                    .declarations
                    .index
                    .get(&code)
                    .copied()
                    .ok_or_else(|| self.error(format!("unknown identifier `{code}`")))?;
                let value = Value::from_bits(
                    BitVec::repeat(v == vcd::Value::V1, 1),
                    matches!(v, vcd::Value::X | vcd::Value::Z),
                );
                Some(Step::Change(index, Some(value)))
            }
            C::ChangeVector(code, digits) => {
                let index = self
                    .declarations
                    .index
                    .get(&code)
                    .copied()
                    .ok_or_else(|| self.error(format!("unknown identifier `{code}`")))?;
                let digits: Vec<u8> = Vec::<vcd::Value>::from(digits)
                    .iter()
                    .map(|d| match d {
                        vcd::Value::V0 => b'0',
                        vcd::Value::V1 => b'1',
                        vcd::Value::X => b'x',
                        vcd::Value::Z => b'z',
                    })
                    .collect();
                Some(self.vector(index, &digits, true)?)
            }
            C::Comment(text) => {
                self.late_comments.push(super::comment_words(&text));
                None
            }
            C::Begin(_) => {
                self.simulation_open = true;
                None
            }
            C::End(_) => {
                self.simulation_open = false;
                None
            }
            _ => None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::{comment_words, Item};
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// The body as the crate's parser alone reads it (the reader before the scanner):
    /// every item, then the error text or the end's line, time and late comments.
    fn reference(text: &str) -> (Vec<Item>, String) {
        use vcd::Command as C;
        let Ok(r) = VcdReader::new(text.as_bytes(), "f.vcd") else {
            return (Vec::new(), String::new());
        };
        let d = r.declarations();
        let mut p = vcd::Parser::new(text.as_bytes().chain(&b"\n"[..]));
        for c in p.by_ref() {
            if matches!(c, Ok(C::Enddefinitions)) {
                break;
            }
        }
        let mut items = Vec::new();
        let mut time_fs = 0u64;
        let mut late = Vec::new();
        let error = |line: usize, message: String| VcdError {
            file: "f.vcd".into(),
            line,
            message,
        };
        let outcome: Result<(), VcdError> = (|| loop {
            let next = p.next();
            let line = p.line() as usize;
            let command = match next {
                None => return Ok(()),
                Some(Ok(c)) => c,
                Some(Err(e)) => {
                    let parse = e
                        .get_ref()
                        .and_then(|i| i.downcast_ref::<vcd::ParseError>());
                    return Err(match parse {
                        Some(p) => error(p.line() as usize, p.kind().to_string()),
                        None if e.kind() == io::ErrorKind::UnexpectedEof => {
                            error(line, "ends inside a command (cut short?)".into())
                        }
                        None => error(line, format!("cannot read: {e}")),
                    });
                }
            };
            let index = |code: vcd::IdCode| {
                d.index
                    .get(&code)
                    .copied()
                    .ok_or_else(|| error(line, format!("unknown identifier `{code}`")))
            };
            match command {
                C::Timestamp(n) => {
                    let fs = n
                        .checked_mul(d.timescale_fs)
                        .ok_or_else(|| error(line, format!("time `#{n}` overflows")))?;
                    if fs < time_fs {
                        return Err(error(line, format!("time goes backwards: #{n}")));
                    }
                    time_fs = fs;
                    items.push(Item::Time(fs));
                }
                C::ChangeScalar(code, v) => {
                    let value = Value::from_bits(
                        BitVec::repeat(v == vcd::Value::V1, 1),
                        matches!(v, vcd::Value::X | vcd::Value::Z),
                    );
                    items.push(Item::Change(index(code)?, value));
                }
                C::ChangeVector(code, digits) => {
                    let i = index(code)?;
                    let width = d.widths[i];
                    let digits: Vec<vcd::Value> = digits.into();
                    if digits.len() as u64 > u64::from(width) {
                        return Err(error(line, format!("{} digits", digits.len())));
                    }
                    items.push(Item::Change(i, vector_value(&digits, width)));
                }
                C::Comment(text) => late.push(comment_words(&text)),
                _ => {}
            }
        })();
        let end = match outcome {
            Ok(()) => format!("end line {} at {time_fs} {late:?}", p.line()),
            Err(e) => e.to_string(),
        };
        (items, end)
    }

    /// The same, through the scanner.
    fn scanned(text: &str) -> (Vec<Item>, String) {
        let Ok(mut r) = VcdReader::new(text.as_bytes(), "f.vcd") else {
            return (Vec::new(), String::new());
        };
        let mut items = Vec::new();
        let end = loop {
            match r.next_item() {
                Ok(Some(item)) => items.push(item),
                Ok(None) => {
                    break format!(
                        "end line {} at {} {:?}",
                        r.line(),
                        r.time_fs(),
                        r.late_comments()
                    )
                }
                Err(e) if e.message.starts_with("a value of ") => {
                    let digits = e.message["a value of ".len()..]
                        .split(' ')
                        .next()
                        .unwrap_or("")
                        .to_string();
                    break format!("f.vcd: line {}: {digits} digits", e.line);
                }
                Err(e) => break e.to_string(),
            }
        };
        (items, end)
    }

    const HEAD: &str = "$timescale 10ps $end\n$scope module top $end\n\
        $var wire 1 ! a $end\n$var wire 8 \" q [7:0] $end\n\
        $var wire 100 #a wide $end\n$upscope $end\n$enddefinitions $end";

    #[test]
    fn the_scanner_reads_as_the_crate_does() {
        let bodies = [
            "\n#0\n$dumpvars\n1!\nb101 \"\n$end\n#5\n0!\n",
            " #0 1! b1 \" x! Z! bxz1 \" bZ \"\r\n#7\tb11111111 \" #9",
            "\n# 5\n1 !\nb 101 \"\nb101\n\"\n$ end\n",
            "\n#0\n$end\n",
            "\n#0\n$dumpoff\n0!\n$end\n$dumpon $end\n#1\n1!\n",
            "\n#0\n1?\n",
            "\n#0\nb101 ?\n",
            "\n#5\n#4\n",
            "\n#18446744073709551615\n",
            "\n#99999999999999999999\n",
            "\n#+5\n#0005\n",
            "\n#0\nb111111111 \"\n",
            "\n#0\nb10q1 \"\n",
            "\n#0\nq!\n",
            "\n#0\n1!",
            "\n#0\nb101",
            "\n#0\nb101 ",
            "\n#0\n$comment tooltouch end cycles=3 $end\n#3",
            "\n#0\n$comment cut",
            "\n#0\nr1.5 !\ns hello !\n1!\n",
            "\n#0\nb1 #a\nb1010101010101010101010101010101010101010101010101010101010101010101 #a\n",
            "\n#0\n$unknown $end\n",
            "\n#0\n1!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!\n",
            "",
            "\n",
        ];
        for body in bodies {
            let text = format!("{HEAD}{body}");
            assert_eq!(scanned(&text), reference(&text), "{body:?}");
        }
    }

    #[test]
    fn the_scanner_reads_mangled_dumps_as_the_crate_does() {
        let mut body = String::from("\n#0\n$dumpvars\n0!\nb0 \"\nb0 #a\n$end\n");
        for k in 1..200u64 {
            body.push_str(&format!("#{}\n{}!\nb{:b} \"\n", k * 3, k % 2, k % 256));
        }
        body.push_str("$comment tooltouch end cycles=200 $end\n");
        let alphabet = b" \n\r\t#$01xzbBr!\"q9e";
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for _ in 0..400 {
            let mut bytes = body.clone().into_bytes();
            for _ in 0..rng.random_range(1..4) {
                if bytes.is_empty() {
                    break;
                }
                let at = rng.random_range(0..bytes.len());
                match rng.random_range(0..3) {
                    0 => {
                        bytes.remove(at);
                    }
                    1 => bytes.insert(at, alphabet[rng.random_range(0..alphabet.len())]),
                    _ => bytes.truncate(at),
                }
            }
            let text = format!("{HEAD}{}", String::from_utf8_lossy(&bytes));
            assert_eq!(scanned(&text), reference(&text), "{text:?}");
        }
    }

    #[test]
    fn a_body_longer_than_the_buffer_is_read_whole() {
        let mut body = String::from("\n#0\n");
        let mut k = 0u64;
        while body.len() < 3 * BUFFER {
            k += 1;
            body.push_str(&format!("#{k}\n{}!\nb{:b} \"\n", k % 2, k % 256));
        }
        // A comment longer than the look-ahead, across a refill.
        body.push_str(&format!("$comment {} $end\n", "w ".repeat(AHEAD)));
        let text = format!("{HEAD}{body}");
        let (items, end) = scanned(&text);
        assert_eq!((items.len() as u64, end.clone()), {
            let (i, e) = reference(&text);
            (i.len() as u64, e)
        });
        // `#0`, then a time and two changes per step.
        assert_eq!(items.len() as u64, 1 + 3 * k);
        assert!(end.starts_with("end line"), "{}", &end[..80]);
    }
}
