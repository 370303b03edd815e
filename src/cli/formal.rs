//! `tooltouch formal`: proves a user's `tt_frontend` equal to the reference derived from
//! the golden model, for every input sequence from power-on ([`crate::formal`],
//! docs/formal.md). The settings file is read as `tooltouch vectors` reads it.
//!
//! Exit codes: 0 proven; 1 not equal (a counterexample, replayed against the golden
//! model); 2 bad input (a missing file, a design that does not elaborate, a port missing or
//! of the wrong width, a missing tool); 3 undecided (no engine concluded within its limit:
//! not proven).

use anyhow::Context;
use std::path::PathBuf;
use std::process::ExitCode;
use tooltouch_formal::engines::{Engine, PORTFOLIO};
use tooltouch_formal::{prove, FormalError, Outcome, Request, DEFAULT_SECONDS};
use tooltouch_settings::load::load_settings;
use tooltouch_vectors::output::OutputFolder;

/// Exit code of an undecided proof.
pub const UNDECIDED: u8 = 3;

/// The files `tooltouch formal` may leave in its output folder.
const KNOWN: [&str; 19] = [
    "tt_frontend_props.sv",
    "replay.txt",
    "tt_formal_replay.v",
    "counterexample.vcd",
    "golden.vcd",
    "stim.hex",
    "expect.hex",
    "tt_frontend_ref.v",
    "tt_formal_top.v",
    "miter.aig",
    "miter.map",
    "miter.ys",
    "miter.log",
    "interface.ys",
    "interface.log",
    "interface.json",
    "dprove.log",
    "scorr-pdr.log",
    "report.txt",
];

/// Arguments of `tooltouch formal`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Exit codes: 0 proven (equal on every input sequence from power-on); 1 not equal (a \
counterexample: counterexample.vcd holds its pins and the design's outputs, golden.vcd the \
model's; `tooltouch check --expected golden.vcd --dut counterexample.vcd` shows the first \
difference; a counterexample that needs a reset after power-on has no golden.vcd, the \
golden vectors cannot carry rst: the report shows its clock-by-clock replay); 2 bad input (missing file, syntax error, missing port, wrong width, missing \
tool); 3 undecided (no engine concluded within its time limit: NOT proven). See docs/formal.md.")]
pub struct Args {
    /// Settings TOML (`[measure]`, `[lathe]`): the configuration the reference is generated
    /// from, and the clock of the counterexample's VCD. Without it, the defaults.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// The design's Verilog / SystemVerilog files.
    #[arg(long, num_args = 1.., required = true)]
    pub dut: Vec<PathBuf>,
    /// The design's top module.
    #[arg(long, default_value = tooltouch_hdl_gen::TOP)]
    pub top: String,
    /// Output folder (created): the miter, the engines' logs, report.txt, the contract's
    /// assertions as a bind file (tt_frontend_props.sv) and, when the designs differ,
    /// counterexample.vcd and golden.vcd.
    #[arg(long, default_value = "formal")]
    pub out: PathBuf,
    /// The design makes the diagnostic counters REVOLUTIONS and PULSES readable through
    /// the MCU register file (`tooltouch hdl --mcu-diagnostics`).
    #[arg(long)]
    pub mcu_diagnostics: bool,
    /// Engines to try, in order (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub engines: Option<Vec<EngineArg>>,
    /// Wall-time limit of each engine, s (1..=86400).
    #[arg(long, default_value_t = DEFAULT_SECONDS, value_parser = clap::value_parser!(u64).range(1..=86400))]
    pub engine_seconds: u64,
}

/// An engine as `--engines` spells it (see [`Engine`]).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum EngineArg {
    /// Signal correspondence, then property-directed reachability.
    ScorrPdr,
    /// Latch correspondence, then induction.
    Dprove,
    /// Interpolation.
    Interpolation,
    /// Bounded model checking (finds differences only).
    Bmc,
}

impl From<EngineArg> for Engine {
    fn from(a: EngineArg) -> Engine {
        match a {
            EngineArg::ScorrPdr => Engine::ScorrPdr,
            EngineArg::Dprove => Engine::Dprove,
            EngineArg::Interpolation => Engine::Interpolation,
            EngineArg::Bmc => Engine::Bmc,
        }
    }
}

/// Runs `tooltouch formal`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let settings = load_settings(args.config.as_deref(), None)?;
    let clock_hz = settings.clock.as_ref().map_or(50_000_000, |c| c.hz);
    let request = Request {
        config: settings.config,
        mcu_diagnostics: args.mcu_diagnostics,
        clock_hz,
        files: args.dut.clone(),
        top: args.top.clone(),
        engines: args.engines.as_ref().map_or_else(
            || PORTFOLIO.to_vec(),
            |e| e.iter().map(|&a| Engine::from(a)).collect(),
        ),
        seconds_per_engine: args.engine_seconds,
        replay: true,
    };
    let mut known: Vec<String> = KNOWN.iter().map(|s| s.to_string()).collect();
    for e in PORTFOLIO {
        known.push(format!("{}.log", e.name()));
        known.push(format!("{}.cex", e.name()));
    }
    let out = OutputFolder::create(&args.out, known)?;
    let report = match prove(&request, out.staging()) {
        Ok(r) => r,
        Err(e @ (FormalError::BadInput(_) | FormalError::Design(_))) => {
            eprintln!("error: {e}");
            return Ok(ExitCode::from(super::BAD_INPUT));
        }
        Err(e) => return Err(e).context("tooltouch formal"),
    };
    // Name the files where they will be once committed, not in the staging folder.
    let staging = std::fs::canonicalize(out.staging())
        .with_context(|| format!("reading {}", out.staging().display()))?;
    let mut text = report.lines().join("\n").replace(
        &staging.display().to_string(),
        &args.out.display().to_string(),
    );
    text.push('\n');
    out.write("report.txt", &text)?;
    out.write(
        tooltouch_formal::assertions::PROPS_FILE,
        tooltouch_formal::assertions::bind_file(&request.config),
    )?;
    out.commit()?;
    super::write_stdout(format_args!("{text}"));
    Ok(match report.outcome {
        Outcome::Proven { .. } => ExitCode::SUCCESS,
        Outcome::NotEqual { .. } => ExitCode::from(super::NOT_PASSED),
        Outcome::Undecided => ExitCode::from(UNDECIDED),
    })
}
