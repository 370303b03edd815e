//! The `measure` and `check` commands end to end through the built binary: files written,
//! bad settings named, check's exit codes (0 match, 1 mismatch, 2 bad input).

use std::path::Path;
use std::process::Output;

use crate::common;
use common::{text, tooltouch};

fn measure(dir: &Path, extra: &[&str]) -> Output {
    let out = dir.to_str().unwrap();
    let mut args = vec!["measure", "--out", out, "--no-progress"];
    if !extra.contains(&"--repeats") {
        args.extend_from_slice(&["--repeats", "2"]);
    }
    args.extend_from_slice(extra);
    tooltouch(&args)
}

#[test]
fn measure_writes_its_files_and_check_accepts_them() {
    let dir = tempfile::tempdir().unwrap();
    let o = measure(dir.path(), &["--method", "counter", "--seed", "3"]);
    assert!(o.status.success(), "{}", text(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("decided 2/2"), "{table}");
    for f in [
        "contact_density.svg",
        "diameters.svg",
        "measure.vcd",
        "events.ttv",
        "expected_outputs.ttv",
        "summary.json",
    ] {
        let len = std::fs::metadata(dir.path().join(f))
            .map(|m| m.len())
            .unwrap_or(0);
        assert!(len > 100, "{f}: {len} bytes");
    }
    let staging_left = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(Result::ok)
        .any(|e| e.file_name().to_string_lossy().starts_with('.'));
    assert!(
        !staging_left,
        "a staging folder was left in the output folder"
    );
    let vcd = std::fs::read_to_string(dir.path().join("measure.vcd")).unwrap();
    assert!(
        vcd.trim_end().ends_with(" $end")
            && vcd
                .lines()
                .last()
                .unwrap()
                .starts_with("$comment tooltouch end cycles="),
        "the golden VCD ends with its closing comment"
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["summary"]["decided"], 2);
    assert_eq!(summary["settings"]["lathe"]["seed"], 3);
    assert_eq!(summary["measurements"].as_array().unwrap().len(), 2);

    for f in ["measure.vcd", "expected_outputs.ttv"] {
        let p = dir.path().join(f);
        let p = p.to_str().unwrap();
        let o = tooltouch(&["check", "--expected", p, "--dut", p]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o));
        assert!(text(&o).starts_with("OK"), "{}", text(&o));
    }
}

#[test]
fn check_exit_codes_for_mismatch_and_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let o = measure(dir.path(), &["--repeats", "1"]);
    assert!(o.status.success(), "{}", text(&o));
    let e = dir.path().join("measure.vcd");
    // Flip the first register_now rise into a 0.
    let golden = std::fs::read_to_string(&e).unwrap();
    let dump = tooltouch_vectors::vcd::Dump::parse(&golden, "e").unwrap();
    let id = &dump.find_in_scope("outputs", "register_now").unwrap().id;
    let flipped = golden.replacen(&format!("\n1{id}\n"), &format!("\n0{id}\n"), 1);
    assert_ne!(flipped, golden);
    let d = dir.path().join("dut.vcd");
    std::fs::write(&d, flipped).unwrap();
    let o = tooltouch(&[
        "check",
        "--expected",
        e.to_str().unwrap(),
        "--dut",
        d.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("signal register_now expected 0x1 got 0x0"),
        "{}",
        text(&o)
    );
    let junk = dir.path().join("junk.vcd");
    std::fs::write(&junk, "this is not a dump").unwrap();
    let o = tooltouch(&[
        "check",
        "--expected",
        e.to_str().unwrap(),
        "--dut",
        junk.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("junk.vcd"), "{}", text(&o));
    let o = tooltouch(&[
        "check",
        "--expected",
        "/nonexistent.vcd",
        "--dut",
        junk.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

#[test]
fn bad_settings_name_the_field_and_range() {
    let dir = tempfile::tempdir().unwrap();
    let o = measure(dir.path(), &["--i-def", "5000"]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("`i_def` = 5000") && text(&o).contains("0..=1023"),
        "{}",
        text(&o)
    );

    let o = measure(dir.path(), &["--rpm", "0"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("`rpm`"), "{}", text(&o));

    let o = measure(dir.path(), &["--z-step-mm", "0.5"]);
    assert!(
        text(&o).contains("`cycle.z_step_mm`") && text(&o).contains("nose radius"),
        "{}",
        text(&o)
    );

    let toml = dir.path().join("bad.toml");
    std::fs::write(
        &toml,
        "[measure]\nglitch_cycles = 4\nfire_threshold = 70000\n",
    )
    .unwrap();
    let o = measure(dir.path(), &["--config", toml.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("`fire_threshold` = 70000") && text(&o).contains("1..=65535"),
        "{}",
        text(&o)
    );

    // Flags win over the file.
    let o = measure(
        dir.path(),
        &[
            "--config",
            toml.to_str().unwrap(),
            "--fire-threshold",
            "40000",
            "--repeats",
            "1",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));

    std::fs::write(&toml, "[lathe]\nrmp = 800.0\n").unwrap();
    let o = measure(dir.path(), &["--config", toml.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("bad.toml") && text(&o).contains("rmp"),
        "{}",
        text(&o)
    );
}
