//! `tooltouch vectors` through the built binary: the golden files of a user's stimulus.
//! A stimulus given as `measure`'s own VCD, its event stream or its run-length pins gives
//! back `measure`'s files byte for byte; a testbench-style dump (other scopes, `pin_`
//! names, picoseconds) reads the same; force event streams give `control`'s outputs; a
//! stimulus that cannot be read names the file, the line or byte and the signal.

use std::path::Path;
use std::process::Output;

use crate::common;
use common::{s, text, tooltouch};

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

use crate::common::FAST_LATHE as FAST;

/// A `measure` run of the fast lathe with its whole VCD, in `dir/m`; returns the settings
/// file and the run's folder.
fn measured(dir: &Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let toml = dir.join("fast.toml");
    std::fs::write(&toml, FAST).unwrap();
    let m = dir.join("m");
    let o = tooltouch(&[
        "measure",
        "--config",
        s(&toml),
        "--out",
        s(&m),
        "--no-progress",
        "--vcd",
        "all",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    (toml, m)
}

fn vectors(stimulus: &Path, extra: &[&str], out: &Path) -> Output {
    let mut args = vec!["vectors", "--stimulus", s(stimulus), "--out", s(out)];
    args.extend_from_slice(extra);
    tooltouch(&args)
}

#[test]
fn measures_vcd_events_and_pins_give_back_its_files() {
    let w = tempfile::tempdir().unwrap();
    let (toml, m) = measured(w.path());
    let v1 = w.path().join("from_vcd");
    let o = vectors(&m.join("measure.vcd"), &["--config", s(&toml)], &v1);
    assert!(o.status.success(), "{}", text(&o));
    for (mine, theirs) in [
        ("golden.vcd", "measure.vcd"),
        ("events.ttv", "events.ttv"),
        ("expected_outputs.ttv", "expected_outputs.ttv"),
    ] {
        assert!(
            read(&v1.join(mine)) == read(&m.join(theirs)),
            "{mine} differs from measure's {theirs}"
        );
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&v1.join("summary.json"))).unwrap();
    assert_eq!(summary["cycles"], 104230, "{summary}");
    assert_eq!(summary["clock_hz"], 1_000_000);
    assert_eq!(
        summary["decisions"].as_array().unwrap().len(),
        1,
        "{summary}"
    );
    let measured: serde_json::Value =
        serde_json::from_slice(&read(&m.join("summary.json"))).unwrap();
    assert_eq!(summary["measure_hash"], measured["measure_hash"]);
    assert_eq!(summary["events"], measured["events"]);

    // The event stream (no settings needed: it carries its configuration and tick rate)
    // and the run-length pins give the same files.
    let v2 = w.path().join("from_events");
    let o = vectors(&m.join("events.ttv"), &[], &v2);
    assert!(o.status.success(), "{}", text(&o));
    let v3 = w.path().join("from_hex");
    let o = vectors(&v1.join("stim.hex"), &["--config", s(&toml)], &v3);
    assert!(o.status.success(), "{}", text(&o));
    for f in [
        "golden.vcd",
        "events.ttv",
        "expected_outputs.ttv",
        "stim.hex",
        "expect.hex",
    ] {
        assert!(
            read(&v3.join(f)) == read(&v1.join(f)),
            "from stim.hex: {f} differs"
        );
    }
    // An event stream ends with its last event: the same events and outputs, the same
    // expected response, a stimulus that stops at the last event's clock.
    for f in ["events.ttv", "expected_outputs.ttv", "expect.hex"] {
        assert!(
            read(&v2.join(f)) == read(&v1.join(f)),
            "from events: {f} differs"
        );
    }
    let from_events: serde_json::Value =
        serde_json::from_slice(&read(&v2.join("summary.json"))).unwrap();
    let last_decision = summary["decisions"][0]["clock"].as_u64().unwrap();
    let cycles = from_events["cycles"].as_u64().unwrap();
    assert!(last_decision < cycles && cycles < 104230, "{from_events}");
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&v1.join("golden.vcd")),
        "--dut",
        s(&v2.join("golden.vcd")),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("too short"), "{}", text(&o));
}

#[test]
fn a_testbench_style_dump_reads_as_the_golden_one() {
    let w = tempfile::tempdir().unwrap();
    let (toml, m) = measured(w.path());
    let golden = String::from_utf8(read(&m.join("measure.vcd"))).unwrap();
    // Picoseconds, a `tb.dut` hierarchy holding pins and outputs side by side, the pins
    // named as the ports of tt_frontend, no tooltouch comments.
    let mut in_inputs = false;
    let dut: String = golden
        .lines()
        .filter(|l| !l.starts_with("$comment"))
        .map(|l| {
            if let Some(t) = l.strip_prefix('#') {
                return format!("#{}\n", t.parse::<u64>().unwrap() * 1000);
            }
            if l.starts_with("$scope module inputs") {
                in_inputs = true;
                return "$scope module dut $end\n".into();
            }
            if l.starts_with("$upscope") {
                in_inputs = false;
            }
            let l = if in_inputs && l.starts_with("$var") {
                let p: Vec<&str> = l.split(' ').collect();
                format!("{} {} {} {} pin_{} $end", p[0], p[1], p[2], p[3], p[4])
            } else {
                l.replace("$timescale 1ns", "$timescale 1ps")
                    .replace("module tooltouch", "module tb")
                    .replace("module outputs", "module dut")
            };
            format!("{l}\n")
        })
        .collect();
    let d = w.path().join("dut.vcd");
    std::fs::write(&d, dut).unwrap();
    let v = w.path().join("v");
    let o = vectors(&d, &["--config", s(&toml)], &v);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        read(&v.join("golden.vcd")) == golden.as_bytes(),
        "golden.vcd differs"
    );
}

#[test]
fn a_stimulus_that_cannot_be_read_names_the_file_the_place_and_the_signal() {
    let w = tempfile::tempdir().unwrap();
    let (toml, m) = measured(w.path());
    let golden = String::from_utf8(read(&m.join("measure.vcd"))).unwrap();
    let out = w.path().join("v");
    let o = vectors(&m.join("measure.vcd"), &["--config", s(&toml)], &out);
    assert!(o.status.success(), "{}", text(&o));
    let before: Vec<(String, Vec<u8>)> = ["golden.vcd", "summary.json", "stim.hex"]
        .iter()
        .map(|f| (f.to_string(), read(&out.join(f))))
        .collect();
    let bad = |name: &str, content: &[u8], extra: &[&str], needles: &[&str]| {
        let p = w.path().join(name);
        std::fs::write(&p, content).unwrap();
        let o = vectors(&p, extra, &out);
        assert!(!o.status.success(), "{name}: {}", text(&o));
        for n in needles {
            assert!(
                text(&o).contains(n),
                "{name}: expected `{n}` in: {}",
                text(&o)
            );
        }
    };
    // The contact pin (code `"`) is x from time 0: its line is named.
    let x = golden.replacen("\n0\"\n", "\nx\"\n", 1);
    let line = x.lines().position(|l| l == "x\"").unwrap() + 1;
    bad(
        "x.vcd",
        x.as_bytes(),
        &["--config", s(&toml)],
        &[
            "x.vcd",
            &format!("line {line}:"),
            "pin `contact` is x or z at clock 0",
        ],
    );
    let missing = golden.replacen(" scale_b $end", " scale_c $end", 1);
    bad(
        "missing.vcd",
        missing.as_bytes(),
        &[],
        &["missing.vcd", "pin `scale_b`"],
    );
    bad(
        "bad.hex",
        b"0000000002\n0100000010\nzz\n",
        &[],
        &["bad.hex", "line 3", "`zz`"],
    );
    bad(
        "short.hex",
        b"0000000003\n0100000010\n",
        &[],
        &["short.hex", "announces 3 segments, the file holds 1"],
    );
    let events = read(&m.join("events.ttv"));
    bad(
        "cut.ttv",
        &events[..events.len() - 15],
        &[],
        &["cut.ttv", "truncated at byte"],
    );
    bad(
        "clock.vcd",
        golden.as_bytes(),
        &["--clock-hz", "2000000"],
        &["clock.vcd", "1000000 Hz", "--clock-hz says 2000000 Hz"],
    );
    // Another configuration than the event stream's.
    let other = w.path().join("other.toml");
    std::fs::write(&other, "[measure]\ni_def = 300\n").unwrap();
    bad(
        "events.ttv",
        &events,
        &["--config", s(&other)],
        &["events.ttv", "made with configuration"],
    );
    // None of these runs touched the folder of the good one.
    for (f, bytes) in before {
        assert!(read(&out.join(&f)) == bytes, "{f} changed by a failed run");
    }
    let hidden = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .count();
    assert_eq!(hidden, 0, "a staging folder was left behind");
}

#[test]
fn force_event_streams_give_controls_outputs_and_replace_a_measurement_set() {
    let w = tempfile::tempdir().unwrap();
    let (toml, m) = measured(w.path());
    let c = w.path().join("c");
    let o = tooltouch(&["control", "--out", s(&c)]);
    assert!(o.status.success(), "{}", text(&o));
    let out = w.path().join("v");
    let o = vectors(&m.join("measure.vcd"), &["--config", s(&toml)], &out);
    assert!(o.status.success(), "{}", text(&o));
    assert!(out.join("golden.vcd").is_file());
    let o = vectors(&c.join("pi_estimated.events.ttv"), &[], &out);
    assert!(o.status.success(), "{}", text(&o));
    assert!(read(&out.join("expected_outputs.ttv")) == read(&c.join("pi_estimated.outputs.ttv")));
    assert!(read(&out.join("events.ttv")) == read(&c.join("pi_estimated.events.ttv")));
    // The measurement files of the earlier run are gone: nothing left to mislead.
    for f in ["golden.vcd", "stim.hex", "expect.hex"] {
        assert!(!out.join(f).exists(), "stale {f} left");
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&out.join("summary.json"))).unwrap();
    assert!(summary["measure_hash"].is_null(), "{summary}");
    assert!(
        summary["force_output_records"].as_u64().unwrap() > 100,
        "{summary}"
    );
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&out.join("expected_outputs.ttv")),
        "--dut",
        s(&c.join("pi_estimated.outputs.ttv")),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
}
