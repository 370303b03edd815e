//! One sweep point on one scenario: the fixed-point model's decision (cycle level, exact
//! fast-forward over settled clocks) against the float reference's.

use super::reference::{self, Intent};
use super::scenario::Approach;
use tooltouch_model::{FrontEnd, MeasureConfig};

/// Unwraps a `bits`-wide two's-complement count to the value nearest `reference`.
pub fn unwrap(position: i32, bits: u8, reference: i64) -> i64 {
    let modulus = 1i64 << bits;
    let p = i64::from(position);
    p + (reference - p + modulus / 2).div_euclid(modulus) * modulus
}

/// The model's decision on one scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModelDecision {
    /// Clock after which `register_now` was first high.
    pub cycle: u64,
    /// The latched `decision_position` (`scale_bits` two's complement).
    pub position: i32,
}

/// Runs the cycle-level model over the approach and returns its decision, if any.
/// Clocks where the front end is settled are skipped (exact: they change no register).
pub fn model_decision(a: &Approach, config: &MeasureConfig) -> Option<ModelDecision> {
    let mut fe = FrontEnd::new(config);
    let mut k = 0u64;
    for seg in &a.stimulus.segments {
        let end = k + u64::from(seg.cycles);
        while k < end {
            if fe.is_settled(seg.pins) {
                k = end;
                break;
            }
            fe.clock(seg.pins);
            if fe.measurement().register_now() {
                return Some(ModelDecision {
                    cycle: k,
                    position: fe.outputs().decision_position,
                });
            }
            k += 1;
        }
    }
    None
}

/// Errors of one point on one scenario.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    /// Both decided.
    Both {
        /// Model minus reference decision revolution (whole revolutions since the arm).
        revolution_error: i64,
        /// Model's latched diameter minus the reference's (the tool's exact diameter at the
        /// reference decision), µm.
        diameter_error_um: f64,
    },
    /// Only one of them decided within the approach.
    Miss,
    /// Neither decided.
    Neither,
}

/// Compares the model configured by `config` with the reference device `intent` on one
/// scenario.
pub fn evaluate(a: &Approach, config: &MeasureConfig, intent: &Intent) -> Outcome {
    let reference = reference::decision_cycle(a, intent);
    let model = model_decision(a, config);
    match (model, reference) {
        (Some(m), Some(r)) => {
            let rev = |t: f64| a.revs_since_arm(t).floor() as i64;
            // The CNC knows roughly where the slide is: unwrap the `scale_bits`-wide count
            // around the count the slide reads at the decision.
            let bits = config.settings().scale_bits;
            let count = unwrap(m.position, bits, a.count_at(m.cycle as f64));
            let model_um = a.start_um + count as f64 * a.scale_resolution_um;
            Outcome::Both {
                revolution_error: rev(m.cycle as f64) - rev(r),
                diameter_error_um: 2.0 * (model_um - a.tool_um(r)),
            }
        }
        (None, None) => Outcome::Neither,
        _ => Outcome::Miss,
    }
}
