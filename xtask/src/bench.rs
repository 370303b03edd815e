//! `cargo xtask bench`: the speed table of the golden model against Verilator and Icarus
//! (cycles/s and ratios, fast-forward, event level, control periods, state bytes), printed
//! by `benches/speed.rs` in its `--table` mode. Pass `--criterion` to also run the
//! criterion benches of the root package.

use anyhow::Result;

/// Runs the speed table (and, with `--criterion`, every criterion bench).
pub fn run(args: &[String]) -> Result<()> {
    let root = crate::process::root();
    crate::process::run(
        &root,
        "cargo",
        &[
            "bench",
            "-p",
            "tooltouch",
            "--bench",
            "speed",
            "--",
            "--table",
        ],
    )?;
    if args.iter().any(|a| a == "--criterion") {
        crate::process::run(&root, "cargo", &["bench", "-p", "tooltouch"])?;
    }
    Ok(())
}
