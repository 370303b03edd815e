//! A file given to `check`, told from its first bytes (a binary vector stream, a VCD or an
//! FST), and a dump (VCD or FST) opened as declarations and a stream of changes.

use super::BadInput;
use crate::vcd::{Changes, Declarations, VcdReader};
use std::io::{BufRead as _, BufReader};
use std::path::Path;

/// Opens `path` for reading, buffered (1 MiB).
pub(crate) fn open(path: &Path) -> Result<BufReader<std::fs::File>, BadInput> {
    std::fs::File::open(path)
        .map(|f| BufReader::with_capacity(1 << 20, f))
        .map_err(|e| BadInput(format!("{}: {e}", path.display())))
}

/// What a file given to `check` holds, told from its first bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// A binary vector stream (magic `TTVX`).
    Binary,
    /// A VCD (its first non-blank byte is `$`).
    Vcd,
    /// An FST (its blocks, from a header block on: `fst_reader::is_fst_file`).
    Fst,
    /// Nothing at all.
    Empty,
    /// Anything else.
    Unknown,
}

impl Kind {
    pub(crate) fn describe(self) -> &'static str {
        match self {
            Kind::Binary => "a binary vector file (TTVX)",
            Kind::Vcd => "a VCD",
            Kind::Fst => "an FST",
            Kind::Empty => "empty (0 bytes)",
            Kind::Unknown => "neither",
        }
    }
}

/// The kind of the file behind `r` (peeked, not consumed).
pub(crate) fn kind_of(r: &mut BufReader<std::fs::File>, path: &Path) -> Result<Kind, BadInput> {
    let head = r
        .fill_buf()
        .map_err(|e| BadInput(format!("{}: {e}", path.display())))?;
    let kind = if head.is_empty() {
        Kind::Empty
    } else if head.starts_with(&tooltouch_model::wire::MAGIC) {
        Kind::Binary
    } else if head.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'$') {
        Kind::Vcd
    } else {
        Kind::Unknown
    };
    Ok(if kind == Kind::Unknown && crate::fst::is_fst(r) {
        Kind::Fst
    } else {
        kind
    })
}

/// A dump's declarations and its changes, read as a stream.
pub(crate) type OpenDump = (Declarations, Box<dyn Changes>);

/// Opens the dump (VCD or FST) at `path`, named `name` in errors.
pub(crate) fn open_dump(path: &Path, name: &str) -> Result<OpenDump, BadInput> {
    let mut r = open(path)?;
    let kind = kind_of(&mut r, path)?;
    open_dump_as(r, kind, path, name)
}

pub(crate) fn open_dump_as(
    r: BufReader<std::fs::File>,
    kind: Kind,
    path: &Path,
    name: &str,
) -> Result<OpenDump, BadInput> {
    match kind {
        Kind::Fst => {
            drop(r);
            let (d, changes) = crate::fst::open(path, name)?;
            Ok((d, Box::new(changes)))
        }
        Kind::Vcd => {
            let reader = VcdReader::new(r, name)?;
            Ok((reader.declarations().clone(), Box::new(reader)))
        }
        _ => Err(BadInput(format!(
            "{name}: {}, not a dump (VCD or FST)",
            kind.describe()
        ))),
    }
}
