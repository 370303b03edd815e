//! A swept point as a settings file (`tooltouch tune point`): the `[measure]` table of a
//! measurement point, or the default `[measure]` table and the `[force]` design of a force
//! point, in the format `tooltouch hdl --config`, `tooltouch vectors --config`,
//! `tooltouch cosim firmware --config` and `cargo xtask firmware --config` read.
//!
//! The point is rebuilt from the spec stored in `results.json` (a sweep is deterministic),
//! and checked against the row the sweep wrote for it, so a results file that its spec no
//! longer describes (another version of the sweep) is refused, not silently misread.

use super::Results;
use anyhow::{anyhow, bail};
use serde::Serialize;
use tooltouch_model::MeasureSettings;
use tooltouch_settings::firmware_config::ForceDesign;
use tooltouch_settings::force_design::ForcePoint;

/// The settings file's tables.
#[derive(Serialize)]
struct File {
    measure: MeasureSettings,
    #[serde(skip_serializing_if = "Option::is_none")]
    force: Option<ForceDesign>,
}

fn stale(index: usize, what: &str) -> anyhow::Error {
    anyhow!(
        "point {index}: results.json's spec no longer makes the point it holds ({what} differs; \
         made by another version of tooltouch?)"
    )
}

/// The settings file (TOML text, a comment line first) of point `index` of `results`.
pub fn settings_toml(results: &Results, index: usize) -> anyhow::Result<String> {
    let total = results.points + results.force_points;
    let (file, about) = if index < results.points {
        let points = results.spec.points()?;
        let point = points
            .get(index)
            .ok_or_else(|| stale(index, "the point count"))?;
        let s = point.settings;
        if let Some(row) = results.rows.iter().find(|r| r.index == index) {
            if row.i_def != s.i_def
                || row.charge_bits != s.charge_bits
                || row.scale_bits != s.scale_bits
                || row.glitch_cycles != s.glitch_cycles
                || row.fire_threshold != s.fire_threshold
                || tooltouch_settings::renamed_value(&row.method).unwrap_or(&row.method)
                    != super::spec::method_name(s.method)
            {
                return Err(stale(index, "the measurement settings"));
            }
        }
        let about = results
            .rows
            .iter()
            .find(|r| r.index == index)
            .map_or_else(String::new, |r| {
                format!(
                    ": {} {}, {} logic cells, mean |diameter error| {} µm",
                    r.method,
                    r.contact_rule,
                    r.logic_cells,
                    r.diameter_error_um
                        .map_or_else(|| "n/a".to_string(), |e| format!("{e:.3}"))
                )
            });
        (
            File {
                measure: s,
                force: None,
            },
            format!("measurement point {index}{about}"),
        )
    } else if index < total {
        let k = index - results.points;
        let points = results.spec.force.points()?;
        let p = points
            .get(k)
            .ok_or_else(|| stale(index, "the point count"))?;
        if let Some(row) = results.force.iter().find(|r| r.index == index) {
            if row.controller != p.controller
                || row.kp_percent != p.kp_percent
                || row.ki_percent != p.ki_percent
            {
                return Err(stale(index, "the force design"));
            }
        }
        let design = force_design(p);
        (
            File {
                measure: MeasureSettings::default(),
                force: Some(design),
            },
            format!(
                "force point {index}: {} at kp {} % / ki {} % of the design",
                p.controller, p.kp_percent, p.ki_percent
            ),
        )
    } else {
        bail!("point {index}: the sweep has points 0..{total}");
    };
    let body = toml::to_string(&file).map_err(|e| anyhow!("point {index}: writing TOML: {e}"))?;
    Ok(format!("# tooltouch tune, {about}\n{body}"))
}

/// The `[force]` design of a force point.
fn force_design(p: &ForcePoint) -> ForceDesign {
    ForceDesign {
        controller: p.controller.to_string(),
        kp_percent: p.kp_percent,
        // The adaptive law has no integral gain (0 in the sweep); any valid value.
        ki_percent: p.ki_percent.max(1),
        force_source: match p.source {
            tooltouch_model::force::config::ForceSource::Estimated => "estimated",
            tooltouch_model::force::config::ForceSource::Measured => "measured",
        }
        .to_string(),
    }
}

/// A measurement point's settings file (the tables `tune point` writes for it), after the
/// comment line `# {comment}`.
pub fn measurement_toml(settings: &MeasureSettings, comment: &str) -> anyhow::Result<String> {
    let file = File {
        measure: *settings,
        force: None,
    };
    let body = toml::to_string(&file).map_err(|e| anyhow!("writing TOML: {e}"))?;
    Ok(format!("# {comment}\n{body}"))
}

/// A force point's settings file (the default `[measure]` table and its `[force]` design,
/// as `tune point` writes it), after the comment line `# {comment}`.
pub fn force_toml(p: &ForcePoint, comment: &str) -> anyhow::Result<String> {
    let file = File {
        measure: MeasureSettings::default(),
        force: Some(force_design(p)),
    };
    let body = toml::to_string(&file).map_err(|e| anyhow!("writing TOML: {e}"))?;
    Ok(format!("# {comment}\n{body}"))
}
