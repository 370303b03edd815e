//! `cargo xtask hdl-report`: writes the Verilog of the default configuration with
//! `tooltouch hdl`, synthesizes the chip top `tt_fpga` with yosys `synth_ice40`, places
//! and routes it with nextpnr-ice40 for an HX8K (ct256), and prints logic cells,
//! flip-flops and fmax against the targets (≥ 150 MHz, ≤ 400 logic cells).
//!
//! nextpnr exits 1 when `--freq` is not met, so fmax is read from its log, and a missed
//! target is reported, not an error.

use anyhow::{bail, Context, Result};
use std::process::Command;

/// Target clock, MHz.
const TARGET_MHZ: f64 = 150.0;
/// Target size, iCE40 logic cells.
const TARGET_CELLS: u64 = 400;
/// synth_ice40 options: ABC9 mapping, and clock enables only for enables shared by 64
/// or more flip-flops (otherwise nextpnr promotes each enable to a global buffer, which
/// costs more than a LUT input). Chosen by trying the combinations; see the README.
const SYNTH_FLAGS: &str = "-abc9 -dffe_min_ce_use 64";
/// Placement seed, fixed so that the report is repeatable (fmax varies by a few MHz
/// with the seed).
const SEED: &str = "1";

/// The design files in compile order (as written by `tooltouch hdl`).
const FILES: &[&str] = &[
    "tt_synchronizer.v",
    "tt_glitch_filter.v",
    "tt_edge_detect.v",
    "tt_pulse_counter.v",
    "tt_density_detector.v",
    "tt_quadrature_decoder.v",
    "tt_position_latch.v",
    "tt_measurement.v",
    "tt_frontend.v",
    "tt_fpga.v",
];

/// Sums the counts of yosys `stat` lines whose cell name starts with `prefix`, in the
/// last statistics block of `log`.
fn cells(log: &str, prefix: &str) -> u64 {
    let last = log
        .rfind("Number of cells")
        .map(|i| &log[i..])
        .unwrap_or(log);
    last.lines()
        .map(str::trim)
        .filter(|l| l.starts_with(prefix))
        .filter_map(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        .sum()
}

/// yosys synth_ice40 + nextpnr-ice40 on the default configuration.
pub fn report() -> Result<()> {
    let root = crate::root();
    let out = root.join("target/hdl-report");
    let rtl = out.join("rtl");
    crate::run(
        &root,
        "cargo",
        &[
            "run",
            "--quiet",
            "--release",
            "-p",
            "tooltouch",
            "--",
            "hdl",
            "--out",
            &rtl.to_string_lossy(),
        ],
    )?;
    let files: Vec<String> = FILES
        .iter()
        .map(|f| rtl.join(f).to_string_lossy().into_owned())
        .collect();
    let json = out.join("tt_fpga.json");
    let synth_log = out.join("synth.log");
    let script = format!(
        "read_verilog {}; synth_ice40 {SYNTH_FLAGS} -top tt_fpga -json {}",
        files.join(" "),
        json.display()
    );
    crate::run(
        &out,
        "yosys",
        &["-q", "-l", &synth_log.to_string_lossy(), "-p", &script],
    )
    .context("yosys is needed: run `cargo xtask setup`")?;
    let synth = std::fs::read_to_string(&synth_log).context("reading synth.log")?;
    let pnr_log = out.join("pnr.log");
    let freq = format!("{TARGET_MHZ}");
    println!("$ nextpnr-ice40 --hx8k --package ct256 --seed {SEED} --freq {freq} …");
    let status = Command::new("nextpnr-ice40")
        .args([
            "--hx8k",
            "--package",
            "ct256",
            "--pcf-allow-unconstrained",
            "--seed",
            SEED,
            "--freq",
        ])
        .arg(&freq)
        .arg("--json")
        .arg(&json)
        .arg("-l")
        .arg(&pnr_log)
        .arg("--quiet")
        .status()
        .context("could not start nextpnr-ice40: run `cargo xtask setup`")?;
    let pnr = std::fs::read_to_string(&pnr_log).context("reading pnr.log")?;
    let fmax = pnr
        .lines()
        .rev()
        .filter(|l| l.contains("Max frequency for clock"))
        .filter_map(|l| {
            let after = l.split("': ").nth(1)?;
            after.split_whitespace().next()?.parse::<f64>().ok()
        })
        .next();
    let lcs = pnr
        .lines()
        .rev()
        .filter(|l| l.contains("ICESTORM_LC:"))
        .filter_map(|l| {
            let after = l.split("ICESTORM_LC:").nth(1)?;
            after.split('/').next()?.trim().parse::<u64>().ok()
        })
        .next();
    let (Some(fmax), Some(lcs)) = (fmax, lcs) else {
        bail!(
            "nextpnr-ice40 ({status}) gave no fmax or cell count; see {}",
            pnr_log.display()
        );
    };
    let ffs = cells(&synth, "SB_DFF");
    let luts = cells(&synth, "SB_LUT4");
    let carries = cells(&synth, "SB_CARRY");
    println!("\nHDL synthesis report: default configuration, iCE40 HX8K (ct256), top tt_fpga");
    println!(
        "  logic cells (ICESTORM_LC): {lcs} (target <= {TARGET_CELLS}: {})",
        verdict(lcs <= TARGET_CELLS)
    );
    println!("  flip-flops (SB_DFF*):      {ffs}");
    println!("  LUT4s / carries:           {luts} / {carries}");
    println!(
        "  fmax:                      {fmax:.2} MHz (target >= {TARGET_MHZ}: {})",
        verdict(fmax >= TARGET_MHZ)
    );
    println!("  logs: {} {}", synth_log.display(), pnr_log.display());
    // Per-module breakdown (hierarchy kept; the counts differ a little from the flat
    // synthesis above, which optimizes across module boundaries).
    let blocks_log = out.join("blocks.log");
    let script = format!(
        "read_verilog {}; synth_ice40 {SYNTH_FLAGS} -noflatten -top tt_fpga; stat",
        files.join(" ")
    );
    crate::run(
        &out,
        "yosys",
        &["-q", "-l", &blocks_log.to_string_lossy(), "-p", &script],
    )?;
    let blocks = std::fs::read_to_string(&blocks_log).context("reading blocks.log")?;
    println!("\n  per module (yosys -noflatten): LUT4 / flip-flops / carries");
    let last = blocks
        .rfind("Printing statistics")
        .map(|i| &blocks[i..])
        .unwrap_or(&blocks);
    for section in last.split("=== ").skip(1) {
        let name = section.split_whitespace().next().unwrap_or("?");
        if name == "design" {
            continue;
        }
        println!(
            "    {name:<24} {:>4} / {:>4} / {:>4}",
            cells(section, "SB_LUT4"),
            cells(section, "SB_DFF"),
            cells(section, "SB_CARRY")
        );
    }
    Ok(())
}

fn verdict(ok: bool) -> &'static str {
    if ok {
        "met"
    } else {
        "MISSED"
    }
}
