//! The errors of a proof run and the helpers the formal files share (tool lookup, I/O
//! errors with their path, a log's tail).

use std::path::{Path, PathBuf};

/// Errors of a proof run that are not a verdict.
#[derive(Debug, thiserror::Error)]
pub enum FormalError {
    /// The request is wrong: a missing file, a port missing or of the wrong width.
    #[error("{0}")]
    BadInput(String),
    /// yosys could not read or elaborate the design (its error lines).
    #[error("the design does not elaborate:\n{0}")]
    Design(String),
    /// A tool is not installed.
    #[error("`{0}` was not found on PATH: run `cargo xtask setup` to install it")]
    ToolMissing(String),
    /// A tool failed for another reason.
    #[error("{0}")]
    Tool(String),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

pub(super) fn io(path: &Path) -> impl FnOnce(std::io::Error) -> FormalError + '_ {
    move |source| {
        if source.kind() == std::io::ErrorKind::NotFound && path.components().count() == 1 {
            FormalError::ToolMissing(path.display().to_string())
        } else {
            FormalError::Io {
                path: path.to_path_buf(),
                source,
            }
        }
    }
}

pub(super) fn find(tool: &str) -> Result<(), FormalError> {
    tooltouch_rtl_sim::runner::find_tool(tool)
        .map(|_| ())
        .map_err(|_| FormalError::ToolMissing(tool.to_string()))
}

/// The last `n` lines of `text`.
pub(super) fn tail(text: &str, n: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}
