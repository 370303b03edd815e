//! `cargo xtask hdl-report`: writes the Verilog of the default configuration with
//! `tooltouch hdl`, synthesizes the chip top `tt_fpga` with yosys `synth_ice40`, places
//! and routes it with nextpnr-ice40 for an HX8K (ct256), and prints logic cells,
//! flip-flops and fmax against the targets (≥ 150 MHz, ≤ 400 logic cells).
//!
//! nextpnr exits 1 when `--freq` is not met, so fmax is read from its log, and a missed
//! target is reported, not an error.
//!
//! It then refits the tuning cost model (`host/tune/src/cost.rs`): its calibration points are
//! synthesized again and `host/tune/src/cost_model.json` rewritten with the fresh
//! measurements and their least-squares fit, by running the model's check
//! (`tests/tune/cost_model.rs`) with `TOOLTOUCH_BLESS=1`. Unchanged synthesis, unchanged
//! file; otherwise `git diff` shows which points moved.
//!
//! It also builds the bitstreams of the SPI design ([`bitstreams`], also a step of
//! `cargo xtask test`): `tt_fpga_spi` (the kernel with run-time thresholds behind the SPI
//! register interface) synthesized once, placed and routed with each board's pin
//! constraints (`hdl-gen/boards/*.pcf`, every port constrained) at the board's 12 MHz
//! clock, and packed by icepack into `target/hdl-report/<board>/tt_fpga_spi.bin`.
//!
//! `cargo xtask bless-hdl`: rewrites the Verilog snapshots under `hdl-gen/snapshots/` and
//! the generated output lists of the scoreboards under `host/abi/` by running their tests
//! (`hdl-gen/tests/snapshots.rs`, `hdl-gen/tests/scoreboard_lists.rs`) with
//! `TOOLTOUCH_BLESS=1`, so the files are written by the same code that compares them.

use anyhow::{bail, Context, Result};
use std::path::Path;
use std::process::Command;

/// Environment variable that makes a snapshot test rewrite its committed files.
const BLESS_VAR: &str = "TOOLTOUCH_BLESS";

/// Runs `cargo args…` in the workspace root with [`BLESS_VAR`] set.
fn cargo_blessing(args: &[&str]) -> Result<()> {
    let root = crate::process::root();
    println!("$ {BLESS_VAR}=1 cargo {}", args.join(" "));
    let status = Command::new("cargo")
        .args(args)
        .current_dir(&root)
        .env(BLESS_VAR, "1")
        .status()
        .context("could not start cargo")?;
    if !status.success() {
        bail!("`cargo {}` failed ({status})", args.join(" "));
    }
    Ok(())
}

/// The folders `cargo xtask bless-hdl` rewrites files in.
const BLESSED_HDL: [&str; 2] = ["hdl-gen/snapshots", "host/rtl-sim"];

/// `cargo xtask bless-hdl`: rewrites `hdl-gen/snapshots/` and the scoreboards' generated
/// regions, and lists what changed.
pub fn bless_snapshots() -> Result<()> {
    cargo_blessing(&[
        "test",
        "--release",
        "-p",
        "tooltouch-hdl-gen",
        "--test",
        "snapshots",
        "--test",
        "scoreboard_lists",
        "--",
        "--nocapture",
    ])?;
    let mut status = vec!["status", "--short", "--"];
    status.extend(BLESSED_HDL);
    crate::process::run(&crate::process::root(), "git", &status)?;
    println!(
        "review the changes with `git diff {}`",
        BLESSED_HDL.join(" ")
    );
    Ok(())
}

/// Target clock, MHz.
const TARGET_MHZ: f64 = 150.0;
/// Target size, iCE40 logic cells.
const TARGET_CELLS: u64 = 400;
/// synth_ice40 options: clock enables only for enables shared by 64 or more flip-flops
/// (otherwise nextpnr promotes each enable to a global buffer, which costs more than a LUT
/// input), and the classic ABC mapping: on this design it gives 10–25 MHz more than
/// `-abc9` for the same cell count (measured over seeds 1–3; see docs/hdl.md).
const SYNTH_FLAGS: &str = "-dffe_min_ce_use 64";
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
    "tt_checks.v",
    "tt_measurement.v",
    "tt_frontend.v",
    "tt_fpga.v",
];

/// Runs of one synthesis when yosys's ABC aborts (return code 134): ABC's assertion
/// crashes come and go between identical runs, so an abort is synthesized once more.
const ABC_ATTEMPTS: u32 = 2;

/// yosys `read_verilog <files>; synth_ice40 SYNTH_FLAGS <options><after>` in `dir`,
/// logging to `log`; returns the log. An ABC abort is retried ([`ABC_ATTEMPTS`]); any
/// other failure names the log's last lines.
fn synth_ice40(
    dir: &Path,
    files: &[String],
    options: &str,
    after: &str,
    log: &Path,
) -> Result<String> {
    let script = format!(
        "read_verilog {}; synth_ice40 {SYNTH_FLAGS} {options}{after}",
        files.join(" ")
    );
    let log_arg = log.to_string_lossy();
    let args = ["-q", "-l", &log_arg, "-p", &script];
    let mut attempt = 1;
    loop {
        println!("$ (cd {}) yosys {}", dir.display(), args.join(" "));
        let status = Command::new("yosys")
            .args(args)
            .current_dir(dir)
            .status()
            .context("could not start yosys: run `cargo xtask setup`")?;
        let text = std::fs::read_to_string(log).unwrap_or_default();
        if status.success() {
            return Ok(text);
        }
        let abc_aborted = text
            .lines()
            .any(|l| l.contains("ABC: execution of command") && l.contains("return code 134"));
        if abc_aborted && attempt < ABC_ATTEMPTS {
            println!("yosys's ABC aborted (return code 134): synthesizing again");
            attempt += 1;
            continue;
        }
        let lines: Vec<&str> = text.lines().collect();
        bail!(
            "yosys failed ({status}); last lines of {}:\n{}",
            log.display(),
            lines[lines.len().saturating_sub(30)..].join("\n")
        );
    }
}

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

/// One synthesized variant's figures.
struct Synthesis {
    lcs: u64,
    ffs: u64,
    luts: u64,
    carries: u64,
    fmax: f64,
}

/// `cargo xtask hdl-report [--boards [--config settings.toml]]`: the synthesis report, or
/// with `--boards` only the two boards' bitstreams.
pub fn report_command(args: &[String]) -> Result<()> {
    match (
        args.first().map(String::as_str),
        args.get(1).map(String::as_str),
        args.get(2),
    ) {
        (None, _, _) => report(),
        (Some("--boards"), None, _) => bitstreams(None),
        (Some("--boards"), Some("--config"), Some(path)) if args.len() == 3 => {
            bitstreams(Some(path))
        }
        _ => anyhow::bail!("usage: cargo xtask hdl-report [--boards [--config settings.toml]]"),
    }
}

/// yosys synth_ice40 + nextpnr-ice40 on the default configuration: the chip as generated
/// by default (the MCU reads the measurement registers), then with the diagnostic
/// counters readable too (`tooltouch hdl --mcu-diagnostics`).
pub fn report() -> Result<()> {
    let root = crate::process::root();
    let out = root.join("target/hdl-report");
    let main = synthesize(&out, false)?;
    println!("\nHDL synthesis report: default configuration, iCE40 HX8K (ct256), top tt_fpga, seed {SEED}");
    println!(
        "  logic cells (ICESTORM_LC): {} (target <= {TARGET_CELLS}: {})",
        main.lcs,
        verdict(main.lcs <= TARGET_CELLS)
    );
    println!("  flip-flops (SB_DFF*):      {}", main.ffs);
    println!(
        "  LUT4s / carries:           {} / {}",
        main.luts, main.carries
    );
    println!(
        "  fmax:                      {:.2} MHz (target >= {TARGET_MHZ}: {})",
        main.fmax,
        verdict(main.fmax >= TARGET_MHZ)
    );
    let logs = out.join("default");
    println!(
        "  logs: {}",
        logs.strip_prefix(&root).unwrap_or(&logs).display()
    );
    print_blocks(&out.join("default"))?;
    let diag = synthesize(&out, true)?;
    println!(
        "\n  with --mcu-diagnostics (REVOLUTIONS and PULSES readable): {} logic cells, {} flip-flops, \
         fmax {:.2} MHz",
        diag.lcs, diag.ffs, diag.fmax
    );
    bitstreams(None)?;
    refit_cost_model()
}

/// A board the SPI design is built for.
struct Board {
    /// Folder under `target/hdl-report/`, and the pcf's name under `hdl-gen/boards/`.
    name: &'static str,
    /// What it is.
    what: &'static str,
    /// nextpnr-ice40's device and package options.
    device: [&'static str; 3],
    /// The board oscillator, MHz (no PLL: the design runs at it).
    clock_mhz: u32,
}

/// The two boards: the iCEBreaker and the iCE40-HX8K breakout board.
const BOARDS: [Board; 2] = [
    Board {
        name: "icebreaker",
        what: "iCEBreaker (iCE40UP5K-SG48)",
        device: ["--up5k", "--package", "sg48"],
        clock_mhz: 12,
    },
    Board {
        name: "hx8k-breakout",
        what: "iCE40-HX8K breakout (iCE40HX8K-CT256)",
        device: ["--hx8k", "--package", "ct256"],
        clock_mhz: 12,
    },
];

/// The last `Max frequency for clock` of a nextpnr log, MHz.
fn fmax_of(pnr: &str) -> Option<f64> {
    pnr.lines()
        .rev()
        .filter(|l| l.contains("Max frequency for clock"))
        .filter_map(|l| {
            let after = l.split("': ").nth(1)?;
            after.split_whitespace().next()?.parse::<f64>().ok()
        })
        .next()
}

/// The last `ICESTORM_LC: used / available` of a nextpnr log.
fn logic_cells_of(pnr: &str) -> Option<(u64, u64)> {
    pnr.lines()
        .rev()
        .filter_map(|l| {
            let after = l.split("ICESTORM_LC:").nth(1)?;
            let mut parts = after.split('/');
            let used = parts.next()?.trim().parse::<u64>().ok()?;
            let total = parts
                .next()?
                .split_whitespace()
                .next()?
                .parse::<u64>()
                .ok()?;
            Some((used, total))
        })
        .next()
}

/// Writes the SPI design of the default configuration, or of the settings file `config`,
/// synthesizes it once and builds each board's bitstream; fails when a board's timing is
/// not met at its clock.
pub fn bitstreams(config: Option<&str>) -> Result<()> {
    let root = crate::process::root();
    let t = std::time::Instant::now();
    let out = root.join("target/hdl-report/spi");
    let rtl = out.join("rtl");
    let rtl_arg = rtl.to_string_lossy().into_owned();
    let config = config
        .map(|c| std::fs::canonicalize(c).with_context(|| format!("settings file {c}")))
        .transpose()?
        .map(|p| p.to_string_lossy().into_owned());
    let config = config.as_deref();
    let mut args = vec![
        "run",
        "--quiet",
        "--release",
        "-p",
        "tooltouch-rtl-sim",
        "--example",
        "spi_design",
        "--",
        &rtl_arg,
    ];
    if let Some(path) = config {
        args.extend(["--config", path]);
    }
    println!("$ cargo {}", args.join(" "));
    // The old design's files go: the listing names exactly the files synthesized.
    let _ = std::fs::remove_dir_all(&rtl);
    let listing = Command::new("cargo")
        .args(&args)
        .current_dir(&root)
        .output()
        .context("could not start cargo")?;
    if !listing.status.success() {
        bail!(
            "writing the SPI design failed: {}",
            String::from_utf8_lossy(&listing.stderr)
        );
    }
    let files: Vec<String> = String::from_utf8_lossy(&listing.stdout)
        .lines()
        .map(str::to_string)
        .collect();
    let json = out.join("tt_fpga_spi.json");
    let synth_log = out.join("synth.log");
    synth_ice40(
        &out,
        &files,
        &format!("-top tt_fpga_spi -json {}", json.display()),
        "",
        &synth_log,
    )?;
    let mut lines = Vec::new();
    for board in &BOARDS {
        let dir = root.join("target/hdl-report").join(board.name);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        let pcf = root
            .join("hdl-gen/boards")
            .join(format!("{}.pcf", board.name));
        let asc = dir.join("tt_fpga_spi.asc");
        let bin = dir.join("tt_fpga_spi.bin");
        let log = dir.join("pnr.log");
        let freq = board.clock_mhz.to_string();
        println!(
            "$ nextpnr-ice40 {} --pcf {} --freq {freq} --seed {SEED} …",
            board.device.join(" "),
            pcf.strip_prefix(&root).unwrap_or(&pcf).display()
        );
        let status = Command::new("nextpnr-ice40")
            .args(board.device)
            .arg("--pcf")
            .arg(&pcf)
            .args(["--freq", &freq, "--seed", SEED, "--json"])
            .arg(&json)
            .arg("--asc")
            .arg(&asc)
            .arg("-l")
            .arg(&log)
            .arg("--quiet")
            .status()
            .context("could not start nextpnr-ice40: run `cargo xtask setup`")?;
        let pnr = std::fs::read_to_string(&log).unwrap_or_default();
        let (Some(fmax), Some((lcs, total))) = (fmax_of(&pnr), logic_cells_of(&pnr)) else {
            bail!(
                "{}: nextpnr-ice40 ({status}) gave no fmax or cell count; see {}",
                board.what,
                log.display()
            );
        };
        if !status.success() || fmax < f64::from(board.clock_mhz) {
            bail!(
                "{}: timing not met at {} MHz (fmax {fmax:.2} MHz, nextpnr {status}); see {}",
                board.what,
                board.clock_mhz,
                log.display()
            );
        }
        crate::process::run(
            &dir,
            "icepack",
            &[&asc.to_string_lossy(), &bin.to_string_lossy()],
        )?;
        let size = std::fs::metadata(&bin).map(|m| m.len()).unwrap_or(0);
        lines.push(format!(
            "  {:<38} {lcs:>5} / {total} logic cells, fmax {fmax:.2} MHz (clock {} MHz: met), {} ({size} bytes)",
            board.what,
            board.clock_mhz,
            bin.strip_prefix(&root).unwrap_or(&bin).display()
        ));
    }
    println!(
        "\nSPI design tt_fpga_spi, {}, seed {SEED} ({:.0} s):",
        config.map_or("default configuration".to_string(), |c| format!(
            "configuration of {c}"
        )),
        t.elapsed().as_secs_f64()
    );
    for l in &lines {
        println!("{l}");
    }
    if config.is_none() {
        check_doc_figure(
            &root,
            &format!("SPI design tt_fpga_spi, default configuration, seed {SEED}:"),
            &lines,
        )?;
    }
    Ok(())
}

/// The page that shows the default SPI design's per-board figures.
const BOARDS_PAGE: &str = "docs/hdl.md";

/// Checks that [`BOARDS_PAGE`] shows `lines` right after the line `heading` (the figures
/// of this run, the wall time aside); with `TOOLTOUCH_BLESS_FIGURES=1` rewrites them instead.
fn check_doc_figure(root: &Path, heading: &str, lines: &[String]) -> Result<()> {
    let path = root.join(BOARDS_PAGE);
    let text = std::fs::read_to_string(&path).with_context(|| format!("reading {BOARDS_PAGE}"))?;
    let page: Vec<&str> = text.lines().collect();
    let Some(at) = page.iter().position(|l| *l == heading) else {
        bail!("{BOARDS_PAGE} has no line `{heading}` above the boards' figures");
    };
    let shown = &page[at + 1..(at + 1 + lines.len()).min(page.len())];
    if shown.iter().copied().eq(lines.iter().map(String::as_str)) {
        println!("{BOARDS_PAGE} shows these figures");
        return Ok(());
    }
    if std::env::var_os("TOOLTOUCH_BLESS_FIGURES").is_some() {
        let mut new: Vec<&str> = page[..=at].to_vec();
        new.extend(lines.iter().map(String::as_str));
        new.extend(&page[(at + 1 + shown.len())..]);
        std::fs::write(&path, new.join("\n") + "\n")
            .with_context(|| format!("writing {BOARDS_PAGE}"))?;
        println!("{BOARDS_PAGE}: the boards' figures rewritten");
        return Ok(());
    }
    bail!(
        "{BOARDS_PAGE} shows other figures under `{heading}`:\n{}\nthis run:\n{}\n\
         (rewrite them with TOOLTOUCH_BLESS_FIGURES=1 cargo xtask hdl-report --boards)",
        shown.join("\n"),
        lines.join("\n")
    )
}

/// Refits the tuning cost model from a fresh synthesis of its calibration points.
fn refit_cost_model() -> Result<()> {
    println!("\nTuning cost model: refit from a fresh synthesis of its calibration points");
    cargo_blessing(&[
        "test",
        "--release",
        "--test",
        "tune",
        "cost_model::",
        "--",
        "--nocapture",
    ])?;
    crate::process::run(
        &crate::process::root(),
        "git",
        &["status", "--short", "--", "host/tune/src/cost_model.json"],
    )?;
    println!("review the changes with `git diff host/tune/src/cost_model.json`");
    Ok(())
}

/// Writes the Verilog of the default configuration into `out/<variant>/rtl`, synthesizes
/// and places it.
fn synthesize(out: &Path, diagnostics: bool) -> Result<Synthesis> {
    let root = crate::process::root();
    let out = out.join(if diagnostics {
        "diagnostics"
    } else {
        "default"
    });
    let rtl = out.join("rtl");
    let rtl_arg = rtl.to_string_lossy().into_owned();
    let mut args = vec![
        "run",
        "--quiet",
        "--release",
        "-p",
        "tooltouch",
        "--",
        "hdl",
        "--out",
        &rtl_arg,
    ];
    if diagnostics {
        args.push("--mcu-diagnostics");
    }
    crate::process::run(&root, "cargo", &args)?;
    let files: Vec<String> = FILES
        .iter()
        .map(|f| rtl.join(f).to_string_lossy().into_owned())
        .collect();
    let json = out.join("tt_fpga.json");
    let synth_log = out.join("synth.log");
    let synth = synth_ice40(
        &out,
        &files,
        &format!("-top tt_fpga -json {}", json.display()),
        "",
        &synth_log,
    )?;
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
    Ok(Synthesis {
        lcs,
        ffs: cells(&synth, "SB_DFF"),
        luts: cells(&synth, "SB_LUT4"),
        carries: cells(&synth, "SB_CARRY"),
        fmax,
    })
}

/// Per-module breakdown of the variant in `out` (hierarchy kept; the counts differ a little
/// from the flat synthesis, which optimizes across module boundaries).
fn print_blocks(out: &Path) -> Result<()> {
    let rtl = out.join("rtl");
    let files: Vec<String> = FILES
        .iter()
        .map(|f| rtl.join(f).to_string_lossy().into_owned())
        .collect();
    let blocks_log = out.join("blocks.log");
    let blocks = synth_ice40(
        out,
        &files,
        "-noflatten -top tt_fpga",
        "; stat",
        &blocks_log,
    )?;
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
