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
use tooltouch_vectors::check::{check_files, CheckOptions, Report, Verdict};

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
    /// Device-under-test trace: a VCD of any tool (each golden output matched with the
    /// signal of its name in the DUT's top scope), or a binary Outputs stream (measurement
    /// or force outputs, or the firmware's own trace with its profile and status records).
    #[arg(long)]
    pub dut: PathBuf,
    /// The DUT's top scope in a VCD, a dotted path such as `tt_testbench.dut` (default:
    /// the shallowest scope declaring golden outputs). Its ports are compared, never a
    /// signal deeper down.
    #[arg(long, value_name = "SCOPE")]
    pub dut_scope: Option<String>,
    /// Also write the verdict, the signals matched and the first mismatch as JSON to FILE
    /// (for CI) when the comparison ran (exit 0 or 1; bad input writes nothing).
    #[arg(long, value_name = "FILE", value_hint = clap::ValueHint::FilePath)]
    pub json: Option<PathBuf>,
    /// On a VCD mismatch, write FILE, a VCD of golden and DUT side by side around the first
    /// mismatching clock, and beside it FILE with the extension `.gtkw`, a GTKWave save file
    /// with the cursor on it.
    #[arg(long, value_name = "FILE", value_hint = clap::ValueHint::FilePath)]
    pub window: Option<PathBuf>,
}

/// Runs `tooltouch check`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    for path in args.json.iter().chain(&args.window) {
        if let Err(e) = tooltouch_vectors::output::check_output_file(path) {
            eprintln!("error: {e:#}");
            return Ok(ExitCode::from(2));
        }
    }
    let options = CheckOptions {
        dut_scope: args.dut_scope.clone(),
        window: args.window.clone(),
    };
    let result = check_files(&args.expected, &args.dut, &options);
    if let (Some(path), Ok(_)) = (&args.json, &result) {
        let json = tooltouch_vectors::check::json::report_json(&args.expected, &args.dut, &result);
        tooltouch_vectors::output::write_file(path, json.as_bytes())?;
    }
    match result {
        Ok(Report {
            verdict: Verdict::Match(line),
            ..
        }) => {
            outln!("{line}");
            Ok(ExitCode::SUCCESS)
        }
        Ok(Report {
            verdict: Verdict::Mismatch(line),
            details,
            ..
        }) => {
            outln!("MISMATCH: {line}");
            for d in details {
                outln!("{d}");
            }
            Ok(ExitCode::from(1))
        }
        Err(e) => {
            eprintln!("error: {e}");
            Ok(ExitCode::from(2))
        }
    }
}
