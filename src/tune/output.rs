//! Files of a sweep in `--out DIR`: `results.json` (everything, re-readable by `tune
//! merge`), `results.csv` (one row per measurement point), `force.csv` (one row per
//! force-control gain point) and `pareto.svg` (diameter error against logic cells, each
//! method's Pareto front highlighted).

use super::{Results, Row};
use anyhow::{Context, Result};
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// `results.json`.
pub const JSON: &str = "results.json";
/// `results.csv`.
pub const CSV: &str = "results.csv";
/// `pareto.svg`.
pub const SVG: &str = "pareto.svg";
/// `force.csv`.
pub const FORCE_CSV: &str = "force.csv";

/// The CSV text of the force rows.
pub fn force_csv(rows: &[super::force::ForceRow]) -> String {
    let mut out = String::from(
        "index,controller,force_source,kp_percent,ki_percent,iae_model,iae_reference,iae_error,overshoot_pct\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{:.4},{:.4},{:.4},{:.2}",
            r.index,
            r.controller,
            r.force_source,
            r.kp_percent,
            r.ki_percent,
            r.iae_model,
            r.iae_reference,
            r.iae_error,
            r.overshoot_pct
        );
    }
    out
}

const COLUMNS: &str = "index,method,contact_rule,charge_bits,scale_bits,glitch_cycles,i_def,\
window_revs,law,charge,discharge,fire_threshold,rearm_threshold,flip_flops,logic_cells,\
decided,misses,diameter_error_um,max_diameter_error_um,revolution_error,pareto";

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x:.4}"))
}

/// The CSV text of `rows`.
pub fn csv(rows: &[Row]) -> String {
    let mut out = String::from(COLUMNS);
    out.push('\n');
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.index,
            r.method,
            r.contact_rule,
            r.charge_bits,
            r.scale_bits,
            r.glitch_cycles,
            r.i_def,
            r.window_revs,
            r.law,
            r.charge,
            r.discharge,
            r.fire_threshold,
            r.rearm_threshold,
            r.flip_flops,
            r.logic_cells,
            r.decided,
            r.misses,
            opt(r.diameter_error_um),
            opt(r.max_diameter_error_um),
            opt(r.revolution_error),
            r.pareto
        );
    }
    out
}

/// Writes `results.json`, `results.csv` and (for a whole sweep) `pareto.svg` into `dir`.
pub fn write(results: &Results, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let json = serde_json::to_string_pretty(results).context("encoding results")?;
    let p = dir.join(JSON);
    std::fs::write(&p, json + "\n").with_context(|| format!("writing {}", p.display()))?;
    let p = dir.join(CSV);
    std::fs::write(&p, csv(&results.rows)).with_context(|| format!("writing {}", p.display()))?;
    let p = dir.join(FORCE_CSV);
    std::fs::write(&p, force_csv(&results.force))
        .with_context(|| format!("writing {}", p.display()))?;
    if results.shard.is_none() {
        plot(&results.rows, &dir.join(SVG))?;
    }
    Ok(())
}

/// Reads `results.json` from a directory (or the file itself).
pub fn read(path: &Path) -> Result<Results> {
    let file = if path.is_dir() {
        path.join(JSON)
    } else {
        path.to_path_buf()
    };
    let text =
        std::fs::read_to_string(&file).with_context(|| format!("reading {}", file.display()))?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a tune results file", file.display()))
}

/// Scatter of diameter error against logic cells, one colour per decision method, each
/// method's Pareto front joined by a line.
pub fn plot(rows: &[Row], path: &Path) -> Result<()> {
    // Log scale: errors span a scale count's fraction to whole revolutions of feed; an
    // error below 1 nm is drawn at 1 nm.
    let pts: Vec<(&str, u32, f64, bool)> = rows
        .iter()
        .filter(|r| r.misses == 0)
        .filter_map(|r| {
            r.diameter_error_um
                .map(|e| (r.method.as_str(), r.logic_cells, e.max(1e-3), r.pareto))
        })
        .collect();
    let (mut x0, mut x1) = (u32::MAX, 0u32);
    let (mut y0, mut y1) = (f64::MAX, 0.0f64);
    for &(_, x, y, _) in &pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if pts.is_empty() {
        (x0, x1, y0, y1) = (0, 1, 1e-3, 1.0);
    }
    let mut methods: Vec<&str> = pts.iter().map(|p| p.0).collect();
    methods.sort_unstable();
    methods.dedup();
    let palette = [BLUE, RED, GREEN, MAGENTA, CYAN];
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    let draw = || -> std::result::Result<(), Box<dyn std::error::Error>> {
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "tooltouch tune: latched-diameter error vs FPGA cost",
                ("sans-serif", 20),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(
                x0.saturating_sub(10)..(x1 + 10),
                (y0 / 1.5..(y1 * 1.5).max(y0 * 2.0)).log_scale(),
            )?;
        chart
            .configure_mesh()
            .x_desc("logic cells (iCE40 LUT4, estimated)")
            .y_desc("mean |diameter error| vs float reference, µm (log)")
            .draw()?;
        for (i, m) in methods.iter().enumerate() {
            let colour = palette[i % palette.len()];
            chart
                .draw_series(
                    pts.iter()
                        .filter(|p| p.0 == *m)
                        .map(|&(_, x, y, _)| Circle::new((x, y), 3, colour.mix(0.35).filled())),
                )?
                .label(m.to_string())
                .legend(move |(x, y)| Circle::new((x, y), 3, colour.mix(0.35).filled()));
            let mut front: Vec<(u32, f64)> = pts
                .iter()
                .filter(|p| p.0 == *m && p.3)
                .map(|&(_, x, y, _)| (x, y))
                .collect();
            front.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
            chart
                .draw_series(LineSeries::new(
                    front.iter().copied(),
                    colour.stroke_width(2),
                ))?
                .label(format!("{m}: Pareto front"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x - 8, y), (x + 8, y)], colour.stroke_width(2))
                });
            chart.draw_series(
                front
                    .iter()
                    .map(|&(x, y)| Circle::new((x, y), 5, colour.filled())),
            )?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| anyhow::anyhow!("drawing {}: {e}", path.display()))
}
