//! FST dumps feed `tooltouch check` as VCD dumps do: the generated testbench's `+fst` dump
//! under Icarus (`vvp -fst`) checks OK against the golden VCD (under Verilator:
//! tests/hdl/testbench_tools.rs), and a one-point fault dumped as FST by Verilator (built
//! with `--trace-fst`) and by Icarus gives the same first mismatch (cycle, signals, both
//! values) and `--json` verdict as the Icarus VCD path; a cut FST is bad input naming the
//! file.

use super::faults::{check_with, check_with_reports, golden_vcd, observable_config, stimulus};
use std::path::{Path, PathBuf};
use tooltouch_hdl_gen::{Fault, Options};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_rtl_sim::cosim::{cosim, CosimPlan};
use tooltouch_rtl_sim::runner::{Simulator, Trace};

/// Runs the testbench of `fault` under `sim` in `dir` with a `+nostop` dump of `trace`
/// (`Trace::Vcd` under Icarus: its plain `+vcd`), returning the dump's path and whether the
/// testbench passed.
fn dump(
    config: &MeasureConfig,
    s: &Stimulus,
    dir: &Path,
    fault: Fault,
    sim: Simulator,
    trace: Trace,
) -> (PathBuf, bool) {
    let (plusarg, file) = match trace {
        Trace::Fst => ("+fst", "dut.fst"),
        _ => ("+vcd", "dut.vcd"),
    };
    let plan = CosimPlan {
        options: Options {
            fault,
            ..Options::default()
        },
        simulators: vec![sim],
        plusargs: vec![plusarg.into(), "+nostop".into()],
        trace,
        ..CosimPlan::default()
    };
    let report = cosim(config, std::slice::from_ref(s), dir, &plan).expect("cosim");
    let dut = dir.join("case0").join(file);
    assert!(dut.is_file(), "{sim} wrote no {file}");
    (dut, report.runs[0].passed)
}

#[test]
fn hdl_fst_dumps_of_verilator_and_icarus_check_as_the_vcd_does() {
    let config = observable_config();
    let mut s = stimulus(&config);
    let work = tempfile::tempdir().expect("temporary folder");
    let golden = golden_vcd(work.path(), &mut s, &config);
    for fault in [Fault::None, Fault::FesBeforeIndex] {
        let base = work.path().join(format!("{fault:?}"));
        let (vcd, _) = dump(
            &config,
            &s,
            &base.join("icarus-vcd"),
            fault,
            Simulator::Icarus,
            Trace::Vcd,
        );
        let (code, text, reference, _) = check_with_reports(&golden, &vcd, &base);
        let expected_code = if fault == Fault::None { 0 } else { 1 };
        assert_eq!(code, Some(expected_code), "{text}");
        let verdict_of = |text: &str| text.lines().next().unwrap_or("").to_string();
        // The correct design under Verilator with its FST: tests/hdl/testbench_tools.rs
        // (docs/hdl.md's command line); here the fault, one Verilator build.
        let sims: &[(Simulator, &str)] = if fault == Fault::None {
            &[(Simulator::Icarus, "tt_testbench.dut")]
        } else {
            &[
                (Simulator::Verilator, "TOP.tt_testbench.dut"),
                (Simulator::Icarus, "tt_testbench.dut"),
            ]
        };
        for &(sim, scope) in sims {
            let dir = base.join(format!("{sim}-fst"));
            let (fst, passed) = dump(&config, &s, &dir, fault, sim, Trace::Fst);
            assert_eq!(passed, fault == Fault::None, "{sim} {fault:?}");
            let head = std::fs::read(&fst).expect("dut.fst");
            assert_eq!(
                head.first(),
                Some(&0),
                "{sim}: dut.fst is not an FST (header block 0)"
            );
            let (code, fst_text, json, window) = check_with_reports(&golden, &fst, &dir);
            assert_eq!(code, Some(expected_code), "{sim} {fault:?}: {fst_text}");
            assert_eq!(json["dut_scope"], scope, "{sim}: {json}");
            for m in json["matches"].as_array().expect("matches") {
                let leaf = m["golden"].as_str().unwrap().rsplit('.').next().unwrap();
                assert_eq!(m["dut"], format!("{scope}.{leaf}"), "{sim}: {m}");
            }
            // The same first mismatch, cycle, signals and both values, as the VCD path.
            assert_eq!(json["verdict"], reference["verdict"], "{sim} {fault:?}");
            assert_eq!(
                json["first_mismatch"], reference["first_mismatch"],
                "{sim} {fault:?}: {fst_text}\nVCD: {text}"
            );
            if fault == Fault::None {
                assert!(
                    fst_text.contains(&format!("in DUT scope `{scope}`")),
                    "{fst_text}"
                );
                assert!(!window.exists(), "a window written for a pass");
            } else {
                assert!(json["first_mismatch"]["cycle"].as_u64().is_some(), "{json}");
                assert_eq!(verdict_of(&fst_text), verdict_of(&text), "{sim}");
                assert!(window.is_file(), "{sim}: no window VCD");
            }
            if fault == Fault::None && sim == Simulator::Icarus {
                // Cut in half: bad input naming the file, never a panic or a pass.
                let cut = dir.join("cut.fst");
                std::fs::write(&cut, &head[..head.len() / 2]).expect("cut.fst");
                let (code, text) = check_with(&golden, &cut, &[]);
                assert_eq!(code, Some(2), "{text}");
                assert!(
                    text.contains("cut.fst") && !text.contains("panicked"),
                    "{text}"
                );
            }
        }
    }
}
