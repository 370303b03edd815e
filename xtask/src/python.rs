//! The Python package (python/): a venv with the pinned tools, the wheel built by maturin
//! and installed into it (`cargo xtask setup`), its pytest suite and the cocotb bench of the
//! generated RTL, tests/cocotb (`cargo xtask test`).
//!
//! The venv lives in `target/py-venv` so `cargo clean` removes it with every other build
//! product and git ignores it with target/. Its packages come from
//! `python/requirements-dev.txt` (exact `==` pins) and are reinstalled only when that file
//! changes (a copy is kept in the venv as a stamp). The wheel is rebuilt on every setup:
//! maturin builds through cargo in the workspace's `target/release`, so an unchanged
//! crate costs a few seconds and the host crate's release build is shared with the tests.

use crate::process::{root, run};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The venv, relative to the workspace root.
const VENV: &str = "target/py-venv";
/// Where maturin writes the wheel, relative to the workspace root.
const WHEELS: &str = "target/py-wheels";
/// The pinned requirements, relative to the workspace root.
const REQUIREMENTS: &str = "python/requirements-dev.txt";
/// A copy of the requirements the venv was last installed from.
const STAMP: &str = "requirements-installed.txt";

/// A program of the venv (`python`, `pip`, `maturin`).
fn venv_program(root: &Path, name: &str) -> PathBuf {
    root.join(VENV).join("bin").join(name)
}

/// Creates the venv, installs the pinned requirements when they changed, builds the wheel
/// and installs it.
pub fn setup() -> Result<()> {
    let root = root();
    let python = venv_program(&root, "python");
    if !python.is_file() {
        run(&root, "python3", &["-m", "venv", VENV]).context(
            "creating the Python venv needs CPython >= 3.9 with the venv module as `python3` \
             (Debian: apt-get install python3-venv)",
        )?;
    }
    let requirements = std::fs::read_to_string(root.join(REQUIREMENTS))
        .with_context(|| format!("reading {REQUIREMENTS}"))?;
    let stamp = root.join(VENV).join(STAMP);
    if std::fs::read_to_string(&stamp).ok().as_deref() != Some(requirements.as_str()) {
        let pip = venv_program(&root, "pip");
        run(
            &root,
            &pip.to_string_lossy(),
            &["install", "--quiet", "--requirement", REQUIREMENTS],
        )?;
        std::fs::write(&stamp, &requirements).context("writing the venv's requirements stamp")?;
    }
    let wheels = root.join(WHEELS);
    if wheels.exists() {
        std::fs::remove_dir_all(&wheels).with_context(|| format!("removing {WHEELS}"))?;
    }
    let maturin = venv_program(&root, "maturin");
    run(
        &root,
        &maturin.to_string_lossy(),
        &[
            "build",
            "--release",
            "--quiet",
            "--manifest-path",
            "python/Cargo.toml",
            "--out",
            WHEELS,
        ],
    )?;
    let wheel = std::fs::read_dir(&wheels)
        .with_context(|| format!("reading {WHEELS}"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "whl"))
        .with_context(|| format!("maturin wrote no wheel into {WHEELS}"))?;
    run(
        &root,
        &python.to_string_lossy(),
        &[
            "-m",
            "pip",
            "install",
            "--quiet",
            "--force-reinstall",
            "--no-deps",
            &wheel.to_string_lossy(),
        ],
    )?;
    println!("setup: Python package installed into {VENV}");
    Ok(())
}

/// Runs the package's pytest suite in the venv against the release CLI.
pub fn test() -> Result<()> {
    pytest("python/tests")
}

/// Runs the cocotb bench of `tt_frontend` (tests/cocotb) under Icarus and Verilator, in
/// the venv, with the release CLI generating the Verilog.
pub fn cocotb() -> Result<()> {
    pytest("tests/cocotb")
}

/// `pytest -q <tests>` in the venv with `TOOLTOUCH_BIN` set to the release CLI (built).
fn pytest(tests: &str) -> Result<()> {
    let root = root();
    let python = venv_program(&root, "python");
    if !python.is_file() {
        bail!("no Python venv at {VENV}: run `cargo xtask setup` first");
    }
    run(
        &root,
        "cargo",
        &[
            "build",
            "--release",
            "-p",
            "tooltouch",
            "--bin",
            "tooltouch",
        ],
    )?;
    let cli = root.join("target/release/tooltouch");
    println!(
        "$ (cd {}) {VENV}/bin/python -m pytest {tests}",
        root.display()
    );
    let status = std::process::Command::new(&python)
        .args(["-m", "pytest", "-q", tests])
        .env("TOOLTOUCH_BIN", &cli)
        .current_dir(&root)
        .status()
        .context("could not start the venv's python")?;
    if !status.success() {
        bail!("pytest {tests} failed ({status})");
    }
    Ok(())
}
