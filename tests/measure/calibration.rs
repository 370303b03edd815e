//! Calibration on a reference part (`tooltouch_metrology::calibration`, docs/accuracy.md;
//! the papers' S1–S3): the offsets it stores, the residual bias it leaves, the files it
//! refuses, and `calibrate` / `measure --calibration` as a user runs them.
//!
//! Bounds: an as-cut reference (the workpiece's own form and roughness) at the calibrated
//! conditions leaves no bias beyond the sampling error, 3 standard errors of the two
//! simulations plus 0.10 µm (half a count of the scale on the diameter: the two runs draw
//! their roughness at other Z positions). A round reference leaves the form-dependent part
//! of the counter's bias (the S9 share level and the lag on the workpiece's form); the
//! budget cannot predict the round reference itself (a round surface is crossed within one
//! window: the fast-feed regime it refuses, asserted here), so the test holds the sign and
//! size: the residual is below −0.5 µm (the workpiece's S9 share-level term alone is
//! −0.55 µm) by more than 3 standard errors.

use tooltouch_metrology::budget::{predict, Outcome};
use tooltouch_metrology::calibration::{
    calibrate, calibrated_variants, reference_scenario, residuals, CalibrationError, ReferencePart,
};
use tooltouch_metrology::simulate::config_of;
use tooltouch_model::measure::config::DecisionMethod;
use tooltouch_model::MeasureSettings;
use tooltouch_plant::lathe::LatheScenario;
use tooltouch_settings::Settings;

const REPEATS: u32 = 60;

fn reference(as_cut: bool) -> ReferencePart {
    ReferencePart {
        diameter_mm: 40.0,
        roughness_um: 0.05,
        as_cut,
    }
}

#[test]
fn an_as_cut_reference_removes_the_bias_at_the_calibrated_conditions() {
    let (_, machine) = Settings::default().resolve().unwrap();
    let measure = MeasureSettings::default();
    let cal = calibrate(&measure, &machine, &reference(true), REPEATS).unwrap();
    for r in residuals(&measure, &machine, &cal, REPEATS, &[], &[]).unwrap() {
        assert!(
            r.residual_um.abs() <= 3.0 * r.standard_error_um + 0.10,
            "{}: raw {:+.2} µm, offset {:+.2}, residual {:+.2} ± {:.2}",
            r.variant,
            r.raw_bias_um,
            r.offset_um,
            r.residual_um,
            r.standard_error_um
        );
    }
}

#[test]
fn a_round_reference_leaves_the_form_part_of_the_bias() {
    // Without the spindle path's loads, so that the form is all that differs between the
    // reference and the workpiece (the path's orbit lies on both).
    let (_, mut machine) = Settings::default().resolve().unwrap();
    machine.spindle_path = tooltouch_plant::lathe::SpindlePath::none();
    let measure = MeasureSettings::default();
    let round = reference(false);
    let cal = calibrate(&measure, &machine, &round, REPEATS).unwrap();
    let rows = residuals(&measure, &machine, &cal, REPEATS, &[], &[]).unwrap();
    let on_reference = reference_scenario(&machine, &round);
    for (variant, r) in calibrated_variants().zip(&rows) {
        if variant.method != DecisionMethod::Counter {
            continue;
        }
        let config = config_of(&measure, variant).unwrap();
        assert!(
            matches!(
                predict(&config, &on_reference, variant),
                Outcome::Refused { .. }
            ),
            "{}: the budget predicts the round reference",
            variant.name()
        );
        let Outcome::Predicted(p) = predict(&config, &machine, variant) else {
            panic!("{}: the workpiece refused", variant.name());
        };
        let share = p.terms.iter().find(|t| t.formula == "S9").unwrap().value_um;
        assert!(share < -0.5, "{}: S9 {share:+.2} µm", variant.name());
        assert!(
            r.residual_um < -0.5 - 3.0 * r.standard_error_um,
            "{}: residual {:+.2} ± {:.2} µm after a round reference",
            variant.name(),
            r.residual_um,
            r.standard_error_um
        );
    }
}

#[test]
fn a_file_from_another_configuration_feed_or_speed_is_refused() {
    let (config, machine) = Settings::default().resolve().unwrap();
    let measure = MeasureSettings::default();
    let cal = calibrate(&measure, &machine, &reference(false), 4).unwrap();
    assert!(cal
        .entry_for(&config, machine.feed_mm_per_rev, machine.rpm)
        .is_ok());
    let other = MeasureSettings {
        i_def: 600,
        ..measure
    }
    .validate()
    .unwrap();
    assert!(matches!(
        cal.entry_for(&other, machine.feed_mm_per_rev, machine.rpm),
        Err(CalibrationError::OtherConfiguration { .. })
    ));
    assert!(matches!(
        cal.entry_for(&config, 0.002, machine.rpm),
        Err(CalibrationError::OtherFeed { .. })
    ));
    assert!(matches!(
        cal.entry_for(&config, machine.feed_mm_per_rev, machine.rpm + 200.0),
        Err(CalibrationError::OtherSpeed { .. })
    ));
    let density = MeasureSettings {
        method: DecisionMethod::Density,
        ..measure
    }
    .validate()
    .unwrap();
    assert!(matches!(
        cal.entry_for(&density, machine.feed_mm_per_rev, machine.rpm),
        Err(CalibrationError::NoEntry { .. })
    ));
    // What moves the path and the count: another scale, a lighter pass, no loads.
    assert!(cal.entry_for_machine(&config, &machine).is_ok());
    let other_scale = LatheScenario {
        scale_resolution_um: 0.5,
        ..machine.clone()
    };
    assert!(matches!(
        cal.entry_for_machine(&config, &other_scale),
        Err(CalibrationError::OtherResolution { .. })
    ));
    let mut lighter = machine.clone();
    lighter.spindle_path.cutting_force_n = 10.0;
    let e = cal.entry_for_machine(&config, &lighter).unwrap_err();
    assert!(
        matches!(
            e,
            CalibrationError::OtherSpindlePath {
                field: "spindle_path.cutting_force_n",
                ..
            }
        ),
        "{e}"
    );
    // The message states how far the path's offset moves (the budget's path model).
    assert!(
        e.to_string().contains("+2.92 µm in the file's state"),
        "{e}"
    );
    let mut unloaded = machine.clone();
    unloaded.spindle_path.loads = false;
    assert!(matches!(
        cal.entry_for_machine(&config, &unloaded),
        Err(CalibrationError::OtherSpindlePath {
            field: "spindle_path.loads",
            ..
        })
    ));
    let mut bad = cal.clone();
    bad.format = "something else".into();
    assert!(matches!(
        bad.entry_for(&config, machine.feed_mm_per_rev, machine.rpm),
        Err(CalibrationError::Format(_))
    ));
    let bad_reference = ReferencePart {
        diameter_mm: f64::NAN,
        ..reference(false)
    };
    assert!(calibrate(&measure, &machine, &bad_reference, 4).is_err());
}

#[test]
fn calibrate_then_measure_with_the_file_and_refuse_another_configuration() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cal.json");
    let bin = env!("CARGO_BIN_EXE_tooltouch");
    let o = std::process::Command::new(bin)
        .args([
            "calibrate",
            "--reference-mm",
            "40",
            "--repeats",
            "10",
            "--out",
        ])
        .arg(&file)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("tooltouch-calibration/3"), "{text}");
    let measure = |extra: &[&str]| {
        std::process::Command::new(bin)
            .args(["measure", "--no-progress", "--vcd", "none", "--out"])
            .arg(dir.path().join("out"))
            .arg("--calibration")
            .arg(&file)
            .args(extra)
            .output()
            .unwrap()
    };
    let o = measure(&[]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("calibrated (offset"), "{stdout}");
    let summary = std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap();
    assert!(summary.contains("\"calibration\""), "{summary}");
    let o = measure(&["--i-def", "600"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("another configuration"), "{stderr}");
    let o = measure(&["--rpm", "1000"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("made at 800 rpm, this run measures at 1000 rpm"),
        "{stderr}"
    );
}

/// The firmware applies the offset in whole scale counts to the latched position
/// (model::measure::calibration); the host subtracts the µm offset from the diameter. On the
/// default workpiece the two calibrated diameters differ by the rounding of the offset to a
/// count only: at most half a count on the radius, the scale's resolution on the diameter.
#[test]
fn the_firmwares_corrected_position_gives_the_hosts_calibrated_diameter() {
    use tooltouch_metrology::calibration::{corrected_mm, firmware_corrected_mm};
    use tooltouch_model::measure::calibration::corrected_position;
    use tooltouch_plant::lathe::{CycleSettings, LatheScenario};
    use tooltouch_plant::measurement_cycle::{self, unwrap_position};

    let (config, machine) = Settings::default().resolve().unwrap();
    let measure = MeasureSettings::default();
    let cal = calibrate(&measure, &machine, &reference(true), 10).unwrap();
    let (feed, rpm) = (machine.feed_mm_per_rev, machine.rpm);
    let entry = cal.entry_for(&config, feed, rpm).unwrap().clone();
    let record = cal.firmware_record(&config, feed, rpm).unwrap();
    let res = machine.scale_resolution_um;
    assert_eq!(record.offset_counts, entry.offset_counts);
    assert_eq!(
        f64::from(entry.offset_counts),
        (entry.offset_um / (2.0 * res)).round(),
        "{entry:?}"
    );
    assert_ne!(
        record.offset_counts, 0,
        "a calibration that corrects something"
    );
    let workpiece = LatheScenario {
        cycle: CycleSettings {
            repeats: 12,
            ..machine.cycle
        },
        ..machine.clone()
    };
    let run = measurement_cycle::run(&workpiece, &config, &mut |_| {}).unwrap();
    let bits = config.settings().scale_bits;
    let mut worst: f64 = 0.0;
    let mut decided = 0;
    for m in &run.measurements {
        let (Some(p), Some(d)) = (m.decision_position, m.diameter_mm) else {
            continue;
        };
        decided += 1;
        // The register the FPGA latched: the position's low `scale_bits` bits.
        let latched = corrected_position(p as i32, 0, bits);
        let reported = corrected_position(latched, record.offset_counts, bits);
        let position = unwrap_position(reported, bits, p - i64::from(record.offset_counts));
        assert_eq!(position, p - i64::from(record.offset_counts));
        let firmware = 2.0 * (run.home_count as f64 + position as f64 + 0.5) * res / 1000.0;
        assert!((firmware - firmware_corrected_mm(d, &entry)).abs() < 1e-9);
        let difference = (firmware - corrected_mm(d, &entry)) * 1000.0;
        assert!(
            difference.abs() <= res + 1e-9,
            "{difference} µm, more than the {res} µm resolution"
        );
        worst = worst.max(difference.abs());
    }
    assert!(decided >= 10, "{decided} decided");
    eprintln!(
        "offset {:+.3} µm = {} counts: firmware vs host calibrated diameter within {worst:.4} µm",
        entry.offset_um, entry.offset_counts
    );
}
