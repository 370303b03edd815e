//! `tooltouch check`: compares a device-under-test's output trace with the golden expected
//! trace and reports the first difference (VCD contract in docs/CONTRACT.md; binary
//! Outputs streams record by record). The comparisons are in [`tooltouch_vectors::check`].
//!
//! Exit codes: 0 match, 1 mismatch (a differing value, a trace that ends before or after
//! the other, a firmware that lost or overflowed events), 2 bad input (unreadable or
//! malformed file, a golden file cut short, bytes after a stream's END, configuration
//! mismatch, missing or zero-width signal).

use std::path::PathBuf;
use std::process::ExitCode;
use tooltouch_vectors::check::{compare_files, Verdict};

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
