//! Output folders that cannot mislead, through the built binary: a run into a folder
//! holding another run's files replaces all of that command's files and removes the stale
//! ones (`measure --vcd none` removes the earlier measure.vcd; `control` removes other
//! controllers' files); a failed run leaves the folder as it was; no staging folder is left
//! behind. `measure` exits 1 when a measurement did not decide, its files written.

use std::path::Path;
use std::process::Output;

use crate::common;
use common::{s, text, tooltouch};

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

use crate::common::FAST_LATHE as FAST;

fn measure(toml: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "measure",
        "--config",
        s(toml),
        "--out",
        s(out),
        "--no-progress",
    ];
    args.extend_from_slice(extra);
    tooltouch(&args)
}

#[test]
fn measure_replaces_its_files_and_removes_the_stale_vcd() {
    let w = tempfile::tempdir().unwrap();
    let toml = w.path().join("fast.toml");
    std::fs::write(&toml, FAST).unwrap();
    let out = w.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    // 4800 rpm: at the demo lathe's 6000 rpm the glitch filter loses FES pulses (a fault).
    let o = measure(&toml, &out, &["--rpm", "4800"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(out.join("measure.vcd").is_file());
    let o = measure(
        &toml,
        &out,
        &["--rpm", "4800", "--vcd", "none", "--i-def", "500"],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        names(&out),
        [
            "contact_density.svg",
            "diameters.svg",
            "events.ttv",
            "expected_outputs.ttv",
            "notes.txt",
            "summary.json"
        ],
        "measure.vcd of the earlier run removed, the user's file kept, no staging folder"
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["vcd"], "none");

    // A failed run changes nothing.
    let before: Vec<Vec<u8>> = names(&out)
        .iter()
        .map(|n| std::fs::read(out.join(n)).unwrap())
        .collect();
    let o = measure(&toml, &out, &["--i-def", "5000"]);
    assert!(!o.status.success());
    let after: Vec<Vec<u8>> = names(&out)
        .iter()
        .map(|n| std::fs::read(out.join(n)).unwrap())
        .collect();
    assert!(before == after, "a failed run changed the folder");
}

#[test]
fn measure_names_a_fault_shows_no_diameter_for_it_and_exits_1() {
    // At 6000 rpm and 1 MHz the 4-clock glitch filter loses FES pulses: `pulses_lost`.
    let w = tempfile::tempdir().unwrap();
    let toml = w.path().join("fast.toml");
    std::fs::write(&toml, FAST).unwrap();
    let out = w.path().join("out");
    let o = measure(&toml, &out, &["--rpm", "6000", "--vcd", "none"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("—   FAULT pulses_lost\n")
            && t.contains("status: 0/1 confirmed; 1 faulted")
            && t.contains("(1 faulted) (exit code 1)"),
        "{t}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let m = &json["measurements"][0];
    assert_eq!(m["fault_names"], serde_json::json!(["pulses_lost"]));
    assert_eq!(
        (m["faults"].as_u64(), m["accepted"].as_bool()),
        (Some(2), Some(false))
    );
    assert!(m["diameter_mm"].is_null());
    assert_eq!(json["summary"]["faulted"], 1);
    // The same lathe at 4800 rpm is clean: every measurement confirmed.
    let o = measure(&toml, &out, &["--rpm", "4800", "--vcd", "none"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("status: 1/1 confirmed, no fault"),
        "{}",
        text(&o)
    );
}

#[test]
fn measure_exits_1_when_a_measurement_does_not_decide() {
    let w = tempfile::tempdir().unwrap();
    let toml = w.path().join("fast.toml");
    std::fs::write(&toml, FAST).unwrap();
    let out = w.path().join("out");
    let o = measure(&toml, &out, &["--max-approach-revs", "1"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("decided 0/1")
            && text(&o).contains("1 of 1 measurements did not decide or were not accepted ("),
        "{}",
        text(&o)
    );
    assert!(out.join("summary.json").is_file(), "the files are written");
    let help = tooltouch(&["measure", "--help"]);
    assert!(
        text(&help).contains(
            "1 the run completed and wrote its files, but some measurement did not decide"
        ),
        "{}",
        text(&help)
    );
}

#[test]
fn control_replaces_other_controllers_files() {
    let w = tempfile::tempdir().unwrap();
    let out = w.path().join("c");
    let o = tooltouch(&["control", "--out", s(&out), "--force", "both"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(out.join("pi_measured.outputs.ttv").is_file());
    let o = tooltouch(&["control", "--out", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        names(&out),
        [
            "control.csv",
            "control.json",
            "pi_estimated.csv",
            "pi_estimated.events.ttv",
            "pi_estimated.json",
            "pi_estimated.outputs.ttv",
            "pi_estimated.svg"
        ]
    );
}
