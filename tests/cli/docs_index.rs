//! docs/README.md, the docs index, is complete: it names every subcommand that `tooltouch
//! --help` lists, links every page under docs/, and its `cargo xtask` table lists exactly the
//! verbs that `xtask/src/main.rs` dispatches.

use crate::common;

use common::{text, tooltouch};
use std::collections::BTreeSet;
use std::path::Path;

fn read(path: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_index_names_every_subcommand() {
    let help = tooltouch(&["--help"]);
    assert!(help.status.success(), "{}", text(&help));
    let help = String::from_utf8_lossy(&help.stdout).into_owned();
    let commands: Vec<&str> = help
        .split_once("Commands:")
        .expect("`tooltouch --help` has no `Commands:`")
        .1
        .lines()
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|&c| c != "help")
        .collect();
    assert!(commands.len() >= 10, "{commands:?}");
    let index = read("docs/README.md");
    let missing: Vec<&&str> = commands
        .iter()
        .filter(|c| !index.contains(&format!("`tooltouch {c}")))
        .collect();
    assert!(
        missing.is_empty(),
        "docs/README.md names no `tooltouch <command>` for {missing:?}"
    );
}

#[test]
fn the_index_links_every_page() {
    let index = read("docs/README.md");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if name.ends_with(".md") && name != "README.md" && !index.contains(&format!("]({name}")) {
            missing.push(name);
        }
    }
    assert!(missing.is_empty(), "docs/README.md links no {missing:?}");
}

/// The verbs of the `match verb` in xtask's main: each arm's string literals.
fn xtask_verbs() -> BTreeSet<String> {
    let main = read("xtask/src/main.rs");
    let body = main
        .split_once("match verb {")
        .expect("xtask/src/main.rs has no `match verb {`")
        .1;
    let mut verbs = BTreeSet::new();
    for line in body.lines() {
        let line = line.trim();
        if line.starts_with("other =>") {
            break;
        }
        let Some((pattern, _)) = line.split_once("=>") else {
            continue;
        };
        for alternative in pattern.split('|') {
            let word = alternative.trim().trim_matches('"');
            if !word.starts_with('-') && !word.is_empty() {
                verbs.insert(word.to_string());
            }
        }
    }
    verbs
}

#[test]
fn the_index_lists_the_xtask_verbs_of_xtask() {
    let verbs = xtask_verbs();
    assert!(
        verbs.contains("test") && verbs.contains("mutants"),
        "{verbs:?}"
    );
    let index = read("docs/README.md");
    let table = index
        .split_once("## `cargo xtask`")
        .expect("docs/README.md has no `## `cargo xtask`` section")
        .1;
    let listed: BTreeSet<String> = table
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split_once('`'))
        .map(|(verb, _)| verb.to_string())
        .collect();
    // `ci` is `test` under another name; the table says so in `test`'s row.
    let expected: BTreeSet<String> = verbs.into_iter().filter(|v| v != "ci").collect();
    assert_eq!(
        listed, expected,
        "docs/README.md's `cargo xtask` table against xtask/src/main.rs"
    );
}
