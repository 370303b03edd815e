//! `tooltouch control` and `tooltouch wear` write their terminal table's metrics and their
//! plots' time series as CSV and JSON (docs/control.md, docs/wear.md): the same rows in
//! both, the columns named in the header, a row per run and per sample, and the values
//! the terminal table prints.

use crate::common;

use common::{s, text, tooltouch};
use std::path::Path;

/// The header and rows of a CSV file (no quoted commas in these tables).
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let t = std::fs::read_to_string(path).unwrap();
    let mut lines = t.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

fn json(path: &Path) -> Vec<serde_json::Value> {
    serde_json::from_str::<Vec<serde_json::Value>>(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Every CSV cell equals its JSON field (numbers compared as numbers, empty as null).
fn assert_same_rows(stem: &Path) {
    let (header, rows) = csv(&stem.with_extension("csv"));
    let objects = json(&stem.with_extension("json"));
    assert_eq!(rows.len(), objects.len(), "{}", stem.display());
    for (row, object) in rows.iter().zip(&objects) {
        for (name, cell) in header.iter().zip(row) {
            let v = &object[name.as_str()];
            match v {
                serde_json::Value::Null => {
                    assert!(cell.is_empty() || cell == "inf", "{name}: {cell}")
                }
                serde_json::Value::Number(n) => {
                    assert_eq!(n.as_f64().unwrap(), cell.parse::<f64>().unwrap(), "{name}")
                }
                serde_json::Value::String(t) => assert_eq!(t, cell, "{name}"),
                serde_json::Value::Bool(b) => assert_eq!(b.to_string(), *cell, "{name}"),
                other => panic!("{name}: {other}"),
            }
        }
    }
}

#[test]
fn control_writes_its_metrics_and_series_as_csv_and_json() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("c");
    let o = tooltouch(&[
        "control",
        "--controller",
        "all",
        "--force",
        "both",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let printed = String::from_utf8_lossy(&o.stdout).into_owned();
    let (header, rows) = csv(&out.join("control.csv"));
    assert_eq!(
        header,
        [
            "controller",
            "force",
            "engine",
            "seed",
            "overshoot_pct",
            "settling_s",
            "steady_error_n",
            "iae_ns",
            "override_min_pct",
            "override_max_pct"
        ]
    );
    assert_eq!(rows.len(), 6, "three controllers × two force sources");
    for r in &rows {
        // The terminal row of the same run prints the same figures, rounded.
        let overshoot: f64 = r[4].parse().unwrap();
        let iae: f64 = r[7].parse().unwrap();
        let line = printed
            .lines()
            .find(|l| {
                l.split_whitespace()
                    .take(2)
                    .eq([r[0].as_str(), r[1].as_str()])
            })
            .unwrap_or_else(|| panic!("no terminal row for {r:?} in {printed}"));
        assert!(
            line.contains(&format!("{overshoot:.1}%")) && line.contains(&format!("{iae:.1}Ns")),
            "{line} vs {r:?}"
        );
        assert!(
            line.contains(&format!("{}-{}", r[8], r[9])),
            "{line} vs {r:?}"
        );
        let series = out.join(format!("{}_{}", r[0], r[1]));
        assert_same_rows(&series);
        let (h, samples) = csv(&series.with_extension("csv"));
        assert_eq!(
            h,
            [
                "t_s",
                "reference_n",
                "force_true_n",
                "force_estimated_n",
                "force_measured_n",
                "override_pct"
            ]
        );
        assert!(samples.len() > 100, "{} samples", samples.len());
        let t: Vec<f64> = samples.iter().map(|s| s[0].parse().unwrap()).collect();
        assert!(t.windows(2).all(|w| w[1] > w[0]), "time increases");
    }
    assert_same_rows(&out.join("control"));
}

#[test]
fn wear_writes_its_verdicts_and_series_as_csv_and_json() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("w");
    let o = tooltouch(&["wear", "--out", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let printed = String::from_utf8_lossy(&o.stdout).into_owned();
    let (header, rows) = csv(&out.join("wear.csv"));
    assert_eq!(
        header,
        [
            "tool",
            "threshold",
            "alarm_at_s",
            "alarm_power_w",
            "alarm_cut",
            "verdict"
        ]
    );
    assert_eq!(rows.len(), 4, "two tools × two thresholds");
    for r in &rows {
        let line = printed
            .lines()
            .find(|l| {
                l.split_whitespace()
                    .take(2)
                    .eq([r[0].as_str(), r[1].as_str()])
            })
            .unwrap();
        let printed_verdict = match r[5].as_str() {
            "false-alarm" => "FALSE ALARM",
            "missed" => "MISSED",
            v => v,
        };
        assert!(line.ends_with(printed_verdict), "{line} vs {r:?}");
        if r[2].is_empty() {
            assert!(line.contains("none") && r[3].is_empty() && r[4].is_empty());
        } else {
            let t: f64 = r[2].parse().unwrap();
            assert!(line.contains(&format!("{t:.2} s")), "{line} vs {r:?}");
            let p: f64 = r[3].parse().unwrap();
            assert!(p > 0.0);
        }
    }
    assert_same_rows(&out.join("wear"));
    for tool in ["new", "worn"] {
        let stem = out.join(format!("wear_{tool}"));
        assert_same_rows(&stem);
        let (h, samples) = csv(&stem.with_extension("csv"));
        assert_eq!(
            h[..4],
            [
                "t_s",
                "motor_power_w",
                "monitored_power_w",
                "constant_threshold_w"
            ]
        );
        assert!(samples.len() > 100);
    }
}

#[test]
fn wear_settings_that_are_bad_exit_2_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("[wear]\nteeth = 0\n", "teeth"),
        ("[wear]\nspeed = 3\n", "speed"),
        (
            "[wear]\ncuts = [{ depth_mm = 2, rpm = 300, feed_per_tooth_mm = 0.2, seconds = -1 }]\n",
            "cuts[0].seconds",
        ),
        (
            "[wear]\nidle_power = [{ rpm = 300, watts = 300 }]\ncuts = [{ depth_mm = 2, rpm = 500, feed_per_tooth_mm = 0.2, seconds = 5 }]\n",
            "idle_power",
        ),
    ];
    for (i, (file, key)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("bad{i}.toml"));
        std::fs::write(&path, file).unwrap();
        let o = tooltouch(&["wear", "--config", s(&path)]);
        assert_eq!(o.status.code(), Some(2), "{file}: {}", text(&o));
        assert!(text(&o).contains(key), "{file}: {}", text(&o));
    }
    // Nine distinct conditions: one more than the firmware holds.
    let cuts: Vec<String> = (1..=9)
        .map(|d| format!("{{ depth_mm = {d}, rpm = 300, feed_per_tooth_mm = 0.1, seconds = 1 }}"))
        .collect();
    let path = dir.path().join("nine.toml");
    std::fs::write(&path, format!("[wear]\ncuts = [{}]\n", cuts.join(", "))).unwrap();
    let o = tooltouch(&["wear", "--config", s(&path)]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("at most 8"), "{}", text(&o));
}
