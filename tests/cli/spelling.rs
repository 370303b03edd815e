//! One spelling for every enum value (kebab-case, docs/cli.md): the new spelling works on
//! the command line, in settings files and in sweep specs; the old one (`--method single`,
//! `single_pulse`, `permanent_contact`) still works for one release, gives the same
//! result, and warns on standard error naming the new one. Every sweep flag's help shows
//! its syntax.

use crate::common;

use common::{s, text, tooltouch, FAST_LATHE};
use std::path::Path;

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The vector files of a measure run (its summary holds wall times).
fn vectors(dir: &Path) -> (Vec<u8>, Vec<u8>) {
    (
        std::fs::read(dir.join("events.ttv")).unwrap(),
        std::fs::read(dir.join("expected_outputs.ttv")).unwrap(),
    )
}

#[test]
fn measure_reads_the_old_spellings_with_a_warning_and_the_same_result() {
    let d = tempfile::tempdir().unwrap();
    let new_file = d.path().join("new.toml");
    let old_file = d.path().join("old.toml");
    let body = "[measure]\nmethod = \"single-pulse\"\n";
    let cycle = "retract_at = \"permanent-contact\"\n";
    let fast = FAST_LATHE.replace("[lathe.cycle]\n", &format!("[lathe.cycle]\n{cycle}"));
    std::fs::write(&new_file, format!("{body}{fast}")).unwrap();
    std::fs::write(
        &old_file,
        format!("{body}{fast}")
            .replace("single-pulse", "single_pulse")
            .replace("permanent-contact", "permanent_contact"),
    )
    .unwrap();
    let run = |config: &Path, extra: &[&str], out: &str| {
        let out = d.path().join(out);
        let mut args = vec![
            "measure",
            "--config",
            s(config),
            "--vcd",
            "none",
            "--no-progress",
            "--out",
            s(&out),
        ];
        args.extend_from_slice(extra);
        let o = tooltouch(&args);
        assert!(o.status.success(), "{}", text(&o));
        (stderr(&o), vectors(&out))
    };
    let (quiet, reference) = run(&new_file, &[], "new");
    assert!(!quiet.contains("warning"), "{quiet}");
    let (warned, same) = run(&old_file, &[], "old");
    assert_eq!(same, reference);
    assert!(
        warned.contains("method: `single_pulse` is the old spelling of `single-pulse`"),
        "{warned}"
    );
    assert!(
        warned
            .contains("retract_at: `permanent_contact` is the old spelling of `permanent-contact`"),
        "{warned}"
    );
    // The flag: `--method single-pulse`, and the old `--method single`.
    let (quiet, flag_new) = run(&new_file, &["--method", "single-pulse"], "flag-new");
    assert!(!quiet.contains("warning"), "{quiet}");
    assert_eq!(flag_new, reference);
    let (warned, flag_old) = run(&new_file, &["--method", "single"], "flag-old");
    assert_eq!(flag_old, reference);
    assert!(
        warned.contains("--method: `single` is the old spelling of `single-pulse`"),
        "{warned}"
    );
    // The summary and the help use the new spelling only.
    let summary = std::fs::read_to_string(d.path().join("old/summary.json")).unwrap();
    assert!(summary.contains("\"single-pulse\"") && !summary.contains("single_pulse"));
    let help = text(&tooltouch(&["measure", "--help"]));
    assert!(
        help.contains("single-pulse") && help.contains("permanent-contact"),
        "{help}"
    );
    assert!(
        !help.contains("single_pulse") && !help.contains("[possible values: single,"),
        "{help}"
    );
}

#[test]
fn tune_reads_the_old_method_spelling_with_a_warning_and_the_same_result() {
    let d = tempfile::tempdir().unwrap();
    let one_point = [
        "--scenarios",
        "1",
        "--revolutions",
        "8",
        "--contact-rule",
        "sticky",
        "--law",
        "linear",
        "--charge-bits",
        "10",
        "--scale-bits",
        "16",
        "--glitch-cycles",
        "4",
        "--force-controller",
        "none",
    ];
    let run = |method: &str, out: &str| {
        let out = d.path().join(out);
        let mut args = vec!["tune", "--method", method, "--out", s(&out)];
        args.extend_from_slice(&one_point);
        let o = tooltouch(&args);
        assert!(o.status.success(), "{}", text(&o));
        (
            stderr(&o),
            std::fs::read_to_string(out.join("results.csv")).unwrap(),
        )
    };
    let (quiet, new) = run("counter,single-pulse", "new");
    assert!(!quiet.contains("warning"), "{quiet}");
    assert!(
        new.contains(",single-pulse,") && !new.contains("single_pulse"),
        "{new}"
    );
    let (warned, old) = run("counter,single_pulse", "old");
    assert_eq!(old, new);
    assert!(
        warned.contains("--method: `single_pulse` is the old spelling of `single-pulse`"),
        "{warned}"
    );
    // In a spec file too.
    let spec = d.path().join("spec.toml");
    std::fs::write(
        &spec,
        "method = [\"single_pulse\"]\nscenarios = 1\n[force]\ncontroller = []\n",
    )
    .unwrap();
    let o = tooltouch(&[
        "tune",
        "--spec",
        s(&spec),
        "--charge-bits",
        "10",
        "--glitch-cycles",
        "4",
        "--out",
        s(&d.path().join("spec")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        stderr(&o).contains("spec.toml: method: `single_pulse` is the old spelling"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn every_sweep_flag_shows_its_syntax_in_the_help() {
    let definition = tooltouch::cli::Cli::definition();
    let tune = definition.find_subcommand("tune").unwrap();
    let mut checked = 0;
    for a in tune.get_arguments() {
        let help = a.get_help().map(|h| h.to_string()).unwrap_or_default();
        let value_name = a
            .get_value_names()
            .and_then(|v| v.first())
            .map(|v| v.to_string());
        match value_name.as_deref() {
            Some("VALUES") => assert!(
                help.contains("`a,b,c`, `a`, `a..=b` or `a..=b:step`"),
                "--{:?}: {help}",
                a.get_long()
            ),
            Some("NAMES") => assert!(
                help.contains("a comma list of:"),
                "--{:?}: {help}",
                a.get_long()
            ),
            _ => continue,
        }
        checked += 1;
    }
    assert_eq!(
        checked, 18,
        "every sweep parameter has a flag with its syntax"
    );
    let help = text(&tooltouch(&["tune", "--help"]));
    assert!(
        help.contains("--charge-bits <VALUES>") && help.contains("a..=b:step"),
        "{help}"
    );
}

#[test]
fn control_vectors_are_ttv_files_like_every_vector_file() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("c");
    std::fs::create_dir_all(&out).unwrap();
    // A stale file of the old name is removed by the run.
    std::fs::write(out.join("pi_estimated.events.bin"), b"old").unwrap();
    let o = tooltouch(&["control", "--out", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    for f in ["pi_estimated.events.ttv", "pi_estimated.outputs.ttv"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    assert!(!out.join("pi_estimated.events.bin").exists());
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&out.join("pi_estimated.outputs.ttv")),
        "--dut",
        s(&out.join("pi_estimated.outputs.ttv")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
}
