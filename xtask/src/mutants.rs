//! `cargo xtask mutants [--file F]…`: mutation testing with cargo-mutants (installed when
//! missing), of the golden model against its own unit tests and of the firmware's
//! handlers against their host tests, with a score per file.
//!
//! Why it is shaped so: the firmware runs the model's kernels, so co-simulation cannot see
//! a wrong kernel; the model's own tests can, and this verb measures how well. It is not
//! part of `cargo xtask test` (a full run takes hours on two cores): run it per file while
//! writing tests, and record the last run in docs/mutants.md. Mutants that no test can
//! kill are listed with their reason in docs/mutants.md and skipped by
//! `.cargo/mutants.toml` (the handlers have none: every one is caught).
//!
//! The model's mutants are built in cargo-mutants' scratch copy of the workspace; the
//! firmware is its own workspace with a path dependency on `../model`, which a copy of
//! `firmware/` alone would lose, so its mutants are applied in place (cargo-mutants puts
//! the file back after each one) — leave `firmware/src` alone while it runs.

use anyhow::{bail, Context, Result};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use crate::process::root;

/// The tail of the model's `cargo mutants` command: after the first `--`, the arguments of
/// `cargo test` (its unit tests only), after the second those of the test binary (without
/// the test kit's slow profile sweep; the kit itself is not mutated).
const MODEL_TEST_ARGS: &[&str] = &[
    "--",
    "--lib",
    "--",
    "--skip",
    "testing::tests::every_profile_validates",
];

/// The firmware file whose mutants the handlers' host tests are measured on.
const FIRMWARE_HANDLERS: &str = "firmware/src/handlers.rs";

/// `cargo xtask mutants [--file F]…`: every model file and the handlers, or only the
/// files named (paths from the workspace root).
pub fn run(args: &[String]) -> Result<()> {
    let mut files = Vec::new();
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--file" | "-f" => files.push(rest.next().context("--file needs a path")?.clone()),
            other => bail!("unknown argument `{other}` (usage: cargo xtask mutants [--file F]…)"),
        }
    }
    ensure_installed()?;
    let root = root();
    let (firmware, model): (Vec<_>, Vec<_>) =
        files.iter().partition(|f| f.starts_with("firmware/"));
    let everything = files.is_empty();
    let mut scores = BTreeMap::new();
    if everything || !model.is_empty() {
        let out = root.join("target/mutants/model");
        let argv = model_argv(&out, &model);
        cargo_mutants(&root, &argv, &out)?;
        tally(&out.join("mutants.out"), "", &mut scores)?;
    }
    if everything || !firmware.is_empty() {
        if let Some(other) = firmware.iter().find(|f| f.as_str() != FIRMWARE_HANDLERS) {
            bail!("firmware mutants are measured on {FIRMWARE_HANDLERS} only, not {other}");
        }
        let out = root.join("target/mutants/firmware");
        let host = crate::firmware::host_triple()?;
        let argv: Vec<String> = vec![
            "mutants".into(),
            "--in-place".into(),
            "--file".into(),
            "src/handlers.rs".into(),
            "--no-default-features".into(),
            format!("--cargo-arg=--target={host}"),
            "--output".into(),
            out.display().to_string(),
        ];
        cargo_mutants(&root.join("firmware"), &argv, &out)?;
        tally(&out.join("mutants.out"), "firmware/", &mut scores)?;
    }
    print_scores(&scores);
    Ok(())
}

/// `cargo mutants …` for the model's mutants of `files` (every file when empty), results
/// in `out`.
fn model_argv(out: &Path, files: &[&String]) -> Vec<String> {
    let mut argv: Vec<String> = [
        "mutants",
        "--package",
        "tooltouch-model",
        "--features",
        "testing",
        "--output",
    ]
    .map(String::from)
    .to_vec();
    argv.push(out.display().to_string());
    for f in files {
        argv.push("--file".into());
        argv.push((*f).clone());
    }
    argv.extend(MODEL_TEST_ARGS.iter().map(|s| s.to_string()));
    argv
}

/// Installs cargo-mutants with `cargo install --locked` unless `cargo mutants --version`
/// already works.
fn ensure_installed() -> Result<()> {
    let present = Command::new("cargo")
        .args(["mutants", "--version"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !present {
        crate::process::run(&root(), "cargo", &["install", "cargo-mutants", "--locked"])?;
    }
    Ok(())
}

/// Runs `cargo mutants` in `dir`, its results in `out` (created with its parents). Its exit status is 2 when mutants were missed and 3 on
/// timeouts: results, not failures; anything else non-zero is.
fn cargo_mutants(dir: &Path, argv: &[String], out: &Path) -> Result<()> {
    // cargo-mutants creates `out` itself but not its parents (`target/mutants/`).
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    println!("$ (cd {}) cargo {}", dir.display(), argv.join(" "));
    let status = Command::new("cargo")
        .args(argv)
        .current_dir(dir)
        .status()
        .context("could not start `cargo mutants`")?;
    match status.code() {
        Some(0 | 2 | 3) => Ok(()),
        _ => bail!("`cargo {}` failed ({status})", argv.join(" ")),
    }
}

/// Mutant outcomes of one file.
#[derive(Default)]
struct Score {
    caught: u32,
    timeout: u32,
    missed: u32,
    unviable: u32,
}

/// Adds the outcomes listed in cargo-mutants' `caught.txt`, `timeout.txt`, `missed.txt`
/// and `unviable.txt` (one mutant a line, `path:line:col: …`) to `scores`, paths prefixed
/// with `prefix`.
fn tally(out: &Path, prefix: &str, scores: &mut BTreeMap<String, Score>) -> Result<()> {
    for name in ["caught.txt", "timeout.txt", "missed.txt", "unviable.txt"] {
        let path = out.join(name);
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            let file = line.split(':').next().unwrap_or(line);
            let s = scores.entry(format!("{prefix}{file}")).or_default();
            match name {
                "caught.txt" => s.caught += 1,
                "timeout.txt" => s.timeout += 1,
                "missed.txt" => s.missed += 1,
                _ => s.unviable += 1,
            }
        }
    }
    Ok(())
}

/// Prints a Markdown table: per file the outcomes and the score, caught (timeouts
/// included) over viable mutants.
fn print_scores(scores: &BTreeMap<String, Score>) {
    println!("\n| file | caught | timeout | missed | unviable | score |");
    println!("|---|---:|---:|---:|---:|---:|");
    let mut total = Score::default();
    for (file, s) in scores {
        println!("{}", row(file, s));
        total.caught += s.caught;
        total.timeout += s.timeout;
        total.missed += s.missed;
        total.unviable += s.unviable;
    }
    println!("{}", row("**all**", &total));
}

fn row(file: &str, s: &Score) -> String {
    let killed = s.caught + s.timeout;
    let viable = killed + s.missed;
    let score = if viable == 0 {
        "–".to_string()
    } else {
        format!("{:.1} %", 100.0 * f64::from(killed) / f64::from(viable))
    };
    format!(
        "| {file} | {} | {} | {} | {} | {score} |",
        s.caught, s.timeout, s.missed, s.unviable
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_model_test_arguments_follow_the_separator() {
        let file = "model/src/measure/density.rs".to_string();
        let argv = model_argv(Path::new("out"), &[&file]);
        let tail: Vec<&str> = argv.iter().map(String::as_str).collect();
        // cargo-mutants' own options, then `--` and cargo test's, then `--` and the binary's.
        let first = tail.iter().position(|a| *a == "--").unwrap();
        assert_eq!(&tail[first..first + 3], ["--", "--lib", "--"]);
        assert!(tail[..first]
            .windows(2)
            .any(|w| w == ["--file", file.as_str()]));
        assert!(tail[..first].windows(2).any(|w| w == ["--output", "out"]));
    }

    #[test]
    fn outcomes_are_tallied_per_file() {
        let dir = std::env::temp_dir().join(format!("xtask-mutants-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
        write(
            "caught.txt",
            "src/a.rs:1:1: replace f with ()\nsrc/a.rs:2:1: replace g with ()\nsrc/b.rs:3:1: x\n",
        );
        write("timeout.txt", "src/b.rs:4:1: replace h -> u32 with 1\n");
        write("missed.txt", "src/a.rs:5:9: replace < with <= in f\n");
        write("unviable.txt", "\n");
        let mut scores = BTreeMap::new();
        tally(&dir, "firmware/", &mut scores).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let a = &scores["firmware/src/a.rs"];
        assert_eq!((a.caught, a.timeout, a.missed, a.unviable), (2, 0, 1, 0));
        assert_eq!(row("a", a), "| a | 2 | 0 | 1 | 0 | 66.7 % |");
        let b = &scores["firmware/src/b.rs"];
        assert_eq!(row("b", b), "| b | 1 | 1 | 0 | 0 | 100.0 % |");
        assert_eq!(
            row("none", &Score::default()),
            "| none | 0 | 0 | 0 | 0 | – |"
        );
    }
}
