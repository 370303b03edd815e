//! Verilator and Icarus runners, and the lint gates (Verilator `-Wall`, yosys `check`).
//!
//! Every tool is looked up on `PATH` first; a missing one is [`HdlError::ToolMissing`],
//! whose message names `cargo xtask setup`.

use super::{io_err, HdlError, Result};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Instant;

/// Finds `tool` on `PATH`.
pub fn find_tool(tool: &str) -> Result<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|d| d.join(tool))
        .find(|p| p.is_file())
        .ok_or_else(|| HdlError::ToolMissing { tool: tool.into() })
}

/// Last `n` lines of a tool's combined output.
fn tail(out: &Output, n: usize) -> String {
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

fn describe(cmd: &Command) -> String {
    let mut s = cmd.get_program().to_string_lossy().into_owned();
    for a in cmd.get_args() {
        s.push(' ');
        s.push_str(&a.to_string_lossy());
    }
    s
}

/// Runs `cmd` (whose program is `tool`), failing with the output's tail on a non-zero
/// exit.
fn run_checked(tool: &str, cmd: &mut Command) -> Result<Output> {
    find_tool(tool)?;
    let out = cmd.output().map_err(|e| HdlError::ToolFailed {
        command: describe(cmd),
        status: "could not start".into(),
        output: e.to_string(),
    })?;
    if !out.status.success() {
        return Err(HdlError::ToolFailed {
            command: describe(cmd),
            status: out.status.to_string(),
            output: tail(&out, 40),
        });
    }
    Ok(out)
}

/// `verilator --lint-only -Wall` on the design files (not the testbench), top
/// `tooltouch_hdl_gen::FPGA_TOP` (which instantiates every module). Any warning is an error.
pub fn lint_verilator(files: &[PathBuf]) -> Result<()> {
    let mut cmd = Command::new("verilator");
    cmd.args([
        "--lint-only",
        "-Wall",
        "--top-module",
        tooltouch_hdl_gen::FPGA_TOP,
    ])
    .args(files);
    let out = run_checked("verilator", &mut cmd)?;
    let text = tail(&out, 60);
    if text.contains("%Warning") || text.contains("%Error") {
        return Err(HdlError::Check {
            check: "verilator --lint-only -Wall".into(),
            details: text,
        });
    }
    Ok(())
}

/// What the yosys structural check found.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct YosysCheck {
    /// Flip-flop cells after `proc; opt` (coarse `$dff`/`$sdff`… cells, any width).
    pub dff_cells: usize,
    /// The `check` pass's log.
    pub log: String,
}

/// yosys: `hierarchy -check; proc; check -assert` (fails on undriven or multiply driven
/// wires and logic loops) and asserts that no latch cell exists after `proc`.
pub fn yosys_check(files: &[PathBuf], work: &Path) -> Result<YosysCheck> {
    let mut script = String::new();
    for f in files {
        script.push_str(&format!("read_verilog {}\n", f.display()));
    }
    script.push_str(&format!(
        "hierarchy -check -top {top}\n\
         proc\n\
         flatten\n\
         opt_clean\n\
         check -assert\n\
         select -assert-none t:$dlatch t:$adlatch t:$dlatchsr t:$sr\n\
         stat\n",
        top = tooltouch_hdl_gen::FPGA_TOP
    ));
    let ys = work.join("check.ys");
    std::fs::write(&ys, script).map_err(io_err(&ys))?;
    let mut cmd = Command::new("yosys");
    cmd.arg("-q").arg("-l").arg(work.join("check.log")).arg(&ys);
    run_checked("yosys", &mut cmd)?;
    let log_path = work.join("check.log");
    let log = std::fs::read_to_string(&log_path).map_err(io_err(&log_path))?;
    // proc logs "Latch inferred for signal …" (and "No latch inferred …" otherwise).
    if log
        .lines()
        .any(|l| l.trim_start().starts_with("Latch inferred"))
    {
        return Err(HdlError::Check {
            check: "yosys proc".into(),
            details: "a latch was inferred".into(),
        });
    }
    let dff_cells = log
        .lines()
        .filter(|l| l.trim_start().starts_with("$") && l.contains("dff"))
        .filter_map(|l| l.split_whitespace().last()?.parse::<usize>().ok())
        .sum();
    Ok(YosysCheck { dff_cells, log })
}

/// Which simulator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Simulator {
    /// Verilator 5 (`--cc --exe` with the generated C++ driver).
    Verilator,
    /// Icarus Verilog (`iverilog -g2005` + `vvp`).
    Icarus,
}

impl std::fmt::Display for Simulator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Simulator::Verilator => "verilator",
            Simulator::Icarus => "icarus",
        })
    }
}

/// C++ optimisation of a Verilator build. Verilator 5.006 compiles at `-Os` unless told
/// otherwise (docs/architecture.md, pitfalls).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CxxOpt {
    /// `-O3` for every part: slower to build, fastest to run (benchmarks, long runs).
    O3,
    /// `-O1`: quicker to build (many configurations, short runs).
    O1,
}

/// A compiled testbench.
#[derive(Clone, Debug, PartialEq)]
pub struct Build {
    /// The simulator.
    pub simulator: Simulator,
    /// The executable (Verilator) or the `vvp` image (Icarus).
    pub image: PathBuf,
    /// Build wall time, s.
    pub seconds: f64,
}

/// Which dump a Verilator build can write (the testbench's `+vcd` / `+fst`); Icarus can
/// always dump, VCD or (run with `vvp -fst`, [`run_with`]) FST.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Trace {
    /// No tracing compiled in (quickest build and run; `+vcd` / `+fst` write nothing).
    #[default]
    None,
    /// `--trace`: VCD.
    Vcd,
    /// `--trace-fst`: FST.
    Fst,
}

/// Compiles the testbench `files` (design files, `tt_testbench.v`, and the Verilator
/// driver `tt_testbench_main.cpp`, which Icarus skips) into `work`.
pub fn build(sim: Simulator, files: &[PathBuf], work: &Path, opt: CxxOpt) -> Result<Build> {
    build_traced(sim, files, work, opt, Trace::None)
}

/// [`build`], with Verilator's tracing `trace` compiled in (Icarus ignores it).
pub fn build_traced(
    sim: Simulator,
    files: &[PathBuf],
    work: &Path,
    opt: CxxOpt,
    trace: Trace,
) -> Result<Build> {
    std::fs::create_dir_all(work).map_err(io_err(work))?;
    let t = Instant::now();
    let image = match sim {
        Simulator::Verilator => {
            // Without --timing: the C++ driver (tt_testbench_main.cpp, among `files`)
            // clocks the testbench, which builds faster and runs ~an order faster.
            let mdir = work.join("obj_verilator");
            let flags = match opt {
                CxxOpt::O3 => "OPT_FAST=-O3 OPT_GLOBAL=-O3 OPT_SLOW=-O3",
                CxxOpt::O1 => "OPT_FAST=-O1 OPT_GLOBAL=-O1 OPT_SLOW=-O1",
            };
            let mut cmd = Command::new("verilator");
            cmd.args(["--cc", "--exe", "--build", "--top-module"])
                .arg(tooltouch_hdl_gen::TESTBENCH)
                .arg("-Mdir")
                .arg(&mdir)
                .args(["-o", "tb", "-MAKEFLAGS", flags])
                .args(match trace {
                    Trace::None => &[][..],
                    Trace::Vcd => &["--trace"][..],
                    Trace::Fst => &["--trace-fst"][..],
                })
                .args(files);
            run_checked("verilator", &mut cmd)?;
            mdir.join("tb")
        }
        Simulator::Icarus => {
            let image = work.join("tb.vvp");
            let mut cmd = Command::new("iverilog");
            cmd.args(["-g2005", "-s", tooltouch_hdl_gen::TESTBENCH, "-o"])
                .arg(&image)
                .args(
                    files
                        .iter()
                        .filter(|f| f.extension().is_some_and(|e| e == "v")),
                );
            run_checked("iverilog", &mut cmd)?;
            image
        }
    };
    Ok(Build {
        simulator: sim,
        image,
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// The outcome of one testbench run.
#[derive(Clone, Debug, PartialEq)]
pub struct SimRun {
    /// The simulator.
    pub simulator: Simulator,
    /// Clock cycles simulated (from the `TESTBENCH OK|FAIL` line).
    pub cycles: u64,
    /// Whether every output matched on every cycle.
    pub passed: bool,
    /// The testbench's first `MISMATCH …` line, if any.
    pub first_mismatch: Option<String>,
    /// Wall time of the run, s.
    pub seconds: f64,
    /// The simulator's output (tail).
    pub output: String,
}

impl SimRun {
    /// Simulated clock cycles per wall-clock second.
    pub fn cycles_per_second(&self) -> f64 {
        if self.seconds > 0.0 {
            self.cycles as f64 / self.seconds
        } else {
            0.0
        }
    }
}

/// Runs a compiled testbench in `vectors` (the directory holding `stim.hex` and
/// `expect.hex`) with the given plusargs (e.g. `+vcd`, `+fst`, `+nostop`).
///
/// A run that mismatches is `Ok` with `passed == false`; a run that ends without the
/// testbench's verdict line is an error.
pub fn run(build: &Build, vectors: &Path, plusargs: &[&str]) -> Result<SimRun> {
    run_with(build, vectors, plusargs, false)
}

/// [`run`]; `icarus_fst`: Icarus dumps FST (`vvp -fst`) instead of VCD (Verilator: the
/// build's [`Trace`] decides).
pub fn run_with(
    build: &Build,
    vectors: &Path,
    plusargs: &[&str],
    icarus_fst: bool,
) -> Result<SimRun> {
    let mut cmd = match build.simulator {
        Simulator::Verilator => Command::new(&build.image),
        Simulator::Icarus => {
            find_tool("vvp")?;
            let mut c = Command::new("vvp");
            c.arg("-n").arg(&build.image);
            if icarus_fst {
                c.arg("-fst");
            }
            c
        }
    };
    cmd.args(plusargs).current_dir(vectors);
    let t = Instant::now();
    let out = cmd.output().map_err(|e| HdlError::ToolFailed {
        command: describe(&cmd),
        status: "could not start".into(),
        output: e.to_string(),
    })?;
    let seconds = t.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let first_mismatch = stdout
        .lines()
        .find(|l| l.starts_with("MISMATCH"))
        .map(|l| l.trim().to_string());
    let verdict = stdout
        .lines()
        .find_map(|l| l.strip_prefix("TESTBENCH ").map(str::to_string));
    let output = tail(&out, 20);
    let (passed, cycles) = match verdict
        .as_deref()
        .map(|v| v.split_whitespace().collect::<Vec<_>>())
    {
        Some(v) if v.first() == Some(&"OK") && v.len() == 2 => {
            (out.status.success(), v[1].parse().unwrap_or(0))
        }
        Some(v) if v.first() == Some(&"FAIL") && v.len() == 3 => (false, v[2].parse().unwrap_or(0)),
        _ if first_mismatch.is_some() => (false, 0),
        _ => {
            return Err(HdlError::ToolFailed {
                command: describe(&cmd),
                status: format!("{} without a TESTBENCH verdict", out.status),
                output,
            })
        }
    };
    Ok(SimRun {
        simulator: build.simulator,
        cycles,
        passed: passed && first_mismatch.is_none(),
        first_mismatch,
        seconds,
        output,
    })
}
