//! `tooltouch hdl --config` takes the testbench clock from the settings file's `[lathe]
//! clock_hz`, as `tooltouch measure` does, so a testbench and the golden VCD share one
//! period; a `--clock-hz` that contradicts the file is refused.

use crate::common;

use common::{s, text, tooltouch, FAST_LATHE};
use std::path::Path;

/// The testbench's clock period, ns (`localparam integer PERIOD`).
fn testbench_period_ns(dir: &Path) -> u64 {
    let tb = std::fs::read_to_string(dir.join("tt_testbench.v")).expect("tt_testbench.v");
    let line = tb
        .lines()
        .find(|l| l.contains("localparam integer PERIOD"))
        .expect("a PERIOD parameter");
    line.split('=')
        .nth(1)
        .unwrap()
        .trim()
        .trim_end_matches(';')
        .parse()
        .unwrap()
}

/// The clock stated in the golden VCD's header comment (`clock_hz=N`).
fn vcd_clock_hz(vcd: &Path) -> u64 {
    let text = std::fs::read_to_string(vcd).expect("measure.vcd");
    let at = text.find("clock_hz=").expect("a clock_hz comment") + "clock_hz=".len();
    let digits: String = text[at..]
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().unwrap()
}

#[test]
fn cli_hdl_testbench_and_golden_vcd_share_the_settings_clock() {
    let work = tempfile::tempdir().unwrap();
    let settings = work.path().join("settings.toml");
    std::fs::write(&settings, FAST_LATHE).unwrap();
    let measured = work.path().join("measure");
    let o = tooltouch(&["measure", "--config", s(&settings), "--out", s(&measured)]);
    assert!(o.status.success(), "{}", text(&o));
    let rtl = work.path().join("rtl");
    let o = tooltouch(&["hdl", "--config", s(&settings), "--out", s(&rtl)]);
    assert!(o.status.success(), "{}", text(&o));
    let clock_hz = vcd_clock_hz(&measured.join("measure.vcd"));
    assert_eq!(clock_hz, 1_000_000, "the demo lathe's [lathe] clock_hz");
    assert_eq!(testbench_period_ns(&rtl), 1_000_000_000 / clock_hz);
    // A --clock-hz that agrees with the file is accepted.
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&settings),
        "--clock-hz",
        "1000000",
        "--out",
        s(&rtl),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(testbench_period_ns(&rtl), 1000);
}

#[test]
fn cli_hdl_refuses_a_clock_flag_that_contradicts_the_settings() {
    let work = tempfile::tempdir().unwrap();
    let settings = work.path().join("settings.toml");
    std::fs::write(&settings, FAST_LATHE).unwrap();
    let rtl = work.path().join("rtl");
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&settings),
        "--clock-hz",
        "50000000",
        "--out",
        s(&rtl),
    ]);
    let message = text(&o);
    assert!(!o.status.success(), "{message}");
    assert!(
        message.contains("--clock-hz 50000000 contradicts [lathe] clock_hz of")
            && message.contains("= 1000000 Hz"),
        "{message}"
    );
    assert!(!rtl.exists(), "a refused run writes nothing");
}

#[test]
fn cli_hdl_takes_the_clock_flag_when_the_settings_state_none() {
    let work = tempfile::tempdir().unwrap();
    let settings = work.path().join("settings.toml");
    std::fs::write(&settings, "[measure]\nglitch_cycles = 2\n").unwrap();
    let rtl = work.path().join("rtl");
    let o = tooltouch(&["hdl", "--config", s(&settings), "--out", s(&rtl)]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        testbench_period_ns(&rtl),
        20,
        "50 MHz, measure's default clock"
    );
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&settings),
        "--clock-hz",
        "25000000",
        "--out",
        s(&rtl),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(testbench_period_ns(&rtl), 40);
}
