//! `tooltouch check`: compares a device-under-test's output trace with the golden expected
//! trace and reports the first difference (VCD contract in docs/CONTRACT.md; binary
//! Outputs streams record by record). The comparisons are in [`crate::vectors::check`].
//!
//! Exit codes: 0 match, 1 mismatch (a differing value, a trace that ends before or after
//! the other, a firmware that lost or overflowed events), 2 bad input (unreadable or
//! malformed file, a golden file cut short, bytes after a stream's END, configuration
//! mismatch, missing or zero-width signal).

pub use crate::vectors::check::{compare_binary, compare_vcd, BadInput, Verdict};
use crate::vectors::check::{compare_vcd_sides, VcdSide};
use crate::vectors::vcd::VcdReader;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `tooltouch check`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Exit codes: 0 match; 1 mismatch (a value, a trace that ends before or after the other, \
a firmware trace that lost or overflowed events); 2 bad input (unreadable, malformed, a \
golden VCD without its closing `tooltouch end` comment, bytes after a stream's END, \
another configuration, a missing or zero-width signal).")]
pub struct Args {
    /// Golden expected trace: a VCD written by `tooltouch measure` or `tooltouch
    /// vectors`, or a binary Outputs stream (expected_outputs.ttv, a `tooltouch control`
    /// `*.outputs.bin`).
    #[arg(long)]
    pub expected: PathBuf,
    /// Device-under-test trace: a VCD of any tool (signals matched by leaf name), or a
    /// binary Outputs stream (measurement or force outputs, or the firmware's own trace
    /// with its profile and status records).
    #[arg(long)]
    pub dut: PathBuf,
}

fn open(path: &Path) -> Result<BufReader<std::fs::File>, BadInput> {
    std::fs::File::open(path)
        .map(|f| BufReader::with_capacity(1 << 20, f))
        .map_err(|e| BadInput(format!("{}: {e}", path.display())))
}

/// Whether the file starts with the binary vector magic (peeked, not consumed).
fn is_binary(r: &mut BufReader<std::fs::File>, path: &Path) -> Result<bool, BadInput> {
    let head = r
        .fill_buf()
        .map_err(|e| BadInput(format!("{}: {e}", path.display())))?;
    Ok(head.starts_with(&tooltouch_model::wire::MAGIC))
}

fn read(path: &Path) -> Result<Vec<u8>, BadInput> {
    std::fs::read(path).map_err(|e| BadInput(format!("{}: {e}", path.display())))
}

/// Compares two files (VCD or binary, the same kind both); VCDs are streamed.
pub fn compare_files(expected: &Path, dut: &Path) -> Result<Verdict, BadInput> {
    let (en, dn) = (expected.display().to_string(), dut.display().to_string());
    let mut e = open(expected)?;
    let mut d = open(dut)?;
    match (is_binary(&mut e, expected)?, is_binary(&mut d, dut)?) {
        (true, true) => compare_binary(&read(expected)?, &en, &read(dut)?, &dn),
        (false, false) => {
            let mut e = VcdReader::new(e, &en)?;
            let mut d = VcdReader::new(d, &dn)?;
            let ed = e.declarations().clone();
            let dd = d.declarations().clone();
            let late = std::cell::RefCell::new(Vec::new());
            let verdict = {
                let mut es = VcdSide {
                    name: &en,
                    declarations: &ed,
                    changes: &mut CommentsKept {
                        reader: &mut e,
                        late: &late,
                    },
                };
                let mut ds = VcdSide {
                    name: &dn,
                    declarations: &dd,
                    changes: &mut d,
                };
                compare_vcd_sides(&mut es, &mut ds, &|| late.borrow().clone())?
            };
            Ok(verdict)
        }
        _ => Err(BadInput(format!(
            "{en} and {dn}: one is a binary vector file and the other is not; compare like with like"
        ))),
    }
}

/// A reader that copies its late comments out when it reaches the end, so the golden
/// side's closing comment can be looked up while the reader is borrowed.
struct CommentsKept<'a, R> {
    reader: &'a mut VcdReader<R>,
    late: &'a std::cell::RefCell<Vec<String>>,
}

impl<R: BufRead> crate::vectors::vcd::Changes for CommentsKept<'_, R> {
    fn next_change(
        &mut self,
    ) -> Result<Option<(u64, usize, crate::vectors::vcd::Value)>, crate::vectors::vcd::VcdError>
    {
        let c = self.reader.next_change()?;
        if c.is_none() {
            *self.late.borrow_mut() = self.reader.late_comments().to_vec();
        }
        Ok(c)
    }
    fn end_fs(&self) -> u64 {
        self.reader.end_fs()
    }
    fn line(&self) -> usize {
        self.reader.line()
    }
}

/// Runs `tooltouch check`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match compare_files(&args.expected, &args.dut) {
        Ok(Verdict::Match(line)) => {
            outln!("{line}");
            Ok(ExitCode::SUCCESS)
        }
        Ok(Verdict::Mismatch(line)) => {
            outln!("MISMATCH: {line}");
            Ok(ExitCode::from(1))
        }
        Err(e) => {
            eprintln!("error: {e}");
            Ok(ExitCode::from(2))
        }
    }
}
