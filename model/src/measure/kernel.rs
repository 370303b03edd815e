//! The measurement front end as one kernel: the pulse counter, the density detector, the
//! quadrature decoder and the two position latches, driven one event at a time.
//!
//! This is the logic both timings share. The event level ([`crate::measure::events`]) calls these
//! methods once per timestamped event; the cycle level ([`crate::measure::frontend`]) calls them for
//! the edges detected in one clock, in the canonical order of
//! [`crate::measure::events::MeasureEvent::CANONICAL_ORDER`]: arm, contact, index, FES, scale. The
//! latches therefore capture the scale position as it was *before* a scale edge in the
//! same clock.

use crate::measure::config::{ContactRule, DecisionMethod, MeasureConfig};
use crate::measure::density::DensityDetector;
use crate::measure::latch::PositionLatch;
use crate::measure::outputs::MeasureOutputs;
use crate::measure::pulse_counter::PulseCounter;
use crate::measure::quadrature::QuadratureDecoder;

/// The combined measurement kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Measurement {
    rule: ContactRule,
    method: DecisionMethod,
    armed: bool,
    contact: bool,
    /// Contact was active since the previous FES pulse (the sticky rule's bit).
    sticky: bool,
    counter: PulseCounter,
    density: DensityDetector,
    scale: QuadratureDecoder,
    first_contact: PositionLatch,
    decision: PositionLatch,
    revolutions: u16,
    pulses: u32,
}

impl Measurement {
    /// Power-on state: disarmed, position 0, scale lines 00.
    pub fn new(config: &MeasureConfig) -> Self {
        let s = config.settings();
        Measurement {
            rule: s.contact_rule,
            method: s.method,
            armed: false,
            contact: false,
            sticky: false,
            counter: PulseCounter::new(config),
            density: DensityDetector::new(config),
            scale: QuadratureDecoder::new(config),
            first_contact: PositionLatch::new(),
            decision: PositionLatch::new(),
            revolutions: 0,
            pulses: 0,
        }
    }

    /// The CNC's arm line changed. A rising edge starts a measurement cycle: counts,
    /// charge, latches and the decision are cleared. A falling edge ends it; the results
    /// are held for the CNC to read until the next rising edge.
    pub fn on_arm(&mut self, level: bool) {
        if level && !self.armed {
            self.counter.reset();
            self.density.reset();
            self.first_contact.clear();
            self.decision.clear();
            self.revolutions = 0;
            self.pulses = 0;
        }
        self.armed = level;
    }

    /// The contact line changed to `level`. A rising edge sets the sticky bit and, while
    /// armed, latches the first-contact position (and decides, for single-pulse method).
    pub fn on_contact(&mut self, level: bool) {
        self.contact = level;
        if level {
            self.sticky = true;
            if self.armed {
                let position = self.scale.position();
                self.first_contact.capture(position);
                if self.method == DecisionMethod::SinglePulse {
                    self.decision.capture(position);
                }
            }
        }
    }

    /// An index pulse (start of a revolution).
    pub fn on_index(&mut self) {
        if self.armed {
            self.counter.on_index();
            self.revolutions = self.revolutions.saturating_add(1);
        }
    }

    /// An FES pulse: forms the pulse's contact bit by the configured rule, consumes the
    /// sticky bit, and while armed feeds the counter and the capacitor; the configured
    /// detector's decision latches the position.
    pub fn on_fes(&mut self) {
        self.on_fes_raises();
    }

    /// [`Measurement::on_fes`], returning whether this pulse raised "register now" (its
    /// decision latched the position). A pulse never lowers it, so a caller driving the
    /// output pin needs to drive it only when this is `true`.
    #[inline(always)]
    pub fn on_fes_raises(&mut self) -> bool {
        let bit = self.next_pulse_bit();
        self.sticky = self.contact;
        if !self.armed {
            return false;
        }
        self.pulses = self.pulses.wrapping_add(1);
        // Both detectors step on every pulse; the configured one's decision latches the
        // position (single pulse: neither). The method is read only when a detector
        // decides, which is rare.
        let counter_decides = self.counter.on_pulse(bit) && self.method == DecisionMethod::Counter;
        let density_decides = self.density.on_pulse(bit) && self.method == DecisionMethod::Density;
        (counter_decides || density_decides) && self.decision.capture(self.scale.position())
    }

    /// `n` FES pulses with no other event between them, as a hardware counter reports
    /// them: the same state as `n` calls of [`Measurement::on_fes`] (the first pulse takes
    /// the contact rule's bit, the others the contact level), at the cost of one call
    /// (constant time but for the exponential charge law, see
    /// [`DensityDetector::on_pulses`]). Returns whether one of them raised "register now";
    /// the position latched is the one all of them see. The firmware counts FES pulses in
    /// a timer and folds them in with this before every other event.
    pub fn on_fes_run(&mut self, n: u32) -> bool {
        if n == 0 {
            return false;
        }
        let first = self.next_pulse_bit();
        self.sticky = self.contact;
        if !self.armed {
            return false;
        }
        self.pulses = self.pulses.wrapping_add(n);
        let rest = self.contact;
        let counter_decides =
            self.counter.on_pulses(first, rest, n) && self.method == DecisionMethod::Counter;
        let density_decides =
            self.density.on_pulses(first, rest, n) && self.method == DecisionMethod::Density;
        (counter_decides || density_decides) && self.decision.capture(self.scale.position())
    }

    /// How many more FES pulses, with no other event between them, raise "register now":
    /// `Some(k)` when the `k`-th does, `1 <= k <= limit`; `None` when none of the next
    /// `limit` does (disarmed, decided, single-pulse method, or not that soon). The
    /// firmware sets its FES counter's compare interrupt from this, so the deciding pulse
    /// interrupts and no other pulse need to.
    pub fn fes_to_decision(&self, limit: u32) -> Option<u32> {
        if !self.armed || self.decision.valid() {
            return None;
        }
        let first = self.next_pulse_bit();
        let rest = self.contact;
        let k = match self.method {
            DecisionMethod::Counter => self.counter.pulses_to_decision(first, rest),
            DecisionMethod::Density => self.density.pulses_to_fire(first, rest, limit),
            DecisionMethod::SinglePulse => None,
        }?;
        (k <= limit).then_some(k)
    }

    /// The contact bit the next FES pulse carries under the configured rule: the contact
    /// level (sampled) or whether contact was seen since the previous pulse (sticky).
    #[inline(always)]
    fn next_pulse_bit(&self) -> bool {
        match self.rule {
            ContactRule::Sampled => self.contact,
            ContactRule::Sticky => self.sticky,
        }
    }

    /// New levels of the scale's A and B lines.
    pub fn on_scale(&mut self, a: bool, b: bool) {
        self.scale.on_ab(a, b);
    }

    /// Test hook ([`crate::measure::events::MeasureEvent::PresetPulses`]): the FES pulse count
    /// since arm becomes `pulses`; nothing else changes.
    pub fn preset_pulses(&mut self, pulses: u32) {
        self.pulses = pulses;
    }

    /// Whether "register now" is raised.
    pub fn register_now(&self) -> bool {
        self.decision.valid()
    }

    /// Snapshot of every output.
    pub fn outputs(&self) -> MeasureOutputs {
        MeasureOutputs {
            armed: self.armed,
            contact: self.contact,
            register_now: self.decision.valid(),
            decision_position: self.decision.position(),
            first_contact: self.first_contact.valid(),
            first_contact_position: self.first_contact.position(),
            position: self.scale.position(),
            scale_errors: self.scale.errors(),
            count: self.counter.count(),
            last_window_count: self.counter.last_window_count(),
            charge: self.density.charge(),
            density_armed: self.density.armed(),
            density_fired: self.density.fired(),
            revolutions: self.revolutions,
            pulses: self.pulses,
        }
    }

    /// The pulse counter (read-only).
    pub fn counter(&self) -> &PulseCounter {
        &self.counter
    }
    /// The density detector (read-only).
    pub fn density(&self) -> &DensityDetector {
        &self.density
    }
    /// The quadrature decoder (read-only).
    pub fn scale(&self) -> &QuadratureDecoder {
        &self.scale
    }
    /// The sticky contact bit.
    pub fn sticky(&self) -> bool {
        self.sticky
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::config::{ChargeLaw, MeasureSettings};
    use proptest::prelude::*;

    fn measurement(method: DecisionMethod, rule: ContactRule) -> Measurement {
        let s = MeasureSettings {
            pulses_per_rev: 16,
            i_def: 8,
            method,
            contact_rule: rule,
            ..Default::default()
        };
        Measurement::new(&s.validate().unwrap())
    }

    #[test]
    fn sticky_rule_counts_a_burst_between_pulses_sampled_does_not() {
        for (rule, expected) in [(ContactRule::Sticky, 1), (ContactRule::Sampled, 0)] {
            let mut m = measurement(DecisionMethod::Counter, rule);
            m.on_arm(true);
            m.on_contact(true);
            m.on_contact(false);
            m.on_fes();
            assert_eq!(m.outputs().count, expected, "{rule:?}");
            m.on_fes();
            assert_eq!(m.outputs().count, expected, "{rule:?}: consumed");
        }
    }

    #[test]
    fn counter_decision_latches_the_position_before_a_same_clock_scale_edge() {
        let mut m = measurement(DecisionMethod::Counter, ContactRule::Sampled);
        m.on_arm(true);
        m.on_scale(true, false);
        m.on_contact(true);
        assert_eq!(m.outputs().first_contact_position, 1);
        for _ in 0..9 {
            m.on_fes();
        }
        m.on_scale(true, true);
        let o = m.outputs();
        assert!(o.register_now);
        assert_eq!((o.decision_position, o.position), (1, 2));
    }

    #[test]
    fn register_bits_truncate_positions_to_scale_bits() {
        let config = MeasureConfig::default();
        let mut m = Measurement::new(&config);
        m.on_scale(false, true);
        let o = m.outputs();
        assert_eq!(o.position, -1);
        let bits = o.register_bits(&config);
        let widths = MeasureOutputs::widths(&config);
        assert_eq!(widths[6], ("position", 24));
        assert_eq!(bits[6], 0xff_ffff, "position -1 in 24 bits");
        assert_eq!(bits[11], 1, "density_armed at reset");
    }

    #[test]
    fn disarm_holds_results_and_rearm_clears_them() {
        let mut m = measurement(DecisionMethod::SinglePulse, ContactRule::Sampled);
        m.on_arm(true);
        m.on_contact(true);
        assert!(m.register_now());
        m.on_arm(false);
        m.on_fes();
        assert!(m.register_now());
        assert_eq!(m.outputs().pulses, 0, "no counting while disarmed");
        m.on_arm(true);
        assert!(!m.register_now());
    }

    prop_compose! {
        /// A random valid configuration over every method, rule and charge law, small
        /// enough that runs of a few hundred pulses cross every threshold.
        fn any_config()(
            method in 0u8..3, sticky in any::<bool>(), exponential in any::<bool>(),
            charge_bits in 4u8..=9, a in any::<u32>(), b in any::<u32>(),
            fire in any::<u32>(), rearm in any::<u32>(), i_def in 0u32..32,
        ) -> MeasureConfig {
            let full = (1u32 << charge_bits) - 1;
            let charge_law = if exponential {
                ChargeLaw::Exponential {
                    charge_shift: (a % (u32::from(charge_bits) + 1)) as u8,
                    discharge_shift: (b % (u32::from(charge_bits) + 1)) as u8,
                }
            } else {
                ChargeLaw::Linear {
                    charge_step: 1 + a % full,
                    discharge_step: 1 + b % full,
                }
            };
            let fire_threshold = 1 + fire % full;
            let s = MeasureSettings {
                pulses_per_rev: 16,
                window_revs: 2,
                i_def,
                method: match method {
                    0 => DecisionMethod::Counter,
                    1 => DecisionMethod::Density,
                    _ => DecisionMethod::SinglePulse,
                },
                contact_rule: if sticky { ContactRule::Sticky } else { ContactRule::Sampled },
                charge_bits,
                charge_law,
                fire_threshold,
                rearm_threshold: rearm % fire_threshold,
                ..Default::default()
            };
            s.validate().unwrap()
        }
    }

    /// A random event: arm, contact, index, scale, or a run of FES pulses (`Err(n)`).
    fn apply_op(m: &mut Measurement, op: u8) -> Result<(), u32> {
        match op % 16 {
            0 => m.on_arm(true),
            1 => m.on_arm(false),
            2 | 3 => m.on_contact(true),
            4 | 5 => m.on_contact(false),
            6 => m.on_index(),
            7 => m.on_scale(op & 16 != 0, op & 32 != 0),
            _ => return Err(u32::from(op >> 2)),
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn a_run_of_fes_pulses_equals_as_many_single_pulses(
            config in any_config(),
            ops in proptest::collection::vec(any::<u8>(), 0..300),
        ) {
            let mut batched = Measurement::new(&config);
            let mut single = batched;
            for (i, op) in ops.into_iter().enumerate() {
                match apply_op(&mut batched, op) {
                    Ok(()) => {
                        let _ = apply_op(&mut single, op);
                    }
                    Err(n) => {
                        let raised = batched.on_fes_run(n);
                        let mut any = false;
                        for _ in 0..n {
                            any |= single.on_fes_raises();
                        }
                        prop_assert_eq!(raised, any, "op {}: run of {} raised", i, n);
                    }
                }
                prop_assert_eq!(batched, single, "state after op {}", i);
            }
        }

        #[test]
        fn fes_to_decision_names_the_pulse_that_raises_register_now(
            config in any_config(),
            ops in proptest::collection::vec(any::<u8>(), 0..200), limit in 0u32..80,
        ) {
            let mut m = Measurement::new(&config);
            for (i, op) in ops.into_iter().enumerate() {
                if let Err(n) = apply_op(&mut m, op) {
                    m.on_fes_run(n);
                }
                let predicted = m.fes_to_decision(limit);
                let mut probe = m;
                let first = (1..=limit).find(|_| probe.on_fes_raises());
                prop_assert_eq!(predicted, first, "after op {}", i);
            }
        }
    }

    proptest! {
        #[test]
        fn on_fes_raises_exactly_when_register_now_rises(
            method in 0u8..3, sticky in any::<bool>(),
            ops in proptest::collection::vec(0u8..12, 0..800),
        ) {
            let method = match method {
                0 => DecisionMethod::Counter,
                1 => DecisionMethod::Density,
                _ => DecisionMethod::SinglePulse,
            };
            let rule = if sticky { ContactRule::Sticky } else { ContactRule::Sampled };
            let mut m = measurement(method, rule);
            for (i, op) in ops.into_iter().enumerate() {
                match op {
                    0 | 1 => m.on_arm(op == 0),
                    2 | 3 => m.on_contact(op == 2),
                    4 => m.on_index(),
                    5 | 6 => m.on_scale(op == 5, op == 6),
                    _ => {
                        let before = m.register_now();
                        let raised = m.on_fes_raises();
                        prop_assert_eq!(raised, !before && m.register_now(), "op {}", i);
                    }
                }
            }
        }
    }
}
