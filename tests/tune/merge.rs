//! `tooltouch tune`: a sweep split into shards and merged equals the unsharded sweep, and
//! bad sweep specifications are errors naming the parameter.

use std::process::Command;
use tooltouch::cli::tune::write_files;
use tooltouch_tune::scenario::ApproachSettings;
use tooltouch_tune::{self as tune, output, Overrides, Shard, SweepSpec};

/// A small sweep: 12 points on 2 short scenarios (64 ppr at 6000 rpm).
fn small_spec() -> SweepSpec {
    let mut spec = SweepSpec {
        scenarios: 2,
        approach: ApproachSettings {
            rpm: 6000.0,
            pulses_per_rev: 64,
            revolutions: 12,
            ..Default::default()
        },
        ..Default::default()
    };
    spec.apply(&Overrides {
        values: vec![
            ("method".into(), "counter,density".into()),
            ("contact_rule".into(), "sticky".into()),
            ("charge_bits".into(), "6..=12:6".into()),
            ("glitch_cycles".into(), "0,4".into()),
            ("scale_bits".into(), "16".into()),
            ("i_def".into(), "32".into()),
            ("law".into(), "linear".into()),
            ("force.controller".into(), "pi".into()),
            ("force.kp_percent".into(), "100".into()),
            ("force.ki_percent".into(), "50,100".into()),
        ],
        ..Default::default()
    })
    .unwrap();
    spec
}

#[test]
fn sharded_and_merged_equals_unsharded() {
    let spec = small_spec();
    let whole = tune::run(&spec, None, &|| {}).unwrap();
    assert_eq!(whole.points, 8);
    assert_eq!(whole.rows.len(), 8);
    assert_eq!(whole.force_points, 2);
    assert_eq!(whole.force.len(), 2);
    for f in &whole.force {
        assert!(f.iae_model > 0.0 && f.iae_reference > 0.0, "{f:?}");
    }
    assert!(whole.rows.iter().any(|r| r.pareto), "a front exists");
    let parts: Vec<_> = (0..3)
        .map(|k| tune::run(&spec, Some(Shard { k, n: 3 }), &|| {}).unwrap())
        .collect();
    assert_eq!(parts.iter().map(|p| p.rows.len()).sum::<usize>(), 8);
    assert_eq!(parts.iter().map(|p| p.force.len()).sum::<usize>(), 2);
    // Through the files, as a batch system would.
    let dir = tempfile::tempdir().unwrap();
    let mut dirs = Vec::new();
    for (k, p) in parts.iter().enumerate() {
        let d = dir.path().join(format!("shard{k}"));
        write_files(p, &d).unwrap();
        dirs.push(d);
    }
    let read: Vec<_> = dirs.iter().map(|d| output::read(d).unwrap()).collect();
    let merged = tune::merge(&read).unwrap();
    assert_eq!(merged, whole);
    let (a, b) = (dir.path().join("whole"), dir.path().join("merged"));
    write_files(&whole, &a).unwrap();
    write_files(&merged, &b).unwrap();
    for f in [output::JSON, output::CSV, output::FORCE_CSV, output::SVG] {
        let x = std::fs::read(a.join(f)).unwrap();
        assert!(!x.is_empty(), "{f}");
        assert_eq!(x, std::fs::read(b.join(f)).unwrap(), "{f} differs");
    }
    // A missing or doubled shard is an error.
    let e = tune::merge(&read[..2]).unwrap_err().to_string();
    assert!(e.contains("missing"), "{e}");
    let twice = [
        read[0].clone(),
        read[0].clone(),
        read[1].clone(),
        read[2].clone(),
    ];
    let e = tune::merge(&twice).unwrap_err().to_string();
    assert!(e.contains("twice"), "{e}");
}

#[test]
fn the_cli_merges_shards_like_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("spec.toml");
    std::fs::write(
        &spec,
        "scenarios = 1\nmethod = [\"counter\"]\ncontact_rule = \"sticky,sampled\"\n\
         charge_bits = [8]\nscale_bits = \"16\"\nglitch_cycles = \"0..=4:2\"\ni_def = 32\n\
         law = [\"exponential\"]\ndischarge_shift = [4]\n[force]\ncontroller = []\n\
         [approach]\nrpm = 6000.0\npulses_per_rev = 64\nrevolutions = 10\n",
    )
    .unwrap();
    let exe = env!("CARGO_BIN_EXE_tooltouch");
    let run = |args: &[&str]| {
        let out = Command::new(exe).args(args).output().unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let p = |s: &str| dir.path().join(s).to_string_lossy().into_owned();
    let spec_s = spec.to_string_lossy().into_owned();
    run(&["tune", "--spec", &spec_s, "--out", &p("whole")]);
    run(&[
        "tune",
        "--spec",
        &spec_s,
        "--shard",
        "0/2",
        "--out",
        &p("s0"),
    ]);
    run(&[
        "tune",
        "--spec",
        &spec_s,
        "--shard",
        "1/2",
        "--out",
        &p("s1"),
    ]);
    run(&["tune", "merge", &p("s0"), &p("s1"), "--out", &p("merged")]);
    let whole = std::fs::read_to_string(dir.path().join("whole/results.json")).unwrap();
    let merged = std::fs::read_to_string(dir.path().join("merged/results.json")).unwrap();
    assert_eq!(whole, merged);
    assert_eq!(output::read(&dir.path().join("whole")).unwrap().points, 6);
}

fn cli_error(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .arg("tune")
        .args(args)
        .args(["--out", "/nonexistent/never-written"])
        .output()
        .unwrap();
    assert!(!out.status.success(), "{args:?} was accepted");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn bad_specs_are_errors_naming_the_parameter() {
    for (args, names) in [
        (
            &["--charge-bits", "16..=8"][..],
            "`charge_bits`: empty range 16..=8",
        ),
        (
            &["--glitch-cycles", "two"][..],
            "`glitch_cycles`: `two` is not an integer",
        ),
        (
            &["--scale-bits", "8..=16:0"][..],
            "`scale_bits`: range step 0",
        ),
        (
            &["--scale-bits", "40"][..],
            "`scale_bits`: value 40 is out of range",
        ),
        (
            &["--method", "guess"][..],
            "`method`: unknown value `guess`",
        ),
        (&["--law", ""][..], "`law`: no values"),
        (
            &["--shard", "3/3"][..],
            "`shard`: K = 3 must be below N = 3",
        ),
        (&["--shard", "0/0"][..], "`shard`: N must be at least 1"),
        (&["--shard", "1-2"][..], "`shard`: `1-2` is not K/N"),
        (&["--i-def", "2000"][..], "`i_def`"),
        (&["--rearm-percent", "80"][..], "`rearm_percent`"),
        (
            &["--force-controller", "pd"][..],
            "`force.controller`: unknown value `pd`",
        ),
        (
            &["--kp-percent", "0"][..],
            "`force.kp_percent`: value 0 is out of range",
        ),
    ] {
        let e = cli_error(args);
        assert!(e.contains(names), "{args:?}: {e}");
    }
}

#[test]
fn bad_spec_files_name_the_parameter() {
    let e = SweepSpec::from_toml("charge_bitz = [8]").unwrap_err();
    assert_eq!(e.parameter, "charge_bitz");
    let mut s = SweepSpec::from_toml("charge_bits = []").unwrap();
    assert_eq!(s.points().unwrap_err().parameter, "charge_bits");
    s = SweepSpec::from_toml("scenarios = 0").unwrap();
    assert_eq!(s.points().unwrap_err().parameter, "scenarios");
}
