//! `cargo xtask fuzz`: coverage-guided fuzzing of every decoder and parser (the targets of
//! `fuzz/`) with libFuzzer, on the stable toolchain.
//!
//! libFuzzer comes from the `libfuzzer-sys` crate (its C++ sources, built with the
//! system's C++ compiler), and the coverage it is guided by from LLVM's SanitizerCoverage
//! pass, which stable rustc runs with `-C passes=sancov-module` and its `-C llvm-args`: no
//! nightly toolchain, no `RUSTC_BOOTSTRAP`, no `cargo fuzz`. No sanitizer either: the code
//! is safe Rust, and what the targets look for is a panic (overflow checks and debug
//! assertions are on), a hang (`-timeout`) or unbounded memory (`-rss_limit_mb`). The
//! flags apply to the target triple only (named explicitly, so build scripts and proc
//! macros are built without them) in their own target directory (`target/fuzz`), so the
//! ordinary builds keep their cache.
//!
//! The instrumented build is a second release build of the whole dependency tree (20 min
//! on 2 cores the first time, cached in `target/fuzz` after). The short pass of `cargo
//! xtask test` therefore runs the same targets and seeds *without* coverage
//! instrumentation ([`Build::Plain`]): built in the ordinary target directory next to the
//! release test build (only libFuzzer and the target binaries are new), libFuzzer then
//! mutates the seeds blindly — a smoke test against panics on near-valid input, not a
//! search; the coverage-guided search is `cargo xtask fuzz`.
//!
//! Each run starts from the committed seed corpus (`fuzz/corpus/<target>/`, read only) and
//! the inputs found by earlier runs on this machine (`target/fuzz/corpus/<target>/`). An
//! input that fails is written to `target/fuzz/artifacts/<target>/` and fails the verb
//! naming it; once fixed, it belongs in `fuzz/regressions/<target>/`, which `cargo test`
//! replays (`fuzz/tests/regressions.rs`).

use crate::process::root;
use anyhow::{bail, Context, Result};
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// The fuzz targets (binaries of `fuzz/`), in the order they run.
pub const TARGETS: [&str; 9] = [
    "ttv_outputs",
    "ttv_events",
    "force_chunks",
    "vcd",
    "stimulus",
    "settings",
    "tune_spec",
    "tune_merge",
    "abi",
];

/// Seconds per target of the short pass that `cargo xtask test` runs.
pub const CI_SECONDS: u64 = 3;

/// Coverage instrumentation for libFuzzer, all stable `-C` flags; `--cfg fuzzing` as
/// cargo-fuzz sets it.
const RUSTFLAGS: &[&str] = &[
    "-Cpasses=sancov-module",
    "-Cllvm-args=-sanitizer-coverage-level=4",
    "-Cllvm-args=-sanitizer-coverage-inline-8bit-counters",
    "-Cllvm-args=-sanitizer-coverage-pc-table",
    "-Cllvm-args=-sanitizer-coverage-trace-compares",
    "-Cdebug-assertions",
    "-Coverflow-checks",
    "--cfg=fuzzing",
];

/// Largest input, bytes: room for a few hundred records or VCD lines, small enough that
/// every execution is quick.
const MAX_LEN: u32 = 8192;

/// The host triple, from `rustc -vV`.
fn host_triple() -> Result<String> {
    let out = Command::new("rustc")
        .arg("-vV")
        .output()
        .context("running `rustc -vV`")?;
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("host: ").map(str::to_string))
        .context("`rustc -vV` names no host")
}

/// How the targets are built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Build {
    /// With coverage instrumentation, in `target/fuzz`: the coverage-guided search.
    Guided,
    /// Without, in the ordinary target directory: the short pass of `cargo xtask test`.
    Plain,
}

/// Builds every target; returns the folder of the binaries.
fn build(root: &Path, how: Build) -> Result<std::path::PathBuf> {
    if how == Build::Plain {
        crate::process::run(
            root,
            "cargo",
            &[
                "build",
                "--release",
                "--package",
                "tooltouch-fuzz",
                "--features",
                "libfuzzer",
                "--bins",
            ],
        )
        .context("`cargo xtask setup` installs the C++ compiler libFuzzer needs")?;
        return Ok(root.join("target/release"));
    }
    let triple = host_triple()?;
    let target_dir = root.join("target/fuzz");
    let args = [
        "build",
        "--release",
        "--package",
        "tooltouch-fuzz",
        "--features",
        "libfuzzer",
        "--bins",
        "--target",
        &triple,
        "--target-dir",
        target_dir.to_str().context("target dir is not UTF-8")?,
    ];
    println!(
        "$ RUSTFLAGS=\"{}\" cargo {}",
        RUSTFLAGS.join(" "),
        args.join(" ")
    );
    let status = Command::new("cargo")
        .args(args)
        .current_dir(root)
        .env("RUSTFLAGS", RUSTFLAGS.join(" "))
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .status()
        .context("could not start cargo")?;
    if !status.success() {
        bail!("building the fuzz targets failed ({status}); `cargo xtask setup` installs the C++ compiler libFuzzer needs");
    }
    Ok(target_dir.join(triple).join("release"))
}

/// One target's run: executions and wall time.
struct Run {
    target: &'static str,
    executions: u64,
    seconds: f64,
}

/// Runs `target` for `seconds`; fails naming the input that made it fail.
fn run_target(root: &Path, bin_dir: &Path, target: &'static str, seconds: u64) -> Result<Run> {
    let seeds = root.join("fuzz/corpus").join(target);
    let work = root.join("target/fuzz/corpus").join(target);
    let artifacts = root.join("target/fuzz/artifacts").join(target);
    for d in [&work, &artifacts] {
        std::fs::create_dir_all(d).with_context(|| format!("creating {}", d.display()))?;
    }
    let bin = bin_dir.join(target);
    let t = Instant::now();
    let out = Command::new(&bin)
        .arg(&work)
        .arg(&seeds)
        .arg(format!("-max_total_time={seconds}"))
        .arg(format!("-max_len={MAX_LEN}"))
        .arg("-timeout=10")
        .arg("-rss_limit_mb=1024")
        .arg("-print_final_stats=1")
        .arg(format!("-artifact_prefix={}/", artifacts.display()))
        .current_dir(root)
        .output()
        .with_context(|| format!("could not start {}", bin.display()))?;
    let elapsed = t.elapsed().as_secs_f64();
    let log = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        let tail: Vec<&str> = log.lines().rev().take(40).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        let input = log
            .lines()
            .find_map(|l| l.split("Test unit written to ").nth(1))
            .unwrap_or("(see the log above)");
        bail!(
            "fuzz target `{target}` failed ({}):\n{}\n\nthe failing input: {input}\nreproduce: {} {input}\n\
             once fixed, copy it into fuzz/regressions/{target}/ so `cargo test` replays it",
            out.status,
            tail.join("\n"),
            bin.display()
        );
    }
    let executions = log
        .lines()
        .find_map(|l| l.strip_prefix("stat::number_of_executed_units:"))
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(0);
    Ok(Run {
        target,
        executions,
        seconds: elapsed,
    })
}

/// `cargo xtask fuzz [--target T]… [--seconds N] [--plain]`: builds the targets, runs each
/// (or the named ones) for N seconds (default 60), prints executions per second;
/// `--plain`: the uninstrumented short pass of `cargo xtask test`.
pub fn run(args: &[String]) -> Result<()> {
    let mut targets: Vec<&'static str> = Vec::new();
    let mut seconds = 60u64;
    let mut how = Build::Guided;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--target" => {
                let name = it.next().context("--target needs a name")?;
                let t = TARGETS.iter().find(|t| *t == name).with_context(|| {
                    format!("no fuzz target `{name}`; targets: {}", TARGETS.join(", "))
                })?;
                targets.push(t);
            }
            "--seconds" => {
                let n = it.next().context("--seconds needs a number")?;
                seconds = n.parse().ok().filter(|&n| n > 0).with_context(|| {
                    format!("--seconds `{n}`: a whole number of seconds, 1 or more")
                })?;
            }
            "--plain" => how = Build::Plain,
            other => {
                bail!("cargo xtask fuzz: unknown argument `{other}` (--target T, --seconds N, --plain)")
            }
        }
    }
    if targets.is_empty() {
        targets = TARGETS.to_vec();
    }
    fuzz(&targets, seconds, how)
}

/// Builds and runs `targets` for `seconds` each; prints a table of executions per second.
pub fn fuzz(targets: &[&'static str], seconds: u64, how: Build) -> Result<()> {
    let root = root();
    let bin_dir = build(&root, how)?;
    let mut runs = Vec::new();
    for &t in targets {
        println!("fuzzing `{t}` for {seconds} s");
        runs.push(run_target(&root, &bin_dir, t, seconds)?);
    }
    println!(
        "\n{:<14} {:>12} {:>8} {:>10}",
        "target", "executions", "s", "exec/s"
    );
    for r in &runs {
        println!(
            "{:<14} {:>12} {:>8.1} {:>10.0}",
            r.target,
            r.executions,
            r.seconds,
            r.executions as f64 / r.seconds.max(1e-9)
        );
    }
    Ok(())
}
