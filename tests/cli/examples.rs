//! Every settings file and sweep spec in `examples/` runs as its header says: the test
//! takes the `tooltouch ...` command lines of each file's leading comment, runs them in
//! order in a fresh folder holding a copy of `examples/`, and requires each to succeed
//! (a `check` to pass).

use crate::common;

use std::path::Path;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The commands in the leading comment of the example `file`: each `#   tooltouch …`
/// line, without its trailing `# …` remark, as arguments after `tooltouch`.
fn commands(file: &str) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(Path::new(ROOT).join("examples").join(file)).unwrap();
    text.lines()
        .take_while(|l| l.starts_with('#') || l.trim().is_empty())
        .filter_map(|l| l.trim_start_matches('#').trim().strip_prefix("tooltouch "))
        .map(|c| {
            let c = c.split(" # ").next().unwrap();
            c.split_whitespace().map(String::from).collect()
        })
        .collect()
}

fn copy_examples(to: &Path) {
    let from = Path::new(ROOT).join("examples");
    std::fs::create_dir_all(to.join("examples")).unwrap();
    for e in std::fs::read_dir(&from).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            std::fs::copy(e.path(), to.join("examples").join(e.file_name())).unwrap();
        }
    }
}

fn run_example(file: &str, expected_commands: usize) {
    let work = tempfile::tempdir().unwrap();
    copy_examples(work.path());
    let all = commands(file);
    assert_eq!(all.len(), expected_commands, "{file}: {all:?}");
    for args in all {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_tooltouch"))
            .args(&args)
            .current_dir(work.path())
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{file}: tooltouch {}: {}",
            args.join(" "),
            common::text(&o)
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(
            !stderr.contains("warning"),
            "{file}: an example uses an old spelling: {stderr}"
        );
    }
}

#[test]
fn the_measure_example_runs() {
    run_example("measure.toml", 2);
}

#[test]
fn the_vectors_and_check_example_runs_and_checks() {
    run_example("vectors.toml", 3);
}

#[test]
fn the_hdl_example_runs() {
    run_example("hdl.toml", 2);
}

#[test]
fn the_sweep_spec_runs_whole_and_sharded() {
    run_example("sweep.toml", 4);
}

#[test]
fn the_control_example_runs() {
    run_example("control.toml", 2);
}

#[test]
fn the_wear_example_runs() {
    run_example("wear.toml", 1);
}

#[test]
fn the_wear_presets_of_the_milling_paper_run() {
    for file in [
        "wear-fig6.toml",
        "wear-table2-z1.toml",
        "wear-table2-z5.toml",
    ] {
        run_example(file, 1);
    }
}

#[test]
fn the_first_rig_preset_runs_measure_and_budget() {
    run_example("rig1.toml", 2);
}

#[test]
fn the_second_rig_preset_runs_measure_and_budget() {
    run_example("rig2.toml", 2);
}

#[test]
fn the_spindle_path_example_runs_budget_and_measure() {
    run_example("spindle_path.toml", 2);
}

#[test]
fn the_optimizer_spec_answers() {
    run_example("optimize.toml", 1);
}
