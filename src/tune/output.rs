//! Files of a sweep in `--out DIR`: `results.json` (everything, re-readable by `tune
//! merge`), `results.csv` (one row per measurement point), `force.csv` (one row per
//! force-control gain point) and `pareto.svg` (diameter error against logic cells, each
//! method's Pareto front highlighted).

use super::{Results, Row};
use anyhow::{Context, Result};
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
        crate::plot::pareto::pareto(&results.rows, &dir.join(SVG))?;
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
