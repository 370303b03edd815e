//! The formal equivalence proof of the generated front end: the optimized design
//! ([`crate::TOP`]) equals the reference written from the model's semantics
//! ([`crate::reference`]) on every input sequence, proven by k-induction with yosys's own
//! SAT solver (`sat -tempinduct`, MiniSat inside yosys: no other tool to install).
//!
//! [`files`] writes the design, the reference and the miter (`tt_formal_miter.v`, see
//! [`Miter`]); [`script`] the yosys script; [`prove`] runs it in a folder and reads the
//! verdict: [`Verdict::Proven`] (base case and induction step both hold at some length),
//! [`Verdict::Counterexample`] (the base case fails: a real input trace from power-on,
//! read back from yosys's VCD as pins per clock, [`Trace`]), or [`Verdict::Undecided`]
//! (the base case holds up to the bound but no induction step did — never called proven).
//! [`write_counterexample_vcd`] writes a counterexample as a VCD that `tooltouch vectors`
//! reads as a stimulus and `tooltouch check` as a DUT trace, so the difference shows
//! against the golden model.
//!
//! Reset: the induction holds `rst` low (`-set rst 0`), so it covers every sequence from
//! power-on (the registers' initializers) and every counterexample can be replayed on the
//! model, which has no reset input. A second check ([`Proof::reset_proven`]) shows that one
//! clock with `rst` high, from any state, leads to a state where every assertion holds, so
//! the equality holds after any use of `rst` too.

use crate::design::{Options, VerilogFile};
use crate::emit::Context;
use crate::modules::tt_formal_miter;
pub use crate::modules::tt_formal_miter::{Miter, MITER};
use crate::modules::tt_frontend_ref::{reference, REFERENCE_TOP};
use crate::outputs::output_fields;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::{MeasureConfig, MeasureOutputs};

/// Induction length tried before a proof is given up as undecided. The invariants make
/// the generated designs inductive at length 1 or 2; the bound leaves room for a change that
/// needs a few more clocks, and bounds the base case that looks for a counterexample.
pub const MAX_INDUCTION: u32 = 12;

/// Name of the VCD yosys writes a counterexample to, in the proof's folder.
pub const YOSYS_VCD: &str = "yosys_cex.vcd";

/// The configurations and options the proof covers by name, besides random ones: the
/// default configuration, the MCU's diagnostic counters readable, and the structural
/// variants the lint gates cover (each decision method with an exponential law, no glitch
/// filter, `i_def` 0 and the sampled rule; a linear law with the widest glitch filter and
/// step; a slow exponential law with a one-clock filter; the narrowest and the widest
/// registers).
pub fn variants() -> Vec<(String, MeasureConfig, Options)> {
    use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
    use tooltouch_model::MeasureSettings;
    let mut out = vec![
        (
            "default".to_string(),
            MeasureConfig::default(),
            Options::default(),
        ),
        (
            "default --mcu-diagnostics".to_string(),
            MeasureConfig::default(),
            Options {
                mcu_diagnostics: true,
                ..Options::default()
            },
        ),
    ];
    let laws = [
        (
            "exponential 0/16, no filter, i_def 0, sampled",
            ChargeLaw::Exponential {
                charge_shift: 0,
                discharge_shift: 16,
            },
            0,
            0,
            0,
            ContactRule::Sampled,
        ),
        (
            "linear 65535/1, glitch 255, i_def 1023",
            ChargeLaw::Linear {
                charge_step: 65535,
                discharge_step: 1,
            },
            255,
            100,
            1023,
            ContactRule::Sticky,
        ),
        (
            "exponential 5/3, glitch 1, i_def 7",
            ChargeLaw::Exponential {
                charge_shift: 5,
                discharge_shift: 3,
            },
            1,
            16384,
            7,
            ContactRule::Sticky,
        ),
    ];
    for method in [
        DecisionMethod::SinglePulse,
        DecisionMethod::Counter,
        DecisionMethod::Density,
    ] {
        for (name, law, glitch, rearm, i_def, rule) in laws {
            let settings = MeasureSettings {
                method,
                charge_law: law,
                glitch_cycles: glitch,
                rearm_threshold: rearm,
                i_def,
                contact_rule: rule,
                ..Default::default()
            };
            if let Ok(c) = settings.validate() {
                out.push((format!("{method:?}, {name}"), c, Options::default()));
            }
        }
    }
    for (ppr, revs, charge_bits, scale_bits) in [(16u16, 1u8, 4u8, 8u8), (16384, 16, 24, 32)] {
        let full = (1u32 << charge_bits) - 1;
        let settings = MeasureSettings {
            pulses_per_rev: ppr,
            window_revs: revs,
            i_def: 3,
            charge_bits,
            charge_law: ChargeLaw::Linear {
                charge_step: full,
                discharge_step: full,
            },
            fire_threshold: full,
            rearm_threshold: full - 1,
            scale_bits,
            ..Default::default()
        };
        if let Ok(c) = settings.validate() {
            out.push((
                format!("widths: {ppr} ppr x {revs} rev, charge {charge_bits} bits, scale {scale_bits} bits"),
                c,
                Options::default(),
            ));
        }
    }
    out
}

/// The miter for `config` and `options` (the design as generated with `options`, a fault
/// included, against the reference).
pub fn miter(config: &MeasureConfig, options: &Options) -> Miter {
    tt_formal_miter::emit(&Context::new(config, options))
}

/// Every Verilog file of the proof, in compile order: the design's (without the chip top
/// `tt_fpga`), the reference, the miter.
pub fn files(config: &MeasureConfig, options: &Options, miter: &Miter) -> Vec<VerilogFile> {
    let mut out: Vec<VerilogFile> = crate::generate(config, options)
        .files
        .into_iter()
        .filter(|f| f.name != format!("{}.v", crate::FPGA_TOP))
        .collect();
    out.push(reference(config, options, REFERENCE_TOP));
    out.push(miter.file.clone());
    out
}

/// The yosys script of the proof over `files` (names relative to the folder it runs in):
/// read, flatten, connect the probes, then k-induction of every assertion up to
/// `max_induction` clocks with `rst` held low, a counterexample dumped to [`YOSYS_VCD`];
/// then the reset check.
pub fn script(
    config: &MeasureConfig,
    miter: &Miter,
    files: &[String],
    max_induction: u32,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "read_verilog -formal {}", files.join(" "));
    let _ = writeln!(s, "hierarchy -check -top {MITER}");
    let _ = writeln!(s, "proc");
    let _ = writeln!(s, "flatten");
    for (probe, source) in &miter.probes {
        let _ = writeln!(s, "connect -set {probe} {source}");
    }
    let _ = writeln!(s, "opt_clean");
    let _ = writeln!(s, "check -assert");
    let _ = writeln!(
        s,
        "sat -tempinduct -prove-asserts -set rst 0 -maxsteps {max_induction} \
         -show-inputs -show {} -dump_vcd {YOSYS_VCD}",
        miter
            .assertions
            .iter()
            .map(|(name, _)| name.clone())
            .chain(
                output_fields(config)
                    .iter()
                    .map(|f| format!("opt_{}", f.name))
            )
            .collect::<Vec<_>>()
            .join(",")
    );
    // Reset: from any state (no initial values), one clock with rst high leads to a state
    // where every assertion holds; with the induction above, the designs are equal after
    // any use of rst too.
    let _ = writeln!(s, "setattr -unset init");
    let _ = writeln!(s, "sat -seq 2 -set-at 1 rst 1 -prove-asserts -prove-skip 1");
    s
}

/// The log line of the reset check's success.
const RESET_PROVEN: &str = "SAT proof finished - no model found: SUCCESS!";

/// Input pins of a counterexample, clock by clock from power-on: `pins[k]` (bits as
/// [`pin`]) is sampled by clock `k`; `failed` are the assertions false after the last
/// clock (their `ok_*` names, see [`Miter::assertions`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Trace {
    /// Pin levels per clock.
    pub pins: Vec<u8>,
    /// MCU address per clock.
    pub mcu_addr: Vec<u32>,
    /// The optimized design's outputs registered after each clock, raw bits in
    /// [`crate::output_fields`] order.
    pub outputs: Vec<[u64; MeasureOutputs::FIELD_COUNT]>,
    /// The assertions that fail at the end of the trace.
    pub failed: Vec<String>,
}

/// The outcome of a proof.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Base case and induction step hold at induction length `depth`: equal forever.
    Proven {
        /// Induction length, clocks.
        depth: u32,
    },
    /// The base case fails: a real trace from power-on on which the designs differ (or an
    /// invariant does not hold).
    Counterexample(Trace),
    /// The base case holds for `depth` clocks, but no induction step up to that length
    /// did: not proven.
    Undecided {
        /// Clocks of the base case proven, the longest induction step tried.
        depth: u32,
    },
}

/// A proof run: the verdict, the reset check, its wall time and yosys's log.
#[derive(Clone, Debug)]
pub struct Proof {
    /// The verdict of the induction from power-on (`rst` low).
    pub verdict: Verdict,
    /// Whether one clock of `rst` from any state leads to a state where every assertion
    /// holds (so the verdict extends to any use of `rst`).
    pub reset_proven: bool,
    /// Wall time of yosys, s.
    pub seconds: f64,
    /// The folder holding the files, the script, the log and a counterexample's VCD.
    pub dir: PathBuf,
    /// yosys's output.
    pub log: String,
}

/// Errors of a proof run (not a failed proof: that is a [`Verdict`]).
#[derive(Debug, thiserror::Error)]
pub enum FormalError {
    /// yosys is not installed.
    #[error("`yosys` was not found on PATH: run `cargo xtask setup` to install it")]
    YosysMissing,
    /// A file could not be written or read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// yosys failed for another reason than the proof (or its log holds no verdict).
    #[error("yosys failed in {dir}: {message}\n{tail}")]
    Yosys {
        /// The proof's folder.
        dir: PathBuf,
        /// What went wrong.
        message: String,
        /// The end of its log.
        tail: String,
    },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> FormalError + '_ {
    move |source| FormalError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Writes the proof's files and script into `dir` and runs yosys there: the equivalence
/// of the design generated with `options` and the reference, by k-induction up to
/// `max_induction` clocks.
pub fn prove(
    config: &MeasureConfig,
    options: &Options,
    dir: &Path,
    max_induction: u32,
) -> Result<Proof, FormalError> {
    prove_miter(config, options, &miter(config, options), dir, max_induction)
}

/// [`prove`] with a given miter (e.g. one whose property was edited, to show that the proof
/// notices).
pub fn prove_miter(
    config: &MeasureConfig,
    options: &Options,
    m: &Miter,
    dir: &Path,
    max_induction: u32,
) -> Result<Proof, FormalError> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let mut names = Vec::new();
    for f in files(config, options, m) {
        let p = dir.join(&f.name);
        std::fs::write(&p, &f.text).map_err(io(&p))?;
        names.push(f.name);
    }
    let script_path = dir.join("proof.ys");
    std::fs::write(&script_path, script(config, m, &names, max_induction))
        .map_err(io(&script_path))?;
    let vcd = dir.join(YOSYS_VCD);
    let _ = std::fs::remove_file(&vcd);
    let t = Instant::now();
    let out = Command::new("yosys")
        .args(["-q", "-l", "proof.log", "-s", "proof.ys"])
        .current_dir(dir)
        .output()
        .map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                FormalError::YosysMissing
            } else {
                FormalError::Io {
                    path: PathBuf::from("yosys"),
                    source: e,
                }
            }
        })?;
    let seconds = t.elapsed().as_secs_f64();
    let log_path = dir.join("proof.log");
    let log = std::fs::read_to_string(&log_path).unwrap_or_else(|_| {
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    });
    let tail = |log: &str| {
        let lines: Vec<&str> = log.lines().collect();
        lines[lines.len().saturating_sub(30)..].join("\n")
    };
    let yosys_error = |message: &str| FormalError::Yosys {
        dir: dir.to_path_buf(),
        message: message.to_string(),
        tail: format!(
            "{}\n{}",
            tail(&log),
            String::from_utf8_lossy(&out.stderr).trim()
        ),
    };
    let verdict = if log.contains("Induction step proven: SUCCESS!") {
        let depth = last_number_after(&log, "** Trying induction with length ")
            .ok_or_else(|| yosys_error("no induction length in the log"))?;
        Verdict::Proven { depth }
    } else if log.contains("model found for base case: FAIL!") {
        let text = std::fs::read_to_string(&vcd).map_err(io(&vcd))?;
        Verdict::Counterexample(
            read_yosys_trace(&text, m, config)
                .ok_or_else(|| yosys_error("the counterexample VCD could not be read"))?,
        )
    } else if log.contains("Reached maximum number of time steps -> proof failed.") {
        let depth = last_number_after(&log, "** Trying induction with length ")
            .ok_or_else(|| yosys_error("no induction length in the log"))?;
        Verdict::Undecided { depth }
    } else {
        return Err(yosys_error(if out.status.success() {
            "no verdict in the log"
        } else {
            "yosys exited with an error"
        }));
    };
    Ok(Proof {
        verdict,
        reset_proven: log.contains(RESET_PROVEN),
        seconds,
        dir: dir.to_path_buf(),
        log,
    })
}

/// The number following the last occurrence of `prefix` in `log`.
fn last_number_after(log: &str, prefix: &str) -> Option<u32> {
    let at = log.rfind(prefix)? + prefix.len();
    let digits: String = log[at..].chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

/// Reads the inputs and the failing assertions of yosys's counterexample VCD (`sat
/// -dump_vcd`): one time step per clock, step 1 the power-on state; the inputs of step `k`
/// are sampled by clock `k - 1`, so the last step's inputs (which no clock samples) are
/// dropped.
fn read_yosys_trace(vcd: &str, miter: &Miter, config: &MeasureConfig) -> Option<Trace> {
    let fields = output_fields(config);
    // `$var <type> <width> <id> <name> $end`; values `b<bits> <id>` or `<bit><id>`;
    // time `#<t>`, one per step.
    let mut ids: std::collections::HashMap<String, String> = std::collections::HashMap::new();
    let mut steps: Vec<std::collections::HashMap<String, u64>> = Vec::new();
    let mut current: std::collections::HashMap<String, u64> = std::collections::HashMap::new();
    let mut started = false;
    let mut tokens = vcd.split_whitespace().peekable();
    while let Some(tok) = tokens.next() {
        match tok {
            "$var" => {
                let _kind = tokens.next()?;
                let _width = tokens.next()?;
                let id = tokens.next()?.to_string();
                let name = tokens.next()?.trim_start_matches('\\').to_string();
                ids.insert(id, name);
            }
            t if t.starts_with('#') => {
                if started {
                    steps.push(current.clone());
                }
                started = true;
            }
            t if t.starts_with('b') => {
                let bits = &t[1..];
                let id = tokens.next()?;
                if let Some(name) = ids.get(id) {
                    let value = u64::from_str_radix(&bits.replace(['x', 'z'], "0"), 2).ok()?;
                    current.insert(name.clone(), value);
                }
            }
            t if started && (t.starts_with('0') || t.starts_with('1')) && t.len() > 1 => {
                if let Some(name) = ids.get(&t[1..]) {
                    current.insert(name.clone(), u64::from(t.starts_with('1')));
                }
            }
            _ => {}
        }
    }
    if started {
        steps.push(current);
    }
    let last = steps.last()?;
    let failed = miter
        .assertions
        .iter()
        .filter(|(name, _)| last.get(name.as_str()) == Some(&0))
        .map(|(name, _)| name.clone())
        .collect();
    let clocks = steps.len().checked_sub(1)?;
    Some(Trace {
        pins: steps[..clocks]
            .iter()
            .map(|s| s.get("pins").copied().unwrap_or(0) as u8 & pin::ALL)
            .collect(),
        mcu_addr: steps[..clocks]
            .iter()
            .map(|s| s.get("mcu_addr").copied().unwrap_or(0) as u32)
            .collect(),
        outputs: steps[1..]
            .iter()
            .map(|s| {
                let mut o = [0u64; MeasureOutputs::FIELD_COUNT];
                for (value, f) in o.iter_mut().zip(fields.iter()) {
                    *value = s.get(&format!("opt_{}", f.name)).copied().unwrap_or(0);
                }
                o
            })
            .collect(),
        failed,
    })
}

/// Writes `trace` as a VCD at `clock_hz` (`$timescale 1ns`, rising edge `k` at `k·P`):
/// the six pins in scope `inputs` (each written at the time of the clock that samples it),
/// and, in scope `outputs`, the optimized design's outputs (the value registered after
/// clock `k`, written at `k·P`, as the golden VCD writes them). `tooltouch vectors
/// --stimulus` reads the pins; `tooltouch check --dut` compares the outputs with the
/// golden model's.
pub fn write_counterexample_vcd(
    config: &MeasureConfig,
    trace: &Trace,
    clock_hz: u32,
    path: &Path,
) -> Result<(), FormalError> {
    let (pins, outputs) = (&trace.pins, &trace.outputs);
    let period = u64::from(1_000_000_000 / clock_hz.max(1));
    let fields = output_fields(config);
    let mut v = String::new();
    let _ = writeln!(v, "$comment tooltouch formal counterexample: configuration hash {:016x}, clock {clock_hz} Hz $end", config.hash());
    v.push_str("$timescale 1ns $end\n$scope module tooltouch $end\n$scope module inputs $end\n");
    let id = |i: usize| format!("p{i}");
    let oid = |i: usize| format!("o{i}");
    for (i, name) in pin::NAMES.iter().enumerate() {
        let _ = writeln!(v, "$var wire 1 {} {name} $end", id(i));
    }
    v.push_str("$upscope $end\n$scope module outputs $end\n");
    for (i, f) in fields.iter().enumerate() {
        let _ = writeln!(v, "$var wire {} {} {} $end", f.width, oid(i), f.name);
    }
    v.push_str("$upscope $end\n$upscope $end\n$enddefinitions $end\n");
    let clocks = pins.len().max(outputs.len());
    for k in 0..clocks {
        let _ = writeln!(v, "#{}", k as u64 * period);
        if let Some(p) = pins.get(k) {
            for i in 0..pin::COUNT {
                let _ = writeln!(v, "{}{}", (p >> i) & 1, id(i));
            }
        }
        if let Some(o) = outputs.get(k) {
            for (i, f) in fields.iter().enumerate() {
                let _ = writeln!(v, "b{:0width$b} {}", o[i], oid(i), width = f.width as usize);
            }
        }
    }
    std::fs::write(path, v).map_err(io(path))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::Fault;

    #[test]
    fn every_variant_fills_every_hole_and_declares_every_probe() {
        for (name, config, options) in variants() {
            for fault in [
                Fault::None,
                Fault::FesBeforeIndex,
                Fault::FireThresholdPlusOne,
            ] {
                let options = Options { fault, ..options };
                let m = miter(&config, &options);
                let r = reference(&config, &options, REFERENCE_TOP);
                for f in [&m.file, &r] {
                    assert!(
                        !f.text.contains("${"),
                        "{name} {fault:?}: hole in {}",
                        f.name
                    );
                }
                assert!(
                    r.text.contains(&format!("module {REFERENCE_TOP} (")),
                    "{name}"
                );
                for (probe, _) in &m.probes {
                    assert!(
                        m.file.text.contains(&format!(" {probe};")),
                        "{name}: {probe}"
                    );
                }
                for (ok, _) in &m.assertions {
                    assert!(
                        m.file.text.contains(&format!("assert ({ok});")),
                        "{name}: {ok}"
                    );
                }
                let names: Vec<String> = files(&config, &options, &m)
                    .into_iter()
                    .map(|f| f.name)
                    .collect();
                let s = script(&config, &m, &names, MAX_INDUCTION);
                assert_eq!(
                    s.matches("connect -set probe_").count(),
                    m.probes.len(),
                    "{name}"
                );
            }
        }
    }

    #[test]
    fn the_reference_never_carries_a_fault() {
        let config = MeasureConfig::default();
        let good = reference(&config, &Options::default(), REFERENCE_TOP);
        let faulty = reference(
            &config,
            &Options {
                fault: Fault::FireThresholdPlusOne,
                ..Options::default()
            },
            REFERENCE_TOP,
        );
        assert_eq!(good, faulty);
    }

    #[test]
    fn a_yosys_counterexample_reads_back_as_pins_per_clock() {
        let config = MeasureConfig::default();
        let m = miter(&config, &Options::default());
        // Three steps: power-on, after clock 0, after clock 1; ok_count fails at the end.
        let vcd = "$var wire 6 ! pins $end\n$var wire 4 \" mcu_addr $end\n\
                   $var wire 1 # ok_count $end\n$var wire 11 $ opt_count $end\n\
                   $enddefinitions $end\n\
                   #0\nb000011 !\nb0001 \"\n1#\nb0 $\n\
                   #10\nb001011 !\nb0010 \"\n1#\nb1 $\n\
                   #20\nb000000 !\nb0000 \"\n0#\nb10 $\n";
        let t = read_yosys_trace(vcd, &m, &config).expect("a trace");
        assert_eq!(t.pins, vec![0b11, 0b1011]);
        assert_eq!(t.mcu_addr, vec![1, 2]);
        assert_eq!(t.failed, vec!["ok_count".to_string()]);
        let count = output_fields(&config)
            .iter()
            .position(|f| f.name == "count")
            .expect("count");
        assert_eq!(
            t.outputs.iter().map(|o| o[count]).collect::<Vec<_>>(),
            vec![1, 2]
        );
    }
}
