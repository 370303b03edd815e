//! The recipes of docs/ci.md ("Use tooltouch in your CI", once the README's), run as written.
//!
//! Each recipe is the fenced block after a `<!-- recipe: NAME -->` marker. The RTL and
//! firmware recipes run under `bash -eu` in a fresh folder holding the settings recipe, with
//! the built `tooltouch` first on `PATH` and the generated RTL (without its testbench) in
//! `rtl/` standing in for the user's design. The CI job's `run: |` steps must be those two
//! recipes, line for line, so the job file cannot drift either.

use crate::common;

use std::path::Path;
use std::process::Command;

/// docs/ci.md, the page that holds the recipes.
fn readme() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/ci.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The body of the fenced block that follows `<!-- recipe: name -->`.
fn recipe(readme: &str, name: &str) -> String {
    let marker = format!("<!-- recipe: {name} -->");
    let after = readme
        .split_once(&marker)
        .unwrap_or_else(|| panic!("docs/ci.md has no `{marker}`"))
        .1;
    let mut lines = after.lines().skip_while(|l| l.trim().is_empty());
    let fence = lines.next().unwrap_or_default();
    assert!(
        fence.starts_with("```"),
        "`{marker}` is not followed by a fenced block"
    );
    let body: Vec<&str> = lines.take_while(|l| !l.starts_with("```")).collect();
    body.join("\n") + "\n"
}

/// The `run: |` block of job `job` in the CI job recipe, dedented.
fn job_script(yaml: &str, job: &str) -> String {
    let mut in_job = false;
    let mut in_run = false;
    let mut indent = 0;
    let mut out = Vec::new();
    for line in yaml.lines() {
        let trimmed = line.trim_start();
        let depth = line.len() - trimmed.len();
        if depth == 2 && trimmed.ends_with(':') {
            in_job = trimmed == format!("{job}:");
            in_run = false;
            continue;
        }
        if !in_job {
            continue;
        }
        if in_run {
            if !trimmed.is_empty() && depth < indent {
                in_run = false;
            } else {
                if indent == 0 {
                    indent = depth;
                }
                out.push(line.get(indent..).unwrap_or(""));
                continue;
            }
        }
        if trimmed == "- run: |" {
            in_run = true;
            indent = 0;
            out.clear();
        }
    }
    assert!(
        !out.is_empty(),
        "the CI job recipe has no `run: |` step in job `{job}`"
    );
    out.join("\n") + "\n"
}

/// A fresh folder with the settings recipe and the generated RTL (no testbench) in `rtl/`.
fn workspace(readme: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("settings.toml"), recipe(readme, "settings")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .args(["hdl", "--config", "settings.toml", "--out", "rtl"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "hdl: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::remove_file(dir.path().join("rtl/tt_testbench.v")).unwrap();
    dir
}

/// Runs `script` under `bash -eu` in `dir` with the built `tooltouch` first on PATH.
fn run_recipe(name: &str, script: &str, dir: &Path) -> String {
    let (status, text) = common::bash_with_tooltouch(script, dir);
    assert!(
        status.success(),
        "docs/ci.md recipe `{name}` failed ({status}; missing tools come from `cargo xtask setup`):\n{text}"
    );
    text
}

#[test]
fn rtl_recipe_runs_as_written() {
    let readme = readme();
    let dir = workspace(&readme);
    let text = run_recipe("rtl", &recipe(&readme, "rtl"), dir.path());
    assert!(text.contains("TESTBENCH OK "), "{text}");
    assert!(text.contains("OK: ") && text.contains("cycles"), "{text}");
}

#[test]
fn firmware_recipe_runs_as_written() {
    let readme = readme();
    let dir = workspace(&readme);
    let text = run_recipe("firmware", &recipe(&readme, "firmware"), dir.path());
    assert!(
        text.contains("none lost or overflowed"),
        "the firmware recipe did not check a trace:\n{text}"
    );
}

#[test]
fn ci_job_steps_are_the_recipes() {
    let readme = readme();
    let yaml = recipe(&readme, "ci-job");
    for job in ["rtl", "firmware"] {
        assert_eq!(
            job_script(&yaml, job),
            recipe(&readme, job),
            "the CI job `{job}` in docs/ci.md runs other commands than the `{job}` recipe"
        );
    }
}
