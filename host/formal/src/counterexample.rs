//! A difference found by an engine, turned into something the user can open and replay:
//! ABC's counterexample (`write_cex -n`: every AIGER input `piNN@F=V` at every frame `F`)
//! read back through yosys's map as the six pins and `mcu_addr` per clock
//! ([`Counterexample`]), then replayed ([`replay`]): the golden model's response to those
//! pins (`golden.vcd`, `stim.hex`, `expect.hex`, as `tooltouch vectors` writes them), the
//! generated testbench run on the user's design in Icarus (its VCD dump,
//! `counterexample.vcd`, holds the pins and the design's outputs), and `tooltouch check`'s
//! comparison of the two, whose first mismatch names the clock, signal and both values.
//! Then [`super::clocked`] replays the counterexample's own `mcu_addr` (and `rst`) clock
//! by clock, so a difference only in `mcu_rdata` is shown too. A counterexample that
//! raises `rst` after power-on is replayed by [`super::clocked`] only (its VCD is that
//! replay's dump): the golden vectors cannot carry a reset (the stimulus holds the six
//! pins, the generated testbench drives `rst` low).

use super::error::FormalError;
use super::inputs::Counterexample;
use super::miter::map_inputs;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use tooltouch_hdl_gen::{testbench, TestbenchSpec, TESTBENCH, TOP};
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::MeasureConfig;
use tooltouch_rtl_sim::runner::{build, run, CxxOpt, Simulator};
use tooltouch_vectors::check::Verdict;
use tooltouch_vectors::hex::{golden_vectors, write_vectors};

/// File name of the counterexample's VCD: the pins and the design's outputs per clock.
pub const COUNTEREXAMPLE_VCD: &str = "counterexample.vcd";
/// File name of the golden model's response to the counterexample's pins.
pub const GOLDEN_VCD: &str = "golden.vcd";

/// The `# COUNTEREXAMPLE LENGTH: n` of ABC's `write_cex` text (frames `0 … n − 1`).
pub fn cex_length(text: &str) -> Option<u32> {
    text.lines()
        .find_map(|l| l.strip_prefix("# COUNTEREXAMPLE LENGTH:"))
        .and_then(|n| n.trim().parse().ok())
}

/// Reads ABC's `write_cex -n` text through yosys's AIGER map: the designs differ after
/// `frame` clocks (the output was asserted in frame `frame`).
pub fn read_cex(text: &str, map: &str, frame: u32) -> Result<Counterexample, FormalError> {
    let mut values: BTreeMap<(usize, u32), bool> = BTreeMap::new();
    for line in text.lines() {
        let Some(rest) = line.strip_prefix("pi") else {
            continue;
        };
        let parsed = (|| {
            let (index, rest) = rest.split_once('@')?;
            let (f, v) = rest.split_once('=')?;
            Some((
                index.parse::<usize>().ok()?,
                f.parse::<u32>().ok()?,
                v.trim() == "1",
            ))
        })();
        let (index, f, v) = parsed.ok_or_else(|| {
            FormalError::Tool(format!("ABC's counterexample: unreadable line `{line}`"))
        })?;
        values.insert((index, f), v);
    }
    if frame == 0 {
        return Err(FormalError::Tool(
            "ABC's counterexample differs before the first clock, which the miter does not compare"
                .into(),
        ));
    }
    let inputs = map_inputs(map);
    let value = |index: usize, f: u32| values.get(&(index, f)).copied().unwrap_or(false);
    let mut pins = vec![0u8; frame as usize];
    let mut mcu_addr = vec![0u32; frame as usize + 1];
    let mut rst = vec![false; frame as usize + 1];
    for (index, bit, name) in &inputs {
        if let Some(p) = name
            .strip_prefix("pin_")
            .and_then(|n| pin::NAMES.iter().position(|m| *m == n))
        {
            for (f, slot) in pins.iter_mut().enumerate() {
                if value(*index, f as u32) {
                    *slot |= 1 << p;
                }
            }
        } else if name == "rst" {
            for (f, slot) in rst.iter_mut().enumerate() {
                *slot = value(*index, f as u32);
            }
        } else if name == "mcu_addr" {
            for (f, slot) in mcu_addr.iter_mut().enumerate() {
                if value(*index, f as u32) {
                    *slot |= 1 << bit;
                }
            }
        }
    }
    Ok(Counterexample {
        pins,
        mcu_addr,
        rst,
    })
}

/// `cex` with `rst` held low, when that trace still makes the design differ from the model
/// (an engine sets every free input, `rst` too, so a reset in its trace may be needless);
/// otherwise `cex` itself. Checked by [`super::clocked::replay_clocked`] in `dir`.
pub fn without_needless_resets(
    config: &MeasureConfig,
    mcu_diagnostics: bool,
    cex: Counterexample,
    clock_hz: u32,
    files: &[PathBuf],
    top: &str,
    dir: &Path,
) -> Result<Counterexample, FormalError> {
    if !cex.resets() {
        return Ok(cex);
    }
    let lowered = Counterexample {
        rst: vec![false; cex.rst.len()],
        ..cex.clone()
    };
    let differs = super::clocked::replay_clocked(
        config,
        mcu_diagnostics,
        &lowered,
        clock_hz,
        files,
        top,
        dir,
        None,
    )?
    .is_some();
    Ok(if differs { lowered } else { cex })
}

/// What the replay of a counterexample showed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Replay {
    /// `check`'s verdict on the design's simulated trace against the golden model (`None`
    /// when the counterexample resets after power-on, which the golden vectors cannot
    /// carry).
    pub check: Option<Verdict>,
    /// The first difference of the clock-by-clock replay (the counterexample's own
    /// `mcu_addr` and `rst`, `mcu_rdata` against the model's register map).
    pub clocked: Option<super::clocked::ClockedMismatch>,
    /// The generated testbench's own first mismatch (it also compares `mcu_rdata`, at
    /// address `k mod 16` at clock `k`).
    pub testbench: Option<String>,
    /// The files written: the counterexample's VCD and the golden VCD.
    pub counterexample_vcd: PathBuf,
    /// The golden model's response (`None` with a reset).
    pub golden_vcd: Option<PathBuf>,
}

/// Replays `cex` in `dir`: writes the golden model's response to its pins (golden VCD and
/// the testbench's vectors), runs the generated testbench on the design `files` (top
/// `top`) in Icarus with its VCD dump, renames the dump [`COUNTEREXAMPLE_VCD`], and
/// compares it with the golden VCD as `tooltouch check` does.
pub fn replay(
    config: &MeasureConfig,
    mcu_diagnostics: bool,
    cex: &Counterexample,
    clock_hz: u32,
    files: &[PathBuf],
    top: &str,
    dir: &Path,
) -> Result<Replay, FormalError> {
    if cex.resets() {
        let clocked = super::clocked::replay_clocked(
            config,
            mcu_diagnostics,
            cex,
            clock_hz,
            files,
            top,
            dir,
            Some(COUNTEREXAMPLE_VCD),
        )?;
        return Ok(Replay {
            check: None,
            clocked,
            testbench: None,
            counterexample_vcd: dir.join(COUNTEREXAMPLE_VCD),
            golden_vcd: None,
        });
    }
    let stimulus = cex.stimulus(clock_hz);
    let golden_vcd = dir.join(GOLDEN_VCD);
    {
        let f = std::fs::File::create(&golden_vcd).map_err(super::error::io(&golden_vcd))?;
        let mut w = std::io::BufWriter::new(f);
        tooltouch_vectors::vcd::write_golden(&mut w, &stimulus, config, None)
            .and_then(|_| std::io::Write::flush(&mut w))
            .map_err(super::error::io(&golden_vcd))?;
    }
    let vectors = golden_vectors(config, &stimulus).map_err(|e| hdl_error(e.into()))?;
    write_vectors(dir, &vectors).map_err(|e| hdl_error(e.into()))?;
    let spec = TestbenchSpec {
        clock_hz,
        stim_depth: vectors.stim_words,
        expect_depth: vectors.expect_words,
        mcu_diagnostics,
    };
    let tb = testbench(config, &spec).ok_or_else(|| {
        FormalError::BadInput(format!(
            "clock {clock_hz} Hz: the period must be a whole number of ns, at least 2"
        ))
    })?;
    let tb_text = tb
        .text
        .replace(&format!("    {TOP} dut ("), &format!("    {top} dut ("));
    let build_dir = dir.join("build_icarus");
    std::fs::create_dir_all(&build_dir).map_err(super::error::io(&build_dir))?;
    let tb_path = build_dir.join(format!("{TESTBENCH}.v"));
    std::fs::write(&tb_path, tb_text).map_err(super::error::io(&tb_path))?;
    let mut all: Vec<PathBuf> = files.to_vec();
    all.push(tb_path);
    let b = build(Simulator::Icarus, &all, &build_dir, CxxOpt::O1).map_err(hdl_error)?;
    let r = run(&b, dir, &["+vcd", "+nostop"]).map_err(hdl_error)?;
    let counterexample_vcd = dir.join(COUNTEREXAMPLE_VCD);
    let dump = dir.join("dut.vcd");
    std::fs::rename(&dump, &counterexample_vcd).map_err(super::error::io(&dump))?;
    let _ = std::fs::remove_dir_all(&build_dir);
    let check = tooltouch_vectors::check::compare_files(&golden_vcd, &counterexample_vcd)
        .map_err(|e| FormalError::Tool(format!("replaying the counterexample: {e}")))?;
    let clocked = super::clocked::replay_clocked(
        config,
        mcu_diagnostics,
        cex,
        clock_hz,
        files,
        top,
        dir,
        None,
    )?;
    Ok(Replay {
        check: Some(check),
        clocked,
        testbench: r.first_mismatch,
        counterexample_vcd,
        golden_vcd: Some(golden_vcd),
    })
}

fn hdl_error(e: tooltouch_rtl_sim::HdlError) -> FormalError {
    match e {
        tooltouch_rtl_sim::HdlError::ToolMissing { tool } => FormalError::ToolMissing(tool),
        other => FormalError::Tool(format!("replaying the counterexample: {other}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn abc_counterexamples_read_back_as_pins_per_clock() {
        let map = "input 0 0 clk\ninput 1 0 pin_arm\ninput 2 0 pin_contact\n\
                   input 3 0 mcu_addr\ninput 4 1 mcu_addr\ninput 5 0 rst\n";
        let cex = "# FALSIFYING OUTPUTS: po0\n# COUNTEREXAMPLE LENGTH: 3\nlo000@0=0\n\
                   pi00@0=0\npi01@0=1\npi02@0=0\npi03@0=0\npi04@0=0\npi05@0=0\n\
                   pi00@1=1\npi01@1=1\npi02@1=1\npi03@1=1\npi04@1=0\npi05@1=1\n\
                   pi00@2=0\npi01@2=0\npi02@2=0\npi03@2=1\npi04@2=1\n";
        assert_eq!(cex_length(cex), Some(3));
        let c = read_cex(cex, map, 2).unwrap();
        assert_eq!(c.pins, vec![pin::ARM, pin::ARM | pin::CONTACT]);
        assert_eq!(c.mcu_addr, vec![0, 1, 3]);
        assert_eq!(c.rst, vec![false, true, false]);
        assert!(c.resets());
        assert_eq!(c.stimulus(1_000_000).total_cycles(), 2);
        assert!(read_cex("pi0x@1=1", map, 2).is_err());
    }
}
