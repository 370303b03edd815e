//! `tooltouch check`: compares a device-under-test's output trace with the golden expected
//! trace and reports the first difference (VCD contract in docs/CONTRACT.md; binary
//! Outputs streams record by record). The comparisons are in [`crate::vectors::check`].
//!
//! Exit codes: 0 match, 1 mismatch (a differing value, a trace that ends before or after
//! the other, a firmware that lost or overflowed events), 2 bad input (unreadable or
//! malformed file, a golden file cut short, bytes after a stream's END, configuration
//! mismatch, missing or zero-width signal).

pub use crate::vectors::check::{compare_binary, compare_vcd, BadInput, Verdict};
use crate::vectors::check::{compare_output_sources, compare_vcd_sides, VcdSide};
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
    /// `*.outputs.ttv`).
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

/// What a file given to `check` holds, told from its first bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A binary vector stream (magic `TTVX`).
    Binary,
    /// A VCD (its first non-blank byte is `$`).
    Vcd,
    /// Nothing at all.
    Empty,
    /// Anything else.
    Unknown,
}

impl Kind {
    fn describe(self) -> &'static str {
        match self {
            Kind::Binary => "a binary vector file (TTVX)",
            Kind::Vcd => "a VCD",
            Kind::Empty => "empty (0 bytes)",
            Kind::Unknown => "neither",
        }
    }
}

/// The kind of the file behind `r` (peeked, not consumed).
fn kind_of(r: &mut BufReader<std::fs::File>, path: &Path) -> Result<Kind, BadInput> {
    let head = r
        .fill_buf()
        .map_err(|e| BadInput(format!("{}: {e}", path.display())))?;
    Ok(if head.is_empty() {
        Kind::Empty
    } else if head.starts_with(&tooltouch_model::wire::MAGIC) {
        Kind::Binary
    } else if head.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'$') {
        Kind::Vcd
    } else {
        Kind::Unknown
    })
}

/// Why a file of kind `kind` cannot be compared, naming it and its role.
fn unusable(kind: Kind, name: &str, role: &str, head: &[u8]) -> BadInput {
    match kind {
        Kind::Empty => BadInput(format!(
            "{name} (the {role} trace): empty file (0 bytes): expected a VCD or a binary vector file"
        )),
        _ => {
            let shown: Vec<String> = head.iter().take(8).map(|b| format!("{b:02x}")).collect();
            BadInput(format!(
                "{name} (the {role} trace): byte 0: neither a binary vector file (it would start \
                 with \"TTVX\") nor a VCD (it would start with a `$` command); it starts with {}",
                shown.join(" ")
            ))
        }
    }
}

/// Compares two files (VCD or binary, the same kind both), both read as streams.
pub fn compare_files(expected: &Path, dut: &Path) -> Result<Verdict, BadInput> {
    let (en, dn) = (expected.display().to_string(), dut.display().to_string());
    let mut e = open(expected)?;
    let mut d = open(dut)?;
    let (ek, dk) = (kind_of(&mut e, expected)?, kind_of(&mut d, dut)?);
    for (kind, name, role, r) in [(ek, &en, "golden", &mut e), (dk, &dn, "DUT", &mut d)] {
        if matches!(kind, Kind::Empty | Kind::Unknown) {
            let head = r.fill_buf().unwrap_or(&[]).to_vec();
            return Err(unusable(kind, name, role, &head));
        }
    }
    match (ek, dk) {
        (Kind::Binary, Kind::Binary) => {
            drop((e, d));
            compare_output_sources(&|| open(expected), &en, &|| open(dut), &dn)
        }
        (Kind::Vcd, Kind::Vcd) => {
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
            "{en} (the golden trace) is {} and {dn} (the DUT trace) is {}: compare like with like",
            ek.describe(),
            dk.describe()
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
