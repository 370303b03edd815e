//! `tooltouch check` never passes a short trace and reads every trace a device emits
//! (through the built binary; exit codes 0 match, 1 mismatch, 2 bad input):
//! - a DUT VCD that stops early (`head -n 96520 measure.vcd`, at a clock's boundary) or
//!   runs on is a mismatch naming both ends; a golden VCD cut short (at a line's end near
//!   700 kB) or with a zero-width output is bad input;
//! - a `.ttv` with bytes or a second stream after its END, or of another configuration,
//!   is bad input; a shorter one is a mismatch naming both record counts;
//! - force output streams (`tooltouch control --out`) and the firmware's own trace (its
//!   profile and status records) are read; a lost or overflowed event is a mismatch with
//!   its count, the firmware's error record is bad input.

use std::path::Path;
use tooltouch_model::wire::{kind, Record, MAX_PAYLOAD, RECORD_HEADER_LEN};

use crate::common;
use common::{text, tooltouch};

fn check(expected: &Path, dut: &Path) -> (Option<i32>, String) {
    let o = tooltouch(&[
        "check",
        "--expected",
        expected.to_str().unwrap(),
        "--dut",
        dut.to_str().unwrap(),
    ]);
    (o.status.code(), text(&o))
}

/// A default `measure` run of one measurement (its VCD: 55 130 001 clocks) in a fresh
/// folder.
fn default_run() -> tempfile::TempDir {
    let dir = work();
    let o = tooltouch(&[
        "measure",
        "--out",
        dir.path().to_str().unwrap(),
        "--no-progress",
        "--repeats",
        "1",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    dir
}

fn work() -> tempfile::TempDir {
    tempfile::tempdir().expect("temporary folder")
}

#[test]
fn a_dut_vcd_that_stops_early_is_a_mismatch_naming_both_ends() {
    let run = default_run();
    let golden = run.path().join("measure.vcd");
    let text_ = std::fs::read_to_string(&golden).unwrap();
    let w = work();
    let dut = w.path().join("dut.vcd");
    // The case: `head -n 96520 measure.vcd > dut.vcd`, ended at a clock's
    // boundary (before the last time line within them), so the trace stops early rather
    // than in the middle of a clock's changes.
    let lines: Vec<&str> = text_.lines().take(96520).collect();
    let whole = lines.iter().rposition(|l| l.starts_with('#')).unwrap();
    let head: String = lines[..whole].iter().map(|l| format!("{l}\n")).collect();
    std::fs::write(&dut, head).unwrap();
    let (code, out) = check(&golden, &dut);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("the DUT trace ends at cycle")
            && out.contains("the golden trace at cycle 66410000 (time 1328200000 ns)")
            && out.contains("too short"),
        "{out}"
    );
    // A DUT trace that runs on past the golden one is a mismatch too.
    let longer = format!("{text_}#1400000000\n");
    std::fs::write(&dut, longer).unwrap();
    let (code, out) = check(&golden, &dut);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("too long") && out.contains("cycle 70000000"),
        "{out}"
    );
    // The whole file still matches itself.
    let (code, out) = check(&golden, &golden);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.starts_with("OK: 66410001 cycles"), "{out}");
}

#[test]
fn a_golden_vcd_cut_short_or_with_a_zero_width_output_is_bad_input() {
    let run = default_run();
    let golden = run.path().join("measure.vcd");
    let bytes = std::fs::read(&golden).unwrap();
    let w = work();
    let cut = w.path().join("cut.vcd");
    // At a line's end, so the reader meets a whole file cut short, not a cut line.
    let at = bytes[..700_000].iter().rposition(|&b| b == b'\n').unwrap() + 1;
    std::fs::write(&cut, &bytes[..at]).unwrap();
    let (code, out) = check(&cut, &golden);
    assert_eq!(code, Some(2), "{out}");
    assert!(
        out.contains("cut.vcd") && out.contains("cut short"),
        "{out}"
    );

    let text_ = String::from_utf8(bytes).unwrap();
    let var = text_
        .lines()
        .find(|l| l.starts_with("$var") && l.contains(" charge "))
        .unwrap()
        .to_string();
    let zero = w.path().join("zero.vcd");
    let parts: Vec<&str> = var.split(' ').collect();
    let zero_var = format!("$var wire 0 {} charge $end", parts[3]);
    std::fs::write(&zero, text_.replacen(&var, &zero_var, 1)).unwrap();
    let (code, out) = check(&zero, &golden);
    assert_eq!(code, Some(2), "{out}");
    assert!(out.contains("`charge` is 0 bits wide"), "{out}");

    // Another configuration in the DUT's stamp.
    let stamp = text_
        .lines()
        .find(|l| l.starts_with("$comment tooltouch measure_hash="))
        .unwrap();
    let other = w.path().join("other.vcd");
    std::fs::write(
        &other,
        text_.replacen(
            stamp,
            "$comment tooltouch measure_hash=0123456789abcdef clock_hz=50000000 $end",
            1,
        ),
    )
    .unwrap();
    let (code, out) = check(&golden, &other);
    assert_eq!(code, Some(2), "{out}");
    assert!(out.contains("configuration mismatch"), "{out}");
}

#[test]
fn bytes_or_a_second_stream_after_end_and_other_configurations_are_bad_input() {
    let run = default_run();
    let expected = run.path().join("expected_outputs.ttv");
    let bytes = std::fs::read(&expected).unwrap();
    let w = work();
    let tail = w.path().join("tail.ttv");
    let mut junk = bytes.clone();
    junk.extend_from_slice(b"junk");
    std::fs::write(&tail, &junk).unwrap();
    for (e, d) in [(&expected, &tail), (&tail, &expected)] {
        let (code, out) = check(e, d);
        assert_eq!(code, Some(2), "{out}");
        assert!(
            out.contains("tail.ttv") && out.contains("4 more bytes after the END record"),
            "{out}"
        );
    }
    let twice = w.path().join("twice.ttv");
    std::fs::write(&twice, [bytes.clone(), bytes.clone()].concat()).unwrap();
    let (code, out) = check(&expected, &twice);
    assert_eq!(code, Some(2), "{out}");
    assert!(out.contains("a second stream"), "{out}");

    // Another measurement configuration.
    let other = w.path().join("other");
    let o = tooltouch(&[
        "measure",
        "--out",
        other.to_str().unwrap(),
        "--no-progress",
        "--repeats",
        "1",
        "--vcd",
        "none",
        "--i-def",
        "500",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let (code, out) = check(&expected, &other.join("expected_outputs.ttv"));
    assert_eq!(code, Some(2), "{out}");
    assert!(out.contains("configuration hash"), "{out}");

    // A shorter stream: a mismatch naming both record counts.
    let records = bytes.len() - 10; // without END
    let short = w.path().join("short.ttv");
    let n = tooltouch_model::wire::HEADER_LEN
        + 3 * (RECORD_HEADER_LEN + tooltouch_model::wire::measure_outputs::OUTPUTS_LEN);
    let mut s = bytes[..n].to_vec();
    s.extend_from_slice(&bytes[records..]);
    std::fs::write(&short, s).unwrap();
    let (code, out) = check(&expected, &short);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("record 3:") && out.contains("ends after 3 measurement-outputs records"),
        "{out}"
    );
}

fn record(kind: u8, time: u64, payload: &[u8]) -> Vec<u8> {
    let mut buf = [0u8; RECORD_HEADER_LEN + MAX_PAYLOAD];
    let n = Record::new(kind, time, payload).encode(&mut buf).unwrap();
    buf[..n].to_vec()
}

/// `outputs` (an Outputs stream ending with END) as the firmware writes it: the profile
/// and status records before END, `lost` and `overflowed` in the status.
fn as_firmware_trace(outputs: &[u8], events: u32, lost: u32, overflowed: u32) -> Vec<u8> {
    let end = &outputs[outputs.len() - RECORD_HEADER_LEN..];
    let time = u64::from_le_bytes(end[2..10].try_into().unwrap());
    let mut t = outputs[..outputs.len() - RECORD_HEADER_LEN].to_vec();
    t.extend(record(kind::FIRMWARE_PROFILE, time, &[0; 40]));
    t.extend(record(kind::FIRMWARE_FORCE_PROFILE, time, &[0; 24]));
    let mut status = Vec::new();
    for v in [events, lost, overflowed, 1024, 1000, 1000] {
        status.extend_from_slice(&u32::to_le_bytes(v));
    }
    t.extend(record(kind::FIRMWARE_STATUS, time, &status));
    t.extend(record(tooltouch_model::wire::kind::END, time, &[]));
    t
}

#[test]
fn the_firmware_trace_is_read_and_a_lost_event_is_a_mismatch() {
    let run = default_run();
    let expected = run.path().join("expected_outputs.ttv");
    let bytes = std::fs::read(&expected).unwrap();
    let w = work();
    let fw = w.path().join("tooltouch-outputs.bin");
    std::fs::write(&fw, as_firmware_trace(&bytes, 15582, 0, 0)).unwrap();
    let (code, out) = check(&expected, &fw);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("none lost or overflowed"), "{out}");

    std::fs::write(&fw, as_firmware_trace(&bytes, 15582, 3, 0)).unwrap();
    let (code, out) = check(&expected, &fw);
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("lost 3 events and overflowed 0"), "{out}");

    // The firmware's error record: it rejected its input.
    let mut rejected = bytes[..tooltouch_model::wire::HEADER_LEN].to_vec();
    let mut p = [0u8; 18];
    p[0] = 4; // stream does not start with a MEASURE_CONFIG record
    rejected.extend(record(kind::FIRMWARE_ERROR, 0, &p));
    rejected.extend(record(tooltouch_model::wire::kind::END, 0, &[]));
    std::fs::write(&fw, rejected).unwrap();
    let (code, out) = check(&expected, &fw);
    assert_eq!(code, Some(2), "{out}");
    assert!(
        out.contains("rejected its input") && out.contains("MEASURE_CONFIG"),
        "{out}"
    );
}

#[test]
fn force_output_streams_are_checked_field_by_field() {
    let w = work();
    let o = tooltouch(&["control", "--out", w.path().to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let golden = w.path().join("pi_estimated.outputs.ttv");
    let (code, out) = check(&golden, &golden);
    assert_eq!(code, Some(0), "{out}");
    assert!(
        out.starts_with("OK: ") && out.contains("force records × 15 fields"),
        "{out}"
    );

    // Change the override of the 10th record (first payload byte).
    let mut bytes = std::fs::read(&golden).unwrap();
    let at = tooltouch_model::wire::HEADER_LEN
        + 9 * (RECORD_HEADER_LEN + tooltouch_model::wire::force_outputs::FORCE_OUTPUTS_LEN)
        + RECORD_HEADER_LEN;
    bytes[at] ^= 1;
    let dut = w.path().join("dut.bin");
    std::fs::write(&dut, bytes).unwrap();
    let (code, out) = check(&golden, &dut);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("force record 9 (time") && out.contains("override_pct"),
        "{out}"
    );

    // The measured-force run has another force configuration.
    let o = tooltouch(&[
        "control",
        "--out",
        w.path().to_str().unwrap(),
        "--force",
        "both",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let (code, out) = check(&golden, &w.path().join("pi_measured.outputs.ttv"));
    assert_eq!(code, Some(2), "{out}");
    assert!(out.contains("force configuration hash"), "{out}");
}
