//! The generated testbench run as a user runs it, under both simulators: `tooltouch hdl
//! --vectors lathe` writes the RTL and the vectors, then in that folder exactly the
//! commands of docs/hdl.md,
//!
//! - Icarus: `iverilog -g2005 -o tb *.v && vvp tb`,
//! - Verilator 5: `verilator --binary --trace-fst --top-module tt_testbench -o tb *.v &&
//!   obj_dir/tb +fst`, whose `dut.fst` passes `tooltouch check` against the golden VCD,
//!
//! print `TESTBENCH OK <cycles>`; and with a vector file missing, shorter than its header
//! says, or holding an X or Z digit, the testbench stops with its own `TESTBENCH ERROR`
//! line and a non-zero exit. `tooltouch hdl` refuses a depth the testbench cannot hold.
//!
//! A short lathe run keeps it quick (one measurement at 4800 rpm and 1 MHz: 104 230
//! clocks). Needs Icarus Verilog and Verilator: without them the tests fail naming
//! `cargo xtask setup`.

use std::path::Path;
use std::process::{Command, Output};

use crate::common;
use common::{s, text, tooltouch};

use crate::common::FAST_LATHE as FAST;

/// Clocks of the fast lathe's first measurement.
const CYCLES: &str = "104230";

/// Fails naming `cargo xtask setup` when a tool is not installed.
fn require(tools: &[&str]) {
    for tool in tools {
        if let Err(e) = tooltouch_rtl_sim::runner::find_tool(tool) {
            panic!("{e}");
        }
    }
}

/// `tooltouch hdl --config fast.toml --vectors lathe --out <work>/rtl`; returns the folder.
fn rtl_with_vectors(work: &Path) -> std::path::PathBuf {
    let toml = work.join("fast.toml");
    std::fs::write(&toml, FAST).unwrap();
    let rtl = work.join("rtl");
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&toml),
        "--vectors",
        "lathe",
        "--out",
        s(&rtl),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains(&format!("{CYCLES} clocks at 1000000 Hz")),
        "{}",
        text(&o)
    );
    rtl
}

/// Runs `command` with `sh -c` in `dir`, as typed at a prompt.
fn shell(dir: &Path, command: &str) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(command)
        .current_dir(dir)
        .output()
        .expect("sh runs")
}

/// One way to spoil the vectors: what it does, how (on the folder), and the start of the
/// line the testbench must print.
type Spoiled = (&'static str, fn(&Path), &'static str);

/// The vectors spoiled one way each.
fn spoiled_vectors() -> Vec<Spoiled> {
    fn edit(path: &Path, f: impl FnOnce(&mut Vec<String>)) {
        let mut lines: Vec<String> = std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .map(str::to_string)
            .collect();
        f(&mut lines);
        std::fs::write(path, lines.join("\n") + "\n").unwrap();
    }
    vec![
        (
            "stim.hex missing",
            |d| std::fs::remove_file(d.join("stim.hex")).unwrap(),
            "TESTBENCH ERROR stim.hex: cannot open it in the working directory",
        ),
        (
            "expect.hex missing",
            |d| std::fs::remove_file(d.join("expect.hex")).unwrap(),
            "TESTBENCH ERROR expect.hex: cannot open it in the working directory",
        ),
        (
            "expect.hex cut after 100 lines",
            |d| edit(&d.join("expect.hex"), |l| l.truncate(100)),
            "TESTBENCH ERROR expect.hex: its header says {expect} entries, the file holds 99 words after it",
        ),
        (
            "stim.hex cut after 10 lines",
            |d| edit(&d.join("stim.hex"), |l| l.truncate(10)),
            "TESTBENCH ERROR stim.hex: its header says {stim} segments, the file holds 9 words after it",
        ),
        (
            "an X digit in stim.hex word 4",
            |d| edit(&d.join("stim.hex"), |l| l[4].replace_range(0..1, "x")),
            "TESTBENCH ERROR stim.hex word 4: an X or Z digit",
        ),
        (
            "a Z digit in expect.hex word 6",
            |d| edit(&d.join("expect.hex"), |l| l[6].replace_range(3..4, "z")),
            "TESTBENCH ERROR expect.hex word 6: an X or Z digit",
        ),
    ]
}

/// Runs the built testbench (`run`, a command line in `rtl`) on each spoiled copy of the
/// vectors: a non-zero exit with the testbench's own message; then on the vectors as
/// written: `TESTBENCH OK`.
fn check_spoiled_vectors(rtl: &Path, run: &str) {
    let stim = std::fs::read(rtl.join("stim.hex")).unwrap();
    let expect = std::fs::read(rtl.join("expect.hex")).unwrap();
    // The words after each file's header line: what its header says.
    let words = |b: &[u8]| (String::from_utf8_lossy(b).lines().count() - 1).to_string();
    for (what, spoil, message) in spoiled_vectors() {
        let message = message
            .replace("{stim}", &words(&stim))
            .replace("{expect}", &words(&expect));
        let message = message.as_str();
        spoil(rtl);
        let o = shell(rtl, run);
        assert!(
            !o.status.success(),
            "{what}: `{run}` exited {}:\n{}",
            o.status,
            text(&o)
        );
        assert!(
            text(&o).lines().any(|l| l.starts_with(message)),
            "{what}: `{run}` did not say `{message}`:\n{}",
            text(&o)
        );
        std::fs::write(rtl.join("stim.hex"), &stim).unwrap();
        std::fs::write(rtl.join("expect.hex"), &expect).unwrap();
    }
    let o = shell(rtl, run);
    assert!(o.status.success(), "`{run}`:\n{}", text(&o));
    assert!(
        text(&o)
            .lines()
            .any(|l| l == format!("TESTBENCH OK {CYCLES}")),
        "`{run}`:\n{}",
        text(&o)
    );
}

#[test]
fn hdl_icarus_runs_the_generated_testbench_and_stops_on_bad_vectors() {
    require(&["iverilog", "vvp"]);
    let work = tempfile::tempdir().unwrap();
    let rtl = rtl_with_vectors(work.path());
    let o = shell(&rtl, "iverilog -g2005 -o tb *.v && vvp tb");
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o)
            .lines()
            .any(|l| l == format!("TESTBENCH OK {CYCLES}")),
        "{}",
        text(&o)
    );
    check_spoiled_vectors(&rtl, "vvp tb");
}

#[test]
fn hdl_verilator_binary_runs_the_generated_testbench_and_stops_on_bad_vectors() {
    require(&["verilator"]);
    let work = tempfile::tempdir().unwrap();
    let rtl = rtl_with_vectors(work.path());
    // docs/hdl.md's Verilator line with its FST dump, fed to `tooltouch check`.
    let o = shell(
        &rtl,
        "verilator --binary --trace-fst --top-module tt_testbench -o tb *.v && obj_dir/tb +fst",
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o)
            .lines()
            .any(|l| l == format!("TESTBENCH OK {CYCLES}")),
        "{}",
        text(&o)
    );
    let toml = work.path().join("fast.toml");
    let golden = work.path().join("m");
    let o = tooltouch(&["measure", "--config", s(&toml), "--out", s(&golden)]);
    assert!(o.status.success(), "{}", text(&o));
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&golden.join("measure.vcd")),
        "--dut",
        s(&rtl.join("dut.fst")),
    ]);
    assert!(
        o.status.success()
            && text(&o).contains(&format!("OK: {CYCLES} cycles × 17 signals"))
            && text(&o).contains("in DUT scope `TOP.tt_testbench.dut`"),
        "{}",
        text(&o)
    );
    check_spoiled_vectors(&rtl, "obj_dir/tb");
}

#[test]
fn hdl_depths_the_testbench_cannot_hold_are_refused() {
    let work = tempfile::tempdir().unwrap();
    let rtl = work.path().join("rtl");
    for (flag, value) in [
        ("--stim-depth", "4294967295"),
        ("--expect-depth", "67108865"),
        ("--stim-depth", "1"),
    ] {
        let o = tooltouch(&["hdl", "--out", s(&rtl), flag, value]);
        assert!(!o.status.success(), "{flag} {value}: {}", text(&o));
        assert!(
            text(&o).contains(&format!("{flag} {value} is out of range"))
                && text(&o).contains("2..=67108864 words"),
            "{flag} {value}: {}",
            text(&o)
        );
        assert!(!rtl.exists(), "{flag} {value}: a refused run wrote files");
    }
    // The largest depth is accepted.
    let o = tooltouch(&["hdl", "--out", s(&rtl), "--stim-depth", "67108864"]);
    assert!(o.status.success(), "{}", text(&o));
    let tb = std::fs::read_to_string(rtl.join("tt_testbench.v")).unwrap();
    assert!(tb.contains("localparam integer STIM_DEPTH    = 67108864;"));
}
