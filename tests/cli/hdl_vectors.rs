//! `tooltouch hdl --vectors` writes stim.hex and expect.hex beside the RTL so that the
//! generated testbench runs as generated: `cd DIR && iverilog -g2005 -o tb *.v && vvp tb`
//! prints `TESTBENCH OK <cycles>`, from the lathe run of the settings or from a stimulus
//! file, and its `+vcd` dump passes `tooltouch check` against `measure`'s golden VCD.
//! A later run without `--vectors` removes them (no stale vectors beside new RTL).
//!
//! Needs Icarus Verilog: without it the test fails naming `cargo xtask setup`.

use crate::common;
use common::{icarus, s, text, tooltouch};

use crate::common::FAST_LATHE as FAST;

#[test]
fn the_generated_testbench_passes_with_the_vectors_hdl_writes() {
    let w = tempfile::tempdir().unwrap();
    let toml = w.path().join("fast.toml");
    std::fs::write(&toml, FAST).unwrap();
    let m = w.path().join("m");
    let o = tooltouch(&[
        "measure",
        "--config",
        s(&toml),
        "--out",
        s(&m),
        "--no-progress",
    ]);
    assert!(o.status.success(), "{}", text(&o));

    // From the lathe run the settings describe: the span of measure.vcd.
    let rtl = w.path().join("rtl");
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&toml),
        "--out",
        s(&rtl),
        "--vectors",
        "lathe",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("104230 clocks at 1000000 Hz"),
        "{}",
        text(&o)
    );
    let out = icarus(&rtl, &["+vcd"]);
    assert!(
        out.lines().any(|l| l == "TESTBENCH OK 104230"),
        "the testbench did not pass:\n{out}"
    );
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&m.join("measure.vcd")),
        "--dut",
        s(&rtl.join("dut.vcd")),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));

    // From a stimulus file: measure's event stream (no settings: it carries them, but the
    // RTL is generated from the settings, so they are given).
    let rtl2 = w.path().join("rtl2");
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&toml),
        "--out",
        s(&rtl2),
        "--vectors",
        s(&m.join("events.ttv")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let out = icarus(&rtl2, &[]);
    assert!(
        out.lines().any(|l| l.starts_with("TESTBENCH OK ")),
        "the testbench did not pass:\n{out}"
    );

    // Without --vectors the folder keeps no vectors of the earlier run.
    let o = tooltouch(&["hdl", "--config", s(&toml), "--out", s(&rtl)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(rtl.join("tt_testbench.v").is_file());
    for f in ["stim.hex", "expect.hex"] {
        assert!(!rtl.join(f).exists(), "stale {f} left beside the new RTL");
    }
    // An explicit depth too small for the vectors is refused.
    let o = tooltouch(&[
        "hdl",
        "--out",
        s(&rtl),
        "--config",
        s(&toml),
        "--vectors",
        "lathe",
        "--stim-depth",
        "100",
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("--stim-depth 100: stim.hex holds"),
        "{}",
        text(&o)
    );
    assert!(
        rtl.join("tt_testbench.v").is_file(),
        "a failed run removed files"
    );
}
