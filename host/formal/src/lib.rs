//! `tooltouch formal`: an unbounded proof that a user's `tt_frontend` (any RTL with the
//! contract's ports, docs/CONTRACT.md) equals the reference written from the golden
//! model's semantics (`tooltouch_hdl_gen::reference`) on every input sequence from
//! power-on — no invariant written for the design, so any implementation can be proven.
//!
//! 1. [`miter`]: yosys reads the design, its ports are checked against the contract, and
//!    a miter of the design and the reference (same pins and MCU address every clock,
//!    every output, `irq` and `mcu_rdata` compared after every clock) is flattened to an
//!    And-Inverter graph (AIGER).
//! 2. [`engines`]: ABC's engines are tried in turn, each with a wall-time limit, until one
//!    concludes: **proven** (the engine is named), **not equal** (a counterexample), or,
//!    when none concludes, **undecided** with every attempt listed. A bounded search that
//!    finds nothing is never reported as proven.
//! 3. [`counterexample`]: a difference becomes the pins per clock, the golden model's
//!    response and the design's simulated trace (`counterexample.vcd`), which `tooltouch
//!    check` compares; [`clocked`] replays the counterexample's own `mcu_addr` and `rst`
//!    clock by clock against the model's cycle level and MCU register map.
//!
//! Reset and power-on: both designs start from their power-on values (the initializers),
//! as the golden model and the generated testbench do; a register without an initializer
//! starts from any value, so a design relying on `rst` to start is not proven equal.
//! `rst` is a free input, the same for both designs every clock: the proof covers a
//! synchronous reset at any clock (the contract's: every register 0 but `density_armed`
//! after a clock with `rst` high), so a register `rst` leaves is a difference.
//!
//! Depends on the golden model, hdl-gen (the reference, the contract's ports), the plants,
//! the vector formats and the RTL runners of `tooltouch-rtl-sim` (the replays); must not
//! depend on the firmware runners, LinuxCNC, tuning, plots or the command line.

pub mod assertions;
pub mod clocked;
pub mod counterexample;
pub mod engines;
mod error;
pub mod inputs;
pub mod miter;

use counterexample::{read_cex, replay, without_needless_resets, Replay};
use engines::{run_engine, Attempt, Engine, EngineResult};
use error::io;
pub use error::FormalError;
pub use inputs::Counterexample;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tooltouch_model::MeasureConfig;

/// What to prove.
#[derive(Clone, Debug)]
pub struct Request {
    /// The measurement configuration the reference is generated from.
    pub config: MeasureConfig,
    /// Whether the MCU's diagnostic counters (`REVOLUTIONS`, `PULSES`) are readable in the
    /// design (`tooltouch hdl --mcu-diagnostics`).
    pub mcu_diagnostics: bool,
    /// FPGA clock of the counterexample's VCD and testbench, Hz.
    pub clock_hz: u32,
    /// The design's Verilog / SystemVerilog files.
    pub files: Vec<PathBuf>,
    /// Its top module.
    pub top: String,
    /// Engines, in the order tried.
    pub engines: Vec<Engine>,
    /// Wall-time limit of each engine, s.
    pub seconds_per_engine: u64,
    /// Replay a counterexample in Icarus and `check` (off: only the pins are read back).
    pub replay: bool,
}

impl Request {
    /// A request with the default portfolio and time limit.
    pub fn new(config: MeasureConfig, files: Vec<PathBuf>, top: &str) -> Request {
        Request {
            config,
            mcu_diagnostics: false,
            clock_hz: 50_000_000,
            files,
            top: top.to_string(),
            engines: engines::PORTFOLIO.to_vec(),
            seconds_per_engine: DEFAULT_SECONDS,
            replay: true,
        }
    }
}

/// Default wall-time limit of one engine, s.
pub const DEFAULT_SECONDS: u64 = 300;

/// The verdict.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Equal on every input sequence from power-on.
    Proven {
        /// The engine that closed the proof.
        engine: Engine,
    },
    /// Not equal: a trace from power-on after which the outputs differ.
    NotEqual {
        /// The engine that found it.
        engine: Engine,
        /// The inputs, clock by clock.
        counterexample: Counterexample,
        /// Its replay against the golden model (when asked for).
        replay: Option<Box<Replay>>,
    },
    /// No engine concluded within its limit.
    Undecided,
}

/// A proof run.
#[derive(Clone, Debug)]
pub struct Report {
    /// The verdict.
    pub outcome: Outcome,
    /// Every engine run, in order.
    pub attempts: Vec<Attempt>,
    /// The miter's size: inputs, latches, outputs, AND gates.
    pub aiger: [u64; 4],
    /// Wall time of reading the design and building the miter, s.
    pub build_seconds: f64,
    /// Wall time of everything, s.
    pub seconds: f64,
    /// Outputs of the design that are not in the contract (not compared).
    pub extra_outputs: Vec<String>,
}

/// Proves `request` in the folder `dir` (created; it keeps the miter, the logs and a
/// counterexample's files).
pub fn prove(request: &Request, dir: &Path) -> Result<Report, FormalError> {
    let start = Instant::now();
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let dir = &std::fs::canonicalize(dir).map_err(io(dir))?;
    if request.files.is_empty() {
        return Err(FormalError::BadInput(
            "--dut: no design file given".to_string(),
        ));
    }
    let mut files = Vec::with_capacity(request.files.len());
    for f in &request.files {
        if !f.is_file() {
            return Err(FormalError::BadInput(format!(
                "--dut {}: no such file",
                f.display()
            )));
        }
        files.push(std::fs::canonicalize(f).map_err(io(f))?);
    }
    let extra_outputs = miter::read_interface(&request.config, &files, &request.top, dir)?;
    miter::build_aiger(
        &request.config,
        request.mcu_diagnostics,
        &files,
        &request.top,
        dir,
    )?;
    let aig_path = dir.join(miter::AIGER_FILE);
    let aig = std::fs::read(&aig_path).map_err(io(&aig_path))?;
    let aiger = miter::aiger_counts(&aig)
        .ok_or_else(|| FormalError::Tool(format!("{}: no AIGER header", aig_path.display())))?;
    let build_seconds = start.elapsed().as_secs_f64();
    let mut attempts = Vec::new();
    let mut outcome = Outcome::Undecided;
    for &engine in &request.engines {
        let a = run_engine(engine, dir, miter::AIGER_FILE, request.seconds_per_engine)?;
        let result = a.result.clone();
        attempts.push(a);
        match result {
            EngineResult::Proven => {
                outcome = Outcome::Proven { engine };
                break;
            }
            EngineResult::Different { frame, cex } => {
                let map_path = dir.join(miter::MAP_FILE);
                let map = std::fs::read_to_string(&map_path).map_err(io(&map_path))?;
                let mut counterexample = read_cex(&cex, &map, frame)?;
                let replay = if request.replay {
                    counterexample = without_needless_resets(
                        &request.config,
                        request.mcu_diagnostics,
                        counterexample,
                        request.clock_hz,
                        &files,
                        &request.top,
                        dir,
                    )?;
                    Some(Box::new(replay(
                        &request.config,
                        request.mcu_diagnostics,
                        &counterexample,
                        request.clock_hz,
                        &files,
                        &request.top,
                        dir,
                    )?))
                } else {
                    None
                };
                outcome = Outcome::NotEqual {
                    engine,
                    counterexample,
                    replay,
                };
                break;
            }
            EngineResult::Undecided { .. } => {}
        }
    }
    Ok(Report {
        outcome,
        attempts,
        aiger,
        build_seconds,
        seconds: start.elapsed().as_secs_f64(),
        extra_outputs,
    })
}

impl Report {
    /// The report as text lines: the verdict first, then every engine's attempt.
    pub fn lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        match &self.outcome {
            Outcome::Proven { engine } => out.push(format!(
                "PROVEN: the design equals the reference on every input sequence from power-on ({}, {:.1} s)",
                engine.describe(),
                self.seconds
            )),
            Outcome::NotEqual {
                engine,
                counterexample,
                replay,
            } => {
                out.push(format!(
                    "NOT EQUAL: the outputs differ after clock {} of a {}-clock trace from power-on (found by {}, {:.1} s)",
                    counterexample.clocks().saturating_sub(1),
                    counterexample.clocks(),
                    engine.name(),
                    self.seconds
                ));
                if let Some(r) = replay {
                    let clocked = r.clocked.as_ref().map_or_else(
                        || "no difference (the replay disagrees with the miter)".to_string(),
                        ToString::to_string,
                    );
                    match &r.check {
                        Some(tooltouch_vectors::check::Verdict::Mismatch(m)) => {
                            out.push(format!("replayed against the golden model: {m}"));
                            out.push(format!("replayed clock by clock: {clocked}"));
                        }
                        Some(tooltouch_vectors::check::Verdict::Match(m)) => out.push(format!(
                            "replayed against the golden model: the {} outputs match ({m}); \
                             replayed clock by clock with the counterexample's mcu_addr: {clocked}",
                            tooltouch_model::MeasureOutputs::FIELD_COUNT
                        )),
                        None => {
                            let resets: Vec<String> = counterexample
                                .rst
                                .iter()
                                .take(counterexample.clocks())
                                .enumerate()
                                .filter(|(_, &r)| r)
                                .map(|(k, _)| k.to_string())
                                .collect();
                            out.push(format!(
                                "replayed clock by clock (rst high at clock {}; the golden vectors cannot carry a reset, so tooltouch check cannot replay it): {clocked}",
                                resets.join(", ")
                            ));
                        }
                    }
                    match &r.golden_vcd {
                        Some(g) => out.push(format!(
                            "counterexample: {} (pins and outputs), golden: {}",
                            r.counterexample_vcd.display(),
                            g.display()
                        )),
                        None => out.push(format!(
                            "counterexample: {} (pins, rst, mcu_addr and the design's signals)",
                            r.counterexample_vcd.display()
                        )),
                    }
                }
            }
            Outcome::Undecided => out.push(format!(
                "UNDECIDED: no engine proved or refuted the equality within its limit ({:.1} s); NOT proven",
                self.seconds
            )),
        }
        out.push(format!(
            "miter: {} inputs, {} latches, {} AND gates (built in {:.1} s)",
            self.aiger[0], self.aiger[1], self.aiger[3], self.build_seconds
        ));
        for a in &self.attempts {
            let what = match &a.result {
                EngineResult::Proven => "proven".to_string(),
                EngineResult::Different { frame, .. } => {
                    format!("outputs differ after {frame} clocks")
                }
                EngineResult::Undecided { why } => format!("undecided: {why}"),
            };
            out.push(format!(
                "  {:<13} {:>7.1} s  {what}",
                a.engine.name(),
                a.seconds
            ));
        }
        if !self.extra_outputs.is_empty() {
            out.push(format!(
                "not compared (not in the contract): {}",
                self.extra_outputs.join(", ")
            ));
        }
        out
    }
}
