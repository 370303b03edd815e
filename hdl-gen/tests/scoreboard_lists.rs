//! The generated regions of the simulator glue (the DPI-C and VPI scoreboards, their C
//! functions and the bench: `tooltouch_hdl_gen::scoreboard_lists`) are what the generator
//! writes from the model's output list now: an output added to `MeasureOutputs::LAYOUT`
//! without rewriting them (or a region edited by hand) fails here. `cargo xtask bless-hdl`
//! (which runs this test with `TOOLTOUCH_BLESS=1`) rewrites them.

use std::path::{Path, PathBuf};
use tooltouch_hdl_gen::scoreboard_lists::{
    marker_name, scoreboard_regions, splice, BEGIN_MARKER, SCOREBOARD_FILES,
};

/// Set to `1` to rewrite the regions instead of comparing with them.
const BLESS_VAR: &str = "TOOLTOUCH_BLESS";
/// The command that rewrites them.
const BLESS_COMMAND: &str = "cargo xtask bless-hdl";

fn repository_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("hdl-gen is a folder of the repository")
        .to_path_buf()
}

/// `file`'s committed text with every region generated afresh, or what is wrong with it.
fn regenerated(file: &str, committed: &str) -> Result<String, String> {
    let regions: Vec<_> = scoreboard_regions()
        .into_iter()
        .filter(|r| r.file == file)
        .collect();
    for line in committed.lines() {
        if let Some(name) = marker_name(line, BEGIN_MARKER) {
            if !regions.iter().any(|r| r.name == name) {
                return Err(format!("{file}: the region `{name}` is not generated"));
            }
        }
    }
    regions.iter().try_fold(committed.to_string(), |text, r| {
        splice(&text, r.name, &r.text).map_err(|e| format!("{file}: {e}"))
    })
}

/// Where `committed` and `fresh` first differ: `path:line` and both lines.
fn first_difference(path: &str, committed: &str, fresh: &str) -> String {
    let (mut a, mut b) = (committed.lines(), fresh.lines());
    let mut line = 1;
    loop {
        match (a.next(), b.next()) {
            (Some(x), Some(y)) if x == y => line += 1,
            (x, y) => {
                return format!(
                    "{path}:{line}: first difference\n    committed: {:?}\n    generated: {:?}",
                    x.unwrap_or("(end of file)"),
                    y.unwrap_or("(end of file)")
                )
            }
        }
    }
}

#[test]
fn the_scoreboards_output_lists_are_the_generated_ones() {
    let root = repository_root();
    let bless = std::env::var(BLESS_VAR).is_ok_and(|v| v == "1");
    let mut problems = Vec::new();
    for file in SCOREBOARD_FILES {
        let path = root.join(file);
        let committed = match std::fs::read_to_string(&path) {
            Ok(text) => text,
            Err(e) => {
                problems.push(format!("{file}: cannot read it ({e})"));
                continue;
            }
        };
        match regenerated(file, &committed) {
            Err(why) => problems.push(why),
            Ok(fresh) if fresh != committed => {
                if bless {
                    std::fs::write(&path, &fresh).expect("writing a scoreboard file");
                    println!("wrote {file}");
                } else {
                    problems.push(first_difference(file, &committed, &fresh));
                }
            }
            Ok(_) => {}
        }
    }
    assert!(
        problems.is_empty(),
        "the scoreboards' output lists differ from the generated ones:\n  {}\n\n\
         If the change is intended, run `{BLESS_COMMAND}` and review the diff.",
        problems.join("\n  ")
    );
}

#[test]
fn every_generated_region_has_its_markers_in_its_file() {
    let root = repository_root();
    for r in scoreboard_regions() {
        let text = std::fs::read_to_string(root.join(r.file)).expect("a scoreboard file");
        assert!(
            text.lines()
                .any(|l| marker_name(l, BEGIN_MARKER) == Some(r.name)),
            "{}: no `{BEGIN_MARKER}{}` line",
            r.file,
            r.name
        );
    }
}
