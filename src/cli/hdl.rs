//! `tooltouch hdl`: writes the Verilog of the FPGA front end (one file per module, the
//! simulation top `tt_frontend.v`, the chip top `tt_fpga.v`) and its self-checking
//! testbench `tt_testbench.v`, all derived from one measurement configuration, and with
//! `--vectors` the testbench's `stim.hex` and `expect.hex` beside them, so that
//! `cd DIR && iverilog -g2005 -o tb *.v && vvp tb` (or `verilator --binary --top-module
//! tt_testbench -o tb *.v && obj_dir/tb`) prints `TESTBENCH OK <cycles>`.
//!
//! The configuration file is read as `tooltouch vectors` reads it
//! ([`super::vectors::load_settings`]): the `[measure]` table of `tooltouch measure`'s
//! settings (or the `MeasureSettings` fields at top level) and the `[lathe]` table (its
//! clock, and the lathe run of `--vectors lathe`); other tables are errors. Without
//! `--config`, the defaults. The testbench's clock is the settings file's `[lathe]
//! clock_hz`, as `tooltouch measure` reads it, so the testbench and the golden VCD share
//! one period; a `--clock-hz` that contradicts it is an error.
//!
//! The hidden `--inject-fault` option generates a deliberately wrong design
//! ([`tooltouch_hdl_gen::Fault`]) for testing testbenches: a bench that passes it is blind.

use super::vectors::CLOCK_RULE;
use anyhow::{bail, Context};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tooltouch_hdl_gen::{
    generate, testbench, Fault, Options, TestbenchSpec, EXPECT_HEX, STIM_HEX, TESTBENCH,
};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_rtl_sim::write_design;
use tooltouch_settings::load::{golden_set_of, load_settings, LoadedSettings};
use tooltouch_vectors::hex::{self, Vectors};
use tooltouch_vectors::output::OutputFolder;
use tooltouch_vectors::stimulus_file::{StatedClock, DEFAULT_CLOCK_HZ};

pub use tooltouch_vectors::hex::DEFAULT_DEPTH;

/// Largest `--stim-depth` / `--expect-depth`, words (the generator's limit).
pub use tooltouch_hdl_gen::MAX_DEPTH;

/// Arguments of `tooltouch hdl`.
#[derive(clap::Args, Debug)]
#[command(after_help = CLOCK_RULE)]
pub struct Args {
    /// Settings TOML: a `[measure]` table (or the measurement fields at top level) and an
    /// optional `[lathe]` table (clock, and the run of `--vectors lathe`).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Output folder (created). A run replaces this command's files in the folder (and
    /// removes those it did not write this time: stim.hex and expect.hex without
    /// `--vectors`, so no stale vectors sit beside new RTL); other files are left alone; a
    /// failed run leaves the folder as it was.
    #[arg(long)]
    pub out: PathBuf,
    /// FPGA clock for the testbench, Hz (the period, 1e9 / clock_hz ns, must be whole; see
    /// the clock rule below).
    #[arg(long)]
    pub clock_hz: Option<u32>,
    /// Largest stimulus the testbench accepts, in `stim.hex` words (segments + 1),
    /// 2..=67108864; default 65536, or with `--vectors` the size of the vectors written.
    #[arg(long)]
    pub stim_depth: Option<usize>,
    /// Largest expected response the testbench accepts, in `expect.hex` words,
    /// 2..=67108864; default 65536, or with `--vectors` the size of the vectors written.
    #[arg(long)]
    pub expect_depth: Option<usize>,
    /// Make the diagnostic counters REVOLUTIONS and PULSES readable through the MCU
    /// register file (about 100 more logic cells in the chip).
    #[arg(long)]
    pub mcu_diagnostics: bool,
    /// Also write the testbench's stim.hex and expect.hex: `lathe` = the first measurement
    /// of the lathe run the settings describe (the span of `tooltouch measure`'s
    /// measure.vcd), or a stimulus FILE as `tooltouch vectors --stimulus` reads it.
    #[arg(long, value_name = "lathe|FILE")]
    pub vectors: Option<String>,
    /// For testing testbenches only: generate the design with this deliberate fault, which
    /// a testbench must report as a mismatch against the model.
    #[arg(long, value_enum, hide = true)]
    pub inject_fault: Option<InjectedFault>,
}

/// A fault `--inject-fault` puts into the generated design: any of [`Fault::ALL`], by its
/// [`Fault::name`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InjectedFault(pub Fault);

/// Every injectable fault, in [`Fault::ALL`]'s order.
const INJECTABLE: [InjectedFault; Fault::ALL.len()] = {
    let mut all = [InjectedFault(Fault::None); Fault::ALL.len()];
    let mut i = 0;
    while i < all.len() {
        all[i] = InjectedFault(Fault::ALL[i]);
        i += 1;
    }
    all
};

impl clap::ValueEnum for InjectedFault {
    fn value_variants<'a>() -> &'a [Self] {
        &INJECTABLE
    }
    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.0.name()))
    }
}

/// Reads the measurement settings of `path` (see the module documentation).
pub fn load_config(path: &Path) -> anyhow::Result<MeasureConfig> {
    Ok(load_settings(Some(path), None)?.config)
}

/// The testbench vectors `--vectors` asks for, with a description of their source.
fn vectors_for(
    what: &str,
    settings: &LoadedSettings,
    config_given: bool,
) -> anyhow::Result<(Vectors, u32, String)> {
    let config = &settings.config;
    let stimulus: Stimulus = if what == "lathe" {
        let mut scenario = settings.lathe.clone();
        scenario.clock_hz = settings.clock.as_ref().map_or(DEFAULT_CLOCK_HZ, |c| c.hz);
        scenario
            .validate(config)
            .map_err(|e| anyhow::anyhow!("--vectors lathe: [lathe] {e}"))?;
        tooltouch_plant::measurement_cycle::check_run_size(&scenario, config)
            .context("--vectors lathe")?;
        let run = tooltouch_plant::measurement_cycle::run(&scenario, config, &mut |_| {})
            .map_err(|e| anyhow::anyhow!("--vectors lathe: {e}"))?;
        let end = run.measurements.first().map_or(0, |m| m.end_cycle);
        Stimulus {
            clock_hz: scenario.clock_hz,
            segments: tooltouch_plant::measurement_cycle::slice(&run.stimulus, 0, end),
        }
    } else {
        let (set, _) = golden_set_of(Path::new(what), settings, config_given)
            .with_context(|| format!("--vectors {what}"))?;
        let Some(cycle) = set.cycle else {
            match set.no_cycle_level {
                Some(why) => bail!("{why}"),
                None => {
                    bail!("{what}: holds no measurement events, nothing for the FPGA testbench")
                }
            }
        };
        if cycle.config.hash() != config.hash() {
            bail!(
                "{what}: made with configuration {:016x}, the RTL is generated from {:016x} (pass its settings with --config)",
                cycle.config.hash(),
                config.hash()
            );
        }
        cycle.stimulus
    };
    let v = hex::golden_vectors(config, &stimulus).map_err(|e| anyhow::anyhow!("{what}: {e}"))?;
    let source = if what == "lathe" {
        "the lathe run's first measurement".to_string()
    } else {
        what.to_string()
    };
    Ok((v, stimulus.clock_hz, source))
}

/// A depth: the one given (in `2..=`[`MAX_DEPTH`], at least `needed`), else `needed`
/// when vectors are written (`needed` > 0: the memories then match the files exactly),
/// else [`DEFAULT_DEPTH`]. Checked here so that no depth reaches the testbench's 32-bit
/// `integer` parameters wrapped.
fn depth(given: Option<usize>, needed: usize, flag: &str, file: &str) -> anyhow::Result<usize> {
    if let Some(d) = given.filter(|d| !(2..=MAX_DEPTH).contains(d)) {
        bail!(
            "{flag} {d} is out of range: allowed 2..={MAX_DEPTH} words, header included (the \
             testbench's memories and its 32-bit Verilog `integer` indices)"
        );
    }
    if needed > MAX_DEPTH {
        bail!(
            "{file} would hold {needed} words, more than the {MAX_DEPTH} a testbench memory may have: \
             give a shorter stimulus"
        );
    }
    match given {
        Some(d) if d < needed => bail!(
            "{flag} {d}: {file} holds {needed} words; give at least {needed} (or leave the flag out)"
        ),
        Some(d) => Ok(d),
        None if needed > 0 => Ok(needed),
        None => Ok(DEFAULT_DEPTH),
    }
}

/// Runs `tooltouch hdl`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut settings = load_settings(args.config.as_deref(), None)?;
    match (args.clock_hz, &settings.clock) {
        (Some(flag), Some(file)) if flag != file.hz => bail!(
            "--clock-hz {flag} contradicts {} = {} Hz: the testbench and the golden VCD must \
             share one clock; leave --clock-hz out or make the two agree",
            file.source,
            file.hz
        ),
        (Some(hz), None) => {
            settings.clock = Some(StatedClock {
                hz,
                source: "--clock-hz".into(),
            });
        }
        _ => {}
    }
    let config = settings.config;
    let vectors = match &args.vectors {
        Some(what) => Some(vectors_for(what, &settings, args.config.is_some())?),
        None => None,
    };
    let clock_hz = match (&vectors, &settings.clock) {
        (Some((_, hz, _)), _) => *hz,
        (None, Some(c)) => c.hz,
        (None, None) => DEFAULT_CLOCK_HZ,
    };
    let words = vectors
        .as_ref()
        .map_or((0, 0), |(v, _, _)| (v.stim_words, v.expect_words));
    let spec = TestbenchSpec {
        clock_hz,
        stim_depth: depth(args.stim_depth, words.0, "--stim-depth", STIM_HEX)?,
        expect_depth: depth(args.expect_depth, words.1, "--expect-depth", EXPECT_HEX)?,
        mcu_diagnostics: args.mcu_diagnostics,
    };
    let Some(tb) = testbench(&config, &spec) else {
        bail!(
            "clock {clock_hz} Hz: the clock period 1e9 / clock_hz ns must be a whole number, at least 2"
        );
    };
    let fault = args.inject_fault.map_or(Fault::None, |f| f.0);
    if !fault.applies_to(&config) {
        bail!(
            "--inject-fault {}: the changed parameter would leave its valid range in this configuration",
            fault.name()
        );
    }
    let options = Options {
        mcu_diagnostics: args.mcu_diagnostics,
        fault,
    };
    let design = generate(&config, &options);
    let mut known: Vec<String> = design.files.iter().map(|f| f.name.clone()).collect();
    let include = tooltouch_hdl_gen::config_include(&config);
    known.extend([
        tb.name.clone(),
        STIM_HEX.into(),
        EXPECT_HEX.into(),
        include.name.clone(),
    ]);
    let out = OutputFolder::create(&args.out, known)?;
    let mut staged = write_design(out.staging(), &design, Some(&tb))?;
    let include_path = out.staging().join(&include.name);
    std::fs::write(&include_path, &include.text)
        .with_context(|| format!("writing {}", include_path.display()))?;
    staged.push(include_path);
    if let Some((v, _, _)) = &vectors {
        hex::write_vectors(out.staging(), v)?;
    }
    out.commit()
        .with_context(|| format!("writing {}", args.out.display()))?;
    outln!(
        "configuration hash {:016x}: {} files in {}",
        config.hash(),
        staged.len(),
        args.out.display()
    );
    for f in &staged {
        if let Some(name) = f.file_name() {
            outln!("  {}", args.out.join(name).display());
        }
    }
    if let Some((v, hz, source)) = &vectors {
        outln!(
            "vectors from {source}: {} clocks at {hz} Hz; {} ({} words), {} ({} words)",
            v.cycles,
            STIM_HEX,
            v.stim_words,
            EXPECT_HEX,
            v.expect_words
        );
        outln!(
            "run: cd {} && iverilog -g2005 -o tb *.v && vvp tb",
            args.out.display()
        );
        println!(
            " or: cd {} && verilator --binary --top-module {TESTBENCH} -o tb *.v && obj_dir/tb",
            args.out.display()
        );
        println!(
            "(*.v is the generated design; for your own tt_frontend compile {TESTBENCH}.v with your files instead)"
        );
    }
    Ok(ExitCode::SUCCESS)
}
