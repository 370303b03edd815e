//! `check` on two files: each told from its first bytes (a binary vector stream, a VCD or
//! an FST), opened as a stream, and compared like with like (a VCD and an FST are both
//! dumps: either side may be either); an empty, unknown or mixed pair is bad input naming
//! the file and its role.

use super::dump::{kind_of, open, open_dump_as, Kind};
use super::{
    compare_output_sources, compare_vcd_sides_with, BadInput, CheckOptions, Report, VcdSide,
    Verdict,
};
use crate::vcd::{Changes, Value, VcdError};
use std::io::BufRead as _;
use std::path::Path;

/// Why a file of kind `kind` cannot be compared, naming it and its role.
fn unusable(kind: Kind, name: &str, role: &str, head: &[u8]) -> BadInput {
    match kind {
        Kind::Empty => BadInput(format!(
            "{name} (the {role} trace): empty file (0 bytes): expected a VCD, an FST or a binary vector file"
        )),
        _ => {
            let shown: Vec<String> = head.iter().take(8).map(|b| format!("{b:02x}")).collect();
            BadInput(format!(
                "{name} (the {role} trace): byte 0: neither a binary vector file (it would start \
                 with \"TTVX\") nor a VCD (it would start with a `$` command) nor an FST (it \
                 would start with its header block, type 0); it starts with {}",
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
        (Kind::Vcd | Kind::Fst, Kind::Vcd | Kind::Fst) => {
            let (ed, mut e) = open_dump_as(e, ek, expected, &en)?;
            let (dd, mut d) = open_dump_as(d, dk, dut, &dn)?;
            let late = std::cell::RefCell::new(Vec::new());
            let verdict = {
                let mut es = VcdSide {
                    name: &en,
                    declarations: &ed,
                    changes: &mut CommentsKept {
                        changes: e.as_mut(),
                        late: &late,
                    },
                };
                let mut ds = VcdSide {
                    name: &dn,
                    declarations: &dd,
                    changes: d.as_mut(),
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

/// A change source that copies its late comments out when it reaches the end, so the
/// golden side's closing comment can be looked up while the source is borrowed.
struct CommentsKept<'a> {
    changes: &'a mut dyn Changes,
    late: &'a std::cell::RefCell<Vec<String>>,
}

impl Changes for CommentsKept<'_> {
    fn next_change(&mut self) -> Result<Option<(u64, usize, Value)>, VcdError> {
        let c = self.changes.next_change()?;
        if c.is_none() {
            *self.late.borrow_mut() = self.changes.late_comments();
        }
        Ok(c)
    }
    fn end_fs(&self) -> u64 {
        self.changes.end_fs()
    }
    fn line(&self) -> usize {
        self.changes.line()
    }
    fn select(&mut self, codes: &[usize]) {
        self.changes.select(codes);
    }
    fn late_comments(&self) -> Vec<String> {
        self.changes.late_comments()
    }
}
