//! FPGA cost estimate of a front-end configuration: flip-flops and logic cells (iCE40
//! `SB_LUT4`) as a linear function of the configuration's register widths, fitted by least
//! squares to yosys `synth_ice40` reports of the generated Verilog.
//!
//! The calibration points below were measured with tooltouch-hdl-gen's `generate` for each
//! configuration (the other fields at `MeasureSettings::default()`, `i_def` = half the
//! window, linear steps full/32 and full/64 or shifts 4/5, thresholds 3/4 and 1/4 of full
//! scale, the MCU read mux without the diagnostic counters), every file of the design but
//! the chip top read into yosys 0.23 with
//!
//! ```text
//! yosys -p "read_verilog tt_*.v; synth_ice40 -top tt_frontend; stat"
//! ```
//!
//! flip-flops = the sum of the `SB_DFF*` cells, logic cells = `SB_LUT4` (carry cells are
//! not counted: they ride in the logic cells' carry chain). Re-measure and update the table
//! when the generator changes; the fit is recomputed from it, and a test checks that it
//! reproduces every point within 5 %.

use tooltouch_model::measure::config::{ChargeLaw, MeasureConfig};

/// One yosys measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Calibration {
    /// `charge_bits`.
    pub charge_bits: u8,
    /// `scale_bits`.
    pub scale_bits: u8,
    /// `glitch_cycles`.
    pub glitch_cycles: u8,
    /// Exponential charge law (else linear).
    pub exponential: bool,
    /// `pulses_per_rev`.
    pub pulses_per_rev: u16,
    /// `window_revs`.
    pub window_revs: u8,
    /// `SB_DFF*` cells.
    pub flip_flops: u32,
    /// `SB_LUT4` cells.
    pub logic_cells: u32,
}

#[allow(clippy::too_many_arguments)]
const fn c(
    charge_bits: u8,
    scale_bits: u8,
    glitch_cycles: u8,
    exponential: bool,
    pulses_per_rev: u16,
    window_revs: u8,
    flip_flops: u32,
    logic_cells: u32,
) -> Calibration {
    Calibration {
        charge_bits,
        scale_bits,
        glitch_cycles,
        exponential,
        pulses_per_rev,
        window_revs,
        flip_flops,
        logic_cells,
    }
}

/// yosys 0.23 `synth_ice40` of tooltouch-hdl-gen's design (re-measured 2026-11-22 after the
/// decision logic was flattened onto flip-flops and the thresholds written as bit logic).
pub const CALIBRATION: [Calibration; 14] = [
    c(16, 24, 4, false, 1024, 1, 220, 432),
    c(8, 24, 4, false, 1024, 1, 212, 385),
    c(12, 24, 4, false, 1024, 1, 216, 405),
    c(24, 24, 4, false, 1024, 1, 228, 478),
    c(16, 16, 4, false, 1024, 1, 196, 388),
    c(16, 32, 4, false, 1024, 1, 244, 479),
    c(16, 24, 0, false, 1024, 1, 202, 392),
    c(16, 24, 15, false, 1024, 1, 226, 447),
    c(16, 24, 4, true, 1024, 1, 220, 459),
    c(8, 16, 0, true, 1024, 1, 170, 314),
    c(12, 16, 2, true, 256, 1, 182, 370),
    c(16, 24, 4, false, 4096, 4, 230, 449),
    c(20, 28, 8, true, 2048, 2, 247, 524),
    c(10, 20, 1, false, 512, 1, 188, 359),
];

/// Number of model features: 1, charge_bits, scale_bits, count_bits, glitch_bits,
/// window_rev_bits, exponential, no glitch filter (`glitch_cycles` = 0: the filter is one
/// register per pin, without counters).
const FEATURES: usize = 8;

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

fn calibration_features(p: &Calibration) -> [f64; FEATURES] {
    features(
        p.charge_bits,
        p.scale_bits,
        p.glitch_cycles,
        p.exponential,
        u32::from(p.pulses_per_rev) * u32::from(p.window_revs),
        p.window_revs,
    )
}

/// Least-squares coefficients for `y` over the calibration points (normal equations with
/// a tiny ridge so a feature the table does not vary cannot make them singular).
#[allow(clippy::needless_range_loop)]
fn fit(y: impl Fn(&Calibration) -> f64) -> [f64; FEATURES] {
    let mut a = [[0.0f64; FEATURES + 1]; FEATURES];
    for p in &CALIBRATION {
        let x = calibration_features(p);
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
    /// The model fitted to [`CALIBRATION`].
    pub fn fitted() -> Self {
        CostModel {
            flip_flops: fit(|p| f64::from(p.flip_flops)),
            logic_cells: fit(|p| f64::from(p.logic_cells)),
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
    pub fn estimate_calibration(&self, p: &Calibration) -> Cost {
        let x = calibration_features(p);
        Cost {
            flip_flops: Self::eval(&self.flip_flops, &x),
            logic_cells: Self::eval(&self.logic_cells, &x),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_reproduces_every_yosys_point_within_five_percent() {
        let m = CostModel::fitted();
        for p in &CALIBRATION {
            let e = m.estimate_calibration(p);
            let close = |a: u32, b: u32| (f64::from(a) - f64::from(b)).abs() <= 0.05 * f64::from(b);
            assert!(close(e.flip_flops, p.flip_flops), "{p:?}: {e:?}");
            assert!(close(e.logic_cells, p.logic_cells), "{p:?}: {e:?}");
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
