//! One measurement's results, as the closed-loop driver records them and the statistics
//! summarise them. A leaf module, so the statistics read it without importing their parent.

use serde::Serialize;

/// One measurement's results.
#[derive(Clone, Debug, Serialize)]
pub struct MeasurementReport {
    /// Measurement number, from 0.
    pub index: usize,
    /// Axial position, mm from the first measurement.
    pub z_mm: f64,
    /// Clock at which the arm line rose (with an index pulse).
    pub arm_cycle: u64,
    /// Clock after which the model's `first_contact` output was first high.
    pub first_contact_cycle: Option<u64>,
    /// Clock after which the model's `register_now` output was first high.
    pub decision_cycle: Option<u64>,
    /// Clock at which the (spike-free) contact line went high for good: the start of the
    /// run of contact that covered a whole revolution.
    pub permanent_contact_cycle: Option<u64>,
    /// Clock at which the feed stopped.
    pub stop_cycle: u64,
    /// Clock after which the model's `confirmed` output was first high.
    pub confirmed_cycle: Option<u64>,
    /// Clock after which the model's `faults` word was first non-zero: the CNC's alarm.
    pub fault_cycle: Option<u64>,
    /// Clock at which the retract began: the CNC waits, the tool at its stop, for the
    /// confirmation or a fault (`stop_cycle` unless it had to wait).
    pub retract_cycle: u64,
    /// One past the last clock of this measurement (after retract and Z dwell).
    pub end_cycle: u64,
    /// Revolutions from first contact to the decision.
    pub revs_to_decision: Option<f64>,
    /// Revolutions from first contact to permanent contact.
    pub revs_to_permanent: Option<f64>,
    /// Latched scale position at the decision, counts relative to power-on (the model's
    /// `decision_position`, unwrapped from `scale_bits`).
    pub decision_position: Option<i64>,
    /// Latched scale position at first contact, counts relative to power-on.
    pub first_contact_position: Option<i64>,
    /// The model's `confirmed` output at the end of the measurement: the contact pattern
    /// after the decision confirmed it.
    pub confirmed: bool,
    /// The model's `faults` word at the end of the measurement (latched since arm, one bit
    /// per condition: `tooltouch_model::fault`); 0 = none.
    pub faults: u8,
    /// The faults' names, in bit order (empty when none).
    pub fault_names: Vec<&'static str>,
    /// Whether the CNC accepted the measurement: decided, `confirmed` and no fault.
    pub accepted: bool,
    /// Measured diameter of an accepted measurement: `2 · (home count + decision position
    /// + ½) · resolution`, mm (the middle of the latched count's cell). `None` when the
    /// measurement did not decide or was not accepted (see `latched_diameter_mm`).
    pub diameter_mm: Option<f64>,
    /// The diameter of the latched decision position whatever the status, mm: for
    /// diagnosis only, not a trustworthy reading unless `accepted`.
    pub latched_diameter_mm: Option<f64>,
    /// Diameter at the first contact, mm (the single-pulse reading, whatever the method).
    pub first_contact_diameter_mm: Option<f64>,
    /// True mean diameter of the workpiece at this Z, mm.
    pub true_mean_diameter_mm: f64,
    /// True largest diameter of the workpiece at this Z, mm.
    pub true_largest_diameter_mm: f64,
    /// Measured (accepted) minus true mean diameter, µm.
    pub error_vs_mean_um: Option<f64>,
    /// Measured (accepted) minus true largest diameter, µm.
    pub error_vs_largest_um: Option<f64>,
    /// The model's `last_window_count` after each index pulse of the approach (contact
    /// pulses per window: the contact density × window pulses).
    pub window_counts: Vec<u32>,
    /// Fraction of each approach revolution the (spike-free) contact line was high.
    pub contact_fraction: Vec<f64>,
}
