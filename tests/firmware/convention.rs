//! The QEMU firmware by convention: `cd firmware && cargo run --release` boots the image on
//! the bundled demo stream (`firmware/tooltouch-events.bin`, which `tooltouch measure`
//! remakes from `firmware/demo-lathe.toml`) and its trace passes `tooltouch check`; a
//! missing or malformed events file is reported on QEMU's console with its own exit status
//! (docs/firmware.md); `tooltouch cosim firmware` runs an image on a stream — a measurement
//! stream or a force-only one — and checks it (exit 0 on a match, 2 on bad input).
//!
//! Needs qemu-system-arm and the thumbv7m-none-eabi target: without them the test fails
//! with a message naming `cargo xtask setup`.

use std::path::Path;
use std::process::{Command, Output};
use tooltouch_firmware_runner::qemu::{self, exit_code};

use crate::common;
use common::{s, text, tooltouch};

/// Boots `image` in QEMU inside `dir` (which may or may not hold an events file).
fn boot(image: &Path, dir: &Path) -> Output {
    Command::new(qemu::QEMU)
        .args(qemu::QEMU_ARGS)
        .arg("-kernel")
        .arg(image)
        .current_dir(dir)
        .output()
        .expect("qemu-system-arm runs")
}

#[test]
fn cargo_run_boots_the_qemu_image_on_the_demo_stream() {
    let firmware = qemu::firmware_dir();
    let w = tempfile::tempdir().unwrap();
    // The bundled demo stream is what its settings make.
    let o = tooltouch(&[
        "measure",
        "--config",
        s(&firmware.join("demo-lathe.toml")),
        "--out",
        s(&w.path().join("m")),
        "--no-progress",
        "--vcd",
        "none",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        std::fs::read(w.path().join("m/events.ttv")).unwrap()
            == std::fs::read(firmware.join("tooltouch-events.bin")).unwrap(),
        "firmware/tooltouch-events.bin is stale: remake it as firmware/demo-lathe.toml says"
    );

    qemu::check_tools().unwrap_or_else(|e| panic!("{e}"));
    // Under the lock the co-simulation's builds take (firmware/target is shared).
    let images = firmware.join("target/images");
    std::fs::create_dir_all(&images).unwrap();
    let lock = std::fs::File::create(images.join("build.lock")).unwrap();
    lock.lock().unwrap();
    let o = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .args(["run", "--release"])
        .current_dir(&firmware)
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET")
        .env_remove(tooltouch_settings::firmware_config::CONFIG_VAR)
        .output()
        .expect("cargo runs");
    let trace = w.path().join("demo-outputs.ttv");
    std::fs::copy(firmware.join("tooltouch-outputs.bin"), &trace).unwrap();
    drop(lock);
    assert!(o.status.success(), "{}", text(&o));
    let console = String::from_utf8_lossy(&o.stdout);
    assert!(
        console.contains("configuration measure_hash=") && console.contains("replayed 1 stream(s)"),
        "{console}"
    );
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&w.path().join("m/expected_outputs.ttv")),
        "--dut",
        s(&trace),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
}

#[test]
fn a_missing_or_malformed_events_file_has_its_message_and_exit_status() {
    let image = qemu::build_firmware().unwrap_or_else(|e| panic!("{e}"));
    let demo = std::fs::read(qemu::firmware_dir().join("tooltouch-events.bin")).unwrap();
    let w = tempfile::tempdir().unwrap();

    let o = boot(&image, w.path());
    assert_eq!(
        o.status.code(),
        Some(exit_code::NO_EVENTS_FILE),
        "{}",
        text(&o)
    );
    assert!(
        text(&o).contains("cannot open tooltouch-events.bin"),
        "{}",
        text(&o)
    );

    std::fs::write(w.path().join(qemu::EVENTS_FILE), &demo[..1000]).unwrap();
    let o = boot(&image, w.path());
    assert_eq!(
        o.status.code(),
        Some(exit_code::MALFORMED_EVENTS),
        "{}",
        text(&o)
    );
    assert!(
        text(&o).contains("tooltouch-events.bin is malformed at byte"),
        "{}",
        text(&o)
    );
    // The trace ends with the error record, which the host explains.
    let trace = std::fs::read(w.path().join(qemu::OUTPUTS_FILE)).unwrap();
    let e = tooltouch_firmware_runner::trace::parse(&trace)
        .unwrap_err()
        .to_string();
    assert!(e.contains("truncated record"), "{e}");
}

#[test]
fn cosim_firmware_checks_an_image_on_a_stream() {
    let image = qemu::build_firmware().unwrap_or_else(|e| panic!("{e}"));
    let demo = qemu::firmware_dir().join("tooltouch-events.bin");
    let w = tempfile::tempdir().unwrap();
    let trace = w.path().join("trace.ttv");
    let o = tooltouch(&[
        "cosim",
        "firmware",
        "--stimulus",
        s(&demo),
        "--image",
        s(&image),
        "--trace",
        s(&trace),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("none lost or overflowed"), "{}", text(&o));
    assert!(trace.is_file());

    // A force-only stream (`tooltouch control`'s) runs too: the firmware gets the default
    // measurement configuration before it.
    let o = tooltouch(&["control", "--out", s(&w.path().join("ctl"))]);
    assert!(o.status.success(), "{}", text(&o));
    let o = tooltouch(&[
        "cosim",
        "firmware",
        "--stimulus",
        s(&w.path().join("ctl/pi_estimated.events.ttv")),
        "--image",
        s(&image),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("force records"), "{}", text(&o));

    // Bad input: a stimulus that is not one, an image that is not one or does not exist,
    // settings whose configuration is not the stream's.
    let junk = w.path().join("junk.ttv");
    std::fs::write(&junk, b"not a stream").unwrap();
    for args in [
        vec!["--stimulus", s(&junk), "--image", s(&image)],
        vec!["--stimulus", s(&demo), "--image", s(&junk)],
        vec!["--stimulus", s(&demo), "--image", "no-such-image.elf"],
    ] {
        let mut all = vec!["cosim", "firmware"];
        all.extend(args);
        let o = tooltouch(&all);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    }
    let other = w.path().join("other.toml");
    std::fs::write(&other, "[measure]\ni_def = 300\n").unwrap();
    let o = tooltouch(&[
        "cosim",
        "firmware",
        "--stimulus",
        s(&demo),
        "--image",
        s(&image),
        "--config",
        s(&other),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("made with configuration"), "{}", text(&o));
}
