//! `tooltouch hdl --inject-fault NAME` offers every fault hdl-gen injects (`Fault::ALL`, by
//! `Fault::name`), for a user testing their own bench: each writes the design hdl-gen
//! generates with that fault, which differs from the correct one; a fault whose changed
//! parameter would leave its range in the configuration is refused naming it.

use crate::common::{s, text, tooltouch};
use std::path::Path;
use tooltouch_hdl_gen::{generate, Fault, Options};
use tooltouch_model::MeasureConfig;

/// The Verilog files of `dir`, by name.
fn verilog(dir: &Path) -> Vec<(String, String)> {
    let mut files: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "v"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    files.sort();
    files
}

#[test]
fn hdl_inject_fault_writes_each_of_hdl_gens_faults() {
    let w = tempfile::tempdir().unwrap();
    let config = MeasureConfig::default();
    let correct = generate(&config, &Options::default());
    let mut names = Vec::new();
    for fault in Fault::ALL {
        let out = w.path().join(fault.name());
        let o = tooltouch(&["hdl", "--inject-fault", fault.name(), "--out", s(&out)]);
        assert!(
            o.status.success(),
            "--inject-fault {}: {}",
            fault.name(),
            text(&o)
        );
        let want = generate(
            &config,
            &Options {
                fault,
                ..Options::default()
            },
        );
        let written = verilog(&out);
        for f in &want.files {
            let got = written.iter().find(|(n, _)| *n == f.name);
            assert_eq!(
                got.map(|(_, t)| t.as_str()),
                Some(f.text.as_str()),
                "--inject-fault {}: {} is not hdl-gen's",
                fault.name(),
                f.name
            );
        }
        assert_ne!(
            want.files,
            correct.files,
            "{}: the design is the correct one",
            fault.name()
        );
        names.push(fault.name());
    }
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), Fault::ALL.len(), "two faults share a name");

    // The same names in --help's list of values (the option is hidden: ask clap directly).
    let o = tooltouch(&[
        "hdl",
        "--inject-fault",
        "no-such-fault",
        "--out",
        s(&w.path().join("x")),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    for fault in Fault::ALL {
        assert!(
            text(&o).contains(fault.name()),
            "the error does not offer {}: {}",
            fault.name(),
            text(&o)
        );
    }
}

#[test]
fn hdl_inject_fault_refuses_a_fault_outside_its_range() {
    let w = tempfile::tempdir().unwrap();
    let settings = w.path().join("s.toml");
    std::fs::write(&settings, "[measure]\nglitch_cycles = 0\n").unwrap();
    let out = w.path().join("rtl");
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&settings),
        "--inject-fault",
        "glitch-filter-minus-one",
        "--out",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("--inject-fault glitch-filter-minus-one"),
        "{}",
        text(&o)
    );
    assert!(!out.exists(), "a refused run wrote {}", out.display());
}
