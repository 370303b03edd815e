//! `tooltouch check`: compares a device-under-test's output trace with the golden expected
//! trace and reports the first difference (VCD contract in docs/CONTRACT.md; binary
//! Outputs streams record by record).
//!
//! Exit codes: 0 match, 1 mismatch, 2 bad input (unreadable or malformed file,
//! configuration mismatch, missing signal).

use crate::vectors::binary;
use crate::vectors::vcd::{Dump, Value};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `tooltouch check`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Golden expected trace: a VCD written by `tooltouch measure`, or a binary Outputs
    /// stream (expected_outputs.ttv).
    #[arg(long)]
    pub expected: PathBuf,
    /// Device-under-test trace: a VCD of any tool (signals matched by leaf name), or a
    /// binary Outputs stream.
    #[arg(long)]
    pub dut: PathBuf,
}

/// The result of a comparison.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Everything matched; the one-line summary.
    Match(String),
    /// The first difference, as one line.
    Mismatch(String),
}

/// Bad input to `check`, with the file and what is wrong.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);

fn read(path: &Path) -> Result<Vec<u8>, BadInput> {
    std::fs::read(path).map_err(|e| BadInput(format!("{}: {e}", path.display())))
}

fn is_binary(bytes: &[u8]) -> bool {
    bytes.starts_with(&tooltouch_model::wire::MAGIC)
}

/// Compares two files (VCD or binary, the same kind both).
pub fn compare_files(expected: &Path, dut: &Path) -> Result<Verdict, BadInput> {
    let e = read(expected)?;
    let d = read(dut)?;
    let (en, dn) = (expected.display().to_string(), dut.display().to_string());
    match (is_binary(&e), is_binary(&d)) {
        (true, true) => compare_binary(&e, &en, &d, &dn),
        (false, false) => {
            let text = |b: Vec<u8>, n: &str| {
                String::from_utf8(b).map_err(|_| BadInput(format!("{n}: neither a VCD text nor a binary vector file (magic \"TTVX\")")))
            };
            let e = Dump::parse(&text(e, &en)?, &en).map_err(|x| BadInput(x.to_string()))?;
            let d = Dump::parse(&text(d, &dn)?, &dn).map_err(|x| BadInput(x.to_string()))?;
            compare_vcd(&e, &en, &d, &dn)
        }
        _ => Err(BadInput(format!(
            "{en} and {dn}: one is a binary vector file and the other is not; compare like with like"
        ))),
    }
}

fn hex(v: Option<Value>) -> String {
    match v {
        Some(Value {
            unknown: false,
            bits,
        }) => format!("0x{bits:x}"),
        Some(_) => "x".to_string(),
        None => "x (no value yet)".to_string(),
    }
}

/// Compares the `outputs` scope of a golden dump with a DUT dump (VCD contract).
pub fn compare_vcd(e: &Dump, en: &str, d: &Dump, dn: &str) -> Result<Verdict, BadInput> {
    let (hash, clock_hz) = e.golden_stamp().ok_or_else(|| {
        BadInput(format!(
            "{en}: no `$comment tooltouch measure_hash=… clock_hz=…` line: not a golden file"
        ))
    })?;
    if let Some((dut_hash, dut_hz)) = d.golden_stamp() {
        if dut_hash != hash || dut_hz != clock_hz {
            return Err(BadInput(format!(
                "configuration mismatch: {en} has measure_hash={hash:016x} clock_hz={clock_hz}, {dn} has measure_hash={dut_hash:016x} clock_hz={dut_hz}"
            )));
        }
    }
    if clock_hz == 0 || 1_000_000_000 % clock_hz != 0 {
        return Err(BadInput(format!(
            "{en}: clock_hz={clock_hz} does not divide 1e9"
        )));
    }
    let period_fs = 1_000_000_000_000_000 / u64::from(clock_hz);
    let half = period_fs / 2;
    let last_k = e.last_time_fs / period_fs;
    let outputs: Vec<_> = e
        .signals
        .iter()
        .filter(|s| s.scope.last().is_some_and(|l| l == "outputs"))
        .collect();
    if outputs.is_empty() {
        return Err(BadInput(format!("{en}: no `outputs` scope")));
    }
    let mut first: Option<(u64, usize, Option<Value>, Option<Value>)> = None;
    for (i, es) in outputs.iter().enumerate() {
        let ds = d.find_shallowest(&es.name).ok_or_else(|| {
            BadInput(format!(
                "{dn}: no signal named `{}` (expected from {en})",
                es.name
            ))
        })?;
        let mask = if es.width >= 64 {
            u64::MAX
        } else {
            (1u64 << es.width) - 1
        };
        // Values only change at change times, so the first differing sample is at k = 0
        // or at the first sample after some change of either signal.
        let mut ks: Vec<u64> = vec![0];
        for list in [e.changes.get(&es.id), d.changes.get(&ds.id)]
            .into_iter()
            .flatten()
        {
            for &(t, _) in list {
                ks.push(t.saturating_sub(half).div_ceil(period_fs));
            }
        }
        ks.sort_unstable();
        ks.dedup();
        for k in ks {
            if k > last_k || first.is_some_and(|f| k > f.0) {
                break;
            }
            let t = k * period_fs + half;
            let ev = e.value_at(&es.id, t).map(|v| Value {
                bits: v.bits & mask,
                ..v
            });
            let dv = d.value_at(&ds.id, t).map(|v| Value {
                bits: v.bits & mask,
                ..v
            });
            let same = matches!((ev, dv), (Some(a), Some(b)) if !a.unknown && !b.unknown && a.bits == b.bits);
            if !same {
                if first.is_none_or(|f| k < f.0 || (k == f.0 && i < f.1)) {
                    first = Some((k, i, ev, dv));
                }
                break;
            }
        }
    }
    Ok(match first {
        Some((k, i, ev, dv)) => Verdict::Mismatch(format!(
            "cycle {k} (time {} ns): signal {} expected {} got {}",
            k * period_fs / 1_000_000,
            outputs[i].name,
            hex(ev),
            hex(dv)
        )),
        None => Verdict::Match(format!(
            "OK: {} cycles × {} signals of {en} match {dn}",
            last_k + 1,
            outputs.len()
        )),
    })
}

/// Compares two binary Outputs streams record by record.
pub fn compare_binary(e: &[u8], en: &str, d: &[u8], dn: &str) -> Result<Verdict, BadInput> {
    let bad = |x: binary::BinaryError| BadInput(x.to_string());
    let (eh, er) = binary::decode_outputs(e, en, None).map_err(bad)?;
    let (_, dr) = binary::decode_outputs(d, dn, Some(eh.measure_hash)).map_err(bad)?;
    for (i, (a, b)) in er.iter().zip(&dr).enumerate() {
        if a.0 != b.0 {
            return Ok(Verdict::Mismatch(format!(
                "record {i}: time expected {} got {}",
                a.0, b.0
            )));
        }
        for ((name, x), (_, y)) in binary::output_fields(&a.1)
            .iter()
            .zip(binary::output_fields(&b.1).iter())
        {
            if x != y {
                return Ok(Verdict::Mismatch(format!(
                    "record {i} (time {}): field {name} expected 0x{x:x} got 0x{y:x}",
                    a.0
                )));
            }
        }
    }
    if er.len() != dr.len() {
        let i = er.len().min(dr.len());
        return Ok(Verdict::Mismatch(format!(
            "record {i}: expected {} records, {dn} has {}",
            er.len(),
            dr.len()
        )));
    }
    Ok(Verdict::Match(format!(
        "OK: {} records × 15 fields of {en} match {dn}",
        er.len()
    )))
}

/// Runs `tooltouch check`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match compare_files(&args.expected, &args.dut) {
        Ok(Verdict::Match(line)) => {
            println!("{line}");
            Ok(ExitCode::SUCCESS)
        }
        Ok(Verdict::Mismatch(line)) => {
            println!("MISMATCH: {line}");
            Ok(ExitCode::from(1))
        }
        Err(e) => {
            eprintln!("error: {e}");
            Ok(ExitCode::from(2))
        }
    }
}
