//! The calibration configurations the cost model is fitted to and one yosys measurement of
//! each. A leaf module, so the synthesis runner builds and returns them without importing
//! its parent.

use serde::{Deserialize, Serialize};
use tooltouch_model::measure::config::ChargeLaw;
use tooltouch_model::MeasureSettings;

/// One calibration configuration: the widths and structure the model's features read.
/// The other fields are derived from them by [`CalibrationPoint::settings`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CalibrationPoint {
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
}

const fn point(
    charge_bits: u8,
    scale_bits: u8,
    glitch_cycles: u8,
    exponential: bool,
    pulses_per_rev: u16,
    window_revs: u8,
) -> CalibrationPoint {
    CalibrationPoint {
        charge_bits,
        scale_bits,
        glitch_cycles,
        exponential,
        pulses_per_rev,
        window_revs,
    }
}

/// The configurations the model is fitted to: the default widths, each width varied
/// alone, then mixed ones.
pub const CALIBRATION_POINTS: [CalibrationPoint; 14] = [
    point(16, 24, 4, false, 1024, 1),
    point(8, 24, 4, false, 1024, 1),
    point(12, 24, 4, false, 1024, 1),
    point(24, 24, 4, false, 1024, 1),
    point(16, 16, 4, false, 1024, 1),
    point(16, 32, 4, false, 1024, 1),
    point(16, 24, 0, false, 1024, 1),
    point(16, 24, 15, false, 1024, 1),
    point(16, 24, 4, true, 1024, 1),
    point(8, 16, 0, true, 1024, 1),
    point(12, 16, 2, true, 256, 1),
    point(16, 24, 4, false, 4096, 4),
    point(20, 28, 8, true, 2048, 2),
    point(10, 20, 1, false, 512, 1),
];

impl CalibrationPoint {
    /// The full settings: the point's fields, `i_def` half the window, the linear law's
    /// steps full/64 up and full/32 down or the exponential law's shifts 4 up and 5 down,
    /// fire at 3/4 and re-arm at 1/4 of full scale, the rest [`MeasureSettings::default`].
    pub fn settings(&self) -> MeasureSettings {
        let full = (1u32 << self.charge_bits) - 1;
        let window = u32::from(self.pulses_per_rev) * u32::from(self.window_revs);
        MeasureSettings {
            charge_bits: self.charge_bits,
            scale_bits: self.scale_bits,
            glitch_cycles: self.glitch_cycles,
            pulses_per_rev: self.pulses_per_rev,
            window_revs: self.window_revs,
            i_def: window / 2,
            charge_law: if self.exponential {
                ChargeLaw::Exponential {
                    charge_shift: 4,
                    discharge_shift: 5,
                }
            } else {
                ChargeLaw::Linear {
                    charge_step: full / 64,
                    discharge_step: full / 32,
                }
            },
            fire_threshold: full * 3 / 4,
            rearm_threshold: full / 4,
            ..MeasureSettings::default()
        }
    }
}

/// One yosys measurement of a calibration point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Calibration {
    /// The configuration.
    #[serde(flatten)]
    pub point: CalibrationPoint,
    /// `SB_DFF*` cells.
    pub flip_flops: u32,
    /// `SB_LUT4` cells.
    pub logic_cells: u32,
}
