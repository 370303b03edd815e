//! The component under `halrun`, bit for bit: the golden stimulus through LinuxCNC's
//! `streamer`, every output through two `sampler`s, and `tooltouch check` on the two Outputs
//! streams: 17 measurement fields (the status, `confirmed` and `faults`, among them; the
//! alarm pin `fault` checked against `faults`) and 15 force fields in every servo period.

use crate::common::{s, text, tooltouch};
use crate::hal::{halrun, stream_hal_file, work_dir, write_config};
use tooltouch_linuxcnc::files::{
    dut_outputs, golden_outputs, header, outputs_stream, streamer_text,
};
use tooltouch_linuxcnc::stimulus::golden_stimulus;
use tooltouch_settings::firmware_config::FirmwareConfig;

/// The settings of the run: 1024 ppr, the counter method, a PI force controller.
pub const SETTINGS: &str =
    "[measure]\nmethod = \"counter\"\n[force]\ncontroller = \"pi\"\nkp_percent = 80\n";

/// Servo periods streamed (1 ms each: 4 s, 80 control ticks, 10 measurement cycles).
const PERIODS: u32 = 4000;

#[test]
fn linuxcnc_the_component_in_halrun_matches_the_golden_model_every_field_every_period() {
    let dir = work_dir();
    let settings = dir.path().join("settings.toml");
    std::fs::write(&settings, SETTINGS).unwrap();
    let config_file = dir.path().join("config.ttc");
    write_config(&settings, &config_file);
    let config = FirmwareConfig::load(Some(&settings)).expect("the settings load");
    let (measure, force) = (config.measure, config.force);
    let rows = golden_stimulus(&measure, &force, PERIODS, 31);
    std::fs::write(dir.path().join("stim.txt"), streamer_text(&rows)).unwrap();
    let hal = stream_hal_file(
        dir.path(),
        &config_file,
        (measure.hash(), force.hash()),
        rows.len(),
        1_000_000,
    );
    let o = halrun(dir.path(), &hal);
    let log = text(&o);
    assert!(o.status.success(), "halrun failed:\n{log}");
    println!("{log}");
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap_or_default();
    let (dut, overruns) = dut_outputs(
        (&read("measure.txt"), "measure.txt"),
        (&read("force.txt"), "force.txt"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let golden = golden_outputs(&measure, &force, &rows);
    let h = header(&measure, &force);
    let golden_file = dir.path().join("golden.ttv");
    let dut_file = dir.path().join("hal.ttv");
    std::fs::write(&golden_file, outputs_stream(h, &golden)).unwrap();
    std::fs::write(&dut_file, outputs_stream(h, &dut)).unwrap();
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&golden_file),
        "--dut",
        s(&dut_file),
    ]);
    let verdict = text(&o);
    println!("{verdict}");
    println!(
        "periods {}, overruns (late thread wakeups, POSIX non-realtime) {}",
        dut.len(),
        overruns.last().copied().unwrap_or(0)
    );
    assert!(o.status.success(), "{verdict}");
    assert!(
        verdict.starts_with(&format!(
            "OK: {PERIODS} records × 17 fields and {PERIODS} force records × "
        )),
        "{verdict}"
    );
    // Every field of every period, the status among them, compared here too (the check's
    // verdict names the fields it compares).
    assert_eq!(dut.len(), golden.len());
    for (k, (d, g)) in dut.iter().zip(&golden).enumerate() {
        assert_eq!(d.0, g.0, "period {k}: the measurement outputs differ");
    }
    // The stream exercised what it should: decisions, force control, a wear alarm cleared.
    let decisions = golden
        .windows(2)
        .filter(|w| w[1].0.register_now && !w[0].0.register_now)
        .count();
    assert!(decisions >= 8, "{decisions} decisions");
    // The status pins moved: confirmed decisions, and faults (the default revolution
    // tolerance is tighter than a period's FES pulses at these speeds).
    assert!(golden.iter().any(|g| g.0.confirmed));
    assert!(golden.iter().any(|g| g.0.faults != 0));
    assert!(golden
        .iter()
        .any(|g| g.1.control_enabled && g.1.override_pct != golden[0].1.override_pct));

    // The check's verdicts on this HAL trace made wrong: one field, one period short.
    let mut wrong = dut.clone();
    let k = 2500;
    wrong[k].0.pulses ^= 1;
    std::fs::write(&dut_file, outputs_stream(h, &wrong)).unwrap();
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&golden_file),
        "--dut",
        s(&dut_file),
    ]);
    let m = text(&o);
    assert!(!o.status.success());
    let want = format!(
        "record {k} (time {k}): field pulses expected 0x{:x} got 0x{:x}",
        golden[k].0.pulses,
        golden[k].0.pulses ^ 1
    );
    assert!(m.contains(&want), "{m}");
    println!("{m}");
    std::fs::write(&dut_file, outputs_stream(h, &dut[..dut.len() - 1])).unwrap();
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&golden_file),
        "--dut",
        s(&dut_file),
    ]);
    let m = text(&o);
    assert!(!o.status.success());
    assert!(
        m.contains(&format!(
            "ends after {} measurement-outputs records",
            PERIODS - 1
        )),
        "{m}"
    );
    println!("{m}");
}
