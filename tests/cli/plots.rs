//! Every plot the command line draws, rendered by its subcommand and read back: the SVG's
//! text elements must hold the plot's axis descriptions and one legend entry per series
//! (or a colour scale past ten series), and the legend must sit beside the chart, not on
//! it. The wear plot's alarm markers must be at the alarm's real power (the one
//! `wear.csv` records), not at a fixed height.

use crate::common;

use common::{s, text, tooltouch, FAST_LATHE};
use std::path::Path;

/// A text element of an SVG: its x position and its text.
#[derive(Debug)]
struct SvgText {
    x: f64,
    text: String,
}

/// Every `<text>` element of the SVG file `path`.
fn texts(path: &Path) -> Vec<SvgText> {
    let svg = std::fs::read_to_string(path).unwrap();
    let mut out = Vec::new();
    for chunk in svg.split("<text").skip(1) {
        let (attributes, rest) = chunk.split_once('>').unwrap();
        let body = rest.split("</text>").next().unwrap();
        let x = attributes
            .split("x=\"")
            .nth(1)
            .and_then(|v| v.split('"').next())
            .and_then(|v| v.parse().ok())
            .unwrap_or(f64::NAN);
        let text = body
            .trim()
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&#39;", "'")
            .replace("&apos;", "'")
            .replace("&amp;", "&");
        out.push(SvgText { x, text });
    }
    out
}

/// The SVG's width, pixels.
fn width(path: &Path) -> f64 {
    let svg = std::fs::read_to_string(path).unwrap();
    let w = svg
        .split("width=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    w.parse().unwrap()
}

/// Checks that `path` has every text of `axes` and of `legend`, and that each legend entry
/// lies in the legend panel (the right 280 pixels), right of every axis label.
fn assert_plot(path: &Path, axes: &[&str], legend: &[&str]) {
    let t = texts(path);
    let has = |wanted: &str| t.iter().find(|e| e.text == wanted);
    for a in axes {
        assert!(
            has(a).is_some(),
            "{}: no axis text `{a}` in {t:?}",
            path.display()
        );
    }
    let panel = width(path) - 280.0;
    for l in legend {
        let e =
            has(l).unwrap_or_else(|| panic!("{}: no legend entry `{l}` in {t:?}", path.display()));
        assert!(
            e.x >= panel,
            "{}: legend entry `{l}` at x = {} is over the chart",
            path.display(),
            e.x
        );
    }
}

fn fast_lathe(dir: &Path) -> std::path::PathBuf {
    let p = dir.join("fast.toml");
    std::fs::write(&p, FAST_LATHE).unwrap();
    p
}

#[test]
fn measure_plots_name_every_measurement_and_tick_whole_numbers() {
    let d = tempfile::tempdir().unwrap();
    let config = fast_lathe(d.path());
    for repeats in [4, 12] {
        let out = d.path().join(format!("m{repeats}"));
        let o = tooltouch(&[
            "measure",
            "--config",
            s(&config),
            "--repeats",
            &repeats.to_string(),
            "--retract-at",
            "permanent-contact",
            "--vcd",
            "none",
            "--no-progress",
            "--out",
            s(&out),
        ]);
        assert!(o.status.success(), "{}", text(&o));
        let density = out.join("contact_density.svg");
        let mut legend = vec![
            "decision level i_def / window = 0.500".to_string(),
            "line: model count / window pulses".to_string(),
            "dot: time in contact / revolution".to_string(),
        ];
        if repeats <= 10 {
            legend.extend((1..=repeats).map(|i| format!("measurement {i}")));
        } else {
            legend.push(format!("measurements 1 (left) … {repeats} (right)"));
        }
        let legend: Vec<&str> = legend.iter().map(String::as_str).collect();
        assert_plot(
            &density,
            &["revolution since arm", "contact density"],
            &legend,
        );
        // Revolutions are counted: whole tick labels (`2`, not `2.0`).
        let labels: Vec<String> = texts(&density).into_iter().map(|t| t.text).collect();
        assert!(
            labels.contains(&"2".to_string()) && !labels.contains(&"2.0".to_string()),
            "{labels:?}"
        );
        let diameters = out.join("diameters.svg");
        assert_plot(
            &diameters,
            &["measurement", "diameter − nominal, µm"],
            &[
                "true largest diameter",
                "true mean diameter",
                "first contact",
                "decision (the method's)",
            ],
        );
        let ticks: Vec<String> = texts(&diameters)
            .into_iter()
            .filter(|t| t.text.parse::<u32>().is_ok())
            .map(|t| t.text)
            .collect();
        assert!(ticks.contains(&"1".to_string()), "{ticks:?}");
        assert!(
            !texts(&diameters).iter().any(|t| t.text == "1.0"),
            "measurement ticks are whole"
        );
    }
}

#[test]
fn control_and_wear_plots_name_their_series_and_mark_alarms_where_they_happen() {
    let d = tempfile::tempdir().unwrap();
    let c = d.path().join("c");
    let o = tooltouch(&["control", "--controller", "pi", "--out", s(&c)]);
    assert!(o.status.success(), "{}", text(&o));
    assert_plot(
        &c.join("pi_estimated.svg"),
        &["t, s", "force, N", "override, %"],
        &[
            "force reference 500 N",
            "true force",
            "estimated force",
            "feed override (lower plot)",
            "depth step at 8 s",
        ],
    );
    let w = d.path().join("w");
    let o = tooltouch(&["wear", "--out", s(&w)]);
    assert!(o.status.success(), "{}", text(&o));
    let table = std::fs::read_to_string(w.join("wear.csv")).unwrap();
    for tool in ["new", "worn"] {
        let svg = w.join(format!("wear_{tool}.svg"));
        let mut legend = vec![
            "motor power (true, period mean)".to_string(),
            "monitored power p-bar".to_string(),
            "constant threshold".to_string(),
            "updating threshold".to_string(),
        ];
        for line in table.lines().filter(|l| l.starts_with(&format!("{tool},"))) {
            let f: Vec<&str> = line.split(',').collect();
            legend.push(if f[2].is_empty() {
                format!("{}: no alarm", f[1])
            } else {
                let (t, p): (f64, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap());
                format!("{} alarm: {t:.2} s, {p:.0} W", f[1])
            });
        }
        let legend: Vec<&str> = legend.iter().map(String::as_str).collect();
        assert_plot(&svg, &["t, s", "power, W"], &legend);
        assert!(!texts(&svg).iter().any(|t| t.text.contains("4000 W")));
    }
}

#[test]
fn the_pareto_plot_labels_every_decade_of_its_log_axis() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("t");
    let spec = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sweep.toml");
    let o = tooltouch(&["tune", "--spec", s(&spec), "--out", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let svg = out.join("pareto.svg");
    let mut legend = Vec::new();
    for m in ["counter", "density", "single-pulse"] {
        legend.push(format!("{m}: every point"));
        legend.push(format!("{m}: Pareto front"));
    }
    let legend: Vec<&str> = legend.iter().map(String::as_str).collect();
    assert_plot(
        &svg,
        &[
            "logic cells (iCE40 LUT4, estimated)",
            "mean |diameter error| vs float reference, µm (log)",
        ],
        &legend,
    );
    let decades: Vec<String> = texts(&svg)
        .into_iter()
        .map(|t| t.text)
        .filter(|t| ["0.001", "0.01", "0.1", "1", "10", "100"].contains(&t.as_str()))
        .collect();
    assert!(decades.len() >= 2, "decade labels: {decades:?}");
    // Minor ticks: eight 3-pixel marks per decade (2…9 ×), besides the decade's own.
    let svg_text = std::fs::read_to_string(&svg).unwrap();
    let minor = svg_text
        .split("points=\"")
        .skip(1)
        .filter(|p| {
            let pts: Vec<(f64, f64)> = p
                .split('"')
                .next()
                .unwrap()
                .split_whitespace()
                .filter_map(|xy| {
                    let (x, y) = xy.split_once(',')?;
                    Some((x.parse().ok()?, y.parse().ok()?))
                })
                .collect();
            pts.len() == 2 && pts[1].0 - pts[0].0 == 3.0 && pts[0].1 == pts[1].1
        })
        .count();
    assert!(
        minor >= 8 * (decades.len() - 1),
        "{minor} minor ticks for {decades:?}"
    );
}
