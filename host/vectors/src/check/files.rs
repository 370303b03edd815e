//! `check` on two files: each told from its first bytes (a binary vector stream or a VCD),
//! opened as a stream, and compared like with like; an empty, unknown or mixed pair is bad
//! input naming the file and its role.

use super::{
    compare_output_sources, compare_vcd_sides_with, BadInput, CheckOptions, Report, VcdSide,
    Verdict,
};
use crate::vcd::{Changes, Value, VcdError, VcdReader};
use std::io::{BufRead, BufReader};
use std::path::Path;

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
    check_files(expected, dut, &CheckOptions::default()).map(|r| r.verdict)
}

/// [`compare_files`] with options, returning the whole [`Report`]: for a VCD mismatch
/// also the report's lines and, with [`CheckOptions::window`], its window files.
pub fn check_files(
    expected: &Path,
    dut: &Path,
    options: &CheckOptions,
) -> Result<Report, BadInput> {
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
            let verdict = compare_output_sources(&|| open(expected), &en, &|| open(dut), &dn)?;
            Ok(Report {
                verdict,
                dut_scope: None,
                matches: Vec::new(),
                first: None,
                details: Vec::new(),
            })
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
                compare_vcd_sides_with(&mut es, &mut ds, &|| late.borrow().clone(), options)?
            };
            let mut report = verdict;
            if report.first.is_some() {
                drop((e, d));
                super::window::add_details(expected, dut, &mut report, options.window.as_deref())?;
            }
            Ok(report)
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

impl<R: BufRead> Changes for CommentsKept<'_, R> {
    fn next_change(&mut self) -> Result<Option<(u64, usize, Value)>, VcdError> {
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
