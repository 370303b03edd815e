//! FST dumps (Verilator `--trace-fst`, Icarus `vvp -fst`, GTKWave's format) read as
//! [`Changes`] for `tooltouch check`, like a VCD: the same [`Declarations`] (scopes,
//! names, widths, one dense code index per signal handle, aliases sharing it), and the
//! value changes in time order.
//!
//! The `fst-reader` crate decodes an FST block by block and hands every change to a
//! callback; [`FstChanges`] runs it on a reader thread that sends the changes in batches
//! of [`BATCH`] over a channel holding at most [`BATCHES_IN_FLIGHT`] of them, so memory
//! is one block of the file plus a few batches, whatever its length. Only the signals
//! [`Changes::select`] names are decoded (the compared outputs, not the whole dumped
//! hierarchy), which is most of the speed on a testbench dump.
//!
//! Not supported, as bad input naming the file: an FST whose whole body is compressed in
//! a gzip wrapper (the crate would inflate it into memory; unwrap it or dump without the
//! wrapper), a time unit finer than 1 fs. Real and string signals are declared but their
//! changes are skipped, as the VCD reader skips them. A value digit other than 0 and 1
//! (x, z, and the 9-state u w l h -) is unknown, like x in a VCD.

use crate::vcd::{Changes, Declarations, Signal, Value, VcdError};
use bitvec::prelude::*;
use fst_reader::{
    FstFilter, FstHierarchyEntry, FstReader, FstSignalHandle, FstSignalValue, ReadSignalsError,
};
use std::io::{BufReader, Read, Seek};
use std::path::Path;
use std::sync::mpsc::{sync_channel, Receiver};
use std::thread::JoinHandle;

/// Changes per batch sent by the reader thread.
pub const BATCH: usize = 4096;
/// Batches the channel holds before the reader thread waits.
pub const BATCHES_IN_FLIGHT: usize = 4;

/// The block type byte of an FST whose body is one gzip stream (`FST_BL_ZWRAPPER`).
const GZIP_WRAPPER: u8 = 254;

type File = BufReader<std::fs::File>;
/// One change: time (fs), dense code index, value.
type Change = (u64, usize, Value);
type Batch = Result<Vec<Change>, String>;

/// Whether the file behind `r` is an FST (its blocks, from the start; `r` is rewound).
pub fn is_fst<R: Read + Seek>(r: &mut R) -> bool {
    fst_reader::is_fst_file(r)
}

/// An FST file's changes in time order (see the module documentation); the reader thread
/// starts at the first [`Changes::next_change`].
pub struct FstChanges {
    file: String,
    reader: Option<FstReader<File>>,
    /// Dense code index → signal handle index.
    handles: Vec<usize>,
    /// Signal handle index → dense code index.
    code_of_handle: Vec<Option<usize>>,
    /// Code indexes to decode (`None`: all).
    selected: Option<Vec<usize>>,
    timescale_fs: u64,
    end_fs: u64,
    batches: Option<Receiver<Batch>>,
    thread: Option<JoinHandle<()>>,
    batch: std::vec::IntoIter<Change>,
    time_fs: u64,
}

fn error(file: &str, message: String) -> VcdError {
    VcdError {
        file: file.to_string(),
        line: 0,
        message,
    }
}

/// Femtoseconds per time unit of `10^exponent` s.
fn unit_fs(exponent: i8, file: &str) -> Result<u64, VcdError> {
    let power = i32::from(exponent) + 15;
    u32::try_from(power)
        .ok()
        .and_then(|p| 10u64.checked_pow(p))
        .ok_or_else(|| {
            error(
                file,
                format!("FST time unit 1e{exponent} s: finer than 1 fs or too coarse"),
            )
        })
}

/// Opens the FST at `path` (named `file` in errors): its declarations, and its changes.
pub fn open(path: &Path, file: &str) -> Result<(Declarations, FstChanges), VcdError> {
    let mut input = BufReader::with_capacity(
        1 << 20,
        std::fs::File::open(path).map_err(|e| error(file, e.to_string()))?,
    );
    let mut first = [0u8; 1];
    input
        .read_exact(&mut first)
        .and_then(|()| input.rewind())
        .map_err(|e| error(file, e.to_string()))?;
    if first[0] == GZIP_WRAPPER {
        return Err(error(
            file,
            "an FST whose whole body is gzip-wrapped cannot be read as a stream: dump it without \
             the wrapper (Verilator and Icarus do by default) or convert it to VCD (fst2vcd)"
                .into(),
        ));
    }
    let mut reader = guarded(|| FstReader::open(input))
        .and_then(|r| r.map_err(|e| e.to_string()))
        .map_err(|e| error(file, format!("not a readable FST: {e}")))?;
    let header = reader.get_header();
    let timescale_fs = unit_fs(header.timescale_exponent, file)?;
    let mut declarations = Declarations::default();
    declarations.timescale_fs = timescale_fs;
    // A golden FST's stamp and end ([`write_golden_fst`]) are its version and date strings.
    for text in [&header.version, &header.date] {
        if text.starts_with("tooltouch ") {
            declarations.comments.push(text.trim().to_string());
        }
    }
    let mut scope: Vec<String> = Vec::new();
    let mut handles = Vec::new();
    let mut code_of_handle: Vec<Option<usize>> = Vec::new();
    let read = guarded(|| {
        reader.read_hierarchy(|entry| match entry {
            FstHierarchyEntry::Scope { name, .. } => scope.push(name),
            FstHierarchyEntry::UpScope => {
                scope.pop();
            }
            FstHierarchyEntry::Var {
                name,
                length,
                handle,
                ..
            } => {
                let index = handle.get_index();
                // The handle as a VCD identifier code: aliases share it, so share a code
                // index, as one net dumped in several scopes does in a VCD.
                let id = vcd::IdCode::from(index as u64).to_string();
                let leaf = name.split('[').next().unwrap_or("").trim().to_string();
                declarations.add(Signal {
                    scope: scope.clone(),
                    name: leaf,
                    width: length,
                    id: id.clone(),
                    line: 0,
                });
                if let Some(code) = declarations.code_index(&id) {
                    if code_of_handle.len() <= index {
                        code_of_handle.resize(index + 1, None);
                    }
                    if code_of_handle[index].is_none() {
                        code_of_handle[index] = Some(code);
                        if handles.len() == code {
                            handles.push(index);
                        }
                    }
                }
            }
            FstHierarchyEntry::Comment { string } => declarations
                .comments
                .push(string.split_whitespace().collect::<Vec<_>>().join(" ")),
            _ => {}
        })
    })
    .and_then(|r| r.map_err(|e| e.to_string()));
    read.map_err(|e| error(file, format!("cannot read its hierarchy: {e}")))?;
    let end_fs = header
        .end_time
        .checked_mul(timescale_fs)
        .ok_or_else(|| error(file, format!("end time {} overflows", header.end_time)))?;
    Ok((
        declarations,
        FstChanges {
            file: file.to_string(),
            reader: Some(reader),
            handles,
            code_of_handle,
            selected: None,
            timescale_fs,
            end_fs,
            batches: None,
            thread: None,
            batch: Vec::new().into_iter(),
            time_fs: 0,
        },
    ))
}

/// Runs `f`, turning a panic of the crate on a malformed file into an error.
fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|p| {
        p.downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "malformed file".into())
    })
}

/// A value from the crate's digits (`0`, `1`, else unknown), most significant first.
fn value_of(digits: &[u8]) -> Value {
    let n = digits.len();
    let mut words = vec![0u64; n.div_ceil(64)];
    let mut unknown = false;
    for (i, &d) in digits.iter().rev().enumerate() {
        match d {
            b'1' => words[i / 64] |= 1 << (i % 64),
            b'0' => {}
            _ => unknown = true,
        }
    }
    let mut bits = BitVec::<u64, Lsb0>::from_vec(words);
    bits.truncate(n);
    Value::from_bits(bits, unknown)
}

/// Why the reader thread's callback stopped.
enum Stop {
    /// The consumer has gone.
    Gone,
    /// A time beyond 64 bits of femtoseconds.
    Overflow(u64),
}

impl FstChanges {
    fn start(&mut self) {
        let Some(mut reader) = self.reader.take() else {
            return;
        };
        let filter = match &self.selected {
            Some(codes) => FstFilter::filter_signals(
                codes
                    .iter()
                    .filter_map(|&c| self.handles.get(c))
                    .map(|&h| FstSignalHandle::from_index(h))
                    .collect(),
            ),
            None => FstFilter::all(),
        };
        let (tx, rx) = sync_channel::<Batch>(BATCHES_IN_FLIGHT);
        let code_of_handle = std::mem::take(&mut self.code_of_handle);
        let timescale_fs = self.timescale_fs;
        let thread = std::thread::spawn(move || {
            let mut batch: Vec<Change> = Vec::with_capacity(BATCH);
            let result = guarded(|| {
                reader.read_signals(&filter, |time, handle, value| {
                    let FstSignalValue::String(digits) = value else {
                        return Ok(());
                    };
                    let Some(Some(code)) = code_of_handle.get(handle.get_index()).copied() else {
                        return Ok(());
                    };
                    if digits.is_empty() {
                        return Ok(());
                    }
                    let fs = time.checked_mul(timescale_fs).ok_or(Stop::Overflow(time))?;
                    batch.push((fs, code, value_of(digits)));
                    if batch.len() == BATCH {
                        let full = std::mem::replace(&mut batch, Vec::with_capacity(BATCH));
                        tx.send(Ok(full)).map_err(|_| Stop::Gone)?;
                    }
                    Ok(())
                })
            });
            let last = match result {
                Ok(Ok(())) => Ok(batch),
                Ok(Err(ReadSignalsError::CallbackError(Stop::Gone))) => return,
                Ok(Err(ReadSignalsError::CallbackError(Stop::Overflow(t)))) => {
                    Err(format!("time {t} overflows 64 bits of femtoseconds"))
                }
                Ok(Err(ReadSignalsError::ReadError(e))) => {
                    Err(format!("cannot read its value changes (cut short?): {e}"))
                }
                Err(panic) => Err(format!("cannot read its value changes: {panic}")),
            };
            if last.as_ref().is_ok_and(Vec::is_empty) {
                return;
            }
            let _ = tx.send(last);
        });
        self.batches = Some(rx);
        self.thread = Some(thread);
    }
}

impl Changes for FstChanges {
    fn next_change(&mut self) -> Result<Option<Change>, VcdError> {
        loop {
            if let Some(c) = self.batch.next() {
                if c.0 < self.time_fs {
                    return Err(error(
                        &self.file,
                        format!("time goes backwards: {} fs after {} fs", c.0, self.time_fs),
                    ));
                }
                self.time_fs = c.0;
                return Ok(Some(c));
            }
            self.start();
            let Some(rx) = &self.batches else {
                return Ok(None);
            };
            match rx.recv() {
                Ok(Ok(batch)) => self.batch = batch.into_iter(),
                Ok(Err(message)) => {
                    self.batches = None;
                    return Err(error(&self.file, message));
                }
                // The reader thread is done.
                Err(_) => {
                    self.batches = None;
                    if let Some(t) = self.thread.take() {
                        let _ = t.join();
                    }
                    return Ok(None);
                }
            }
        }
    }

    fn end_fs(&self) -> u64 {
        self.end_fs
    }

    fn select(&mut self, codes: &[usize]) {
        if self.reader.is_some() {
            self.selected = Some(codes.to_vec());
        }
    }
}

impl Drop for FstChanges {
    fn drop(&mut self) {
        // The reader thread stops at its next send once the channel is gone; what is left
        // to it is the rest of the file's blocks of the selected signals.
        self.batches = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The FST header's version string of a golden FST: the stamp a golden VCD carries in its
/// `$comment` (`tooltouch measure_hash=<hex> clock_hz=<n>`), read back as a comment (the
/// writer crate has no hierarchy comments).
fn golden_stamp_text(config: &tooltouch_model::MeasureConfig, clock_hz: u32) -> String {
    format!(
        "tooltouch measure_hash={:016x} clock_hz={clock_hz}",
        config.hash()
    )
}

/// Bytes of buffered value changes after which the golden FST writer writes a block.
const GOLDEN_BLOCK_BYTES: usize = 16 << 20;

/// Writes the golden trace of `stimulus` clocks `[0, end)` (all of it when `end` is
/// `None`) as an FST to `w`: the signals, scopes and times of the golden VCD
/// ([`crate::vcd::write_golden`]), time unit 1 ns, in blocks of about
/// [`GOLDEN_BLOCK_BYTES`] (memory flat in the length). The VCD's two comments go into the
/// header: its version string is the stamp `tooltouch measure_hash=… clock_hz=…`, its date
/// string the closing `tooltouch end cycles=<n>`; the reader ([`open`]) gives both back as
/// comments, and the last clock is always in the time table. Returns the clocks covered.
pub fn write_golden_fst<W: std::io::Write + Seek>(
    w: W,
    stimulus: &tooltouch_plant::stimulus::Stimulus,
    config: &tooltouch_model::MeasureConfig,
    end: Option<u64>,
) -> std::io::Result<u64> {
    write_golden_blocks(w, stimulus, config, end, GOLDEN_BLOCK_BYTES)
}

/// [`write_golden_fst`] writing a block each `block_bytes` of buffered changes.
fn write_golden_blocks<W: std::io::Write + Seek>(
    w: W,
    stimulus: &tooltouch_plant::stimulus::Stimulus,
    config: &tooltouch_model::MeasureConfig,
    end: Option<u64>,
    block_bytes: usize,
) -> std::io::Result<u64> {
    use fst_writer::{
        FstFileType, FstInfo, FstScopeType, FstSignalType, FstVarDirection, FstVarType,
    };
    use tooltouch_model::measure::frontend::pin;
    let io = |e: fst_writer::FstWriteError| std::io::Error::other(e.to_string());
    let p = crate::vcd::period_ns(stimulus.clock_hz);
    let total = stimulus.total_cycles();
    let cycles = end.unwrap_or(total).min(total);
    let info = FstInfo {
        start_time: 0,
        timescale_exponent: -9,
        version: golden_stamp_text(config, stimulus.clock_hz),
        date: format!("{} cycles={cycles}", crate::vcd::END_COMMENT),
        file_type: FstFileType::Verilog,
    };
    let mut header = fst_writer::FstHeaderWriter::new(w, &info).map_err(io)?;
    let outputs = crate::vcd::output_signals(config);
    let mut ids = Vec::new();
    let mut widths = Vec::new();
    header
        .scope("tooltouch", "", FstScopeType::Module)
        .map_err(io)?;
    header
        .scope("inputs", "", FstScopeType::Module)
        .map_err(io)?;
    for name in pin::NAMES {
        ids.push(
            header
                .var(
                    name,
                    FstSignalType::bit_vec(1),
                    FstVarType::Wire,
                    FstVarDirection::Implicit,
                    None,
                )
                .map_err(io)?,
        );
        widths.push(1u32);
    }
    header.up_scope().map_err(io)?;
    header
        .scope("outputs", "", FstScopeType::Module)
        .map_err(io)?;
    for (name, width) in &outputs {
        ids.push(
            header
                .var(
                    name,
                    FstSignalType::bit_vec(*width),
                    FstVarType::Wire,
                    FstVarDirection::Implicit,
                    None,
                )
                .map_err(io)?,
        );
        widths.push(*width);
    }
    header.up_scope().map_err(io)?;
    header.up_scope().map_err(io)?;
    let mut body = header.finish().map_err(io)?;
    let mut now = vec![0u64; ids.len()];
    let mut digits: Vec<u8> = Vec::with_capacity(64);
    let digits_of = |value: u64, width: u32, digits: &mut Vec<u8>| {
        digits.clear();
        digits.extend((0..width).rev().map(|b| {
            if b < 64 && (value >> b) & 1 == 1 {
                b'1'
            } else {
                b'0'
            }
        }));
    };
    let (covered, last) = crate::vcd::golden_changes(stimulus, config, end, &mut |k, changes| {
        if body.size() > block_bytes {
            body.flush().map_err(io)?;
        }
        body.time_change(k * p).map_err(io)?;
        for &(i, value) in changes {
            now[i] = value;
            digits_of(value, widths[i], &mut digits);
            body.signal_change(ids[i], &digits).map_err(io)?;
        }
        Ok(())
    })?;
    if covered > 0 && last != Some(covered - 1) {
        // The last clock in the time table: one change that repeats a value.
        body.time_change((covered - 1) * p).map_err(io)?;
        body.set_deduplicate(false);
        digits_of(now[0], widths[0], &mut digits);
        body.signal_change(ids[0], &digits).map_err(io)?;
    }
    body.finish().map_err(io)?;
    Ok(covered)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{check_files, CheckOptions, Verdict};
    use rand::SeedableRng;
    use tooltouch_model::MeasureConfig;

    fn stimulus(seed: u64, cycles: u64) -> tooltouch_plant::stimulus::Stimulus {
        let config = MeasureConfig::default();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        tooltouch_plant::random::random_stimulus(&mut rng, &config, 50_000_000, cycles)
    }

    fn golden_vcd(path: &Path, s: &tooltouch_plant::stimulus::Stimulus) {
        let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
        crate::vcd::write_golden(&mut f, s, &MeasureConfig::default(), None).unwrap();
    }

    fn golden_fst(path: &Path, s: &tooltouch_plant::stimulus::Stimulus, block_bytes: usize) {
        let f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
        write_golden_blocks(f, s, &MeasureConfig::default(), None, block_bytes).unwrap();
    }

    #[test]
    fn a_golden_fst_in_many_blocks_checks_like_its_vcd_both_ways() {
        let dir = tempfile::tempdir().unwrap();
        let s = stimulus(7, 30_000);
        let (vcd, fst) = (dir.path().join("g.vcd"), dir.path().join("g.fst"));
        golden_vcd(&vcd, &s);
        golden_fst(&fst, &s, 4096);
        let (d, mut c) = open(&fst, "g.fst").unwrap();
        assert!(
            crate::vcd::golden_end(&d.comments) == Some(s.total_cycles())
                && d.golden_stamp().map(|x| x.1) == Some(50_000_000),
            "{:?}",
            d.comments
        );
        assert_eq!(d.signals.len(), 23);
        assert_eq!(value_of(b"0101"), Value::known(5));
        let wide = value_of(format!("1{}1", "0".repeat(70)).as_bytes());
        assert!(wide.bit(71) && wide.bit(0) && wide.bits.count_ones() == 2 && !wide.unknown);
        assert!(value_of(b"1x0").unknown && value_of(b"z").unknown);
        let mut n = 0;
        while c.next_change().unwrap().is_some() {
            n += 1;
        }
        assert!(n > 1000, "{n} changes");
        assert_eq!(c.end_fs(), (s.total_cycles() - 1) * 20_000_000);
        for (e, dut) in [(&vcd, &fst), (&fst, &vcd), (&fst, &fst)] {
            let r = check_files(e, dut, &CheckOptions::default()).unwrap();
            let Verdict::Match(line) = &r.verdict else {
                panic!("{} against {}: {:?}", e.display(), dut.display(), r.verdict);
            };
            let whole = format!("{} cycles × 17 signals", s.total_cycles());
            assert!(line.contains(&whole), "{line}");
        }
    }

    #[test]
    fn an_fst_of_another_run_mismatches_with_the_vcd_report() {
        let dir = tempfile::tempdir().unwrap();
        let (vcd, fst) = (dir.path().join("g.vcd"), dir.path().join("other.fst"));
        golden_vcd(&vcd, &stimulus(1, 20_000));
        golden_fst(&fst, &stimulus(2, 20_000), GOLDEN_BLOCK_BYTES);
        let window = dir.path().join("w.vcd");
        let options = CheckOptions {
            window: Some(window.clone()),
            ..Default::default()
        };
        let r = check_files(&vcd, &fst, &options).unwrap();
        assert!(matches!(r.verdict, Verdict::Mismatch(_)), "{:?}", r.verdict);
        let first = r.first.expect("a first mismatching clock");
        assert!(!first.differing.is_empty());
        assert!(
            r.details.iter().any(|l| l.starts_with("window: ")),
            "{:?}",
            r.details
        );
        assert!(window.is_file());
    }

    #[test]
    fn a_cut_or_foreign_file_is_bad_input_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let (vcd, fst) = (dir.path().join("g.vcd"), dir.path().join("g.fst"));
        let s = stimulus(3, 5_000);
        golden_vcd(&vcd, &s);
        golden_fst(&fst, &s, GOLDEN_BLOCK_BYTES);
        let bytes = std::fs::read(&fst).unwrap();
        for cut_at in [bytes.len() / 2, bytes.len() - 3, 40] {
            let cut = dir.path().join("cut.fst");
            std::fs::write(&cut, &bytes[..cut_at]).unwrap();
            let e = check_files(&vcd, &cut, &CheckOptions::default())
                .err()
                .unwrap_or_else(|| panic!("a file cut at byte {cut_at} was read"));
            assert!(e.0.contains("cut.fst"), "{e}");
        }
        let other = dir.path().join("other.bin");
        std::fs::write(&other, [7u8, 1, 2, 3]).unwrap();
        let e = check_files(&vcd, &other, &CheckOptions::default())
            .err()
            .unwrap();
        assert!(
            e.0.contains("other.bin") && e.0.contains("nor an FST"),
            "{e}"
        );
    }
}
