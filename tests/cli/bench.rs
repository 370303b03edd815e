//! `tooltouch bench` as a bench user runs it (docs/firmware.md, "The bench"): the expected
//! decision lines of the demo stream, a controller log collected through a fake `probe-rs`
//! (a script that checks its arguments and prints a recorded session, as
//! `probe-rs attach --log-format {s}` prints the controller's defmt log) and checked,
//! a differing, a quiet and a missing probe-rs, and the inputs refused before it starts.
//!
//! `--elf` must be an image with a defmt table: the emulated Nucleo image is built for it
//! (needs the thumbv7em-none-eabihf target: without it the test fails naming `cargo xtask
//! setup`).

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

use crate::common::{s, text, tooltouch};

/// The demo stream and the settings its controller image is built with.
fn demo() -> (PathBuf, PathBuf) {
    let firmware = Path::new(env!("CARGO_MANIFEST_DIR")).join("firmware");
    (
        firmware.join("tooltouch-events.bin"),
        firmware.join("demo-lathe.toml"),
    )
}

/// A fake `probe-rs` in `dir`: it fails unless called as `attach --chip STM32F446RETx
/// --log-format {s} --probe 0483:374b:TEST <elf>`, then prints `log` and waits.
fn fake_probe_rs(dir: &Path, elf: &Path, log: &[String]) -> PathBuf {
    let recorded = dir.join("recorded.log");
    std::fs::write(&recorded, log.join("\n") + "\n").unwrap();
    let script = dir.join("probe-rs");
    std::fs::write(
        &script,
        format!(
            "#!/bin/sh\n[ \"$*\" = 'attach --chip STM32F446RETx --log-format {{s}} --probe \
             0483:374b:TEST {}' ] || {{ echo \"bad arguments: $*\" >&2; exit 3; }}\n\
             cat '{}'\nexec sleep 30\n",
            elf.display(),
            recorded.display()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    script
}

fn collect(stream: &Path, config: &Path, elf: &Path, probe_rs: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "bench",
        "collect",
        "--stream",
        s(stream),
        "--config",
        s(config),
        "--elf",
        s(elf),
        "--probe",
        "0483:374b:TEST",
        "--probe-rs",
        s(probe_rs),
    ];
    args.extend_from_slice(extra);
    let o = tooltouch(&args);
    format!("exit {:?}\n{}", o.status.code(), text(&o))
}

#[test]
fn a_bench_session_is_collected_checked_and_its_differences_named() {
    let (stream, config) = demo();
    let elf = tooltouch_firmware_runner::nucleo::build_emulated().unwrap_or_else(|e| panic!("{e}"));
    let w = tempfile::tempdir().unwrap();

    // The expected lines: the documented line of the demo stream.
    let expected = w.path().join("expected.log");
    let o = tooltouch(&[
        "bench",
        "expect",
        "--stream",
        s(&stream),
        "--config",
        s(&config),
        "--out",
        s(&expected),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let want = std::fs::read_to_string(&expected).unwrap();
    let docs =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/firmware.md"))
            .unwrap()
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
    let want_lines: Vec<String> = want.lines().map(str::to_string).collect();
    assert_eq!(want_lines.len(), 2, "{want}");
    assert!(
        docs.contains(&format!(
            "gives two lines, `{}` and `{}`",
            want_lines[0], want_lines[1]
        )),
        "docs/firmware.md must quote the demo stream's lines {want_lines:?}"
    );

    // A session as the controller logs it: boot lines, then each decision with the
    // board-dependent count after its `;`.
    let mut session = vec![
        "tooltouch firmware on Nucleo-F446RE, SYSCLK 168000000 Hz".to_string(),
        "configuration measure_hash=0 force_hash=0".to_string(),
    ];
    session.extend(
        want_lines
            .iter()
            .map(|l| format!("{l}; 2 ADC samples dropped")),
    );
    let good = w.path().join("good");
    std::fs::create_dir(&good).unwrap();
    let fake = fake_probe_rs(&good, &elf, &session);
    let saved = w.path().join("collected.log");
    let r = collect(&stream, &config, &elf, &fake, &["--out", s(&saved)]);
    assert!(r.starts_with("exit Some(0)"), "{r}");
    assert!(
        r.contains("2 decision lines in the controller's log, every one equal"),
        "{r}"
    );
    assert_eq!(
        std::fs::read_to_string(&saved).unwrap(),
        session.join("\n") + "\n"
    );
    // The saved log checks again offline.
    let o = tooltouch(&[
        "bench",
        "check",
        "--stream",
        s(&stream),
        "--config",
        s(&config),
        "--log",
        s(&saved),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));

    // A controller that latched another position.
    let wrong_dir = w.path().join("wrong");
    std::fs::create_dir(&wrong_dir).unwrap();
    let mut wrong = session.clone();
    // (the session's lines 2.. are the expected lines: the decision, then its confirmation)
    wrong[2] = wrong[2].replacen("position -", "position -1", 1);
    let fake = fake_probe_rs(&wrong_dir, &elf, &wrong);
    let r = collect(&stream, &config, &elf, &fake, &[]);
    assert!(r.starts_with("exit Some(1)"), "{r}");
    assert!(
        r.contains("MISMATCH: the controller's log: decision line 0: expected `register now"),
        "{r}"
    );

    // A controller that never decides: the timeout, then the missing line named.
    let quiet_dir = w.path().join("quiet");
    std::fs::create_dir(&quiet_dir).unwrap();
    let fake = fake_probe_rs(&quiet_dir, &elf, &session[..2]);
    let r = collect(&stream, &config, &elf, &fake, &["--timeout-s", "1"]);
    assert!(r.starts_with("exit Some(1)"), "{r}");
    assert!(r.contains("the first missing: `register now"), "{r}");

    // No probe-rs: how to install it.
    let r = collect(
        &stream,
        &config,
        &elf,
        Path::new("/nonexistent/probe-rs"),
        &[],
    );
    assert!(r.starts_with("exit Some(2)"), "{r}");
    assert!(r.contains("cargo install probe-rs-tools --locked"), "{r}");

    // Refused before probe-rs starts: an ELF without a defmt table, a stream of another
    // configuration than the controller's.
    // A small host ELF (the `tooltouch` binary itself is over the 64 MiB image limit and
    // is refused for its size before its sections are read).
    let host_elf = ["/bin/true", "/usr/bin/true"]
        .into_iter()
        .map(PathBuf::from)
        .find(|p| p.is_file())
        .expect("a host ELF: /bin/true");
    let r = collect(&stream, &config, &host_elf, &fake, &[]);
    assert!(r.starts_with("exit Some(2)"), "{r}");
    assert!(r.contains("no defmt table"), "{r}");
    let other = w.path().join("other.toml");
    std::fs::write(&other, "[measure]\nwindow_revs = 2\n").unwrap();
    let r = collect(&stream, &other, &elf, &fake, &[]);
    assert!(r.starts_with("exit Some(2)"), "{r}");
    assert!(r.contains("made with measure_hash="), "{r}");
    assert!(r.contains("the controller decides with its own"), "{r}");
}
