//! A [`Coverage`] in the YAML form cocotb-coverage exports (`coverage_db.export_to_yaml`),
//! so a cocotb user merges tooltouch's bins with their own covergroups with
//! cocotb-coverage's `merge_coverage` (docs/vectors.md, "Coverage").
//!
//! The hierarchy: `tooltouch` (a cover item), under it `tooltouch.config_<measure hash>`
//! (one cover item per configuration: the bins name configured values, e.g. `window ends
//! with count i_def = 4`, so runs merge bin by bin only at one configuration), under that one
//! cover point per bin group (`tooltouch.config_<hash>.pulse_counter`, …) holding the
//! group's applicable bins with their hits (bins not applicable at the configuration are
//! left out, as cocotb-coverage has no such state). Every bin has weight 1 and `at_least`
//! 1: a cover point's `size` is its number of bins, its `coverage` the number hit; an item's
//! are its children's sums; `cover_percentage` is `100·coverage/size` rounded to 2 places,
//! as cocotb-coverage computes it.

use crate::coverage::Coverage;
use std::fmt::Write as _;

/// The type names cocotb-coverage writes (`str(type(item))`).
const COVER_ITEM: &str = "<class 'cocotb_coverage.coverage.CoverItem'>";
const COVER_POINT: &str = "<class 'cocotb_coverage.coverage.CoverPoint'>";

/// A YAML double-quoted scalar (JSON's string syntax is one).
fn quoted(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".into())
}

/// A group's name as one level of a dotted cover path: lower case, `_` for anything that
/// is not a letter or digit (a `.` would open a level).
fn level(group: &str) -> String {
    group
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect()
}

/// `100·coverage/size` rounded to 2 places, written as Python writes a float.
fn percentage(coverage: usize, size: usize) -> String {
    let p = (coverage as f64 * 100.0 / size as f64 * 100.0).round() / 100.0;
    if p.fract() == 0.0 {
        format!("{p:.1}")
    } else {
        format!("{p}")
    }
}

fn item(out: &mut String, path: &str, kind: &str, coverage: usize, size: usize) {
    let _ = writeln!(out, "{}:", quoted(path));
    let _ = writeln!(out, "  coverage: {coverage}");
    let _ = writeln!(out, "  cover_percentage: {}", percentage(coverage, size));
    let _ = writeln!(out, "  size: {size}");
    let _ = writeln!(out, "  type: {}", quoted(kind));
}

/// The YAML document of `cov`, measured at the configuration of hash `measure_hash`.
pub fn yaml(cov: &Coverage, measure_hash: u64) -> String {
    let config = format!("tooltouch.config_{measure_hash:016x}");
    let mut groups: Vec<&'static str> = Vec::new();
    for b in cov.bins.iter().filter(|b| b.not_applicable.is_none()) {
        if !groups.contains(&b.group) {
            groups.push(b.group);
        }
    }
    let (hit, size) = cov.reached();
    let mut out = String::new();
    item(&mut out, "tooltouch", COVER_ITEM, hit, size);
    item(&mut out, &config, COVER_ITEM, hit, size);
    for group in groups {
        let bins: Vec<_> = cov
            .bins
            .iter()
            .filter(|b| b.group == group && b.not_applicable.is_none())
            .collect();
        let covered = bins.iter().filter(|b| b.hits > 0).count();
        let path = format!("{config}.{}", level(group));
        let _ = writeln!(out, "{}:", quoted(&path));
        let _ = writeln!(out, "  at_least: 1");
        let _ = writeln!(out, "  \"bins:_hits\":");
        for b in &bins {
            let _ = writeln!(out, "    {}: {}", quoted(&b.name), b.hits);
        }
        let _ = writeln!(out, "  coverage: {covered}");
        let _ = writeln!(
            out,
            "  cover_percentage: {}",
            percentage(covered, bins.len())
        );
        let _ = writeln!(out, "  size: {}", bins.len());
        let _ = writeln!(out, "  type: {}", quoted(COVER_POINT));
        let _ = writeln!(out, "  weight: 1");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::Bin;

    #[test]
    fn the_document_nests_groups_under_the_configuration_and_counts_hit_bins() {
        let bin = |group, name: &str, hits, na: bool| Bin {
            group,
            name: name.into(),
            hits,
            not_applicable: na.then(|| "why".into()),
        };
        let cov = Coverage {
            bins: vec![
                bin("pulse counter", "a \"quoted\" bin", 3, false),
                bin("pulse counter", "missed", 0, false),
                bin("pulse counter", "n/a", 0, true),
                bin("MCU", "read", 1, false),
            ],
            cycles: 10,
        };
        let text = yaml(&cov, 0xab);
        let c = "tooltouch.config_00000000000000ab";
        for want in [
            "\"tooltouch\":\n  coverage: 2\n  cover_percentage: 66.67\n  size: 3\n".to_string(),
            format!("\"{c}\":\n  coverage: 2\n"),
            format!("\"{c}.pulse_counter\":\n  at_least: 1\n  \"bins:_hits\":\n    \"a \\\"quoted\\\" bin\": 3\n    \"missed\": 0\n  coverage: 1\n  cover_percentage: 50.0\n  size: 2\n"),
            format!("\"{c}.mcu\":\n"),
        ] {
            assert!(text.contains(&want), "{want}\nnot in\n{text}");
        }
        assert!(!text.contains("n/a"), "{text}");
    }
}
