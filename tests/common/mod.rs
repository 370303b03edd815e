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

/// A path as an argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The fast lathe of the README's verification quick start and of the firmware's demo
/// stream: 1 MHz clock, 6000 rpm, one measurement in about 84 000 clocks.
pub const FAST_LATHE: &str = include_str!("../../firmware/demo-lathe.toml");
