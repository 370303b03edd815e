//! Helpers shared by the tests that run the built `tooltouch` binary.
#![allow(dead_code)] // each test binary uses its own subset

use std::path::Path;
use std::process::{Command, Output};

/// Runs the built `tooltouch` binary with `args`.
pub fn tooltouch(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .args(args)
        .output()
        .expect("the tooltouch binary runs")
}

/// A command's stdout and stderr, as text.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Runs `script` under `bash -euo pipefail` in `dir` with the built `tooltouch` first on
/// PATH, as a user's shell runs a documented recipe; its exit status and its stdout then
/// stderr as text.
pub fn bash_with_tooltouch(script: &str, dir: &Path) -> (std::process::ExitStatus, String) {
    let bin = Path::new(env!("CARGO_BIN_EXE_tooltouch")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = Command::new("bash")
        .args(["-euo", "pipefail", "-c", script])
        .env("PATH", path)
        .current_dir(dir)
        .output()
        .expect("bash runs");
    (out.status, text(&out))
}

/// A path as an argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The fast lathe of docs/quickstart.md's verification quick start and of the firmware's demo
/// stream: 1 MHz clock, 4800 rpm, one measurement in about 104 000 clocks.
pub const FAST_LATHE: &str = include_str!("../../firmware/demo-lathe.toml");

/// `iverilog -g2005 -o tb *.v && vvp tb <plusargs>` in `dir`; returns vvp's output.
pub fn icarus(dir: &Path, plusargs: &[&str]) -> String {
    for tool in ["iverilog", "vvp"] {
        if let Err(e) = tooltouch_rtl_sim::runner::find_tool(tool) {
            panic!("{e}");
        }
    }
    let mut sources: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".v"))
        .collect();
    sources.sort();
    let o = Command::new("iverilog")
        .args(["-g2005", "-o", "tb"])
        .args(&sources)
        .current_dir(dir)
        .output()
        .expect("iverilog runs");
    assert!(o.status.success(), "iverilog: {}", text(&o));
    let o = Command::new("vvp")
        .arg("tb")
        .args(plusargs)
        .current_dir(dir)
        .output()
        .expect("vvp runs");
    text(&o)
}
