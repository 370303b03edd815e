//! Statistics over a series of measurements: mean and scatter (docs/domain.md §2.5).

use super::report::MeasurementReport;
use serde::Serialize;

/// Mean, sample standard deviation (1σ, the "±" of the report) and range of a series.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Spread {
    /// Values in the series.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (0 for fewer than two values).
    pub std: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

impl Spread {
    /// The spread of `values` (`None`s are left out).
    pub fn of(values: impl IntoIterator<Item = Option<f64>>) -> Spread {
        let v: Vec<f64> = values.into_iter().flatten().collect();
        if v.is_empty() {
            return Spread::default();
        }
        let n = v.len();
        let mean = v.iter().sum::<f64>() / n as f64;
        let std = if n > 1 {
            (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt()
        } else {
            0.0
        };
        Spread {
            n,
            mean,
            std,
            min: v.iter().copied().fold(f64::MAX, f64::min),
            max: v.iter().copied().fold(f64::MIN, f64::max),
        }
    }
}

/// Totals of a run.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Summary {
    /// Measurements made.
    pub measurements: usize,
    /// Measurements the CNC accepted (decided, confirmed, no fault): the statistics below
    /// are theirs.
    pub decided: usize,
    /// Measurements with a fault (an alarm: excluded from the statistics).
    pub faulted: usize,
    /// Measurements that decided without a fault but were not confirmed when the CNC
    /// retracted (the approach gave up first; excluded from the statistics).
    pub unconfirmed: usize,
    /// Measured (accepted) diameters, mm.
    pub diameter_mm: Spread,
    /// Errors against the true mean diameter, µm.
    pub error_vs_mean_um: Spread,
    /// Errors against the true largest diameter, µm.
    pub error_vs_largest_um: Spread,
    /// Revolutions from first contact to the decision.
    pub revs_to_decision: Spread,
    /// Revolutions from first contact to permanent contact.
    pub revs_to_permanent: Spread,
    /// One scale count as a diameter, µm (the quantization of the reading).
    pub diameter_quantum_um: f64,
}

impl Summary {
    /// Statistics of `m`, with scale resolution `resolution_um`.
    pub fn of(m: &[MeasurementReport], resolution_um: f64) -> Summary {
        Summary {
            measurements: m.len(),
            decided: m.iter().filter(|r| r.diameter_mm.is_some()).count(),
            faulted: m.iter().filter(|r| r.faults != 0).count(),
            unconfirmed: m
                .iter()
                .filter(|r| r.faults == 0 && !r.confirmed && r.decision_position.is_some())
                .count(),
            diameter_mm: Spread::of(m.iter().map(|r| r.diameter_mm)),
            error_vs_mean_um: Spread::of(m.iter().map(|r| r.error_vs_mean_um)),
            error_vs_largest_um: Spread::of(m.iter().map(|r| r.error_vs_largest_um)),
            revs_to_decision: Spread::of(m.iter().map(|r| r.revs_to_decision)),
            revs_to_permanent: Spread::of(m.iter().map(|r| r.revs_to_permanent)),
            diameter_quantum_um: 2.0 * resolution_um,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_of_a_series() {
        let s = Spread::of([Some(1.0), None, Some(3.0)]);
        assert_eq!((s.n, s.mean, s.min, s.max), (2, 2.0, 1.0, 3.0));
        assert!((s.std - 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(Spread::of([]).n, 0);
    }
}
