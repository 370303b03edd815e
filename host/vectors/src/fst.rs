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
    let mut bits: BitVec<u64, Lsb0> = BitVec::with_capacity(digits.len());
    let mut unknown = false;
    for &d in digits.iter().rev() {
        match d {
            b'0' => bits.push(false),
            b'1' => bits.push(true),
            _ => {
                unknown = true;
                bits.push(false);
            }
        }
    }
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
                    let Some(Some(code)) = code_of_handle.get(handle.get_index()).copied()
                    else {
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
