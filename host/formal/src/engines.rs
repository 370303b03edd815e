//! The proof engines: ABC (`yosys-abc`, installed with yosys) run on the miter's
//! And-Inverter graph, one process per engine with a wall-time limit, as a portfolio.
//!
//! | engine | ABC commands | proves | finds a difference |
//! | --- | --- | --- | --- |
//! | [`Engine::ScorrPdr`] | `scorr; pdr` | PDR (IC3) on the graph reduced by signal correspondence | yes |
//! | [`Engine::Dprove`] | `dprove` | latch correspondence, then induction (and its own BMC, interpolation, PDR) | yes (its BMC) |
//! | [`Engine::Interpolation`] | `int` | Craig interpolation | yes |
//! | [`Engine::Bmc`] | `bmc3` | nothing (bounded) | yes, the shortest |
//!
//! Each engine's answer is read from ABC's own verdict line; a run that ends another way
//! (its time limit, ABC's resource limits, "UNDECIDED") is [`EngineResult::Undecided`].
//! A difference is read back from ABC's `write_cex` (every input at every frame).

use super::error::FormalError;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// One engine of the portfolio.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Engine {
    /// `dprove`: latch correspondence, then induction.
    Dprove,
    /// `scorr; pdr`: property-directed reachability on the reduced graph.
    ScorrPdr,
    /// `int`: interpolation.
    Interpolation,
    /// `bmc3`: bounded model checking, for a difference only.
    Bmc,
}

/// The default portfolio, in the order tried: signal correspondence then PDR closes the
/// generated design in seconds and finds deep differences (5 185 clocks for the fire
/// threshold one too high, in 12 s), where `dprove` did not finish in 120 s
/// (docs/formal.md); `dprove` and interpolation for what PDR does not close; BMC last,
/// for a difference the others did not reach.
pub const PORTFOLIO: [Engine; 4] = [
    Engine::ScorrPdr,
    Engine::Dprove,
    Engine::Interpolation,
    Engine::Bmc,
];

impl Engine {
    /// The engine's name in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Engine::Dprove => "dprove",
            Engine::ScorrPdr => "scorr-pdr",
            Engine::Interpolation => "interpolation",
            Engine::Bmc => "bmc",
        }
    }

    /// What the engine does, for reports.
    pub fn describe(self) -> &'static str {
        match self {
            Engine::Dprove => "ABC dprove: latch correspondence, then induction",
            Engine::ScorrPdr => "ABC scorr; pdr: property-directed reachability",
            Engine::Interpolation => "ABC int: interpolation",
            Engine::Bmc => "ABC bmc3: bounded model checking (finds differences, proves nothing)",
        }
    }

    /// ABC's commands for the engine with a time limit of `seconds`.
    fn commands(self, seconds: u64) -> String {
        let t = seconds.max(1);
        match self {
            Engine::Dprove => format!("dprove -T {t}"),
            Engine::ScorrPdr => format!("scorr; pdr -T {t}"),
            Engine::Interpolation => format!("int -T {t}"),
            Engine::Bmc => format!("bmc3 -T {t}"),
        }
    }
}

/// What one engine concluded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EngineResult {
    /// The miter's output is 0 in every reachable state: the designs are equal.
    Proven,
    /// The output is 1 in frame `frame`; `cex` is ABC's `write_cex` text.
    Different {
        /// Frame (clocks from power-on) at which the designs differ.
        frame: u32,
        /// The counterexample, as ABC wrote it.
        cex: String,
    },
    /// Neither, with ABC's last words.
    Undecided {
        /// Why: the time limit, or ABC's last line.
        why: String,
    },
}

/// One engine's run.
#[derive(Clone, Debug, PartialEq)]
pub struct Attempt {
    /// The engine.
    pub engine: Engine,
    /// Its conclusion.
    pub result: EngineResult,
    /// Wall time, s.
    pub seconds: f64,
}

/// Runs `engine` on the AIGER `aig` (in `dir`) for at most `seconds` of wall time (ABC's
/// own limit, and the process killed a few seconds after it), its output kept in
/// `<engine>.log` in `dir`.
pub fn run_engine(
    engine: Engine,
    dir: &Path,
    aig: &str,
    seconds: u64,
) -> Result<Attempt, FormalError> {
    super::error::find("yosys-abc")?;
    let cex_file = format!("{}.cex", engine.name());
    let log_name = format!("{}.log", engine.name());
    let _ = std::fs::remove_file(dir.join(&cex_file));
    let script = format!(
        "read_aiger {aig}; strash; {}; write_cex -n {cex_file}",
        engine.commands(seconds)
    );
    let log_path = dir.join(&log_name);
    let log_file = std::fs::File::create(&log_path).map_err(super::error::io(&log_path))?;
    let err_file = log_file.try_clone().map_err(super::error::io(&log_path))?;
    let t = Instant::now();
    let mut child = Command::new("yosys-abc")
        .arg("-c")
        .arg(&script)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(log_file)
        .stderr(err_file)
        .spawn()
        .map_err(super::error::io(Path::new("yosys-abc")))?;
    let limit = Duration::from_secs(seconds + 5);
    let mut killed = false;
    loop {
        if child
            .try_wait()
            .map_err(super::error::io(Path::new("yosys-abc")))?
            .is_some()
        {
            break;
        }
        if t.elapsed() > limit {
            // Our own child, by its handle.
            let _ = child.kill();
            let _ = child.wait();
            killed = true;
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let seconds_taken = t.elapsed().as_secs_f64();
    let log = std::fs::read_to_string(&log_path).unwrap_or_default();
    let result = if killed {
        EngineResult::Undecided {
            why: format!("stopped at its time limit of {seconds} s"),
        }
    } else {
        read_verdict(engine, &log, &dir.join(&cex_file))?
    };
    Ok(Attempt {
        engine,
        result,
        seconds: seconds_taken,
    })
}

/// The engine's verdict from ABC's log (and its counterexample file).
fn read_verdict(engine: Engine, log: &str, cex: &Path) -> Result<EngineResult, FormalError> {
    let asserted = log.lines().find_map(|l| {
        let at = l.find("was asserted in frame ")? + "was asserted in frame ".len();
        l[at..]
            .chars()
            .take_while(char::is_ascii_digit)
            .collect::<String>()
            .parse::<u32>()
            .ok()
    });
    let not_equal = log.contains("Networks are not equivalent");
    if asserted.is_some() || not_equal {
        let text = std::fs::read_to_string(cex).map_err(|e| {
            FormalError::Tool(format!(
                "{}: ABC found a difference but wrote no counterexample ({}: {e})",
                engine.name(),
                cex.display()
            ))
        })?;
        let frame = match asserted {
            Some(f) => f,
            None => super::counterexample::cex_length(&text)
                .and_then(|n| n.checked_sub(1))
                .ok_or_else(|| {
                    FormalError::Tool(format!(
                        "{}: the counterexample {} has no length",
                        engine.name(),
                        cex.display()
                    ))
                })?,
        };
        return Ok(EngineResult::Different { frame, cex: text });
    }
    let proven = match engine {
        Engine::Dprove => log.contains("Networks are equivalent"),
        Engine::ScorrPdr | Engine::Interpolation => log.contains("Property proved"),
        Engine::Bmc => false,
    };
    if proven {
        return Ok(EngineResult::Proven);
    }
    let why = log
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with("ABC command line"))
        .unwrap_or("no verdict")
        .to_string();
    Ok(EngineResult::Undecided { why })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_read_from_abc_logs() {
        let none = Path::new("/nonexistent/cex");
        assert_eq!(
            read_verdict(
                Engine::Dprove,
                "No output failed in 12 frames.\nNetworks are equivalent.  Time = 0.25 sec",
                none
            )
            .unwrap(),
            EngineResult::Proven
        );
        assert_eq!(
            read_verdict(Engine::ScorrPdr, "Property proved.  Time = 0.01 sec", none).unwrap(),
            EngineResult::Proven
        );
        // bmc3 never proves.
        assert!(matches!(
            read_verdict(
                Engine::Bmc,
                "No output asserted in 45 frames. Resource limit reached (timeout 5 sec).",
                none
            )
            .unwrap(),
            EngineResult::Undecided { .. }
        ));
        assert!(matches!(
            read_verdict(Engine::ScorrPdr, "Reached timeout (5 seconds) in frame 59.\nProperty UNDECIDED.  Time = 5.05 sec", none).unwrap(),
            EngineResult::Undecided { why } if why.contains("UNDECIDED")
        ));
        // A difference without its counterexample file is a tool error, not a verdict.
        assert!(read_verdict(
            Engine::Bmc,
            "Output 0 of miter \"m\" was asserted in frame 9. Time = 0.02 sec",
            none
        )
        .is_err());
    }
}
