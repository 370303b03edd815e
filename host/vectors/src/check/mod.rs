//! The comparisons behind `tooltouch check`: a device's trace against the golden one,
//! first difference reported, and nothing passed that the golden file does not cover.
//!
//! **VCD** (docs/CONTRACT.md): every signal of the golden `outputs` scope against the DUT
//! signal of the same leaf name, sampled at `k·P + P/2` for every clock `k`. Both files are
//! read as streams in step ([`Changes`]): values only change at change times, so the state
//! between two consecutive change times of either file is constant and only the first
//! sample inside such an interval needs a look, which keeps the work proportional to the
//! changes and the memory to the signals. The golden file must be whole (its closing
//! `tooltouch end cycles=<n>` comment, its last time at clock `n − 1`); a DUT trace that ends
//! at another clock than the golden one is a mismatch that names both ends.
//!
//! **Binary** (`.ttv`): one Outputs stream per file, read record by record
//! ([`binary::OutputReader`], memory flat in the file size; [`compare_output_sources`]):
//! measurement outputs and force outputs record by record, the firmware's status (a lost or
//! overflowed event is a mismatch), record counts, the headers' hashes and tick rates.

mod dump;
mod files;
pub mod json;
pub mod resolve;
pub mod surfer;
pub mod window;

pub use files::{check_files, compare_files};

use super::binary::{self, OutputReader, OutputRecord};
use super::vcd::{golden_end, Changes, Declarations, Signal, Value, VcdError};
use std::io::Read;

/// The result of a comparison.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Everything matched; the one-line summary.
    Match(String),
    /// The first difference, as one line.
    Mismatch(String),
}

/// What `check` was asked beyond the two files.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CheckOptions {
    /// The DUT's top scope in a VCD, a dotted path (`tt_testbench.dut`); `None`: the
    /// shallowest scope declaring golden outputs ([`resolve`]).
    pub dut_scope: Option<String>,
    /// Where to write the mismatch window's VCD, if anywhere (its GTKWave save file goes
    /// beside it, extension `.gtkw`).
    pub window: Option<std::path::PathBuf>,
}

/// One golden output and the DUT signal compared with it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SignalMatch {
    /// The golden signal's dotted path (`tooltouch.outputs.count`).
    pub golden: String,
    /// The DUT signal's dotted path (`tt_testbench.dut.count`).
    pub dut: String,
    /// Declared widths, bits: golden, DUT.
    pub widths: (u32, u32),
}

/// One signal differing at the first mismatching clock.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Differing {
    /// The golden name.
    pub signal: String,
    /// Expected and DUT values as printed (`0x1f`, `x`, `x (no value yet)`).
    pub expected: String,
    /// The DUT's value.
    pub got: String,
}

/// The first mismatching clock of a VCD comparison.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FirstMismatch {
    /// The clock index `k`.
    pub cycle: u64,
    /// Its time `k·P`, ns.
    pub time_ns: u64,
    /// Every golden output differing at that clock, in golden declaration order.
    pub differing: Vec<Differing>,
}

/// A verdict with what stands behind it: the DUT scope and signal matched for each golden
/// output, and the first mismatching clock (VCD comparisons; empty for binary streams).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Report {
    /// The verdict line.
    pub verdict: Verdict,
    /// The DUT's top scope (VCD).
    pub dut_scope: Option<String>,
    /// Golden output → DUT signal (VCD).
    pub matches: Vec<SignalMatch>,
    /// The first mismatching clock of values (not of a trace's end).
    pub first: Option<FirstMismatch>,
    /// The mismatch report's further lines (every differing signal, the pins before it,
    /// the MCU read, the window files), printed after the verdict.
    pub details: Vec<String>,
}

/// Bad input to `check`, with the file and what is wrong.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);

impl From<VcdError> for BadInput {
    fn from(e: VcdError) -> Self {
        BadInput(e.to_string())
    }
}

impl From<binary::BinaryError> for BadInput {
    fn from(e: binary::BinaryError) -> Self {
        BadInput(e.to_string())
    }
}

/// For the `faults` output, the faults by name (` (expected pulses_lost, got none)`), so a
/// mismatch line says which conditions differ; empty for every other signal, and for a
/// value that is unknown or no fault word.
fn fault_names(signal: &str, expected: Option<u64>, got: Option<u64>) -> String {
    let name = |v: Option<u64>| {
        v.and_then(|v| u8::try_from(v).ok())
            .filter(|v| v & !tooltouch_model::fault::ALL == 0)
            .map(|v| tooltouch_model::Faults(v).to_string())
    };
    match (signal == "faults", name(expected), name(got)) {
        (true, Some(a), Some(b)) => format!(" (expected {a}, got {b})"),
        (true, Some(a), None) => format!(" (expected {a})"),
        _ => String::new(),
    }
}

fn hex(v: Option<&Value>) -> String {
    match v {
        Some(v) if !v.unknown => format!("0x{}", v.hex_digits()),
        Some(_) => "x".to_string(),
        None => "x (no value yet)".to_string(),
    }
}

/// One side of a VCD comparison: its name, declarations and change stream, and the
/// comments read after the declarations once the stream is exhausted.
pub struct VcdSide<'a> {
    /// The file name, for messages.
    pub name: &'a str,
    /// Its declarations.
    pub declarations: &'a Declarations,
    /// Its changes in time order.
    pub changes: &'a mut dyn Changes,
}

/// A differing output at the first mismatching clock: its slot, golden and DUT values.
type Difference = (usize, Option<Value>, Option<Value>);

/// A compared output: the golden signal.
struct Compared<'a> {
    golden: &'a Signal,
}

/// The period of a golden file's clock, femtoseconds, from its stamp.
fn golden_period_fs(d: &Declarations, name: &str) -> Result<(u64, u32, u64), BadInput> {
    let (hash, clock_hz) = d.golden_stamp().ok_or_else(|| {
        BadInput(format!(
            "{name}: no `$comment tooltouch measure_hash=… clock_hz=…` line: not a golden file"
        ))
    })?;
    if clock_hz == 0 || 1_000_000_000 % clock_hz != 0 {
        return Err(BadInput(format!(
            "{name}: clock_hz={clock_hz} does not divide 1e9"
        )));
    }
    Ok((hash, clock_hz, 1_000_000_000_000_000 / u64::from(clock_hz)))
}

/// Lookahead over one side's changes.
struct Cursor<'a, 'b> {
    side: &'b mut VcdSide<'a>,
    next: Option<(u64, usize, Value)>,
    done: bool,
}

impl Cursor<'_, '_> {
    fn advance(&mut self) -> Result<(), BadInput> {
        self.next = self.side.changes.next_change()?;
        self.done = self.next.is_none();
        Ok(())
    }
}

/// Reads every change of `cursor` at time `t`, storing the compared ones in `values` and
/// their slots in `touched` when `values` is given.
fn apply_at(
    cursor: &mut Cursor,
    t: u64,
    mut values: Option<&mut Vec<Option<Value>>>,
    touched: &mut Vec<usize>,
    slots: &[Vec<usize>],
) -> Result<(), BadInput> {
    while let Some((time, code, value)) = cursor.next.take() {
        if time != t {
            cursor.next = Some((time, code, value));
            break;
        }
        if let Some(values) = values.as_deref_mut() {
            for &slot in &slots[code] {
                values[slot] = Some(value.clone());
                touched.push(slot);
            }
        }
        cursor.advance()?;
    }
    Ok(())
}

/// Compares the `outputs` scope of a golden dump with a DUT dump (see the module
/// documentation). `late_comments` gives the golden file's comments after its
/// declarations once its stream is read (the closing comment).
pub fn compare_vcd_sides(
    e: &mut VcdSide,
    d: &mut VcdSide,
    late_comments: &dyn Fn() -> Vec<String>,
) -> Result<Verdict, BadInput> {
    compare_vcd_sides_with(e, d, late_comments, &CheckOptions::default()).map(|r| r.verdict)
}

/// [`compare_vcd_sides`] with options, returning the whole [`Report`] (its `details` left
/// empty: [`check_files`] adds them from the files).
pub fn compare_vcd_sides_with(
    e: &mut VcdSide,
    d: &mut VcdSide,
    late_comments: &dyn Fn() -> Vec<String>,
    options: &CheckOptions,
) -> Result<Report, BadInput> {
    let (en, dn) = (e.name.to_string(), d.name.to_string());
    let (hash, clock_hz, period_fs) = golden_period_fs(e.declarations, &en)?;
    let outputs = golden_outputs(e.declarations, &en)?;
    if let Some((dut_hash, dut_hz)) = d.declarations.golden_stamp() {
        if dut_hash != hash || dut_hz != clock_hz {
            return Err(BadInput(format!(
                "configuration mismatch: {en} has measure_hash={hash:016x} clock_hz={clock_hz}, {dn} has measure_hash={dut_hash:016x} clock_hz={dut_hz}"
            )));
        }
    }
    // Slots per code index, on each side.
    let mut e_slots: Vec<Vec<usize>> = vec![Vec::new(); e.declarations.codes().len()];
    let mut d_slots: Vec<Vec<usize>> = vec![Vec::new(); d.declarations.codes().len()];
    let names: Vec<&str> = outputs.iter().map(|c| c.golden.name.as_str()).collect();
    let resolution = resolve::resolve(&names, d.declarations, options.dut_scope.as_deref(), &dn)?;
    let dut_scope = resolution.scope_text();
    let mut matches = Vec::with_capacity(outputs.len());
    for (slot, (c, ds)) in outputs.iter().zip(&resolution.signals).enumerate() {
        matches.push(SignalMatch {
            golden: resolve::path_of(c.golden),
            dut: resolve::path_of(ds),
            widths: (c.golden.width, ds.width),
        });
        let ei = e.declarations.code_index(&c.golden.id);
        let di = d.declarations.code_index(&ds.id);
        if let (Some(ei), Some(di)) = (ei, di) {
            e_slots[ei].push(slot);
            d_slots[di].push(slot);
        }
    }
    // Only the compared signals' changes are needed (an FST source decodes only those).
    let wanted = |slots: &[Vec<usize>]| -> Vec<usize> {
        (0..slots.len()).filter(|&c| !slots[c].is_empty()).collect()
    };
    e.changes.select(&wanted(&e_slots));
    d.changes.select(&wanted(&d_slots));
    let n = outputs.len();
    let mut ec = Cursor {
        side: e,
        next: None,
        done: false,
    };
    let mut dc = Cursor {
        side: d,
        next: None,
        done: false,
    };
    let first = first_mismatch(&mut ec, &mut dc, (&e_slots, &d_slots), n, period_fs)?;
    let e_end = ec.side.changes.end_fs();
    let d_end = dc.side.changes.end_fs();
    let mut comments = ec.side.declarations.comments.clone();
    comments.extend(late_comments());
    let cycles = golden_end(&comments).ok_or_else(|| {
        BadInput(format!(
            "{en}: ends at line {} (time {} ns) without the closing `$comment tooltouch end cycles=… $end` of a golden file: cut short?",
            ec.side.changes.line(),
            e_end / 1_000_000
        ))
    })?;
    if cycles == 0 || e_end != (cycles - 1) * period_fs {
        return Err(BadInput(format!(
            "{en}: its closing comment says {cycles} cycles, but its last time is {} ns (cycle {})",
            e_end / 1_000_000,
            e_end / period_fs
        )));
    }
    let report = |verdict: Verdict, first: Option<FirstMismatch>| Report {
        verdict,
        dut_scope: Some(dut_scope.clone()),
        matches: matches.clone(),
        first,
        details: Vec::new(),
    };
    if let Some((k, all)) = first {
        let differing: Vec<Differing> = all
            .iter()
            .map(|(slot, a, b)| Differing {
                signal: outputs[*slot].golden.name.clone(),
                expected: hex(a.as_ref()),
                got: hex(b.as_ref()),
            })
            .collect();
        let time_ns = k * period_fs / 1_000_000;
        let (a, b) = (&all[0].1, &all[0].2);
        let line = format!(
            "cycle {k} (time {time_ns} ns): signal {} expected {} got {}{}",
            differing[0].signal,
            differing[0].expected,
            differing[0].got,
            fault_names(
                &differing[0].signal,
                a.as_ref().filter(|v| !v.unknown).and_then(Value::to_u64),
                b.as_ref().filter(|v| !v.unknown).and_then(Value::to_u64)
            )
        );
        return Ok(report(
            Verdict::Mismatch(line),
            Some(FirstMismatch {
                cycle: k,
                time_ns,
                differing,
            }),
        ));
    }
    let (e_last, d_last) = (cycles - 1, d_end / period_fs);
    if d_last != e_last {
        let (which, by) = if d_last < e_last {
            ("short", e_last - d_last)
        } else {
            ("long", d_last - e_last)
        };
        return Ok(report(Verdict::Mismatch(format!(
            "the DUT trace ends at cycle {d_last} (time {} ns), the golden trace at cycle {e_last} (time {} ns): {dn} is {by} cycles too {which}",
            d_end / 1_000_000,
            e_end / 1_000_000
        )), None));
    }
    Ok(report(
        Verdict::Match(format!(
            "OK: {cycles} cycles × {n} signals of {en} match {dn} in DUT scope `{dut_scope}`"
        )),
        None,
    ))
}

/// The golden file's compared outputs: its signals in an `outputs` scope (`en` names it).
fn golden_outputs<'a>(
    declarations: &'a Declarations,
    en: &str,
) -> Result<Vec<Compared<'a>>, BadInput> {
    let outputs: Vec<Compared> = declarations
        .signals
        .iter()
        .filter(|s| s.scope.last().is_some_and(|l| l == "outputs"))
        .map(|s| {
            if s.width == 0 {
                return Err(BadInput(format!(
                    "{en}: line {}: golden signal `{}` is 0 bits wide",
                    s.line, s.name
                )));
            }
            Ok(Compared { golden: s })
        })
        .collect::<Result<_, _>>()?;
    if outputs.is_empty() {
        return Err(BadInput(format!("{en}: no `outputs` scope")));
    }
    let has = |name: &str| outputs.iter().any(|c| c.golden.name == name);
    if has("register_now") && !(has("confirmed") && has("faults")) {
        return Err(BadInput(format!(
            "{en}: a golden file of an older tooltouch: its outputs lack `confirmed` and `faults` \
             (the measurement status, with stream format version 2). Regenerate it with the \
             command that made it (`tooltouch vectors` or `tooltouch measure`)"
        )));
    }
    Ok(outputs)
}

/// Reads both sides to their ends (`ec` golden, `dc` DUT; `slots`: each side's compared
/// slots per code index, `n` slots) and returns the first clock at which a compared output
/// differs, with every differing output there.
fn first_mismatch(
    ec: &mut Cursor,
    dc: &mut Cursor,
    (e_slots, d_slots): (&[Vec<usize>], &[Vec<usize>]),
    n: usize,
    period_fs: u64,
) -> Result<Option<(u64, Vec<Difference>)>, BadInput> {
    let half = period_fs / 2;
    let mut ev: Vec<Option<Value>> = vec![None; n];
    let mut dv: Vec<Option<Value>> = vec![None; n];
    let mut differs = vec![true; n];
    let mut differing = n;
    let mut first: Option<(u64, Vec<Difference>)> = None;
    let mut touched: Vec<usize> = Vec::with_capacity(2 * n);

    ec.advance()?;
    dc.advance()?;
    let mut now = 0u64;
    loop {
        let next_time = match (&ec.next, &dc.next) {
            (Some(a), Some(b)) => Some(a.0.min(b.0)),
            (Some(a), None) => Some(a.0),
            (None, Some(b)) => Some(b.0),
            (None, None) => None,
        };
        // The values are constant over [now, next_time): look at its first sample.
        if first.is_none() && differing > 0 {
            let mut limit = u64::MAX;
            if ec.done {
                limit = limit.min(ec.side.changes.end_fs() / period_fs);
            }
            if dc.done {
                limit = limit.min(dc.side.changes.end_fs() / period_fs);
            }
            let k = now.saturating_sub(half).div_ceil(period_fs);
            let inside = next_time.is_none_or(|t| k * period_fs + half < t);
            if inside && k <= limit {
                let all: Vec<_> = (0..n)
                    .filter(|&slot| differs[slot])
                    .map(|slot| (slot, ev[slot].clone(), dv[slot].clone()))
                    .collect();
                if !all.is_empty() {
                    first = Some((k, all));
                }
            }
        }
        let Some(t) = next_time else { break };
        // Apply every change at `t` of both sides (after a mismatch: only read on, so a
        // malformed or cut file is still reported).
        let record = first.is_none();
        touched.clear();
        apply_at(ec, t, record.then_some(&mut ev), &mut touched, e_slots)?;
        apply_at(dc, t, record.then_some(&mut dv), &mut touched, d_slots)?;
        if first.is_none() {
            for &slot in &touched {
                // Exact, at any width: a DUT value with a 1 above the golden width differs
                // (the reader refuses a value wider than its own signal).
                let same = matches!((&ev[slot], &dv[slot]), (Some(a), Some(b)) if !a.unknown && !b.unknown && a == b);
                if differs[slot] == same {
                    differs[slot] = !same;
                    if same {
                        differing -= 1;
                    } else {
                        differing += 1;
                    }
                }
            }
        }
        now = t;
    }
    Ok(first)
}

/// Compares two parsed dumps (see [`compare_vcd_sides`]).
pub fn compare_vcd(
    e: &super::vcd::Dump,
    en: &str,
    d: &super::vcd::Dump,
    dn: &str,
) -> Result<Verdict, BadInput> {
    let (ed, dd) = (e.declarations(), d.declarations());
    let (mut et, mut dt) = (e.timeline(), d.timeline());
    compare_vcd_sides(
        &mut VcdSide {
            name: en,
            declarations: &ed,
            changes: &mut et,
        },
        &mut VcdSide {
            name: dn,
            declarations: &dd,
            changes: &mut dt,
        },
        &Vec::new,
    )
}

fn last_time(last: Option<u64>) -> String {
    last.map_or_else(|| "none".to_string(), |t| format!("time {t}"))
}

/// One side of a binary comparison: its reader, what was counted, the error that stopped it.
struct OutputSide<R> {
    reader: Option<OutputReader<R>>,
    header: Option<tooltouch_model::wire::Header>,
    status: Option<binary::FirmwareStatus>,
    error: Option<binary::BinaryError>,
    measure: usize,
    force: usize,
    last_measure: Option<u64>,
    last_force: Option<u64>,
}

impl<R: Read> OutputSide<R> {
    fn open(src: R, file: &str) -> Self {
        let (reader, error) = match OutputReader::new(src, file) {
            Ok(r) => (Some(r), None),
            Err(e) => (None, Some(e)),
        };
        OutputSide {
            header: reader.as_ref().map(|r| r.header()),
            status: None,
            reader,
            error,
            measure: 0,
            force: 0,
            last_measure: None,
            last_force: None,
        }
    }

    /// The next record of one path (`force` or measurement), counting every record read;
    /// `None` at the end or after an error (kept).
    fn next_of(&mut self, force: bool) -> Option<OutputRecord> {
        loop {
            let r = self.reader.as_mut()?.next_output();
            match r {
                Ok(None) => {
                    self.status = self.reader.take().and_then(|r| r.status());
                    return None;
                }
                Err(e) => {
                    self.reader = None;
                    self.error = Some(e);
                    return None;
                }
                Ok(Some(r @ OutputRecord::Measure(t, _))) => {
                    self.measure += 1;
                    self.last_measure = Some(t);
                    if !force {
                        return Some(r);
                    }
                }
                Ok(Some(r @ OutputRecord::Force(t, _))) => {
                    self.force += 1;
                    self.last_force = Some(t);
                    if force {
                        return Some(r);
                    }
                }
            }
        }
    }
}

/// The first difference of one path's records compared in step (`force`: the force
/// records, else the measurement ones), as `(time, line)`; both sides are read to their
/// end.
fn first_difference<E: Read, D: Read>(
    e: &mut OutputSide<E>,
    d: &mut OutputSide<D>,
    force: bool,
) -> Option<(u64, String)> {
    let mut first = None;
    let mut i = 0usize;
    loop {
        let (a, b) = (e.next_of(force), d.next_of(force));
        let (Some(a), Some(b)) = (a, b) else {
            if a.is_none() && b.is_none() {
                return first;
            }
            continue;
        };
        if first.is_none() {
            first = match (a, b) {
                (OutputRecord::Measure(ta, _), OutputRecord::Measure(tb, _)) if ta != tb => Some((
                    ta.min(tb),
                    format!("record {i}: time expected {ta} got {tb}"),
                )),
                (OutputRecord::Measure(t, a), OutputRecord::Measure(_, b)) => {
                    binary::output_fields(&a)
                        .into_iter()
                        .zip(binary::output_fields(&b))
                        .find(|(x, y)| x.1 != y.1)
                        .map(|((name, x), (_, y))| {
                            (
                                t,
                                format!(
                                    "record {i} (time {t}): field {name} expected 0x{x:x} got 0x{y:x}{}",
                                    fault_names(name, Some(x), Some(y))
                                ),
                            )
                        })
                }
                (OutputRecord::Force(ta, _), OutputRecord::Force(tb, _)) if ta != tb => Some((
                    ta.min(tb),
                    format!("force record {i}: time expected {ta} got {tb}"),
                )),
                (OutputRecord::Force(t, a), OutputRecord::Force(_, b)) => {
                    crate::signals::force_signals(&a)
                        .into_iter()
                        .zip(crate::signals::force_signals(&b))
                        .find(|(x, y)| x.1 != y.1)
                        .map(|((name, x), (_, y))| {
                            (
                                t,
                                format!(
                                    "force record {i} (time {t}): field {name} expected {x} got {y}"
                                ),
                            )
                        })
                }
                _ => None,
            };
        }
        i += 1;
    }
}

/// Compares two Outputs streams of any device record by record (see the module
/// documentation).
pub fn compare_binary(e: &[u8], en: &str, d: &[u8], dn: &str) -> Result<Verdict, BadInput> {
    compare_output_sources(&|| Ok(e), en, &|| Ok(d), dn)
}

/// Compares two Outputs streams read record by record, memory flat in their length:
/// `open_e` and `open_d` give a fresh reader of each (a `BufReader` over the file). The
/// measurement records are compared in one pass over both files, which also reads every
/// record to the end (a malformed record or bytes after END anywhere is bad input, the
/// golden file's first); the force records, when there are any, in a second pass, so that
/// neither side's interleaving of the two paths has to be held. The verdict is
/// the one the whole decoded streams would give.
pub fn compare_output_sources<E: Read, D: Read>(
    open_e: &dyn Fn() -> Result<E, BadInput>,
    en: &str,
    open_d: &dyn Fn() -> Result<D, BadInput>,
    dn: &str,
) -> Result<Verdict, BadInput> {
    let (e_src, d_src) = (open_e()?, open_d()?);
    let mut es = OutputSide::open(e_src, en);
    if let Some(e) = es.error.take() {
        return Err(e.into());
    }
    let mut ds = OutputSide::open(d_src, dn);
    let measure_first = first_difference(&mut es, &mut ds, false);
    if let Some(e) = es.error.take().or_else(|| ds.error.take()) {
        return Err(e.into());
    }
    let (Some(eh), Some(dh)) = (es.header, ds.header) else {
        return Err(BadInput(format!(
            "{en} and {dn}: a stream without a header"
        )));
    };
    for (what, want, got) in [
        ("configuration hash", eh.measure_hash, dh.measure_hash),
        ("force configuration hash", eh.force_hash, dh.force_hash),
    ] {
        if want != got {
            return Err(BadInput(format!(
                "{dn}: {what} {got:016x} does not match the expected {want:016x} of {en} (made with another configuration)"
            )));
        }
    }
    if eh.tick_hz != dh.tick_hz {
        return Err(BadInput(format!(
            "{dn}: tick rate {} Hz, {en} has {} Hz",
            dh.tick_hz, eh.tick_hz
        )));
    }
    if let Some(s) = es.status.filter(|s| s.lost > 0 || s.overflowed > 0) {
        return Err(BadInput(format!(
            "{en}: a firmware trace that lost {} and overflowed {} events cannot be the golden trace",
            s.lost, s.overflowed
        )));
    }
    if let Some(s) = ds.status.filter(|s| s.lost > 0 || s.overflowed > 0) {
        return Ok(Verdict::Mismatch(format!(
            "{dn}: the firmware lost {} events and overflowed {} (its status record, after {} events)",
            s.lost, s.overflowed, s.events
        )));
    }
    // The first difference of each path; the earlier one is reported (the measurement
    // one at equal times).
    let force_first = if es.force > 0 || ds.force > 0 {
        let (e_src, d_src) = (open_e()?, open_d()?);
        let mut e2 = OutputSide::open(e_src, en);
        let mut d2 = OutputSide::open(d_src, dn);
        let first = first_difference(&mut e2, &mut d2, true);
        if let Some(e) = e2.error.or(d2.error) {
            return Err(e.into());
        }
        first
    } else {
        None
    };
    let first = match (measure_first, force_first) {
        (Some(m), Some(f)) if f.0 < m.0 => Some(f),
        (Some(m), _) => Some(m),
        (None, f) => f,
    };
    if let Some((_, line)) = first {
        return Ok(Verdict::Mismatch(line));
    }
    for (what, e_len, d_len, e_last, d_last) in [
        (
            "measurement-outputs",
            es.measure,
            ds.measure,
            last_time(es.last_measure),
            last_time(ds.last_measure),
        ),
        (
            "force-outputs",
            es.force,
            ds.force,
            last_time(es.last_force),
            last_time(ds.last_force),
        ),
    ] {
        if e_len != d_len {
            let i = e_len.min(d_len);
            return Ok(Verdict::Mismatch(format!(
                "record {i}: {dn} ends after {d_len} {what} records (last at {d_last}), {en} after {e_len} (last at {e_last})"
            )));
        }
    }
    let mut summary = format!(
        "OK: {} records × {} fields",
        es.measure,
        tooltouch_model::MeasureOutputs::FIELD_COUNT
    );
    if es.force > 0 {
        let fields = crate::signals::force_signals(&Default::default()).len();
        summary = if es.measure == 0 {
            format!("OK: {} force records × {fields} fields", es.force)
        } else {
            format!("{summary} and {} force records × {fields} fields", es.force)
        };
    }
    if let Some(s) = ds.status {
        summary.push_str(&format!(
            " of {en} match {dn} (firmware: {} events, none lost or overflowed)",
            s.events
        ));
    } else {
        summary.push_str(&format!(" of {en} match {dn}"));
    }
    Ok(Verdict::Match(summary))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vcd::Dump;

    /// A golden dump of one 100-bit output `wide` over 3 clocks at 1 MHz, with `values`
    /// (binary digits) at clocks 0 and 2.
    fn golden_wide(values: [&str; 2]) -> String {
        format!(
            "$comment tooltouch measure_hash=00000000000000aa clock_hz=1000000 $end\n\
             $timescale 1ns $end\n$scope module tooltouch $end\n$scope module outputs $end\n\
             $var wire 100 ! wide [99:0] $end\n$upscope $end\n$upscope $end\n\
             $enddefinitions $end\n#0\nb{} !\n#2000\nb{} !\n\
             $comment tooltouch end cycles=3 $end\n",
            values[0], values[1]
        )
    }

    fn compare(golden: &str, dut: &str) -> Verdict {
        let e = Dump::parse(golden, "e.vcd").unwrap();
        let d = Dump::parse(dut, "d.vcd").unwrap();
        compare_vcd(&e, "e.vcd", &d, "d.vcd").unwrap()
    }

    #[test]
    fn values_wider_than_64_bits_are_read_and_compared_whole() {
        let top = format!("1{}1", "0".repeat(98)); // bits 99 and 0
        let golden = golden_wide(["101", &top]);
        // The same values, the first written with leading zeros: a match.
        let padded = golden_wide([&format!("{}101", "0".repeat(97)), &top]);
        assert_eq!(
            compare(&golden, &padded),
            Verdict::Match(
                "OK: 3 cycles × 1 signals of e.vcd match d.vcd in DUT scope `tooltouch.outputs`"
                    .into()
            )
        );
        // Bit 99 missing at clock 2 (the low 64 bits agree): a mismatch naming both whole
        // values.
        let low_only = golden_wide(["101", "1"]);
        let Verdict::Mismatch(m) = compare(&golden, &low_only) else {
            panic!("bit 99 was not compared");
        };
        assert_eq!(
            m,
            format!(
                "cycle 2 (time 2000 ns): signal wide expected 0x8{}1 got 0x1",
                "0".repeat(23)
            )
        );
    }

    /// A golden dump of the outputs `register_now`, `confirmed` (both 1 bit) and `faults`
    /// (7 bits) over 3 clocks at 1 MHz, `faults` = `faults` at clock 2; `old`: without
    /// `confirmed` and `faults`.
    fn golden_status(faults: u8, old: bool) -> String {
        let (vars, values) = if old {
            (String::new(), String::new())
        } else {
            (
                "$var wire 1 # confirmed $end\n$var wire 7 $ faults [6:0] $end\n".to_string(),
                "0#\nb0 $\n".to_string(),
            )
        };
        let late = if old {
            String::new()
        } else {
            format!("b{faults:b} $\n")
        };
        format!(
            "$comment tooltouch measure_hash=00000000000000aa clock_hz=1000000 $end\n\
             $timescale 1ns $end\n$scope module tooltouch $end\n$scope module outputs $end\n\
             $var wire 1 ! register_now $end\n{vars}$upscope $end\n$upscope $end\n\
             $enddefinitions $end\n#0\n0!\n{values}#2000\n1!\n{late}\
             $comment tooltouch end cycles=3 $end\n"
        )
    }

    #[test]
    fn a_faults_mismatch_names_the_faults_and_an_older_golden_file_is_refused() {
        use tooltouch_model::fault;
        let golden = golden_status(fault::PULSES_LOST | fault::NO_DECISION, false);
        let Verdict::Mismatch(m) = compare(&golden, &golden_status(0, false)) else {
            panic!("the faults were not compared");
        };
        assert_eq!(
            m,
            "cycle 2 (time 2000 ns): signal faults expected 0x12 got 0x0 (expected pulses_lost+no_decision, got none)"
        );
        let e = Dump::parse(&golden_status(0, true), "old.vcd").unwrap();
        let d = Dump::parse(&golden, "d.vcd").unwrap();
        let err = compare_vcd(&e, "old.vcd", &d, "d.vcd")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("old.vcd: a golden file of an older tooltouch: its outputs lack `confirmed` and `faults`")
                && err.contains("Regenerate it"),
            "{err}"
        );
        assert_eq!(fault_names("count", Some(1), Some(2)), "");
        assert_eq!(fault_names("faults", Some(0x80), Some(0)), "");
    }
}
