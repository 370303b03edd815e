//! The G-code measuring cycle on LinuxCNC's simulated lathe, headless: the task layer
//! (`milltask`, `io`, motion) under a copy of the installed `sim/axis/lathe.ini` with the
//! component's HAL (`examples/linuxcnc/tt_measure.hal`), a display that runs
//! `examples/linuxcnc/measure.ngc` through the `linuxcnc` Python module
//! (`examples/linuxcnc/tt_display.py`), and `linuxcnc` under `script` (it wants a terminal).
//! The cycle touches a master and a part with G38.2 on the component's decision, reads the
//! latched positions, computes the diameter and the offset correction, and logs them.

use crate::common::text;
use crate::hal::{as_hal_user, require, root, work_dir, write_config, HAL_USER};
use std::collections::HashMap;
use tooltouch_settings::firmware_config::FirmwareConfig;

/// The installed sample configuration the machine is derived from.
const SAMPLE: &str = "/usr/share/doc/linuxcnc/examples/sample-configs/sim";

/// Master and part: diameters, mm (the part's nominal, and its true turned size).
const MASTER_D: f64 = 40.000;
const NOMINAL_D: f64 = 40.020;
const PART_D: f64 = 40.0246;

#[test]
fn linuxcnc_the_gcode_measuring_cycle_runs_headless_on_the_simulated_lathe() {
    require("linuxcnc");
    require("script");
    let dir = work_dir();
    let d = dir.path();
    let settings = d.join("settings.toml");
    std::fs::write(&settings, crate::bit_for_bit::SETTINGS).unwrap();
    let config_file = d.join("config.ttc");
    write_config(&settings, &config_file);
    let hash = FirmwareConfig::load(Some(&settings))
        .unwrap()
        .measure
        .hash();
    let ini = std::fs::read_to_string(format!("{SAMPLE}/axis/lathe.ini"))
        .unwrap_or_else(|e| panic!("{SAMPLE}/axis/lathe.ini ({e}): run `cargo xtask setup`"));
    let mut out = String::new();
    for line in ini.lines() {
        let key = line.trim_start();
        if ["PYVCP", "POSTGUI_HALFILE", "HALUI", "INTRO_"]
            .iter()
            .any(|k| key.starts_with(k))
        {
            continue;
        }
        if key.starts_with("DISPLAY =") {
            out.push_str(&format!(
                "DISPLAY = {}\nOPEN_FILE = {}\n",
                d.join("tt_display.py").display(),
                d.join("measure.ngc").display()
            ));
        } else if key.starts_with("HALFILE = LIB:basic_sim.tcl") {
            out.push_str("HALFILE = LIB:basic_sim.tcl -no_use_hal_manualtoolchange\nHALFILE = tt_measure.hal\n");
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    std::fs::write(d.join("lathe.ini"), out).unwrap();
    std::fs::copy(format!("{SAMPLE}/lathe.tbl"), d.join("lathe.tbl")).unwrap();
    let examples = root().join("examples/linuxcnc");
    let fill = |name: &str, pairs: &[(&str, String)]| {
        let mut t = std::fs::read_to_string(examples.join(name)).unwrap();
        for (k, v) in pairs {
            t = t.replace(k, v);
        }
        std::fs::write(d.join(name), t).unwrap();
    };
    let inch = |mm: f64| format!("{:.9}", mm / 25.4);
    fill(
        "tt_measure.hal",
        &[
            ("@CONFIG@", config_file.display().to_string()),
            ("@MEASURE_HASH@", format!("{hash:016x}")),
            ("@MASTER_R@", inch(MASTER_D / 2.0)),
            ("@PART_R@", inch(PART_D / 2.0)),
        ],
    );
    fill(
        "measure.ngc",
        &[
            ("@MASTER_D@", format!("{MASTER_D:.4}")),
            ("@NOMINAL_D@", format!("{NOMINAL_D:.4}")),
            ("@LOG@", d.join("gcode.log").display().to_string()),
        ],
    );
    fill("tt_display.py", &[]);
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(
        d.join("tt_display.py"),
        std::fs::Permissions::from_mode(0o755),
    )
    .unwrap();
    // A stale lock from a run that was killed makes `linuxcnc` ask on the terminal.
    let _ = std::fs::remove_file("/tmp/linuxcnc.lock");
    let o = as_hal_user(
        d,
        &format!(
            "script -qec 'linuxcnc {}' /dev/null",
            d.join("lathe.ini").display()
        ),
    );
    let console = text(&o);
    let log = std::fs::read_to_string(d.join("gcode.log")).unwrap_or_default();
    println!("{log}");
    assert!(
        console.contains("tt_display: program")
            && console.contains("finished")
            && !console.contains("did NOT finish"),
        "the program did not finish ({HAL_USER}'s linuxcnc_debug.txt says more):\n{console}"
    );
    assert!(!console.contains("LinuxCNC error"), "{console}");
    let v: HashMap<&str, f64> = log
        .split_whitespace()
        .filter_map(|w| w.split_once('='))
        .filter_map(|(k, x)| Some((k, x.trim_end_matches(')').parse().ok()?)))
        .collect();
    let get = |k: &str| {
        *v.get(k)
            .unwrap_or_else(|| panic!("{k} is not in the G-code's log: {log}"))
    };
    // The diameter from two latched positions. Each touch decides 512 FES pulses in contact
    // into a revolution window (20 ms at 3000 rpm): 10 to 20 ms after the contact, by where
    // the contact begins in the window, 0.8 to 1.7 µm of feed at 5 mm/min, and each
    // position is a 0.5 µm count: the two touches' depths differ by at most 1.7 + 0.5 µm,
    // twice that on the diameter, 4.4 µm.
    let diameter = get("diameter");
    assert!(
        (diameter - PART_D).abs() <= 0.0045,
        "measured {diameter}, true {PART_D}"
    );
    assert!(
        (diameter - (MASTER_D + 2.0 * (get("part_latched") - get("master_latched")))).abs() < 1e-9
    );
    // G38.2 stopped on the component's decision: the probe's trip position is the latched
    // position within a scale count and the feed of a few servo periods (5 mm/min).
    for touch in ["master", "part"] {
        let gap = (get(&format!("{touch}_probe")) - get(&format!("{touch}_latched"))).abs();
        assert!(
            gap < 0.001,
            "{touch}: probe trip and latched position {gap} mm apart"
        );
    }
    // The correction: 70 % of the radial error outside the 2 µm dead zone.
    let err = diameter - NOMINAL_D;
    let want = if err.abs() > 0.002 {
        -0.7 * err / 2.0
    } else {
        0.0
    };
    assert!(
        (get("offset") - want).abs() < 1e-6,
        "offset {} want {want}",
        get("offset")
    );
}
