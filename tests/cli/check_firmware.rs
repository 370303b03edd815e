//! `tooltouch check` reads the firmware's own trace: the QEMU image replays an events
//! stream and its output file (outputs, profile and status records) is checked against
//! the golden outputs `tooltouch measure` or `tooltouch vectors` wrote — a measurement
//! stream, and a stream of both paths (measurement and force events with the force
//! configuration in chunks) whose golden outputs come from `vectors`.
//!
//! Needs qemu-system-arm and the thumbv7m-none-eabi target: without them the test fails
//! with a message naming `cargo xtask setup`.

use std::path::Path;
use std::process::Output;
use tooltouch_firmware_runner::{self as cosim, Fault};

use crate::common;
use common::{s, text, tooltouch};

use crate::common::FAST_LATHE as FAST;

/// Boots the image on `events` and writes its trace to `trace`.
fn run_firmware(image: &Path, events: &Path, trace: &Path) {
    let input = std::fs::read(events).unwrap();
    let (bytes, _) = cosim::qemu::run_image(image, &input).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(trace, bytes).unwrap();
}

fn check(expected: &Path, dut: &Path) -> Output {
    tooltouch(&["check", "--expected", s(expected), "--dut", s(dut)])
}

#[test]
fn the_firmware_trace_passes_check_for_measurement_and_force_streams() {
    let image = cosim::qemu::build_firmware().unwrap_or_else(|e| panic!("{e}"));
    let w = tempfile::tempdir().unwrap();
    let toml = w.path().join("fast.toml");
    std::fs::write(&toml, FAST).unwrap();
    let m = w.path().join("m");
    let o = tooltouch(&[
        "measure",
        "--config",
        s(&toml),
        "--out",
        s(&m),
        "--no-progress",
        "--vcd",
        "none",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let trace = w.path().join("tooltouch-outputs.bin");
    run_firmware(&image, &m.join("events.ttv"), &trace);
    let o = check(&m.join("expected_outputs.ttv"), &trace);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("none lost or overflowed"), "{}", text(&o));

    // Both paths in one stream, as the co-simulation writes it.
    let case = cosim::generate(11, Fault::None);
    assert!(case.force.is_some() && !case.force_events.is_empty());
    let mut input = Vec::new();
    cosim::encode_case(&case, &mut input);
    let events = w.path().join("case.ttv");
    std::fs::write(&events, &input).unwrap();
    let v = w.path().join("v");
    let o = tooltouch(&["vectors", "--stimulus", s(&events), "--out", s(&v)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        std::fs::read(v.join("events.ttv")).unwrap() == input,
        "vectors re-encodes the stream as it was"
    );
    run_firmware(&image, &events, &trace);
    let o = check(&v.join("expected_outputs.ttv"), &trace);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(
        text(&o).contains("force records × 15 fields"),
        "{}",
        text(&o)
    );
}
