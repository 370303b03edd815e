//! One configuration into every embodiment: a non-default point of a small `tooltouch tune`
//! run, written as a settings file by `tooltouch tune point`, goes through `tooltouch hdl
//! --config` and `tooltouch vectors --config` (the generated testbench prints `TESTBENCH
//! OK` under Icarus), the QEMU image built with that configuration baked in (`tooltouch
//! cosim firmware --config`, which builds it, boots it on the vectors' events and checks
//! its trace), and `tooltouch check` of that trace against the golden outputs. The image
//! reports the point's configuration hash in its trace; the default image is refused for
//! the point's stream (exit 2).
//!
//! Needs Icarus Verilog, qemu-system-arm and the thumbv7m-none-eabi target: without them
//! the test fails naming `cargo xtask setup`.

use crate::common;
use common::{icarus, s, text, tooltouch};

use crate::common::FAST_LATHE;

#[test]
fn a_tuned_point_runs_in_the_model_the_rtl_and_the_firmware() {
    let w = tempfile::tempdir().unwrap();
    let p = |name: &str| w.path().join(name);

    // A small sweep: two counter thresholds (400 is not the default 512) and one force
    // design; point 0 is the i_def = 400 one.
    let o = tooltouch(&[
        "tune",
        "--scenarios",
        "1",
        "--revolutions",
        "6",
        "--method",
        "counter",
        "--contact-rule",
        "sticky",
        "--law",
        "linear",
        "--charge-bits",
        "10",
        "--scale-bits",
        "24",
        "--glitch-cycles",
        "0",
        "--i-def",
        "400,512",
        "--force-controller",
        "fuzzy",
        "--kp-percent",
        "50",
        "--ki-percent",
        "100",
        "--out",
        s(&p("tune")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = tooltouch(&[
        "tune",
        "point",
        s(&p("tune")),
        "0",
        "--out",
        s(&p("point.toml")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let point = std::fs::read_to_string(p("point.toml")).unwrap();
    assert!(point.contains("i_def = 400"), "{point}");
    // The force point is a [force] design the firmware can be built with.
    let o = tooltouch(&[
        "tune",
        "point",
        s(&p("tune")),
        "2",
        "--out",
        s(&p("force.toml")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let force = std::fs::read_to_string(p("force.toml")).unwrap();
    assert!(
        force.contains("[force]") && force.contains("controller = \"fuzzy\""),
        "{force}"
    );
    let o = tooltouch(&[
        "cosim",
        "config",
        "--config",
        s(&p("force.toml")),
        "--out",
        s(&p("force.bin")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = tooltouch(&["tune", "point", s(&p("tune")), "3", "--out", s(&p("x"))]);
    assert!(
        !o.status.success() && text(&o).contains("points 0..3"),
        "{}",
        text(&o)
    );

    let settings = p("settings.toml");
    std::fs::write(&settings, format!("{point}\n{FAST_LATHE}")).unwrap();
    let config =
        tooltouch_settings::firmware_config::FirmwareConfig::load(Some(&settings)).unwrap();
    assert_ne!(
        config.measure.hash(),
        tooltouch_model::MeasureConfig::default().hash(),
        "the point is not the default configuration"
    );
    let hash = format!("{:016x}", config.measure.hash());

    // The golden model: a lathe run, its vectors under the same settings.
    let o = tooltouch(&[
        "measure",
        "--config",
        s(&settings),
        "--out",
        s(&p("m")),
        "--no-progress",
        "--vcd",
        "none",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let v = p("v");
    let o = tooltouch(&[
        "vectors",
        "--stimulus",
        s(&p("m").join("events.ttv")),
        "--config",
        s(&settings),
        "--out",
        s(&v),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains(&hash), "{}", text(&o));

    // The RTL generated from the settings passes its testbench on those vectors.
    let rtl = p("rtl");
    let o = tooltouch(&[
        "hdl",
        "--config",
        s(&settings),
        "--out",
        s(&rtl),
        "--vectors",
        s(&v.join("events.ttv")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains(&hash), "{}", text(&o));
    let out = icarus(&rtl, &[]);
    assert!(
        out.lines().any(|l| l.starts_with("TESTBENCH OK ")),
        "the testbench did not pass:\n{out}"
    );

    // The QEMU image built with the settings, on the vectors' events.
    let trace = p("firmware.ttv");
    let o = tooltouch(&[
        "cosim",
        "firmware",
        "--stimulus",
        s(&v.join("events.ttv")),
        "--config",
        s(&settings),
        "--trace",
        s(&trace),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(
        text(&o).contains(&format!("configuration measure_hash={hash}")),
        "the image does not report the point's configuration:\n{}",
        text(&o)
    );
    let bytes = std::fs::read(&trace).unwrap();
    let streams = tooltouch_firmware_runner::trace::parse(&bytes).unwrap();
    assert_eq!(
        streams[0].profile.image_hashes,
        Some((config.measure.hash(), config.force.hash())),
        "the trace's status record names the image's configuration"
    );
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&v.join("expected_outputs.ttv")),
        "--dut",
        s(&trace),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));

    // The default image is not the point's: refused as bad input, naming both.
    let default_image =
        tooltouch_firmware_runner::qemu::build_firmware().unwrap_or_else(|e| panic!("{e}"));
    let o = tooltouch(&[
        "cosim",
        "firmware",
        "--stimulus",
        s(&v.join("events.ttv")),
        "--image",
        s(&default_image),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("was built with configuration") && text(&o).contains(&hash),
        "{}",
        text(&o)
    );
}
