//! Timing the HDL simulators on a stimulus, through the co-simulation runner of
//! [`crate::cosim`] (no runner of our own): the generated design and its
//! self-checking testbench, Verilator's C++ at `-O3` (docs/architecture.md, pitfalls),
//! Icarus as is.
//!
//! The time is the testbench run's wall time (the runner's [`SimRun::seconds`]): process
//! start, `$readmemh` of the vectors, and every clock with the testbench's compare of every
//! output. The run must pass (bit for bit with the model), or the timing is an error.

use crate::cosim::{cosim, CosimPlan};
use crate::runner::{CxxOpt, SimRun, Simulator};
use anyhow::{bail, Result};
use std::path::Path;
use tooltouch_model::MeasureConfig;
use tooltouch_plant::stimulus::Stimulus;

/// One simulator's timing.
#[derive(Clone, Debug, PartialEq)]
pub struct HdlSpeed {
    /// The simulator.
    pub simulator: Simulator,
    /// Clocks simulated.
    pub cycles: u64,
    /// Wall time of the run, s.
    pub seconds: f64,
    /// Build wall time, s.
    pub build_seconds: f64,
}

impl HdlSpeed {
    /// Clocks per second.
    pub fn cycles_per_second(&self) -> f64 {
        self.cycles as f64 / self.seconds.max(1e-9)
    }
}

/// Builds and runs `simulator` on `stimulus` in `work` (Verilator at `-O3`); fails when
/// the run does not pass the testbench's bit-for-bit compare.
pub fn time_simulator(
    simulator: Simulator,
    config: &MeasureConfig,
    stimulus: &Stimulus,
    work: &Path,
) -> Result<HdlSpeed> {
    let plan = CosimPlan {
        simulators: vec![simulator],
        opt: CxxOpt::O3,
        ..CosimPlan::default()
    };
    let report = cosim(config, std::slice::from_ref(stimulus), work, &plan)?;
    let run: &SimRun = match report.runs.first() {
        Some(r) => r,
        None => bail!("{simulator}: the runner returned no run"),
    };
    if !run.passed {
        bail!(
            "{simulator} does not match the model: {}",
            run.first_mismatch
                .as_deref()
                .unwrap_or("(no MISMATCH line)")
        );
    }
    Ok(HdlSpeed {
        simulator,
        cycles: run.cycles,
        seconds: run.seconds,
        build_seconds: report
            .build_seconds
            .iter()
            .find(|(s, _)| *s == simulator)
            .map_or(0.0, |b| b.1),
    })
}
