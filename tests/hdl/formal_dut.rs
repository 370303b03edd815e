//! `tooltouch formal --dut`: the unbounded proof of any `tt_frontend` against the reference
//! derived from the model (`tooltouch::formal`, yosys + ABC, no invariants written for the
//! design):
//!
//! - the generated design is proven in the default configuration (and, ignored by default,
//!   run by `cargo xtask formal`, in every configuration `tooltouch_hdl_gen::formal::variants`
//!   lists);
//! - two independent designs written from docs/CONTRACT.md (`tests/hdl/independent/`,
//!   structured unlike the generated one and unlike each other) are proven in the default
//!   and a small configuration;
//! - single-point faults injected into them each give a counterexample whose replay
//!   (`tooltouch vectors` on its pins, `tooltouch check` against the design's simulated
//!   trace) is a mismatch: three by default, all of them with `TT_FORMAL_ALL=1`; a fault
//!   only `mcu_rdata` shows is reported with its clock, address, register and both values by
//!   the clock-by-clock replay, and a register `rst` does not clear (`rst` is a free input
//!   of the miter) by the clock-by-clock replay of a trace that resets (the golden vectors
//!   cannot carry `rst`), with a counterexample VCD holding `rst`;
//! - bad input (a missing file, a syntax error, a missing port, a wrong width) exits 2 with
//!   the culprit named.
//!
//! Each run prints its verdict, engine and time (`--nocapture`).

use crate::common::{s, text, tooltouch};
use std::path::{Path, PathBuf};
use tooltouch_formal::{prove, Outcome, Request};
use tooltouch_hdl_gen::{output_fields, Options};
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::{MeasureConfig, MeasureSettings};

/// Wall-time limit of each engine in these tests, s: every proof and fault here closes in
/// seconds; the limit only bounds a regression.
const ENGINE_SECONDS: &str = "300";

/// An independent design of `tests/hdl/independent/`.
#[derive(Clone, Copy, Debug)]
enum Independent {
    /// `tt_alt_registered.v`: registered strobes, down-counting filters, one-hot phase.
    Registered,
    /// `tt_alt_previous.v`: previous-level register, no phase/armed/contact registers.
    Previous,
}

impl Independent {
    fn module(self) -> &'static str {
        match self {
            Independent::Registered => "tt_alt_registered",
            Independent::Previous => "tt_alt_previous",
        }
    }
}

/// A single-point fault of the independent designs (their `FAULT` parameter).
const FAULTS: [(u32, &str); 15] = [
    (1, "i_def + 1"),
    (2, "i_def - 1"),
    (3, "fire threshold + 1"),
    (4, "fire threshold - 1"),
    (5, "rearm threshold + 1"),
    (6, "rearm threshold - 1"),
    (7, "glitch filter + 1 clock"),
    (8, "glitch filter - 1 clock"),
    (9, "charge step + 1"),
    (10, "discharge step - 1"),
    (11, "sticky bit not reloaded while disarmed"),
    (12, "first-contact latch not cleared by arm"),
    (13, "position not cleared by rst"),
    (14, "mcu_rdata at address 3 reads the position"),
    (15, "contact at arm not raised"),
];

/// Fault 13 needs a reset after power-on: the golden vectors cannot carry it.
const RESET_FAULT: u32 = 13;
/// Fault 14 shows only on `mcu_rdata`: the golden VCD has no `mcu_rdata`.
const MCU_FAULT: u32 = 14;

/// Writes the independent design's file and a `tt_frontend` wrapper setting its
/// parameters from `config` into `dir`; returns both paths.
fn independent_files(
    design: Independent,
    config: &MeasureConfig,
    fault: u32,
    dir: &Path,
) -> Vec<PathBuf> {
    std::fs::create_dir_all(dir).expect("folder");
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/hdl/independent")
        .join(format!("{}.v", design.module()));
    let s = config.settings();
    let (law, up, down) = match s.charge_law {
        ChargeLaw::Linear {
            charge_step,
            discharge_step,
        } => (0, charge_step, discharge_step),
        ChargeLaw::Exponential {
            charge_shift,
            discharge_shift,
        } => (1, u32::from(charge_shift), u32::from(discharge_shift)),
    };
    let method = match s.method {
        DecisionMethod::SinglePulse => 0,
        DecisionMethod::Counter => 1,
        DecisionMethod::Density => 2,
    };
    let params = [
        ("GLITCH", u64::from(s.glitch_cycles)),
        ("SB", u64::from(s.scale_bits)),
        ("CB", u64::from(config.count_bits())),
        ("QB", u64::from(s.charge_bits)),
        (
            "WINDOW_PULSES",
            u64::from(s.pulses_per_rev) * u64::from(s.window_revs),
        ),
        ("I_DEF", u64::from(s.i_def)),
        ("WINDOW_REVS", u64::from(s.window_revs)),
        ("FIRE", u64::from(s.fire_threshold)),
        ("REARM", u64::from(s.rearm_threshold)),
        ("LAW", law),
        ("UP", u64::from(up)),
        ("DOWN", u64::from(down)),
        ("STICKY", u64::from(s.contact_rule == ContactRule::Sticky)),
        ("METHOD", method),
        ("CAA", u64::from(s.checks.contact_at_arm)),
        ("REV_CHECK", u64::from(s.checks.revolutions)),
        ("PPR", u64::from(s.pulses_per_rev)),
        ("TOL", u64::from(s.checks.pulse_tolerance)),
        ("SCALE_CHECK", u64::from(s.checks.scale_errors)),
        ("PROBE", u64::from(s.checks.probe_revs)),
        ("FES_T", u64::from(s.checks.fes_timeout_cycles)),
        ("CW", u64::from(s.checks.confirm_windows)),
        ("CC", u64::from(config.confirm_count())),
        ("FAULT", u64::from(fault)),
    ];
    let mut p: Vec<String> = params.iter().map(|(n, v)| format!(".{n}({v})")).collect();
    p.push(format!(".HASH(64'h{:016x})", config.hash()));
    let mut ports = vec!["input wire clk".to_string(), "input wire rst".to_string()];
    for n in tooltouch_model::measure::frontend::pin::NAMES {
        ports.push(format!("input wire pin_{n}"));
    }
    ports.push("input wire [3:0] mcu_addr".into());
    ports.push("output wire [31:0] mcu_rdata".into());
    let mut names: Vec<&str> = vec!["clk", "rst"];
    let pin_names: Vec<String> = tooltouch_model::measure::frontend::pin::NAMES
        .iter()
        .map(|n| format!("pin_{n}"))
        .collect();
    names.extend(pin_names.iter().map(String::as_str));
    names.extend(["mcu_addr", "mcu_rdata"]);
    for f in output_fields(config) {
        ports.push(format!("output wire [{}:0] {}", f.width - 1, f.name));
        names.push(f.name);
    }
    ports.push("output wire irq".into());
    names.push("irq");
    let conns: Vec<String> = names.iter().map(|n| format!(".{n}({n})")).collect();
    let top = format!(
        "module tt_frontend (\n    {}\n);\n    {} #({}) u (\n        {}\n    );\nendmodule\n",
        ports.join(",\n    "),
        design.module(),
        p.join(", "),
        conns.join(", ")
    );
    let top_path = dir.join("tt_frontend.v");
    std::fs::write(&top_path, top).expect("writing the wrapper");
    vec![top_path, src]
}

/// The settings file of `settings` in `dir` (a `[measure]` table).
fn settings_file(settings: &MeasureSettings, dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir).expect("folder");
    let mut table = toml::Table::new();
    table.insert(
        "measure".into(),
        toml::Value::try_from(settings).expect("settings as TOML"),
    );
    let path = dir.join("settings.toml");
    std::fs::write(&path, toml::to_string(&table).expect("TOML")).expect("writing");
    path
}

/// A small configuration in which every fault of [`FAULTS`] shows within some tens of
/// clocks: the counter decides on the third contact pulse of 16, a 4-bit capacitor charged
/// by 3 and discharged by 1 re-arms below 6 (so charges 7 and 8 are both reached armed),
/// a one-clock glitch filter.
fn small_settings() -> MeasureSettings {
    MeasureSettings {
        pulses_per_rev: 16,
        i_def: 2,
        charge_bits: 4,
        charge_law: ChargeLaw::Linear {
            charge_step: 3,
            discharge_step: 1,
        },
        fire_threshold: 8,
        rearm_threshold: 6,
        glitch_cycles: 1,
        scale_bits: 8,
        method: DecisionMethod::Counter,
        contact_rule: ContactRule::Sticky,
        // Every check on, with counters a few bits wide (a 6-bit watchdog, a probe fail after
        // 4 revolutions): the proofs' state stays small.
        checks: tooltouch_model::MeasureChecks {
            pulse_tolerance: 1,
            probe_revs: 4,
            fes_timeout_cycles: 40,
            confirm_windows: 2,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Runs `tooltouch formal` on `files`; returns its exit code and output.
fn formal_cli(settings: &Path, files: &[PathBuf], out: &Path) -> (i32, String) {
    let mut args = vec![
        "formal".to_string(),
        "--config".into(),
        s(settings).into(),
        "--out".into(),
        s(out).into(),
        "--engine-seconds".into(),
        ENGINE_SECONDS.into(),
        "--dut".into(),
    ];
    args.extend(files.iter().map(|f| s(f).to_string()));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = tooltouch(&refs);
    (o.status.code().unwrap_or(-1), text(&o))
}

fn assert_proven_cli(name: &str, settings: &Path, files: &[PathBuf], out: &Path) {
    let (code, out_text) = formal_cli(settings, files, out);
    println!("formal --dut {name}:\n{out_text}");
    assert_eq!(code, 0, "{name}: not proven:\n{out_text}");
    assert!(out_text.starts_with("PROVEN"), "{name}: {out_text}");
}

#[test]
fn formal_dut_the_generated_design_is_proven_in_the_default_configuration() {
    let work = tempfile::tempdir().expect("temporary folder");
    let config = MeasureConfig::default();
    let rtl = work.path().join("rtl");
    let paths = tooltouch_rtl_sim::write_design(
        &rtl,
        &tooltouch_hdl_gen::generate(&config, &Options::default()),
        None,
    )
    .expect("writing the design");
    let files: Vec<PathBuf> = paths
        .into_iter()
        .filter(|p| !p.ends_with(format!("{}.v", tooltouch_hdl_gen::FPGA_TOP)))
        .collect();
    let settings = settings_file(&MeasureSettings::default(), work.path());
    assert_proven_cli(
        "generated, default",
        &settings,
        &files,
        &work.path().join("out"),
    );
    let report = std::fs::read_to_string(work.path().join("out/report.txt")).expect("report");
    assert!(report.starts_with("PROVEN"), "{report}");
    let props = std::fs::read_to_string(work.path().join("out/tt_frontend_props.sv"))
        .expect("the assertion bind file");
    assert!(
        props.contains("bind tt_frontend tt_frontend_props"),
        "{props}"
    );
}

/// A generated design omitting one fault condition (the `contact_at_arm` bit never set,
/// `Fault::ContactAtArmNotRaised`) is refuted with a counterexample that names `faults`.
#[test]
fn formal_dut_a_generated_design_omitting_a_fault_condition_is_refuted() {
    let work = tempfile::tempdir().expect("temporary folder");
    let config = MeasureConfig::default();
    let options = Options {
        fault: tooltouch_hdl_gen::Fault::ContactAtArmNotRaised,
        ..Options::default()
    };
    let paths = tooltouch_rtl_sim::write_design(
        &work.path().join("rtl"),
        &tooltouch_hdl_gen::generate(&config, &options),
        None,
    )
    .expect("writing the design");
    let files: Vec<PathBuf> = paths
        .into_iter()
        .filter(|p| !p.ends_with(format!("{}.v", tooltouch_hdl_gen::FPGA_TOP)))
        .collect();
    let settings = settings_file(&MeasureSettings::default(), work.path());
    let (code, out_text) = formal_cli(&settings, &files, &work.path().join("out"));
    println!("formal --dut generated without contact_at_arm:\n{out_text}");
    assert_eq!(code, 1, "expected not equal:\n{out_text}");
    assert!(out_text.contains("faults"), "{out_text}");
}

/// Both independent designs proven in the small configuration; in the default one too with
/// `TT_FORMAL_ALL=1` (about 7 minutes each on a 2-core machine since the checks' 17-bit
/// watchdog).
#[test]
fn formal_dut_independent_designs_are_proven() {
    let work = tempfile::tempdir().expect("temporary folder");
    let all = std::env::var("TT_FORMAL_ALL").is_ok_and(|v| v == "1");
    let mut configurations = vec![("small", small_settings())];
    if all {
        configurations.push(("default", MeasureSettings::default()));
    }
    for (cname, settings) in configurations {
        let config = settings.validate().expect("valid");
        let toml = settings_file(&settings, &work.path().join(cname));
        for design in [Independent::Registered, Independent::Previous] {
            let dir = work.path().join(format!("{cname}_{design:?}"));
            let files = independent_files(design, &config, 0, &dir.join("rtl"));
            assert_proven_cli(
                &format!("{design:?}, {cname}"),
                &toml,
                &files,
                &dir.join("out"),
            );
        }
    }
}

/// Proves the faulty design not equal and replays the counterexample as a user would:
/// `tooltouch vectors` on the counterexample's pins, then `tooltouch check` of the design's
/// simulated trace against the golden response must report a mismatch. Returns the
/// counterexample's length in clocks.
fn assert_fault_found(design: Independent, fault: (u32, &str), work: &Path) -> usize {
    let settings = small_settings();
    let config = settings.validate().expect("valid");
    let dir = work.join(format!("{design:?}_fault{}", fault.0));
    let toml = settings_file(&settings, &dir);
    let files = independent_files(design, &config, fault.0, &dir.join("rtl"));
    let out = dir.join("out");
    let (code, out_text) = formal_cli(&toml, &files, &out);
    println!("formal --dut {design:?} with {}:\n{out_text}", fault.1);
    assert_eq!(
        code, 1,
        "{design:?} with {}: expected not equal:\n{out_text}",
        fault.1
    );
    if fault.0 == RESET_FAULT {
        assert!(
            out_text.contains("replayed clock by clock (rst high at clock")
                && out_text.contains(": position: design 0x"),
            "{design:?} with {}: the replay must reset and show the position:\n{out_text}",
            fault.1
        );
        let vcd = std::fs::read_to_string(out.join("counterexample.vcd")).expect("the VCD");
        assert!(
            vcd.contains(" rst $end"),
            "the counterexample VCD holds rst"
        );
        assert!(
            !out.join("golden.vcd").exists(),
            "no golden VCD without rst"
        );
        return cex_clocks(&out_text);
    }
    if fault.0 == MCU_FAULT {
        assert!(
            out_text.contains("the 17 outputs match")
                && out_text.contains("mcu_rdata at address 3 (FIRST_CONTACT_POSITION): design 0x"),
            "{design:?} with {}: the replay must name the address and register:\n{out_text}",
            fault.1
        );
        return cex_clocks(&out_text);
    }
    assert!(
        out_text.contains("replayed against the golden model: cycle"),
        "{design:?} with {}: the replay must show a mismatch:\n{out_text}",
        fault.1
    );
    let cex = out.join("counterexample.vcd");
    let golden = dir.join("golden");
    let o = tooltouch(&[
        "vectors",
        "--config",
        s(&toml),
        "--stimulus",
        s(&cex),
        "--out",
        s(&golden),
    ]);
    assert!(o.status.success(), "tooltouch vectors: {}", text(&o));
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&golden.join("golden.vcd")),
        "--dut",
        s(&cex),
    ]);
    let t = text(&o);
    println!("  tooltouch check: {}", t.trim());
    assert_eq!(
        o.status.code(),
        Some(1),
        "{design:?} with {}: check must report a mismatch:\n{t}",
        fault.1
    );
    assert!(t.contains("MISMATCH"), "{t}");
    // The length: the golden response covers the counterexample's clocks.
    let g = std::fs::read_to_string(golden.join("golden.vcd")).expect("golden VCD");
    g.rsplit("tooltouch end cycles=")
        .next()
        .and_then(|r| r.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .expect("the golden VCD's end comment")
}

/// The counterexample's length from the report's `… of a N-clock trace …`.
fn cex_clocks(report: &str) -> usize {
    report
        .split("-clock trace")
        .next()
        .and_then(|h| h.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .expect("the report's trace length")
}

#[test]
fn formal_dut_faults_in_independent_designs_give_replayable_counterexamples() {
    let work = tempfile::tempdir().expect("temporary folder");
    let all = std::env::var("TT_FORMAL_ALL").is_ok_and(|v| v == "1");
    let cases: Vec<(Independent, (u32, &str))> = if all {
        [Independent::Registered, Independent::Previous]
            .into_iter()
            .flat_map(|d| FAULTS.iter().map(move |f| (d, *f)))
            .collect()
    } else {
        vec![
            (Independent::Registered, FAULTS[0]),
            (Independent::Previous, FAULTS[3]),
            (Independent::Registered, FAULTS[10]),
            (Independent::Previous, FAULTS[12]),
            (Independent::Registered, FAULTS[13]),
        ]
    };
    for (design, fault) in cases {
        let clocks = assert_fault_found(design, fault, work.path());
        println!(
            "  {design:?}, {}: counterexample of {clocks} clocks",
            fault.1
        );
    }
}

#[test]
fn formal_dut_bad_input_names_the_culprit() {
    let work = tempfile::tempdir().expect("temporary folder");
    let settings = small_settings();
    let config = settings.validate().expect("valid");
    let toml = settings_file(&settings, work.path());
    let good = independent_files(
        Independent::Registered,
        &config,
        0,
        &work.path().join("rtl"),
    );
    let out = work.path().join("out");
    // A missing file.
    let missing = work.path().join("nope.v");
    let (code, t) = formal_cli(&toml, std::slice::from_ref(&missing), &out);
    assert_eq!(code, 2, "{t}");
    assert!(t.contains("nope.v") && t.contains("no such file"), "{t}");
    // A syntax error: yosys's message names the file and line.
    let broken = work.path().join("broken.v");
    std::fs::write(&broken, "module tt_frontend (input wire clk\nendmodule\n").expect("write");
    let (code, t) = formal_cli(&toml, &[broken], &out);
    assert_eq!(code, 2, "{t}");
    assert!(t.contains("broken.v:2"), "{t}");
    // A missing port and a wrong width, from the wrapper edited.
    let wrapper = std::fs::read_to_string(&good[0]).expect("wrapper");
    for (what, from, to, expect) in [
        (
            "missing port",
            "    output wire irq\n",
            "    output wire irq_renamed\n",
            "port `irq` is missing",
        ),
        (
            "wrong width",
            "output wire [4:0] count",
            "output wire [5:0] count",
            "port `count` is 6 bits wide: the contract's is 5 bits",
        ),
    ] {
        assert!(wrapper.contains(from), "{what}: `{from}` not in\n{wrapper}");
        let edited = work.path().join(format!("{}.v", what.replace(' ', "_")));
        std::fs::write(
            &edited,
            wrapper.replace(from, to).replace(
                ".irq(irq)",
                if what == "missing port" {
                    ".irq(irq_renamed)"
                } else {
                    ".irq(irq)"
                },
            ),
        )
        .expect("write");
        let (code, t) = formal_cli(&toml, &[edited, good[1].clone()], &out);
        assert_eq!(code, 2, "{what}: {t}");
        assert!(t.contains(expect), "{what}: expected `{expect}` in {t}");
    }
}

/// The generated design in every configuration `cargo xtask formal` covers, proven by ABC
/// without the invariants of `tooltouch_hdl_gen::formal` (minutes: `cargo xtask formal`;
/// `TT_FORMAL_ENGINE_SECONDS` per engine, default 600). Every configuration must be proven
/// but the one docs/formal.md names, which may stay undecided (its proof is the generator's
/// k-induction with invariants, `tests/hdl/formal.rs`); a difference fails everywhere.
#[test]
#[ignore = "minutes: run by `cargo xtask formal`"]
fn formal_dut_generated_variants_are_proven_without_invariants() {
    let work = tempfile::tempdir().expect("temporary folder");
    let mut failed = Vec::new();
    for (i, (name, config, options)) in tooltouch_hdl_gen::formal::variants().iter().enumerate() {
        let dir = work.path().join(format!("variant{i}"));
        let files: Vec<PathBuf> = tooltouch_rtl_sim::write_design(
            &dir.join("rtl"),
            &tooltouch_hdl_gen::generate(config, options),
            None,
        )
        .expect("writing")
        .into_iter()
        .filter(|p| !p.ends_with(format!("{}.v", tooltouch_hdl_gen::FPGA_TOP)))
        .collect();
        let mut request = Request::new(*config, files, tooltouch_hdl_gen::TOP);
        request.mcu_diagnostics = options.mcu_diagnostics;
        request.seconds_per_engine = std::env::var("TT_FORMAL_ENGINE_SECONDS")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(600);
        // The one configuration no engine closes without invariants (docs/formal.md):
        // bounded to a short limit, and allowed to stay undecided, never to differ.
        let known_hard = name == "Counter, linear 65535/1, glitch 255, i_def 1023";
        if known_hard {
            request.seconds_per_engine = request.seconds_per_engine.min(45);
        }
        let report = prove(&request, &dir.join("out")).expect("the proof runs");
        println!(
            "formal --dut generated, {name}:\n  {}",
            report.lines().join("\n  ")
        );
        match report.outcome {
            Outcome::Proven { .. } => {}
            Outcome::Undecided if known_hard => {}
            _ => failed.push(name.clone()),
        }
    }
    assert!(failed.is_empty(), "not proven: {failed:?}");
}

/// The assertion bind file parses in yosys (`read_verilog -sv -formal`, the `bind` too), and
/// every assertion holds on the generated design for every input sequence and any use of
/// `rst` (ABC `dprove`), in the default and the small configuration; the latency stated one
/// clock early fails, so it is not vacuous.
#[test]
fn formal_dut_the_contract_assertions_hold_on_the_generated_design() {
    use tooltouch_formal::assertions::{bind_file, prove_assertions};
    use tooltouch_formal::engines::EngineResult;
    let work = tempfile::tempdir().expect("temporary folder");
    for (name, settings) in [
        ("default", MeasureSettings::default()),
        ("small", small_settings()),
    ] {
        let config = settings.validate().expect("valid");
        let rtl = work.path().join(name).join("rtl");
        let files: Vec<PathBuf> = tooltouch_rtl_sim::write_design(
            &rtl,
            &tooltouch_hdl_gen::generate(&config, &Options::default()),
            None,
        )
        .expect("writing")
        .into_iter()
        .filter(|p| !p.ends_with(format!("{}.v", tooltouch_hdl_gen::FPGA_TOP)))
        .collect();
        let props = bind_file(&config);
        // The file as the user gets it, bind included, parses with the design.
        let dir = work.path().join(name);
        std::fs::write(dir.join("props_as_given.sv"), &props).expect("write");
        let o = std::process::Command::new("yosys")
            .arg("-q")
            .arg("-p")
            .arg(format!(
                "read_verilog -sv {}; read_verilog -sv -formal {}; hierarchy -top tt_frontend",
                files
                    .iter()
                    .map(|f| s(f).to_string())
                    .collect::<Vec<_>>()
                    .join(" "),
                s(&dir.join("props_as_given.sv"))
            ))
            .output()
            .expect("yosys (run `cargo xtask setup`)");
        assert!(o.status.success(), "{name}: {}", text(&o));
        let a = prove_assertions(
            &config,
            &props,
            &files,
            "tt_frontend",
            &dir.join("hold"),
            300,
        )
        .expect("the proof runs");
        println!("assertions, {name}: {:?} in {:.1} s", a.result, a.seconds);
        assert_eq!(a.result, EngineResult::Proven, "{name}");
        let early = props.replace(
            "for (i = 3; i <= 3 + GLITCH; i = i + 1)",
            "for (i = 2; i <= 2 + GLITCH; i = i + 1)",
        );
        assert_ne!(early, props);
        let a = prove_assertions(
            &config,
            &early,
            &files,
            "tt_frontend",
            &dir.join("early"),
            300,
        )
        .expect("the proof runs");
        let frame = match &a.result {
            EngineResult::Different { frame, .. } => Some(*frame),
            _ => None,
        };
        println!(
            "assertions, {name}, latency one clock early: fails after {frame:?} clocks in {:.1} s",
            a.seconds
        );
        assert!(
            frame.is_some(),
            "{name}: the latency stated one clock early must fail: {:?}",
            a.result
        );
    }
}
