//! yosys `synth_ice40` of the calibration points: writes each point's Verilog with
//! tooltouch-hdl-gen, synthesizes every module but the chip top (the MCU bus registers
//! and the reset synchronizer are a constant the features do not vary), and counts the
//! flip-flop and LUT cells of the last `stat`. The points run in parallel (one yosys per
//! rayon thread); each run's wall time is kept so the cost of the check is visible.

use super::calibration::{Calibration, CalibrationPoint};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use tooltouch_hdl_gen::{generate, Options, FPGA_TOP};
use tooltouch_rtl_sim::runner::find_tool;
use tooltouch_rtl_sim::{io_err, write_design, HdlError, Result};

/// The yosys script, after the `read_verilog` of the design files.
pub const SYNTH_SCRIPT: &str = "synth_ice40 -top tt_frontend; stat";

/// One point's synthesis.
#[derive(Clone, Debug, PartialEq)]
pub struct Synthesis {
    /// The measurement.
    pub calibration: Calibration,
    /// Wall time of the yosys run, s.
    pub seconds: f64,
    /// CPU time of the yosys run (user + system, from its log), s: the wall time an idle
    /// core would take.
    pub cpu_seconds: f64,
}

/// Runs of one point's synthesis when ABC aborts: ABC (the Debian `berkeley-abc` yosys
/// calls) has assertion crashes that come and go between identical runs (return code 134;
/// once in CI, never in 80 runs of the same design here), so an abort is synthesized once
/// more; any other failure, or a second abort, is an error with the log's tail.
pub const ABC_ATTEMPTS: u32 = 2;

/// Whether a yosys log ends in ABC's abort (`ABC: execution of command … failed: return
/// code 134.`).
pub fn abc_aborted(log: &str) -> bool {
    log.lines()
        .any(|l| l.contains("ABC: execution of command") && l.contains("return code 134"))
}

/// `yosys -V`, e.g. `Yosys 0.23 (git sha1 7ce5011c24b)`.
pub fn yosys_version() -> Result<String> {
    let yosys = find_tool("yosys")?;
    let out = Command::new(&yosys)
        .arg("-V")
        .output()
        .map_err(io_err(&yosys))?;
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// `(flip-flops, logic cells)`: the `SB_DFF*` and `SB_LUT4` counts of the last statistics
/// block of a yosys log.
pub fn cell_counts(log: &str) -> (u32, u32) {
    let last = log
        .rfind("Number of cells")
        .map(|i| &log[i..])
        .unwrap_or(log);
    let count = |prefix: &str| -> u32 {
        last.lines()
            .map(str::trim)
            .filter(|l| l.starts_with(prefix))
            .filter_map(|l| l.split_whitespace().nth(1)?.parse::<u32>().ok())
            .sum()
    };
    (count("SB_DFF"), count("SB_LUT4"))
}

/// User + system CPU seconds of a yosys log's `End of script. … CPU: user 2.55s system
/// 0.05s, …` line (0 when absent).
pub fn cpu_seconds(log: &str) -> f64 {
    let Some(line) = log.lines().rev().find(|l| l.starts_with("End of script.")) else {
        return 0.0;
    };
    let after = |key: &str| -> f64 {
        line.split(key)
            .nth(1)
            .and_then(|rest| rest.split('s').next())
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or(0.0)
    };
    after("CPU: user ") + after(" system ")
}

/// Synthesizes one calibration point in `work` (created).
pub fn synthesize(point: &CalibrationPoint, work: &Path) -> Result<Synthesis> {
    let yosys = find_tool("yosys")?;
    let config = point.settings().validate().map_err(|e| HdlError::Check {
        check: "calibration point".into(),
        details: format!("{point:?}: {e}"),
    })?;
    let files = write_design(work, &generate(&config, &Options::default()), None)?;
    let chip_top = format!("{FPGA_TOP}.v");
    let design: Vec<PathBuf> = files
        .into_iter()
        .filter(|f| f.file_name().is_none_or(|n| n != chip_top.as_str()))
        .collect();
    let names: Vec<String> = design
        .iter()
        .map(|f| f.to_string_lossy().into_owned())
        .collect();
    let script = format!("read_verilog {}; {SYNTH_SCRIPT}", names.join(" "));
    let log_path = work.join("synth.log");
    let mut attempt = 1;
    let seconds = loop {
        let t = Instant::now();
        let out = Command::new(&yosys)
            .arg("-q")
            .arg("-l")
            .arg(&log_path)
            .arg("-p")
            .arg(&script)
            .output()
            .map_err(io_err(&yosys))?;
        let seconds = t.elapsed().as_secs_f64();
        if out.status.success() {
            break seconds;
        }
        let log = std::fs::read_to_string(&log_path).unwrap_or_default();
        if attempt < ABC_ATTEMPTS && abc_aborted(&log) {
            eprintln!(
                "{}: yosys's ABC aborted (return code 134), synthesizing again ({}/{ABC_ATTEMPTS})",
                work.display(),
                attempt + 1
            );
            attempt += 1;
            continue;
        }
        let lines: Vec<&str> = log.lines().collect();
        return Err(HdlError::ToolFailed {
            command: format!("yosys -p \"{script}\""),
            status: out.status.to_string(),
            output: format!(
                "{}\nlast lines of {}:\n{}",
                String::from_utf8_lossy(&out.stderr).trim_end(),
                log_path.display(),
                lines[lines.len().saturating_sub(30)..].join("\n")
            ),
        });
    };
    let log = std::fs::read_to_string(&log_path).map_err(io_err(&log_path))?;
    let (flip_flops, logic_cells) = cell_counts(&log);
    if flip_flops == 0 || logic_cells == 0 {
        return Err(HdlError::Check {
            check: "yosys stat".into(),
            details: format!("no SB_DFF or SB_LUT4 cell in {}", log_path.display()),
        });
    }
    Ok(Synthesis {
        calibration: Calibration {
            point: *point,
            flip_flops,
            logic_cells,
        },
        seconds,
        cpu_seconds: cpu_seconds(&log),
    })
}

/// Synthesizes `points` in parallel, point `i` in `work/p<i>`; results in `points` order.
pub fn synthesize_all(points: &[CalibrationPoint], work: &Path) -> Result<Vec<Synthesis>> {
    points
        .par_iter()
        .enumerate()
        .map(|(i, p)| synthesize(p, &work.join(format!("p{i:02}"))))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_counts_read_the_last_statistics_block() {
        let log = "\
   Number of cells:                 10
     SB_DFF                          1
     SB_LUT4                         2
...
   Number of cells:                724
     SB_CARRY                      101
     SB_DFFESR                     169
     SB_DFFSR                       46
     SB_LUT4                       408
";
        assert_eq!(cell_counts(log), (215, 408));
    }

    #[test]
    fn only_abcs_abort_is_synthesized_again() {
        let abort = "ERROR: ABC: execution of command \"\"berkeley-abc\" -s -f \
                     /tmp/yosys-abc-pC8jEU/abc.script 2>&1\" failed: return code 134.";
        assert!(abc_aborted(&format!("4.48.1.1. Executing ABC.\n{abort}\n")));
        assert!(!abc_aborted(&abort.replace("134", "139")));
        assert!(!abc_aborted("ERROR: syntax error, unexpected TOK_ID\n"));
    }

    #[test]
    fn cpu_seconds_read_the_end_of_script_line() {
        let log = "...\nEnd of script. Logfile hash: b7620098b7, CPU: user 2.55s system 0.05s, \
                   MEM: 28.21 MB peak\nYosys 0.23\n";
        assert!((cpu_seconds(log) - 2.60).abs() < 1e-9);
        assert_eq!(cpu_seconds("no such line"), 0.0);
    }
}
