//! `tooltouch hdl`: writes the Verilog of the FPGA front end (one file per module, the
//! simulation top `tt_frontend.v`, the chip top `tt_fpga.v`) and its self-checking
//! testbench `tt_testbench.v`, all derived from one measurement configuration.
//!
//! The configuration file is the `[measure]` table of `tooltouch measure`'s settings
//! (other tables, e.g. `[lathe]`, are ignored here), or a file holding the
//! `MeasureSettings` fields at top level. Without `--config`, the default configuration.

use crate::hdl::write_design;
use anyhow::{bail, Context};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tooltouch_hdl_gen::{generate, testbench, Options, TestbenchSpec};
use tooltouch_model::{MeasureConfig, MeasureSettings};

/// Arguments of `tooltouch hdl`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Settings TOML: a `[measure]` table, or the measurement fields at top level.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Output folder (created).
    #[arg(long)]
    pub out: PathBuf,
    /// FPGA clock for the testbench, Hz (the period, 1e9 / clock_hz ns, must be whole).
    #[arg(long, default_value_t = 50_000_000)]
    pub clock_hz: u32,
    /// Largest stimulus the testbench accepts, in `stim.hex` words (segments + 1).
    #[arg(long, default_value_t = 1 << 16)]
    pub stim_depth: usize,
    /// Largest expected response the testbench accepts, in `expect.hex` words.
    #[arg(long, default_value_t = 1 << 16)]
    pub expect_depth: usize,
    /// Make the diagnostic counters REVOLUTIONS and PULSES readable through the MCU
    /// register file (about 100 more logic cells in the chip).
    #[arg(long)]
    pub mcu_diagnostics: bool,
}

/// Reads the measurement settings of `path` (see the module documentation).
pub fn load_config(path: &Path) -> anyhow::Result<MeasureConfig> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let table: toml::Table =
        toml::from_str(&text).with_context(|| format!("{}: not valid TOML", path.display()))?;
    let settings: MeasureSettings = match table.get("measure") {
        Some(measure) => measure
            .clone()
            .try_into()
            .with_context(|| format!("{}: [measure]", path.display()))?,
        None => toml::from_str(&text).with_context(|| format!("{}", path.display()))?,
    };
    settings
        .validate()
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

/// Runs `tooltouch hdl`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let config = match &args.config {
        Some(p) => load_config(p)?,
        None => MeasureConfig::default(),
    };
    let spec = TestbenchSpec {
        clock_hz: args.clock_hz,
        stim_depth: args.stim_depth,
        expect_depth: args.expect_depth,
        mcu_diagnostics: args.mcu_diagnostics,
    };
    let Some(tb) = testbench(&config, &spec) else {
        bail!(
            "--clock-hz {}: the clock period 1e9 / clock_hz ns must be a whole number, at least 2",
            args.clock_hz
        );
    };
    let options = Options {
        mcu_diagnostics: args.mcu_diagnostics,
        ..Options::default()
    };
    let design = generate(&config, &options);
    let files = write_design(&args.out, &design, Some(&tb))?;
    println!(
        "configuration hash {:016x}: {} files in {}",
        config.hash(),
        files.len(),
        args.out.display()
    );
    for f in &files {
        println!("  {}", f.display());
    }
    Ok(ExitCode::SUCCESS)
}
