//! The measure-then-correct size loop with its measurements made in HAL: every touch of the
//! loop (master, part, for each of the N parts) streamed through the component under
//! `halrun`, the whole trace checked bit for bit, and the loop's table recomputed from the
//! positions the component latched: equal to the golden table, so HAL would have corrected
//! the tool offset exactly as the model did. The table (`size_loop.txt`, `size_loop.csv`)
//! and the plot (`size_loop.svg`) go to `target/tmp/linuxcnc/`. Then the safe loop over 200
//! parts with faulted touches, measured in HAL the same way: re-measures, alarms and stops
//! where the model made them, and no part out of tolerance.

use crate::common::{s, text, tooltouch};
use crate::hal::{halrun, stream_hal_file, work_dir, write_config};
use std::path::PathBuf;
use tooltouch_linuxcnc::files::{
    dut_outputs, golden_outputs, header, outputs_stream, streamer_text,
};
use tooltouch_linuxcnc::size_loop::{
    alarms, counts, golden_readings, reading, replay_with, run, servo_pulse_tolerance, table,
    Alarm, ForcedFault, LoopRules, Role, SizeLoopReport, SizeLoopSettings, TouchFault,
    TouchFaultRates,
};
use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::MeasureConfig;
use tooltouch_settings::firmware_config::FirmwareConfig;
use tooltouch_vectors::output::write_file;

/// The bit-for-bit run's settings with the revolution check's tolerance for the servo rate:
/// at 3000 rpm a 1 ms period holds 51.2 FES pulses of 1024 per revolution
/// ([`servo_pulse_tolerance`]).
const SETTINGS: &str = "[measure]\nmethod = \"counter\"\n[measure.checks]\npulse_tolerance = 64\n\
                        [force]\ncontroller = \"pi\"\nkp_percent = 80\n";

/// Runs `loop_settings` in the model, streams all its touches through the component under
/// `halrun` (servo thread of `period_ns`), checks the trace bit for bit and returns the golden
/// report with HAL's readings of the touches.
fn loop_in_hal(
    loop_settings: &SizeLoopSettings,
    period_ns: u32,
) -> (
    SizeLoopReport,
    Vec<Result<f64, Alarm>>,
    (MeasureConfig, ForceConfig),
) {
    let dir = work_dir();
    let settings = dir.path().join("settings.toml");
    std::fs::write(&settings, SETTINGS).unwrap();
    let config_file = dir.path().join("config.ttc");
    write_config(&settings, &config_file);
    let config = FirmwareConfig::load(Some(&settings)).expect("the settings load");
    let (measure, force) = (config.measure, config.force);
    assert!(
        measure.settings().checks.pulse_tolerance
            >= servo_pulse_tolerance(
                measure.settings().pulses_per_rev,
                loop_settings.rpm,
                f64::from(force.settings().sample_hz)
            )
    );
    let golden = run(loop_settings, &measure, &force);
    let rows = &golden.stream;
    std::fs::write(dir.path().join("stim.txt"), streamer_text(rows)).unwrap();
    let hal = stream_hal_file(
        dir.path(),
        &config_file,
        (measure.hash(), force.hash()),
        rows.len(),
        period_ns,
    );
    let o = halrun(dir.path(), &hal);
    assert!(o.status.success(), "halrun failed:\n{}", text(&o));
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap_or_default();
    let (dut, _) = dut_outputs(
        (&read("measure.txt"), "measure.txt"),
        (&read("force.txt"), "force.txt"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    // The whole trace, bit for bit.
    let h = header(&measure, &force);
    let golden_file = dir.path().join("golden.ttv");
    let dut_file = dir.path().join("hal.ttv");
    std::fs::write(
        &golden_file,
        outputs_stream(h, &golden_outputs(&measure, &force, rows)),
    )
    .unwrap();
    std::fs::write(&dut_file, outputs_stream(h, &dut)).unwrap();
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&golden_file),
        "--dut",
        s(&dut_file),
    ]);
    let verdict = text(&o);
    assert!(o.status.success(), "{verdict}");
    println!("{verdict}");
    // HAL's readings: its latched positions, confirmed and fault pins at each read period.
    let readings = golden
        .touches
        .iter()
        .map(|t| {
            let m = dut.get(t.read_at).map(|d| d.0).unwrap_or_default();
            reading(&m, loop_settings.scale_um)
        })
        .collect();
    // The model's own readings agree (the loop was closed on them).
    assert_eq!(
        golden_readings(loop_settings, &golden, &measure, &force),
        readings
    );
    (golden, readings, (measure, force))
}

#[test]
fn linuxcnc_the_size_loop_measured_in_hal_corrects_as_the_model_does() {
    let loop_settings = SizeLoopSettings::default();
    let (golden, readings, _) = loop_in_hal(&loop_settings, 1_000_000);
    assert_eq!(alarms(&golden), [], "a clean machine alarms");
    let from_hal = replay_with(&loop_settings, &golden, &readings);
    assert_eq!(from_hal, golden.rows);
    let lines = table(&loop_settings, &golden);
    for line in &lines {
        println!("{line}");
    }
    // What the loop is for: every corrected part in tolerance, the uncorrected drifting out.
    assert_eq!(golden.corrected.in_tolerance, loop_settings.parts);
    assert!(golden.uncorrected.in_tolerance < loop_settings.parts / 2);
    assert!(golden.corrected.cpk > 1.0 && golden.uncorrected.cpk < 0.0);

    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("linuxcnc");
    std::fs::create_dir_all(&out).unwrap();
    write_file(
        &out.join("size_loop.txt"),
        (lines.join("\n") + "\n").as_bytes(),
    )
    .unwrap();
    let mut csv = csv::Writer::from_writer(Vec::new());
    for r in &golden.rows {
        csv.serialize(r).unwrap();
    }
    write_file(&out.join("size_loop.csv"), &csv.into_inner().unwrap()).unwrap();
    let col = |f: fn(&tooltouch_linuxcnc::size_loop::PartRow) -> f64| {
        golden.rows.iter().map(f).collect::<Vec<_>>()
    };
    tooltouch_plot::size_loop::size_loop(
        &out.join("size_loop.svg"),
        loop_settings.nominal_mm,
        loop_settings.tolerance_mm,
        &col(|r| r.uncorrected_mm),
        &col(|r| r.corrected_mm),
        &col(|r| r.measured_mm),
    )
    .unwrap();
    println!("table and plot in {}", out.display());
}

/// The goal in HAL: 200 parts with faulted touches (the campaign's rates, and part
/// 10's touch bridged twice), the safe rules. HAL's readings replay to the golden rows —
/// the same re-measures, alarms and stops — and no part is out of tolerance; today's loop
/// and the uncorrected parts over the same parts beside it. The thread runs at 100 µs:
/// the component's clock is its calls, the streamer holds the whole stream.
#[test]
fn linuxcnc_the_safe_size_loop_with_faulted_touches_in_hal() {
    let safe = SizeLoopSettings {
        parts: 200,
        faults: TouchFaultRates::CAMPAIGN,
        forced: Some(ForcedFault {
            part: 10,
            role: Role::Part,
            attempts: 2,
            fault: TouchFault::CoolantBridge,
        }),
        rules: LoopRules::SAFE,
        ..SizeLoopSettings::default()
    };
    let (golden, readings, (measure, force)) = loop_in_hal(&safe, 100_000);
    let from_hal = replay_with(&safe, &golden, &readings);
    // Debug text: NaN (no reading) compares equal there.
    assert_eq!(format!("{from_hal:?}"), format!("{:?}", golden.rows));
    let c = counts(&golden, &readings);
    let today_settings = SizeLoopSettings {
        rules: LoopRules::TODAY,
        ..safe
    };
    let today = run(&today_settings, &measure, &force);
    let t = counts(
        &today,
        &golden_readings(&today_settings, &today, &measure, &force),
    );
    println!("safe loop (HAL): {c:?}\ntoday's loop:    {t:?}");
    assert!(golden.rows[9].stopped, "{:?}", golden.rows[9]);
    assert!(
        c.faulted_touches >= 20 && c.unflagged_faulted_touches >= 5,
        "{c:?}"
    );
    assert!(c.remeasures >= 10 && c.stops >= 1, "{c:?}");
    assert_eq!(c.out_of_tolerance, 0, "{c:?}");
    assert!(c.uncorrected_out_of_tolerance > 150, "{c:?}");
    assert_eq!(t.remeasures, 0);
    assert!(t.alarms > c.stops, "{t:?}");
}
