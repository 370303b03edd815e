//! The reference-part calibration applied where a controller applies it: the FPGA (the
//! kernel) latches the raw position, the firmware reports it corrected by the baked offset
//! (model::measure::calibration), and both images' reports equal the golden model's bit for
//! bit — the QEMU lm3s6965 image in both observation modes, the Nucleo image under
//! netduinoplus2 with its defmt decision line. A stream in another configuration than the
//! calibration's is reported raw (offset 0). Then the newcomer's recipe: `calibrate`,
//! `measure --calibration`, `cosim firmware --calibration` (bake and run), and the residual
//! between the host's calibrated diameter and the firmware's.
//!
//! Needs qemu-system-arm and both thumb targets: without them the tests fail naming
//! `cargo xtask setup`.

use crate::common::{s, text, tooltouch, FAST_LATHE};
use crate::cosim::{lathe_cases, print_report, proptest_seeds};
use std::path::PathBuf;
use std::sync::OnceLock;
use tooltouch_firmware_runner::{self as cosim, nucleo, Case, CosimError, Fault, Observe};
use tooltouch_model::measure::calibration::CalibrationRecord;
use tooltouch_model::MeasureConfig;
use tooltouch_settings::firmware_config::FirmwareConfig;

/// The offset baked: −13 counts, what the as-cut reference gives the counter at the
/// defaults (−2.68 µm on the diameter at 0.1 µm per count, docs/accuracy.md).
const OFFSET: i32 = -13;

/// The default configuration (the lathe cases') with a calibration of [`OFFSET`].
fn calibrated() -> (FirmwareConfig, CalibrationRecord) {
    let record = CalibrationRecord {
        measure_hash: MeasureConfig::default().hash(),
        offset_counts: OFFSET,
        feed_nm_per_rev: 1000,
        speed_milli_rpm: 800_000,
    };
    let config = FirmwareConfig::default()
        .with_calibration(record)
        .unwrap_or_else(|e| panic!("{e}"));
    (config, record)
}

fn qemu_image() -> PathBuf {
    static IMAGE: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    IMAGE
        .get_or_init(|| {
            cosim::qemu::build_configured_firmware(&calibrated().0).map_err(|e| e.to_string())
        })
        .clone()
        .unwrap_or_else(|e| panic!("{e}"))
}

fn nucleo_image() -> PathBuf {
    static IMAGE: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    IMAGE
        .get_or_init(|| {
            nucleo::build_configured_emulated(&calibrated().0).map_err(|e| e.to_string())
        })
        .clone()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The lathe cases (the calibration's configuration) and random cases in other
/// configurations (reported raw).
fn cases(name: &str) -> Vec<Case> {
    let mut cases = lathe_cases();
    let calibrated_hash = MeasureConfig::default().hash();
    let others: Vec<Case> = proptest_seeds(4, name)
        .into_iter()
        .map(|seed| nucleo::for_nucleo(&cosim::generate(seed, Fault::None)))
        .collect();
    assert!(
        others.iter().all(|c| c.config.hash() != calibrated_hash),
        "the random cases are in other configurations"
    );
    cases.extend(others);
    cases
}

/// The decisions the golden model says the image must report: some with the offset (the
/// lathe cases), each the raw latched position minus it.
fn assert_calibrated_decisions(cases: &[Case], observe: Observe, record: &CalibrationRecord) {
    let mut with_offset = 0;
    for case in cases {
        let golden = cosim::golden(case);
        for (i, d) in cosim::golden_decisions(case, observe, Some(record)) {
            let raw = golden[i].decision_position;
            if case.config.hash() == record.measure_hash {
                assert_eq!(d.offset, OFFSET, "{}", case.name);
                assert_eq!(d.position, raw - OFFSET, "{}: no wrap near 0", case.name);
                with_offset += 1;
            } else {
                assert_eq!((d.offset, d.position), (0, raw), "{}", case.name);
            }
        }
    }
    assert!(with_offset >= 4, "only {with_offset} calibrated decisions");
}

#[test]
fn the_qemu_image_reports_the_calibrated_decision_bit_for_bit() {
    let (_, record) = calibrated();
    let image = qemu_image();
    let cases = cases("calibrated qemu cases");
    for observe in [Observe::EveryEvent, Observe::SkipFes] {
        assert_calibrated_decisions(&cases, observe, &record);
        let input = cosim::encode_batch(&cases, observe);
        let (trace, elapsed) =
            cosim::qemu::run_image(&image, &input).unwrap_or_else(|e| panic!("{e}"));
        let report = cosim::check_calibrated_batch(&cases, observe, Some(&record), &trace, elapsed)
            .unwrap_or_else(|e| panic!("{observe:?}: {e}"));
        print_report(&format!("calibrated QEMU image, {observe:?}"), &report);
        // The same trace against an uncalibrated golden model: the first calibrated
        // decision differs by the offset, reported with its time and both values.
        match cosim::check_batch(&cases, observe, &trace, elapsed) {
            Err(CosimError::Mismatch(m)) => {
                assert_eq!(m.signal, "decision.corrected_position", "{m}");
                let (model, firmware): (i64, i64) =
                    (m.model.parse().unwrap(), m.firmware.parse().unwrap());
                assert_eq!(firmware - model, -i64::from(OFFSET), "{m}");
                assert!(m.time > 0 && m.event.is_some(), "{m}");
                eprintln!("  against the raw golden model, as expected: {m}");
            }
            other => panic!("the raw golden model must not match: {other:?}"),
        }
    }
}

#[test]
fn the_nucleo_image_reports_and_logs_the_calibrated_decision() {
    let (_, record) = calibrated();
    let image = nucleo_image();
    let cases = cases("calibrated nucleo cases");
    for observe in [Observe::EveryEvent, Observe::SkipFes] {
        assert_calibrated_decisions(&cases, observe, &record);
        let run = crate::nucleo::run_on(
            &image,
            Some(&record),
            &format!("calibrated Nucleo image, {observe:?}"),
            &cases,
            observe,
        );
        let logged = run
            .log
            .iter()
            .filter(|l| l.contains(&format!("(offset {OFFSET})")))
            .count();
        assert!(logged >= 4, "{:#?}", run.log);
        // The boot names the calibration as `tooltouch cosim config --calibration` does.
        let boot = format!(
            "calibration calibration_hash={:016x} offset={OFFSET} counts",
            record.hash()
        );
        assert_eq!(
            run.log.iter().filter(|l| **l == boot).count(),
            1,
            "`{boot}` once in {:#?}",
            run.log
        );
    }
}

/// Calibrate → bake → run, as docs/accuracy.md's recipe: the firmware reports every
/// decision corrected by the calibration's offset in counts, and its diameter equals the
/// host's `measure --calibration` diameter within the scale's resolution (the offset in
/// counts is the µm offset rounded to the nearest count: at most half a count on the radius).
#[test]
fn calibrate_bake_and_run_gives_the_hosts_calibrated_diameter() {
    let w = tempfile::tempdir().unwrap();
    let p = |name: &str| w.path().join(name);
    let settings = p("lathe.toml");
    std::fs::write(&settings, FAST_LATHE.replace("repeats = 1", "repeats = 3")).unwrap();
    let o = tooltouch(&[
        "calibrate",
        "--config",
        s(&settings),
        "--reference-mm",
        "40",
        "--reference-as-cut",
        "--repeats",
        "6",
        "--out",
        s(&p("cal.json")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = tooltouch(&[
        "measure",
        "--config",
        s(&settings),
        "--calibration",
        s(&p("cal.json")),
        "--vcd",
        "none",
        "--no-progress",
        "--out",
        s(&p("m")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = tooltouch(&[
        "cosim",
        "firmware",
        "--stimulus",
        s(&p("m").join("events.ttv")),
        "--config",
        s(&settings),
        "--calibration",
        s(&p("cal.json")),
        "--trace",
        s(&p("fw.ttv")),
    ]);
    let out = text(&o);
    assert_eq!(o.status.code(), Some(0), "{out}");

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(p("m").join("summary.json")).unwrap())
            .unwrap();
    let entry = &summary["calibration"]["entry"];
    let counts = entry["offset_counts"].as_i64().unwrap();
    let res = entry["scale_resolution_um"].as_f64().unwrap();
    assert_ne!(counts, 0, "a calibration that corrects something: {entry}");
    assert!(
        out.contains(&format!("decisions reported corrected by {counts} counts")),
        "{out}"
    );
    let home = summary["home_count"].as_i64().unwrap();
    let host: Vec<f64> = summary["calibration"]["diameter_mm"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|d| d.as_f64())
        .collect();
    let raw: Vec<i64> = summary["measurements"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|m| m["decision_position"].as_i64())
        .collect();
    let streams = cosim::trace::parse(&std::fs::read(p("fw.ttv")).unwrap()).unwrap();
    let decisions = &streams[0].decisions;
    assert_eq!(
        decisions.len(),
        raw.len(),
        "one report per decided measurement"
    );
    assert_eq!(host.len(), raw.len());
    let bits = 24; // the default configuration's scale_bits
    for ((d, &raw), &host) in decisions.iter().zip(&raw).zip(&host) {
        let (_, d) = d;
        assert_eq!(i64::from(d.offset), counts);
        let position =
            tooltouch_plant::measurement_cycle::unwrap_position(d.position, bits, raw - counts);
        assert_eq!(position, raw - counts, "the raw position minus the offset");
        let firmware = 2.0 * (home as f64 + position as f64 + 0.5) * res / 1000.0;
        let difference_um = (firmware - host) * 1000.0;
        eprintln!(
            "host {host:.5} mm, firmware {firmware:.5} mm: {difference_um:+.4} µm \
             (offset {} µm, {counts} counts)",
            entry["offset_um"]
        );
        assert!(
            difference_um.abs() <= res + 1e-9,
            "within the scale's resolution ({res} µm on the diameter): {difference_um} µm"
        );
    }
}
