//! Files of a sweep in `--out DIR`: `results.json` (everything, re-readable by `tune
//! merge`), `results.csv` (one row per measurement point), `force.csv` (one row per
//! force-control gain point); `pareto.svg` (diameter error against logic cells, each
//! method's Pareto front highlighted) is drawn by the command line from [`pareto_rows`]
//! (`tooltouch-plot`): this crate draws nothing, so the Python package links no plotting.

use super::{Results, Row};
use anyhow::{Context, Result};
use serde::Serialize;
use std::path::Path;

/// `results.json`.
pub const JSON: &str = "results.json";
/// `results.csv`.
pub const CSV: &str = "results.csv";
/// `pareto.svg` (drawn by the command line).
pub const SVG: &str = "pareto.svg";
/// `force.csv`.
pub const FORCE_CSV: &str = "force.csv";

/// The CSV text of a table: a header of `T`'s field names (from its `Serialize`, so the
/// columns are typed once, in the struct), then one record per row. Numbers are written
/// exactly (shortest round-trip form, as in `results.json`), `None` as an empty field. An
/// empty table is its header alone (the columns of `T::default()`).
pub fn csv_table<T: Serialize + Default>(rows: &[T]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    if rows.is_empty() {
        let mut sample = csv::Writer::from_writer(Vec::new());
        sample.serialize(T::default())?;
        let text = sample.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
        let header = text.split_inclusive(|&b| b == b'\n').next().unwrap_or(&[]);
        return Ok(String::from_utf8_lossy(header).into_owned());
    }
    for r in rows {
        w.serialize(r)?;
    }
    let bytes = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    String::from_utf8(bytes).context("CSV text")
}

/// Writes `results.json`, `results.csv` and `force.csv` into `dir`.
pub fn write(results: &Results, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let json = serde_json::to_string_pretty(results).context("encoding results")?;
    let p = dir.join(JSON);
    std::fs::write(&p, json + "\n").with_context(|| format!("writing {}", p.display()))?;
    let p = dir.join(CSV);
    std::fs::write(&p, csv_table(&results.rows)?)
        .with_context(|| format!("writing {}", p.display()))?;
    let p = dir.join(FORCE_CSV);
    std::fs::write(&p, csv_table(&results.force)?)
        .with_context(|| format!("writing {}", p.display()))?;
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

/// The rows `pareto.svg` draws, each with its diameter error, µm (none for a slice of a
/// sweep: its front is not the whole sweep's): those that missed no decision and have an
/// error.
pub fn pareto_rows(results: &Results) -> Option<Vec<(&Row, f64)>> {
    results.shard.is_none().then(|| {
        results
            .rows
            .iter()
            .filter(|r| r.misses == 0)
            .filter_map(|r| r.diameter_error_um.map(|e| (r, e)))
            .collect()
    })
}
