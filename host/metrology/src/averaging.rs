//! `m` measurements at one Z position, averaged (docs/accuracy.md). Repeats at one Z see the
//! same surface (form and roughness), so only what changes between them — the slow spindle
//! errors' phase (S10), the decision grid's phase, the quantization — averages out as
//! `σ/√m`, and what does not stays. That is the law of the paper's S8,
//! Δ_2 = e + ω_Δφ/√m, which it states for the fast-feed single pulse (docs/domain.md §2.1:
//! each fast approach meets the profile at another angle, so the form's scatter ω_Δφ
//! averages and the axis offset e stays); for the 50 % counter it is the slow errors that
//! average.

use serde::Serialize;
use tooltouch_plant::measurement_cycle::{MeasurementReport, Spread};

/// The mean of one Z position's measurements.
#[derive(Clone, Debug, Serialize)]
pub struct ZMean {
    /// Axial position, mm from the first.
    pub z_mm: f64,
    /// Measurements that decided at this Z.
    pub m: usize,
    /// Their mean diameter, mm.
    pub diameter_mm: f64,
    /// Their 1σ, µm (0 for one).
    pub sigma_um: f64,
    /// The 1σ of their mean, `σ/√m`, µm.
    pub sigma_of_mean_um: f64,
    /// The mean's error against the true mean diameter, µm.
    pub error_vs_mean_um: f64,
}

/// The per-Z means of `measurements` (consecutive runs of equal `z_mm`); undecided
/// measurements are left out, a Z with none is skipped.
pub fn per_z_means(measurements: &[MeasurementReport]) -> Vec<ZMean> {
    let mut out = Vec::new();
    let mut start = 0;
    while start < measurements.len() {
        let z = measurements[start].z_mm;
        let end = measurements[start..]
            .iter()
            .position(|r| r.z_mm != z)
            .map_or(measurements.len(), |k| start + k);
        let group = &measurements[start..end];
        let d = Spread::of(group.iter().map(|r| r.diameter_mm));
        let e = Spread::of(group.iter().map(|r| r.error_vs_mean_um));
        if d.n > 0 {
            out.push(ZMean {
                z_mm: z,
                m: d.n,
                diameter_mm: d.mean,
                sigma_um: d.std * 1000.0,
                sigma_of_mean_um: d.std * 1000.0 / (d.n as f64).sqrt(),
                error_vs_mean_um: e.mean,
            });
        }
        start = end;
    }
    out
}
