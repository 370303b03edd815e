//! The checkers must catch a wrong design: a deliberately broken variant of the generated
//! Verilog (a fault injected by hdl-gen, tests only) fails the self-checking testbench,
//! and its VCD dump fails `tooltouch check --expected golden.vcd --dut dut.vcd`, while
//! the correct design passes both.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::process::Command;
use tooltouch_hdl_gen::{Fault, Options};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::random::random_stimulus;
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_rtl_sim::cosim::{cosim, CosimPlan};
use tooltouch_rtl_sim::runner::Simulator;

pub(crate) fn stimulus(config: &MeasureConfig) -> Stimulus {
    let mut rng = ChaCha8Rng::seed_from_u64(0xfa17);
    random_stimulus(&mut rng, config, 50_000_000, 40_000)
}

fn plan(fault: Fault, plusargs: &[&str]) -> CosimPlan {
    CosimPlan {
        options: Options {
            fault,
            ..Options::default()
        },
        simulators: vec![Simulator::Icarus],
        plusargs: plusargs.iter().map(|s| s.to_string()).collect(),
        ..CosimPlan::default()
    }
}

/// Equal steps that divide the fire threshold: every rise from empty passes through it, so
/// [`Fault::FireThresholdPlusOne`] is observable.
pub(crate) fn observable_config() -> MeasureConfig {
    tooltouch_model::MeasureSettings {
        charge_law: tooltouch_model::measure::config::ChargeLaw::Linear {
            charge_step: 4096,
            discharge_step: 4096,
        },
        fire_threshold: 32768,
        rearm_threshold: 8192,
        ..Default::default()
    }
    .validate()
    .expect("valid test configuration")
}

#[test]
fn hdl_injected_faults_fail_the_self_checking_testbench() {
    let config = observable_config();
    let s = stimulus(&config);
    // Preconditions that make both faults observable in this stimulus: the charge sits
    // exactly on the fire threshold at some clock, and an index and an FES edge act in the
    // same clock while armed and in contact.
    let fire = config.settings().fire_threshold;
    let mut fe = tooltouch_model::FrontEnd::new(&config);
    let (mut on_threshold, mut index_with_fes) = (false, false);
    for p in s.cycles() {
        let before = fe.outputs();
        let edges = fe.clock(p);
        on_threshold |= fe.outputs().charge == fire;
        let both = tooltouch_model::measure::frontend::pin::INDEX
            | tooltouch_model::measure::frontend::pin::FES;
        index_with_fes |= edges.changed & edges.levels & both == both && before.armed;
    }
    assert!(
        on_threshold,
        "the stimulus never brings the charge to the fire threshold"
    );
    assert!(
        index_with_fes,
        "the stimulus has no same-clock index and FES edges"
    );
    let work = tempfile::tempdir().expect("temporary folder");
    for (fault, signal) in [
        (Fault::None, None),
        (Fault::FesBeforeIndex, Some("count")),
        (Fault::FireThresholdPlusOne, Some("density_")),
    ] {
        let dir = work.path().join(format!("{fault:?}"));
        let mut p = plan(fault, &[]);
        if fault == Fault::FesBeforeIndex {
            // Verilator too, once: its $fatal must fail the run the same way.
            p.simulators.push(Simulator::Verilator);
        }
        let report = cosim(&config, std::slice::from_ref(&s), &dir, &p).expect("cosim runs");
        for run in &report.runs {
            match signal {
                None => assert!(run.passed, "the correct design failed: {}", run.output),
                Some(name) => {
                    assert!(!run.passed, "{fault:?} was not caught by {}", run.simulator);
                    let m = run.first_mismatch.as_deref().unwrap_or("");
                    assert!(
                        m.starts_with("MISMATCH cycle ") && m.contains(&format!("signal {name}")),
                        "{fault:?} in {}: {m}",
                        run.simulator
                    );
                }
            }
        }
    }
}

fn check(golden: &Path, dut: &Path) -> (bool, String) {
    let (code, text) = check_with(golden, dut, &[]);
    (code == Some(0), text)
}

/// `tooltouch check --expected golden --dut dut <extra>`: exit code, stdout and stderr.
pub(crate) fn check_with(
    golden: &Path,
    dut: &Path,
    extra: &[&std::ffi::OsStr],
) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .arg("check")
        .arg("--expected")
        .arg(golden)
        .arg("--dut")
        .arg(dut)
        .args(extra)
        .output()
        .expect("running tooltouch check");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.code(), text)
}

/// `check_with` writing its `--json` (`dir/check.json`, returned parsed) and `--window`
/// (`dir/mismatch.vcd`, its path returned) reports.
pub(crate) fn check_with_reports(
    golden: &Path,
    dut: &Path,
    dir: &Path,
) -> (Option<i32>, String, serde_json::Value, std::path::PathBuf) {
    let json_path = dir.join("check.json");
    let window = dir.join("mismatch.vcd");
    let (code, text) = check_with(
        golden,
        dut,
        &[
            "--json".as_ref(),
            json_path.as_os_str(),
            "--window".as_ref(),
            window.as_os_str(),
        ],
    );
    let json = serde_json::from_str(&std::fs::read_to_string(&json_path).expect("check.json"))
        .expect("check.json is JSON");
    (code, text, json, window)
}

/// `text` (a VCD) with the `$var` named `name` declared directly in scope `scope` renamed
/// to `new`.
fn rename_var(text: &str, scope: &[&str], name: &str, new: &str) -> String {
    let mut open: Vec<String> = Vec::new();
    let mut renamed = 0;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            let words: Vec<&str> = l.split_whitespace().collect();
            match words.as_slice() {
                ["$scope", _, s, "$end"] => open.push((*s).to_string()),
                ["$upscope", "$end"] => {
                    open.pop();
                }
                ["$var", _, _, _, n, ..] if *n == name && open == scope => {
                    renamed += 1;
                    return l.replacen(&format!(" {name}"), &format!(" {new}"), 1);
                }
                _ => {}
            }
            l.to_string()
        })
        .collect();
    assert_eq!(renamed, 1, "`{name}` declared once in {scope:?}");
    lines.join("\n") + "\n"
}

/// The golden VCD of `s` at `config`, written into `dir`.
pub(crate) fn golden_vcd(
    dir: &Path,
    s: &mut Stimulus,
    config: &MeasureConfig,
) -> std::path::PathBuf {
    // The golden VCD writer skips clock 0 when the stimulus starts with all pins low (a
    // settled front end); start with the next segment so clock 0 is written.
    if s.segments.first().is_some_and(|seg| seg.pins.0 == 0) {
        s.segments.remove(0);
    }
    let golden = dir.join("golden.vcd");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&golden).expect("golden.vcd"));
    tooltouch_vectors::vcd::write_golden(&mut f, s, config, None).expect("writing golden");
    drop(f);
    golden
}

#[test]
fn hdl_check_matches_by_path_and_reports_every_fault() {
    let config = observable_config();
    let mut s = stimulus(&config);
    let work = tempfile::tempdir().expect("temporary folder");
    let golden = golden_vcd(work.path(), &mut s, &config);
    let period_ns = 1_000_000_000 / u64::from(s.clock_hz);
    // The two faults this random stimulus reveals (tests/hdl/stress.rs runs every fault on
    // the stress vectors, with the same report checks).
    for fault in [
        Fault::None,
        Fault::FesBeforeIndex,
        Fault::FireThresholdPlusOne,
    ] {
        let dir = work.path().join(format!("{fault:?}"));
        let report = cosim(
            &config,
            std::slice::from_ref(&s),
            &dir,
            &plan(fault, &["+vcd", "+nostop"]),
        )
        .expect("cosim");
        let dut = dir.join("case0/dut.vcd");
        let (code, text, json, window) = check_with_reports(&golden, &dut, &dir);
        let matches = json["matches"].as_array().expect("matches").clone();
        assert_eq!(
            matches.len(),
            tooltouch_model::MeasureOutputs::FIELD_COUNT,
            "{json}"
        );
        for m in &matches {
            let (g, d) = (m["golden"].as_str().unwrap(), m["dut"].as_str().unwrap());
            let leaf = g
                .strip_prefix("tooltouch.outputs.")
                .expect("a golden output");
            assert_eq!(d, format!("tt_testbench.dut.{leaf}"), "{m}");
        }
        if fault == Fault::None {
            assert!(report.runs[0].passed);
            assert_eq!(code, Some(0), "{text}");
            assert!(text.contains("in DUT scope `tt_testbench.dut`"), "{text}");
            assert_eq!(json["verdict"], "match");
            assert!(!window.exists(), "a window written for a pass");
            // The top-level port renamed: it used to pass on the kernel's own `count`; now
            // bad input naming where `count` was found instead.
            let renamed = dir.join("renamed.vcd");
            let text_vcd = std::fs::read_to_string(&dut).expect("dut.vcd");
            std::fs::write(
                &renamed,
                rename_var(&text_vcd, &["tt_testbench", "dut"], "count", "count_q"),
            )
            .expect("renamed.vcd");
            let (code, text) = check_with(&golden, &renamed, &[]);
            assert_eq!(code, Some(2), "{text}");
            assert!(
                text.contains("no signal named `count`")
                    && text.contains("`tt_testbench.dut.u_measure")
                    && text.contains("not compared"),
                "{text}"
            );
            // Naming the scope explicitly: the same refusal.
            let (code, text) = check_with(
                &golden,
                &renamed,
                &["--dut-scope".as_ref(), "tt_testbench.dut".as_ref()],
            );
            assert_eq!(code, Some(2), "{text}");
            assert!(text.contains("given by --dut-scope"), "{text}");
            let (code, text) = check_with(
                &golden,
                &dut,
                &["--dut-scope".as_ref(), "tt_testbench.nothing".as_ref()],
            );
            assert_eq!(code, Some(2), "{text}");
            assert!(
                text.contains("no such scope") && text.contains("`tt_testbench.dut` (17 of 17)"),
                "{text}"
            );
            continue;
        }
        assert!(!report.runs[0].passed, "{fault:?} passed the testbench");
        let tb = report.runs[0].first_mismatch.clone().unwrap_or_default();
        assert_mismatch_report(
            &format!("{fault:?}"),
            code,
            &text,
            &json,
            &tb,
            &window,
            period_ns,
        );
    }
}

#[test]
fn hdl_tooltouch_check_catches_a_broken_verilog_from_its_vcd() {
    let config = MeasureConfig::default();
    let mut s = stimulus(&config);
    let work = tempfile::tempdir().expect("temporary folder");
    let golden = golden_vcd(work.path(), &mut s, &config);
    for fault in [Fault::None, Fault::FesBeforeIndex] {
        let dir = work.path().join(format!("{fault:?}"));
        let report = cosim(
            &config,
            std::slice::from_ref(&s),
            &dir,
            &plan(fault, &["+vcd", "+nostop"]),
        )
        .expect("cosim");
        let dut = dir.join("case0/dut.vcd");
        assert!(dut.is_file(), "the testbench wrote no dut.vcd");
        let (ok, text) = check(&golden, &dut);
        match fault {
            Fault::None => {
                assert!(report.runs[0].passed);
                assert!(ok, "check rejected the correct design:\n{text}");
            }
            _ => {
                assert!(!report.runs[0].passed);
                assert!(!ok, "check accepted {fault:?}:\n{text}");
                assert!(
                    text.contains("cycle ") && text.contains("signal count"),
                    "check's report of {fault:?}: {text}"
                );
            }
        }
    }
}

/// Checks `check`'s report of a mismatch (`code`, its output `text`, its `--json` value,
/// its `--window` folder) against the testbench's first mismatch line `tb`: the same
/// clock, every differing signal with its DUT path, the pins before it, the MCU read, and
/// a window VCD and GTKWave file that show the mismatch at that clock.
pub(crate) fn assert_mismatch_report(
    what: &str,
    code: Option<i32>,
    text: &str,
    json: &serde_json::Value,
    tb: &str,
    window: &Path,
    period_ns: u64,
) {
    assert_eq!(code, Some(1), "{what}: {text}");
    assert_eq!(json["verdict"], "mismatch");
    let k = json["first_mismatch"]["cycle"]
        .as_u64()
        .expect("a first mismatch");
    let differing = json["first_mismatch"]["signals"]
        .as_array()
        .unwrap()
        .clone();
    assert!(!differing.is_empty());
    // The testbench's own first mismatch is the same clock.
    assert!(
        tb.starts_with(&format!("MISMATCH cycle {k} ")),
        "testbench: {tb}; check: {text}"
    );
    assert!(
        text.contains(&format!(
            "signals differing at cycle {k} ({} of 17)",
            differing.len()
        )),
        "{text}"
    );
    for d in &differing {
        let name = d["signal"].as_str().unwrap();
        assert!(text.contains(&format!("tt_testbench.dut.{name}")), "{text}");
    }
    assert!(
        text.contains("golden input pins of the clocks before it"),
        "{text}"
    );
    assert!(
        text.contains(&format!("  {k:>12} ")),
        "the pin table reaches cycle {k}: {text}"
    );
    assert!(
        text.contains(&format!("mcu_rdata at cycle {k}: ")) && text.contains("read at mcu_addr"),
        "{text}"
    );
    // The window: golden and DUT side by side, `differs.<name>` 1 at clock K for each
    // differing signal; the GTKWave file opens it with the marker on clock K.
    let vcd = std::fs::read_to_string(window).expect("mismatch.vcd");
    let w = tooltouch_vectors::vcd::Dump::parse(&vcd, "mismatch.vcd").expect("a VCD");
    for d in &differing {
        let name = d["signal"].as_str().unwrap();
        let flag = w.find_in_scope("differs", name).expect("differs.<name>");
        let at = |k: u64| {
            w.value_at(&flag.id, k * period_ns * 1_000_000)
                .and_then(|v| v.to_u64())
        };
        assert_eq!(at(k), Some(1), "differs.{name} at cycle {k}");
        assert_eq!(at(k - 1), Some(0), "differs.{name} before cycle {k}");
        let g = w
            .find_in_scope("outputs", name)
            .expect("golden.outputs.<name>");
        let got = w.find_in_scope("dut", name).expect("dut.<name>");
        let hex = |id: &str| {
            w.value_at(id, k * period_ns * 1_000_000)
                .map(|v| format!("0x{}", v.hex_digits()))
        };
        assert_eq!(hex(&g.id).as_deref(), d["expected"].as_str(), "{name}");
        assert_eq!(hex(&got.id).as_deref(), d["got"].as_str(), "{name}");
    }
    let gtkw = std::fs::read_to_string(window.with_extension("gtkw")).expect("mismatch.gtkw");
    assert!(gtkw.contains("[dumpfile] \"mismatch.vcd\""), "{gtkw}");
    let marker = gtkw
        .lines()
        .find(|l| l.starts_with('*'))
        .expect("the marker line");
    assert_eq!(
        marker.split_whitespace().nth(1),
        Some((k * period_ns).to_string().as_str()),
        "{marker}"
    );
    for line in gtkw
        .lines()
        .filter(|l| !l.starts_with(['[', '*', '@', '-']))
    {
        let (scope, rest) = line.rsplit_once('.').expect("a signal path");
        let leaf = rest.split('[').next().unwrap();
        let scope = scope.rsplit('.').next().unwrap();
        assert!(
            w.find_in_scope(scope, leaf).is_some(),
            "{line} is not in mismatch.vcd"
        );
    }
    // The Surfer command file: the same rows, the cursor on clock K.
    let sucl = std::fs::read_to_string(window.with_extension("sucl")).expect("mismatch.sucl");
    assert!(sucl.starts_with("load_file mismatch.vcd\n"), "{sucl}");
    assert!(
        sucl.lines()
            .any(|l| l == format!("cursor_set {}", k * period_ns)),
        "{sucl}"
    );
    let added: Vec<&str> = sucl
        .lines()
        .filter_map(|l| l.strip_prefix("variable_add "))
        .collect();
    let gtkw_rows = gtkw
        .lines()
        .filter(|l| !l.starts_with(['[', '*', '@', '-']))
        .count();
    assert_eq!(added.len(), gtkw_rows, "{sucl}");
    for path in added {
        let (scope, leaf) = path.rsplit_once('.').expect("a signal path");
        let scope = scope.rsplit('.').next().unwrap();
        assert!(
            w.find_in_scope(scope, leaf).is_some(),
            "{path} is not in mismatch.vcd"
        );
    }
    for d in &differing {
        let name = d["signal"].as_str().unwrap();
        assert!(
            sucl.contains(&format!("variable_add differs.{name}\n")),
            "{sucl}"
        );
    }
}
