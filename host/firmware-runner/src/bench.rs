//! The two-board bench's host side: the controller Nucleo's defmt log collected over
//! probe-rs while the lathe player (firmware/src/bin/player) replays a stream on its pins,
//! and its decision lines checked against the golden model's for the same stream
//! (docs/firmware.md, "The bench").
//!
//! probe-rs runs as an external program: `probe-rs attach --chip STM32F446RETx
//! --log-format {s} <controller ELF>` attaches without resetting the running controller
//! and prints each defmt message decoded with the ELF's own table (`{s}`: the message
//! only, the same text [`crate::nucleo::decode_defmt`] gives for the emulated image). The
//! controller's idle logs every change of "register now"; [`decision_lines`] keeps those
//! lines (up to their `;`, since the count of ADC samples dropped depends on the board's
//! timing) and [`expected_lines`] makes the same lines from the golden model.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use tooltouch_model::measure::calibration::{corrected_position, CalibrationRecord};
use tooltouch_model::wire::measure_config::decode_config;
use tooltouch_model::wire::measure_event::decode_event;
use tooltouch_model::wire::{kind, Records, StreamKind};
use tooltouch_model::{Faults, MeasureEvent, MeasureOutputs, Measurement};

/// The controller's chip, as probe-rs names it.
pub const CHIP: &str = "STM32F446RETx";

/// How to install probe-rs (it is not in `cargo xtask setup`: the bench needs the boards).
pub const INSTALL_PROBE_RS: &str =
    "install probe-rs with `cargo install probe-rs-tools --locked` (https://probe.rs)";

/// The largest stream the player's image embeds (firmware/build.rs refuses a larger
/// `TOOLTOUCH_PLAYER_STREAM`: the flash left beside the player's code).
pub const MAX_PLAYER_STREAM_BYTES: u64 = 448 * 1024;

/// Why a bench run could not be collected or checked.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// probe-rs is not installed.
    #[error("`{0}` was not found: {INSTALL_PROBE_RS}")]
    ProbeRsMissing(String),
    /// probe-rs could not be started or read.
    #[error("probe-rs: {0}")]
    ProbeRs(String),
    /// The stream is not a playable event stream.
    #[error("{0}")]
    Stream(String),
}

/// The decision lines the controller logs for `stream` (one event stream with its
/// measurement configuration), from the golden model: at each change of "register now",
/// `register now: position … counts, calibrated … counts (offset …), first contact at …, …
/// revolutions, … FES pulses` or `measurement cycle armed`. `calibration` is the one baked
/// into the controller's image (`None`: none; its offset applies to a stream in its
/// configuration, as the image applies it).
pub fn expected_lines(
    stream: &[u8],
    calibration: Option<&CalibrationRecord>,
) -> Result<Vec<String>, BenchError> {
    let bad = |why: String| BenchError::Stream(why);
    let (header, records) = Records::new(stream).map_err(|e| bad(e.to_string()))?;
    if header.stream != StreamKind::Events {
        return Err(bad("not an event stream".into()));
    }
    let mut model = None::<Measurement>;
    let (mut offset, mut scale_bits) = (0, 32);
    let mut lines = Vec::new();
    let mut on = false;
    let mut status = (0, false);
    for (i, record) in records.enumerate() {
        let record = record.map_err(|e| bad(e.to_string()))?;
        if record.kind == kind::MEASURE_CONFIG {
            let config = decode_config(record.payload()).map_err(|e| bad(e.to_string()))?;
            offset = calibration.map_or(0, |c| c.offset_for(&config));
            scale_bits = config.settings().scale_bits;
            model = Some(Measurement::new(&config));
            (on, status) = (false, (0, false));
            continue;
        }
        let event = match decode_event(&record, 0) {
            Ok(Some(MeasureEvent::PresetPulses(_))) => {
                return Err(bad(format!(
                    "record {i}: the PRESET_PULSES test event has no pin to play"
                )))
            }
            Ok(Some(e)) => e,
            Ok(None) => continue,
            Err(e) => return Err(bad(e.to_string())),
        };
        let Some(m) = model.as_mut() else {
            return Err(bad(format!(
                "record {i}: a measurement event before the MEASURE_CONFIG record"
            )));
        };
        // The controller's clock (TIM5) counts µs of the time the player plays.
        let time = u64::try_from(
            u128::from(record.time) * u128::from(CONTROLLER_CLOCK_HZ)
                / u128::from(header.tick_hz.max(1)),
        )
        .unwrap_or(u64::MAX);
        m.apply_at(time, event);
        let o = m.outputs();
        let s = (o.faults, o.confirmed);
        if o.register_now != on {
            on = o.register_now;
            lines.push(decision_line(&o, offset, scale_bits));
        } else if s != status {
            lines.push(status_line(&o));
        }
        status = s;
    }
    Ok(lines)
}

/// The controller's measurement clock (Hz): its TIM5, the unit of `fes_timeout_cycles`
/// on the board (`tooltouch_firmware::nucleo::timers::CLOCK_HZ`).
pub const CONTROLLER_CLOCK_HZ: u32 = 1_000_000;

/// How the lines name a decision's confirmation.
fn confirmation(confirmed: bool) -> &'static str {
    if confirmed {
        "confirmed"
    } else {
        "not confirmed"
    }
}

/// The line the controller's idle logs when the measurement's status (its faults, the
/// decision's confirmation) changes while "register now" does not: `status: faults
/// pulses_lost+unconfirmed, not confirmed` (the firmware's defmt literal).
pub fn status_line(o: &MeasureOutputs) -> String {
    format!(
        "status: faults {}, {}",
        Faults(o.faults),
        confirmation(o.confirmed)
    )
}

/// The line the controller's idle logs when "register now" changes to
/// `o.register_now`, up to its `;` (the firmware's defmt literal, src/bin/nucleo): at a
/// decision `register now: position … counts, calibrated … counts (offset …), first contact
/// at …, … revolutions, … FES pulses`, the position corrected by `offset` counts in
/// `scale_bits`; at an arm `measurement cycle armed`.
pub fn decision_line(o: &MeasureOutputs, offset: i32, scale_bits: u8) -> String {
    if o.register_now {
        format!(
            "register now: position {} counts, calibrated {} counts (offset {offset}), first \
             contact at {}, {} revolutions, {} FES pulses, faults {}, {}",
            o.decision_position,
            corrected_position(o.decision_position, offset, scale_bits),
            o.first_contact_position,
            o.revolutions,
            o.pulses,
            Faults(o.faults),
            confirmation(o.confirmed)
        )
    } else {
        "measurement cycle armed".to_string()
    }
}

/// The decision lines of a controller's `log`, each up to its `;`.
pub fn decision_lines(log: &[String]) -> Vec<String> {
    log.iter()
        .filter(|l| {
            l.starts_with("register now: ")
                || l.starts_with("measurement cycle armed")
                || l.starts_with("status: ")
        })
        .map(|l| l.split(';').next().unwrap_or(l).trim_end().to_string())
        .collect()
}

/// The first difference of `got` from `want`, or `None` when they are equal.
pub fn first_difference(want: &[String], got: &[String]) -> Option<String> {
    for (i, (w, g)) in want.iter().zip(got).enumerate() {
        if w != g {
            return Some(format!(
                "decision line {i}: expected `{w}`, the controller logged `{g}`"
            ));
        }
    }
    match want.len().cmp(&got.len()) {
        std::cmp::Ordering::Equal => None,
        std::cmp::Ordering::Greater => Some(format!(
            "the controller logged {} decision lines, the golden model expects {}; the first \
             missing: `{}`",
            got.len(),
            want.len(),
            want[got.len()]
        )),
        std::cmp::Ordering::Less => Some(format!(
            "the controller logged {} decision lines, the golden model expects {}; the first \
             extra: `{}`",
            got.len(),
            want.len(),
            got[want.len()]
        )),
    }
}

/// Checks that `elf` (an image's bytes) holds a defmt table, as the controller's Nucleo
/// image does: without one, probe-rs cannot decode its log.
pub fn check_defmt_table(elf: &[u8]) -> Result<(), BenchError> {
    match defmt_decoder::Table::parse(elf) {
        Ok(Some(_)) => Ok(()),
        Ok(None) => Err(BenchError::Stream(
            "the image has no defmt table: is it the controller's Nucleo image (`cargo \
             nucleo-build`, target/thumbv7em-none-eabihf/release/nucleo)?"
                .into(),
        )),
        Err(e) => Err(BenchError::Stream(format!("the image's defmt table: {e}"))),
    }
}

/// The most log lines [`collect`] keeps: a probe-rs that prints without end stops the
/// collection here instead of filling the memory.
pub const MAX_LOG_LINES: usize = 1_000_000;

/// Attaches `probe_rs` (the program: `probe-rs`, or a path) to the running controller
/// whose image is `elf` (`probe`: its `--probe` selector when two are plugged in) and
/// collects its log lines until `want` decision lines arrived, probe-rs ended, `timeout`
/// passed or [`MAX_LOG_LINES`] were read; probe-rs is then stopped.
pub fn collect(
    probe_rs: &str,
    elf: &Path,
    probe: Option<&str>,
    want: usize,
    timeout: Duration,
) -> Result<Vec<String>, BenchError> {
    let mut cmd = Command::new(probe_rs);
    cmd.args(["attach", "--chip", CHIP, "--log-format", "{s}"]);
    if let Some(p) = probe {
        cmd.args(["--probe", p]);
    }
    cmd.arg(elf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    let mut child = match cmd.spawn() {
        Ok(c) => c,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(BenchError::ProbeRsMissing(probe_rs.to_string()))
        }
        Err(e) => {
            return Err(BenchError::ProbeRs(format!(
                "cannot start `{probe_rs}`: {e}"
            )))
        }
    };
    let Some(stdout) = child.stdout.take() else {
        let _ = child.kill();
        return Err(BenchError::ProbeRs("no standard output".into()));
    };
    let (tx, rx) = mpsc::channel();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let deadline = Instant::now() + timeout;
    let mut log = Vec::new();
    let mut decisions = 0;
    while decisions < want && log.len() < MAX_LOG_LINES {
        let left = deadline.saturating_duration_since(Instant::now());
        match rx.recv_timeout(left) {
            Ok(line) => {
                if !decision_lines(std::slice::from_ref(&line)).is_empty() {
                    decisions += 1;
                }
                log.push(line);
            }
            Err(_) => break,
        }
    }
    let _ = child.kill();
    let status = child
        .wait()
        .map_err(|e| BenchError::ProbeRs(format!("waiting for `{probe_rs}`: {e}")))?;
    // Lines already read before the stop (the reader ends with probe-rs's output).
    drop(reader);
    let room = MAX_LOG_LINES.saturating_sub(log.len());
    log.extend(rx.try_iter().take(room));
    if log.is_empty() && status.code().is_some_and(|c| c != 0) {
        return Err(BenchError::ProbeRs(format!(
            "`{probe_rs} attach` failed ({status}) before printing a line: is the controller \
             plugged in and running its image?"
        )));
    }
    Ok(log)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    /// A fresh folder of this test's own under the system's temporary folder.
    fn scratch(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("tooltouch-bench-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn demo() -> Vec<u8> {
        std::fs::read(crate::qemu::firmware_dir().join("tooltouch-events.bin")).unwrap()
    }

    /// A fake `probe-rs` that checks its arguments and prints `log` (a recorded session).
    fn fake_probe_rs(dir: &Path, log: &[String]) -> String {
        let log_file = dir.join("recorded.log");
        std::fs::write(&log_file, log.join("\n") + "\n").unwrap();
        let script = dir.join("probe-rs");
        std::fs::write(
            &script,
            format!(
                "#!/bin/sh\n[ \"$1 $2 $3 $4 $5\" = 'attach --chip {CHIP} --log-format {{s}}' ] \
                 || {{ echo \"bad arguments: $*\" >&2; exit 3; }}\ncat '{}'\nexec sleep 30\n",
                log_file.display()
            ),
        )
        .unwrap();
        std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
        script.display().to_string()
    }

    #[test]
    fn the_demo_stream_decides_and_its_lines_are_the_golden_models() {
        let want = expected_lines(&demo(), None).unwrap();
        // One measurement cycle that decides (the first arm finds "register now" already
        // low, so logs nothing), as the emulated Nucleo's log has it, and the status as it
        // changes before and after the decision (a fault, the confirmation).
        let decisions: Vec<&String> = want
            .iter()
            .filter(|l| l.starts_with("register now: position "))
            .collect();
        assert_eq!(decisions.len(), 1, "{want:?}");
        assert!(decisions[0].contains(" FES pulses, faults "), "{want:?}");
        assert!(
            want.iter()
                .all(|l| l.starts_with("register now: ") || l.starts_with("status: faults ")),
            "{want:?}"
        );
        assert!(want.iter().any(|l| l.ends_with(", confirmed")), "{want:?}");
    }

    #[test]
    fn a_baked_calibration_corrects_the_expected_position_of_its_own_configuration_only() {
        let raw = expected_lines(&demo(), None).unwrap();
        let (header, _) = Records::new(&demo()).unwrap();
        let record = |measure_hash| CalibrationRecord {
            measure_hash,
            offset_counts: -13,
            feed_nm_per_rev: 1000,
            speed_milli_rpm: 800_000,
        };
        let mine = expected_lines(&demo(), Some(&record(header.measure_hash))).unwrap();
        let position = |l: &str| -> i32 {
            l.split("position ")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap()
        };
        let calibrated = |l: &str| -> i32 {
            l.split("calibrated ")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap()
        };
        let decision = |lines: &[String]| -> String {
            lines
                .iter()
                .find(|l| l.starts_with("register now: "))
                .unwrap()
                .clone()
        };
        let (mine_d, raw_d) = (decision(&mine), decision(&raw));
        assert_eq!(calibrated(&mine_d), position(&mine_d) + 13, "{mine:?}");
        assert!(mine_d.contains("(offset -13)"), "{mine:?}");
        assert!(raw_d.contains("(offset 0)"), "{raw:?}");
        assert_eq!(calibrated(&raw_d), position(&raw_d));
        // Made with another configuration: the image applies no offset to this stream.
        let other = expected_lines(&demo(), Some(&record(header.measure_hash ^ 1))).unwrap();
        assert_eq!(other, raw);
    }

    #[test]
    fn a_recorded_session_is_collected_and_checked() {
        let want = expected_lines(&demo(), None).unwrap();
        let dir = scratch("recorded");
        let mut log = vec![
            "tooltouch firmware on Nucleo-F446RE, SYSCLK 168000000 Hz".to_string(),
            "configuration measure_hash=0 force_hash=0".to_string(),
        ];
        log.extend(want.iter().map(|l| format!("{l}; 3 ADC samples dropped")));
        let fake = fake_probe_rs(&dir, &log);
        let elf = dir.join("nucleo.elf");
        let t = Instant::now();
        let got = collect(&fake, &elf, None, want.len(), Duration::from_secs(20)).unwrap();
        // Stopped as soon as every decision arrived (the fake sleeps 30 s after).
        assert!(t.elapsed() < Duration::from_secs(15), "{:?}", t.elapsed());
        assert_eq!(got, log);
        assert_eq!(first_difference(&want, &decision_lines(&got)), None);
        // A controller that decided elsewhere, or missed a decision.
        let mut wrong = decision_lines(&got);
        let at = wrong
            .iter()
            .position(|l| l.starts_with("register now: "))
            .unwrap();
        wrong[at] = wrong[at].replace("register now: position ", "register now: position 1");
        let d = first_difference(&want, &wrong).unwrap();
        assert!(
            d.starts_with(&format!("decision line {at}: expected `register now")),
            "{d}"
        );
        let mut extra = want.clone();
        extra.push("measurement cycle armed".into());
        let d = first_difference(&want, &extra).unwrap();
        assert!(
            d.contains("the first extra: `measurement cycle armed`"),
            "{d}"
        );
        let d = first_difference(&want, &decision_lines(&got[..got.len() - 1])).unwrap();
        assert!(d.contains("the first missing"), "{d}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_quiet_controller_ends_at_the_timeout() {
        let dir = scratch("quiet");
        let fake = fake_probe_rs(&dir, &["booting".to_string()]);
        let t = Instant::now();
        let got = collect(
            &fake,
            Path::new("x.elf"),
            None,
            5,
            Duration::from_millis(500),
        )
        .unwrap();
        assert!(t.elapsed() < Duration::from_secs(10));
        assert_eq!(got, ["booting"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_missing_probe_rs_names_how_to_install_it() {
        let e = collect(
            "/nonexistent/probe-rs",
            Path::new("x.elf"),
            None,
            1,
            Duration::from_secs(1),
        )
        .unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, BenchError::ProbeRsMissing(_)));
        assert!(text.contains("cargo install probe-rs-tools"), "{text}");
    }

    #[test]
    fn the_stream_limit_is_the_players() {
        let build = std::fs::read_to_string(crate::qemu::firmware_dir().join("build.rs")).unwrap();
        assert!(
            build.contains(&format!(
                "const MAX_STREAM: u64 = {} * 1024;",
                MAX_PLAYER_STREAM_BYTES / 1024
            )),
            "firmware/build.rs's MAX_STREAM differs from MAX_PLAYER_STREAM_BYTES"
        );
    }

    #[test]
    fn an_image_without_a_defmt_table_is_refused() {
        // The host test binary itself: an ELF, with no `.defmt` section.
        let me = std::fs::read(std::env::current_exe().unwrap()).unwrap();
        let e = check_defmt_table(&me).unwrap_err().to_string();
        assert!(e.contains("no defmt table"), "{e}");
    }

    #[test]
    fn unplayable_streams_are_refused() {
        let d = demo();
        assert!(expected_lines(&d[..10], None).is_err());
        assert!(expected_lines(&d[1..], None).is_err());
    }
}
