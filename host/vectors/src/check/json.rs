//! `check --json`: the verdict, the DUT signal matched for each golden output and the
//! first mismatching clock, as one JSON object for CI.
//!
//! `{"verdict": "match" | "mismatch" | "bad_input", "exit_code": 0 | 1 | 2, "summary": the
//! verdict line or the error, "expected": path, "dut": path, "dut_scope": dotted path or
//! null, "matches": [{"golden", "dut", "golden_width", "dut_width"}], "first_mismatch":
//! {"cycle", "time_ns", "signals": [{"signal", "expected", "got"}]} or null, "details":
//! [the report's further lines]}`.

use super::{BadInput, Report, Verdict};
use serde_json::{json, Value};
use std::path::Path;

/// The JSON text of `check`'s outcome on `expected` and `dut`.
pub fn report_json(expected: &Path, dut: &Path, result: &Result<Report, BadInput>) -> String {
    let value = match result {
        Err(e) => json!({
            "verdict": "bad_input",
            "exit_code": 2,
            "summary": e.to_string(),
            "expected": expected.display().to_string(),
            "dut": dut.display().to_string(),
            "dut_scope": Value::Null,
            "matches": [],
            "first_mismatch": Value::Null,
            "details": [],
        }),
        Ok(r) => {
            let (verdict, code, line) = match &r.verdict {
                Verdict::Match(l) => ("match", 0, l),
                Verdict::Mismatch(l) => ("mismatch", 1, l),
            };
            let matches: Vec<Value> = r
                .matches
                .iter()
                .map(|m| {
                    json!({
                        "golden": m.golden,
                        "dut": m.dut,
                        "golden_width": m.widths.0,
                        "dut_width": m.widths.1,
                    })
                })
                .collect();
            let first = r.first.as_ref().map_or(Value::Null, |f| {
                json!({
                    "cycle": f.cycle,
                    "time_ns": f.time_ns,
                    "signals": f.differing.iter().map(|d| json!({
                        "signal": d.signal,
                        "expected": d.expected,
                        "got": d.got,
                    })).collect::<Vec<_>>(),
                })
            });
            json!({
                "verdict": verdict,
                "exit_code": code,
                "summary": line,
                "expected": expected.display().to_string(),
                "dut": dut.display().to_string(),
                "dut_scope": r.dut_scope,
                "matches": matches,
                "first_mismatch": first,
                "details": r.details,
            })
        }
    };
    let mut text = serde_json::to_string_pretty(&value).unwrap_or_default();
    text.push('\n');
    text
}
