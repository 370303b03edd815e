//! Snapshot test of the generated Verilog: the files `tooltouch hdl` writes (the design
//! and its testbench) and the testbench's Verilator driver, for the default configuration
//! and for one configuration that takes the other branches of the generators, compared
//! byte for byte with the files committed under `hdl-gen/snapshots/<name>/`. A generator
//! change thus shows as a reviewable diff of the Verilog: run `cargo xtask bless-hdl`
//! (which runs this test with `TOOLTOUCH_BLESS=1`) to rewrite the snapshots, then review
//! `git diff hdl-gen/snapshots`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use tooltouch_hdl_gen::{generate, testbench, verilator_main, Options, TestbenchSpec, VerilogFile};
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::{MeasureConfig, MeasureSettings};

/// Set to `1` to rewrite the snapshots instead of comparing with them.
const BLESS_VAR: &str = "TOOLTOUCH_BLESS";
/// The command that rewrites the snapshots.
const BLESS_COMMAND: &str = "cargo xtask bless-hdl";

/// One committed snapshot: a configuration and how its files are generated.
struct Snapshot {
    /// Folder under `hdl-gen/snapshots/`.
    name: &'static str,
    config: MeasureConfig,
    options: Options,
    testbench: TestbenchSpec,
}

/// The snapshots: the default configuration as `tooltouch hdl` writes it without options,
/// and a configuration taking the other branch of every generator choice it can: the
/// density method, the sampled contact rule, the exponential charge law, no glitch filter,
/// `i_def` = 0, a window of several revolutions, other widths, the diagnostic counters
/// readable by the MCU, another testbench clock and depths.
fn snapshots() -> Vec<Snapshot> {
    let other = MeasureSettings {
        pulses_per_rev: 500,
        i_def: 0,
        window_revs: 3,
        contact_rule: ContactRule::Sampled,
        charge_bits: 12,
        charge_law: ChargeLaw::Exponential {
            charge_shift: 3,
            discharge_shift: 6,
        },
        fire_threshold: 3000,
        rearm_threshold: 1000,
        glitch_cycles: 0,
        scale_bits: 20,
        method: DecisionMethod::Density,
        // The other branch of every check: each off.
        checks: tooltouch_model::MeasureChecks::OFF,
    }
    .validate()
    .expect("the snapshot configuration is valid");
    vec![
        Snapshot {
            name: "default",
            config: MeasureConfig::default(),
            options: Options::default(),
            // `tooltouch hdl`'s defaults.
            testbench: TestbenchSpec {
                clock_hz: 50_000_000,
                stim_depth: 1 << 16,
                expect_depth: 1 << 16,
                mcu_diagnostics: false,
            },
        },
        Snapshot {
            name: "density-exponential-sampled",
            config: other,
            options: Options {
                mcu_diagnostics: true,
                ..Options::default()
            },
            testbench: TestbenchSpec {
                clock_hz: 100_000_000,
                stim_depth: 4096,
                expect_depth: 8192,
                mcu_diagnostics: true,
            },
        },
    ]
}

/// Every file of a snapshot, in compile order.
fn generated(s: &Snapshot) -> Vec<VerilogFile> {
    let mut files = generate(&s.config, &s.options).files;
    files.extend(testbench(&s.config, &s.testbench));
    files.extend(verilator_main(&s.config, &s.testbench));
    files
}

fn snapshot_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("snapshots")
}

/// Names of the files in `dir` (none when it does not exist).
fn files_in(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok())
                .filter(|e| e.path().is_file())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default()
}

/// Where `committed` and `fresh` first differ: `path:line` and both lines.
fn first_difference(path: &str, committed: &str, fresh: &str) -> String {
    let mut a = committed.split_inclusive('\n');
    let mut b = fresh.split_inclusive('\n');
    let mut line = 1;
    loop {
        match (a.next(), b.next()) {
            (Some(x), Some(y)) if x == y => line += 1,
            (x, y) => {
                let show = |l: Option<&str>| match l {
                    Some(l) => format!("{:?}", l.trim_end_matches('\n')),
                    None => "(end of file)".to_string(),
                };
                return format!(
                    "{path}:{line}: first difference\n    committed: {}\n    generated: {}",
                    show(x),
                    show(y)
                );
            }
        }
    }
}

/// Rewrites the snapshot folders: the generated files, no other file, no other folder.
fn bless(root: &Path, snapshots: &[Snapshot]) {
    let names: BTreeSet<&str> = snapshots.iter().map(|s| s.name).collect();
    if let Ok(entries) = std::fs::read_dir(root) {
        for e in entries.filter_map(|e| e.ok()) {
            let stale =
                e.path().is_dir() && !names.contains(e.file_name().to_string_lossy().as_ref());
            if stale {
                std::fs::remove_dir_all(e.path()).expect("removing a stale snapshot folder");
                println!("removed {}", e.path().display());
            }
        }
    }
    for s in snapshots {
        let dir = root.join(s.name);
        std::fs::create_dir_all(&dir).expect("creating the snapshot folder");
        let files = generated(s);
        let keep: BTreeSet<String> = files.iter().map(|f| f.name.clone()).collect();
        for stale in files_in(&dir).difference(&keep) {
            std::fs::remove_file(dir.join(stale)).expect("removing a stale snapshot file");
            println!("removed {}/{stale}", dir.display());
        }
        for f in &files {
            let path = dir.join(&f.name);
            if std::fs::read_to_string(&path).ok().as_deref() != Some(f.text.as_str()) {
                std::fs::write(&path, &f.text).expect("writing a snapshot file");
                println!("wrote {}", path.display());
            }
        }
    }
}

#[test]
fn generated_verilog_equals_the_committed_snapshots() {
    let root = snapshot_root();
    let snapshots = snapshots();
    if std::env::var(BLESS_VAR).is_ok_and(|v| v == "1") {
        bless(&root, &snapshots);
        return;
    }
    let mut problems = Vec::new();
    let folders: BTreeSet<String> = std::fs::read_dir(&root)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok())
                .filter(|e| e.path().is_dir())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    let names: BTreeSet<String> = snapshots.iter().map(|s| s.name.to_string()).collect();
    for stale in folders.difference(&names) {
        problems.push(format!(
            "hdl-gen/snapshots/{stale}/: no such snapshot is generated"
        ));
    }
    for s in &snapshots {
        let dir = root.join(s.name);
        let files = generated(s);
        let fresh: BTreeSet<String> = files.iter().map(|f| f.name.clone()).collect();
        for stale in files_in(&dir).difference(&fresh) {
            problems.push(format!(
                "hdl-gen/snapshots/{}/{stale}: committed but no longer generated",
                s.name
            ));
        }
        for f in &files {
            let shown = format!("hdl-gen/snapshots/{}/{}", s.name, f.name);
            match std::fs::read_to_string(dir.join(&f.name)) {
                Err(_) => problems.push(format!("{shown}: generated but not committed")),
                Ok(committed) if committed != f.text => {
                    problems.push(first_difference(&shown, &committed, &f.text));
                }
                Ok(_) => {}
            }
        }
    }
    assert!(
        problems.is_empty(),
        "the generated Verilog differs from the committed snapshots:\n  {}\n\n\
         If the change is intended, run `{BLESS_COMMAND}` and review `git diff hdl-gen/snapshots`.",
        problems.join("\n  ")
    );
}

#[test]
fn a_difference_is_shown_with_its_file_and_line() {
    let shown = first_difference("f.v", "a\nb\nc\n", "a\nB\nc\n");
    assert!(shown.starts_with("f.v:2: first difference"), "{shown}");
    assert!(shown.contains("committed: \"b\"") && shown.contains("generated: \"B\""));
    let shorter = first_difference("f.v", "a\n", "a\nb\n");
    assert!(
        shorter.starts_with("f.v:2:") && shorter.contains("(end of file)"),
        "{shorter}"
    );
}
