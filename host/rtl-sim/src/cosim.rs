//! Co-simulation of the generated Verilog with the golden cycle model: one configuration,
//! a batch of stimuli, the testbench built once per simulator and run once per stimulus.

use super::runner::{build_traced, lint_verilator, run_with, CxxOpt, SimRun, Simulator, Trace};
use super::{write_design, HdlError, Result};
use std::path::Path;
use tooltouch_hdl_gen::{generate, testbench, verilator_main, Options, TestbenchSpec};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_vectors::hex::{golden_vectors, write_vectors};

/// What to run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CosimPlan {
    /// Generation options (a fault, in tests of the checkers).
    pub options: Options,
    /// Simulators to run.
    pub simulators: Vec<Simulator>,
    /// C++ optimisation of the Verilator build.
    pub opt: CxxOpt,
    /// Lint the design with `verilator --lint-only -Wall` first.
    pub lint: bool,
    /// Extra plusargs (`+vcd`, `+fst`, `+nostop`).
    pub plusargs: Vec<String>,
    /// The dump format: Verilator built with `--trace` / `--trace-fst`, Icarus run with
    /// `vvp -fst` for [`Trace::Fst`] (Icarus dumps VCD otherwise).
    pub trace: Trace,
}

impl Default for CosimPlan {
    fn default() -> Self {
        CosimPlan {
            options: Options::default(),
            simulators: vec![Simulator::Verilator, Simulator::Icarus],
            opt: CxxOpt::O1,
            lint: false,
            plusargs: Vec::new(),
            trace: Trace::None,
        }
    }
}

/// Every run of a batch.
#[derive(Clone, Debug, PartialEq)]
pub struct CosimReport {
    /// Runs, stimulus by stimulus, simulator by simulator.
    pub runs: Vec<SimRun>,
    /// Build wall time per simulator, s.
    pub build_seconds: Vec<(Simulator, f64)>,
    /// Clock cycles per stimulus (from the model).
    pub cycles: Vec<u64>,
}

impl CosimReport {
    /// The first failing run, if any.
    pub fn first_failure(&self) -> Option<&SimRun> {
        self.runs.iter().find(|r| !r.passed)
    }
}

/// Writes the design, its testbench and each stimulus's vectors under `work`
/// (`work/rtl`, `work/case<i>`), builds each simulator once, runs every case, and checks
/// that each run simulated the model's number of cycles. Mismatches are reported in the
/// returned runs (`passed == false`), not as errors.
pub fn cosim(
    config: &MeasureConfig,
    stimuli: &[Stimulus],
    work: &Path,
    plan: &CosimPlan,
) -> Result<CosimReport> {
    let clock_hz = stimuli
        .first()
        .map(|s| s.clock_hz)
        .ok_or_else(|| HdlError::Stimulus("no stimulus to simulate".into()))?;
    if stimuli.iter().any(|s| s.clock_hz != clock_hz) {
        return Err(HdlError::Stimulus(
            "the stimuli of one batch must share a clock frequency".into(),
        ));
    }
    let mut vectors = Vec::with_capacity(stimuli.len());
    for (i, s) in stimuli.iter().enumerate() {
        let v = golden_vectors(config, s)?;
        write_vectors(&work.join(format!("case{i}")), &v)?;
        vectors.push(v);
    }
    let spec = TestbenchSpec {
        clock_hz,
        stim_depth: vectors.iter().map(|v| v.stim_words).max().unwrap_or(2),
        expect_depth: vectors.iter().map(|v| v.expect_words).max().unwrap_or(2),
        mcu_diagnostics: plan.options.mcu_diagnostics,
    };
    if !spec.depths_fit() {
        return Err(HdlError::Stimulus(format!(
            "vectors of {} stim.hex and {} expect.hex words: more than the testbench's {} words",
            spec.stim_depth,
            spec.expect_depth,
            tooltouch_hdl_gen::MAX_DEPTH
        )));
    }
    let tb = testbench(config, &spec).ok_or_else(|| {
        HdlError::Stimulus(format!(
            "clock {clock_hz} Hz: the period must be a whole number of ns, at least 2"
        ))
    })?;
    let design = generate(config, &plan.options);
    let rtl = work.join("rtl");
    let mut files = write_design(&rtl, &design, Some(&tb))?;
    if plan.lint {
        lint_verilator(&files[..files.len() - 1])?;
    }
    // The Verilator driver (same clock as the testbench, so it exists whenever `tb` does).
    if let Some(main) = verilator_main(config, &spec) {
        let p = rtl.join(&main.name);
        std::fs::write(&p, &main.text).map_err(super::io_err(&p))?;
        files.push(p);
    }
    let plusargs: Vec<&str> = plan.plusargs.iter().map(String::as_str).collect();
    let mut report = CosimReport {
        runs: Vec::new(),
        build_seconds: Vec::new(),
        cycles: vectors.iter().map(|v| v.cycles).collect(),
    };
    for &sim in &plan.simulators {
        let b = build_traced(
            sim,
            &files,
            &work.join(format!("build_{sim}")),
            plan.opt,
            plan.trace,
        )?;
        report.build_seconds.push((sim, b.seconds));
        for (i, v) in vectors.iter().enumerate() {
            let r = run_with(
                &b,
                &work.join(format!("case{i}")),
                &plusargs,
                plan.trace == Trace::Fst,
            )?;
            if r.passed && r.cycles != v.cycles {
                return Err(HdlError::Check {
                    check: format!("{sim} case {i}"),
                    details: format!(
                        "the testbench simulated {} cycles, the model {}",
                        r.cycles, v.cycles
                    ),
                });
            }
            report.runs.push(r);
        }
    }
    Ok(report)
}
