//! FPGA cost estimate of a front-end configuration: flip-flops and logic cells (iCE40
//! `SB_LUT4`) as a linear function of the configuration's register widths, fitted by least
//! squares to yosys `synth_ice40` runs of the generated Verilog.
//!
//! The model is data, not code: `host/tune/src/cost_model.json` holds the yosys measurement of
//! every [`CALIBRATION_POINTS`] configuration and the coefficients fitted to them, and
//! [`CostModel::fitted`] reads the coefficients from it (compiled in with `include_str!`).
//! `cargo xtask hdl-report` refits it: it synthesizes every calibration point again
//! ([`synthesis`]) and rewrites the file (by running `tests/tune/cost_model.rs` with
//! `TOOLTOUCH_BLESS=1`). That test, run by `cargo test`, fails when a committed
//! measurement is more than 2 % off a fresh synthesis, so a generator change that moves
//! the cost cannot go unnoticed; this module's unit tests check that the committed
//! coefficients are the fit of the committed measurements.
//!
//! A measurement is the sum of the `SB_DFF*` cells (flip-flops) and the `SB_LUT4` cells
//! (logic cells; carry cells are not counted: they ride in the logic cells' carry chain)
//! of [`synthesis::SYNTH_SCRIPT`] on every file of the design but the chip top.

mod calibration;
pub mod synthesis;

pub use calibration::{Calibration, CalibrationPoint, CALIBRATION_POINTS};

use serde::{Deserialize, Serialize};
use tooltouch_model::measure::config::{ChargeLaw, MeasureConfig};

/// Number of model features: 1, charge_bits, scale_bits, count_bits, glitch_bits,
/// window_rev_bits, exponential, no glitch filter (`glitch_cycles` = 0: the filter is one
/// register per pin, without counters).
pub const FEATURES: usize = 8;

/// Names of the features, in coefficient order.
pub const FEATURE_NAMES: [&str; FEATURES] = [
    "1",
    "charge_bits",
    "scale_bits",
    "count_bits",
    "glitch_bits",
    "window_rev_bits",
    "exponential",
    "no_glitch_filter",
];

fn bits_for(max: u64) -> f64 {
    f64::from(tooltouch_model::measure::config::bits_for(max))
}

/// The features of a configuration given by its widths.
fn features(
    charge_bits: u8,
    scale_bits: u8,
    glitch_cycles: u8,
    exponential: bool,
    window_pulses: u32,
    window_revs: u8,
) -> [f64; FEATURES] {
    [
        1.0,
        f64::from(charge_bits),
        f64::from(scale_bits),
        bits_for(window_pulses.into()),
        bits_for(glitch_cycles.into()),
        bits_for(u64::from(window_revs) - 1),
        f64::from(u8::from(exponential)),
        f64::from(u8::from(glitch_cycles == 0)),
    ]
}

fn point_features(p: &CalibrationPoint) -> [f64; FEATURES] {
    features(
        p.charge_bits,
        p.scale_bits,
        p.glitch_cycles,
        p.exponential,
        u32::from(p.pulses_per_rev) * u32::from(p.window_revs),
        p.window_revs,
    )
}

/// Least-squares coefficients for `y` over `points` (normal equations with a tiny ridge
/// so a feature the points do not vary cannot make them singular).
#[allow(clippy::needless_range_loop)]
fn fit(points: &[Calibration], y: impl Fn(&Calibration) -> f64) -> [f64; FEATURES] {
    let mut a = [[0.0f64; FEATURES + 1]; FEATURES];
    for p in points {
        let x = point_features(&p.point);
        for i in 0..FEATURES {
            for j in 0..FEATURES {
                a[i][j] += x[i] * x[j];
            }
            a[i][FEATURES] += x[i] * y(p);
        }
    }
    for (i, row) in a.iter_mut().enumerate() {
        row[i] += 1e-6;
    }
    // Gauss–Jordan elimination with partial pivoting.
    for col in 0..FEATURES {
        let pivot = (col..FEATURES)
            .max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs()))
            .unwrap_or(col);
        a.swap(col, pivot);
        let d = a[col][col];
        for v in a[col].iter_mut() {
            *v /= d;
        }
        for r in 0..FEATURES {
            if r != col {
                let f = a[r][col];
                let pivot_row = a[col];
                for (v, p) in a[r].iter_mut().zip(pivot_row.iter()) {
                    *v -= f * p;
                }
            }
        }
    }
    let mut out = [0.0; FEATURES];
    for (o, row) in out.iter_mut().zip(a.iter()) {
        *o = row[FEATURES];
    }
    out
}

/// The fitted cost model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostModel {
    flip_flops: [f64; FEATURES],
    logic_cells: [f64; FEATURES],
}

/// Estimated size of one configuration on an iCE40.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Cost {
    /// Flip-flops.
    pub flip_flops: u32,
    /// Logic cells (4-input LUTs).
    pub logic_cells: u32,
}

impl Default for CostModel {
    fn default() -> Self {
        Self::fitted()
    }
}

impl CostModel {
    /// The committed model (coefficients of `host/tune/src/cost_model.json`).
    pub fn fitted() -> Self {
        CostModelFile::committed().model()
    }

    /// The least-squares fit to `points`.
    pub fn fit(points: &[Calibration]) -> Self {
        CostModel {
            flip_flops: fit(points, |p| f64::from(p.flip_flops)),
            logic_cells: fit(points, |p| f64::from(p.logic_cells)),
        }
    }

    fn eval(coef: &[f64; FEATURES], x: &[f64; FEATURES]) -> u32 {
        let v: f64 = coef.iter().zip(x).map(|(a, b)| a * b).sum();
        v.round().max(0.0) as u32
    }

    /// Estimated cost of `config`.
    pub fn estimate(&self, config: &MeasureConfig) -> Cost {
        let s = config.settings();
        let x = features(
            s.charge_bits,
            s.scale_bits,
            s.glitch_cycles,
            matches!(s.charge_law, ChargeLaw::Exponential { .. }),
            config.window_pulses(),
            s.window_revs,
        );
        Cost {
            flip_flops: Self::eval(&self.flip_flops, &x),
            logic_cells: Self::eval(&self.logic_cells, &x),
        }
    }

    /// Estimated cost of a calibration point (for checking the fit).
    pub fn estimate_point(&self, p: &CalibrationPoint) -> Cost {
        let x = point_features(p);
        Cost {
            flip_flops: Self::eval(&self.flip_flops, &x),
            logic_cells: Self::eval(&self.logic_cells, &x),
        }
    }
}

/// Format tag of the cost model file.
pub const COST_MODEL_FORMAT: &str = "tooltouch-cost-model-1";

/// Path of the committed cost model, relative to the workspace root.
pub const COST_MODEL_PATH: &str = "host/tune/src/cost_model.json";

/// The committed cost model file's contents.
const COMMITTED: &str = include_str!("cost_model.json");

/// The cost model file: how it was measured, the measurements, and the coefficients
/// fitted to them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostModelFile {
    /// [`COST_MODEL_FORMAT`].
    pub format: String,
    /// `yosys -V` of the synthesis.
    pub yosys: String,
    /// The yosys script ([`synthesis::SYNTH_SCRIPT`]).
    pub script: String,
    /// [`FEATURE_NAMES`].
    pub features: Vec<String>,
    /// One measurement per [`CALIBRATION_POINTS`] entry, in its order.
    pub measurements: Vec<Calibration>,
    /// Flip-flop coefficients, one per feature.
    pub flip_flops: [f64; FEATURES],
    /// Logic-cell coefficients, one per feature.
    pub logic_cells: [f64; FEATURES],
}

impl CostModelFile {
    /// The committed file (compiled in).
    pub fn committed() -> Self {
        Self::parse(COMMITTED).unwrap_or_else(|e| panic!("{COST_MODEL_PATH}: {e}"))
    }

    /// Reads a cost model file's text.
    pub fn parse(text: &str) -> Result<Self, String> {
        let file: CostModelFile = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if file.format != COST_MODEL_FORMAT {
            return Err(format!(
                "format `{}`, expected `{COST_MODEL_FORMAT}`",
                file.format
            ));
        }
        if file.features != FEATURE_NAMES {
            return Err(format!(
                "features {:?}, expected {FEATURE_NAMES:?}",
                file.features
            ));
        }
        Ok(file)
    }

    /// The file for `measurements` synthesized with yosys `yosys_version`: the
    /// measurements and their least-squares fit.
    pub fn refit(measurements: Vec<Calibration>, yosys_version: &str) -> Self {
        let model = CostModel::fit(&measurements);
        CostModelFile {
            format: COST_MODEL_FORMAT.into(),
            yosys: yosys_version.into(),
            script: synthesis::SYNTH_SCRIPT.into(),
            features: FEATURE_NAMES.iter().map(|s| s.to_string()).collect(),
            measurements,
            flip_flops: model.flip_flops,
            logic_cells: model.logic_cells,
        }
    }

    /// The model of the file's coefficients.
    pub fn model(&self) -> CostModel {
        CostModel {
            flip_flops: self.flip_flops,
            logic_cells: self.logic_cells,
        }
    }

    /// The file's text: JSON with one measurement per line (so a refit shows as a diff of
    /// the points that moved), the coefficients written so they read back to the same
    /// `f64`.
    pub fn to_json(&self) -> String {
        fn json<T: Serialize + ?Sized>(value: &T) -> String {
            serde_json::to_string(value).unwrap_or_default()
        }
        fn list(items: Vec<String>) -> String {
            format!("[\n    {}\n  ]", items.join(",\n    "))
        }
        let numbers = |c: &[f64; FEATURES]| list(c.iter().map(json).collect());
        format!(
            "{{\n  \"format\": {},\n  \"yosys\": {},\n  \"script\": {},\n  \
             \"features\": {},\n  \"measurements\": {},\n  \"flip_flops\": {},\n  \
             \"logic_cells\": {}\n}}\n",
            json(&self.format),
            json(&self.yosys),
            json(&self.script),
            json(&self.features),
            list(self.measurements.iter().map(json).collect()),
            numbers(&self.flip_flops),
            numbers(&self.logic_cells),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_reproduces_every_yosys_point_within_five_percent() {
        let file = CostModelFile::committed();
        let m = CostModel::fitted();
        for p in &file.measurements {
            let e = m.estimate_point(&p.point);
            let close = |a: u32, b: u32| (f64::from(a) - f64::from(b)).abs() <= 0.05 * f64::from(b);
            assert!(close(e.flip_flops, p.flip_flops), "{p:?}: {e:?}");
            assert!(close(e.logic_cells, p.logic_cells), "{p:?}: {e:?}");
        }
    }

    #[test]
    fn the_committed_coefficients_are_the_fit_of_the_committed_measurements() {
        let file = CostModelFile::committed();
        let points: Vec<CalibrationPoint> = file.measurements.iter().map(|m| m.point).collect();
        assert_eq!(
            points, CALIBRATION_POINTS,
            "{COST_MODEL_PATH}: other points"
        );
        assert_eq!(
            CostModel::fit(&file.measurements),
            file.model(),
            "{COST_MODEL_PATH}: the coefficients are not the fit of its measurements"
        );
        assert_eq!(
            CostModelFile::parse(&file.to_json()),
            Ok(file.clone()),
            "the file does not read back to itself"
        );
        assert_eq!(
            file.to_json(),
            COMMITTED,
            "{COST_MODEL_PATH} is not as written"
        );
    }

    #[test]
    fn every_calibration_point_is_a_valid_configuration() {
        for p in &CALIBRATION_POINTS {
            let s = p.settings().validate().expect("valid calibration point");
            assert_eq!(s.settings().charge_bits, p.charge_bits);
            assert!(s.settings().fire_threshold > s.settings().rearm_threshold);
        }
    }

    #[test]
    fn wider_registers_cost_more() {
        let m = CostModel::fitted();
        let narrow = tooltouch_model::MeasureSettings {
            charge_bits: 8,
            scale_bits: 16,
            charge_law: tooltouch_model::measure::config::ChargeLaw::Linear {
                charge_step: 8,
                discharge_step: 4,
            },
            fire_threshold: 192,
            rearm_threshold: 64,
            ..Default::default()
        };
        let narrow = m.estimate(&narrow.validate().unwrap());
        let wide = m.estimate(&tooltouch_model::MeasureConfig::default());
        assert!(wide.flip_flops > narrow.flip_flops);
        assert!(wide.logic_cells > narrow.logic_cells);
    }
}
