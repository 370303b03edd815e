//! Force-control gain sweep: each controller of the force path (docs/domain.md §3: PI, adaptive
//! F11, fuzzy PI) with its gains scaled around the Ziegler–Nichols design on the nominal process
//! F10 ([`tooltouch_plant::reference::design`]), run on the depth-step scenario
//! ([`tooltouch_plant::drive::scenario`]) twice — with the fixed-point model kernel and with the float
//! reference stack — and compared by the integral of absolute force error (IAE, N·s).
//!
//! The fixed-point error of a gain point is `|IAE_model − IAE_reference|`; the IAE itself
//! says how good the gains are. The force path runs in firmware, so it has no FPGA cost.

use serde::{Deserialize, Serialize};
use tooltouch_plant::drive::scenario::{run, ControlScenario, Engine};
use tooltouch_settings::force_design::{source_name, ForcePoint};

/// Results of one force point.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ForceRow {
    /// The point's index in the whole sweep (after the measurement points).
    pub index: usize,
    /// Controller.
    pub controller: String,
    /// Force feedback.
    pub force_source: String,
    /// Proportional gain, percent of the design.
    pub kp_percent: u32,
    /// Integral gain, percent of the design.
    pub ki_percent: u32,
    /// IAE of the fixed-point model kernel, N·s.
    pub iae_model: f64,
    /// IAE of the float reference, N·s.
    pub iae_reference: f64,
    /// `|iae_model − iae_reference|`, N·s.
    pub iae_error: f64,
    /// Overshoot after the depth step, model, % of the reference force.
    pub overshoot_pct: f64,
}

/// Runs one force point with both engines.
pub fn row(index: usize, p: &ForcePoint) -> ForceRow {
    let (iae_model, iae_reference, overshoot_pct) = match p.settings.validate() {
        Ok(config) => {
            let sc = ControlScenario::new(config);
            let m = run(&sc, Engine::Model, false).metrics;
            let r = run(&sc, Engine::Reference, false).metrics;
            (m.iae, r.iae, m.overshoot_pct)
        }
        Err(_) => (f64::NAN, f64::NAN, f64::NAN),
    };
    ForceRow {
        index,
        controller: p.controller.into(),
        force_source: source_name(p.source).into(),
        kp_percent: p.kp_percent,
        ki_percent: p.ki_percent,
        iae_model,
        iae_reference,
        iae_error: (iae_model - iae_reference).abs(),
        overshoot_pct,
    }
}
