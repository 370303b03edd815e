//! The measurement front end as one kernel: the pulse counter, the density detector, the
//! quadrature decoder and the two position latches, driven one event at a time.
//!
//! This is the logic both timings share. The event level ([`crate::measure::events`]) calls these
//! methods once per timestamped event; the cycle level ([`crate::measure::frontend`]) calls them
//! for the edges detected in one clock, in the canonical order of
//! [`crate::measure::events::MeasureEvent::CANONICAL_ORDER`]: arm, contact, index, FES, scale. The
//! latches therefore capture the scale position as it was *before* a scale edge in the
//! same clock.

use crate::measure::checks::MeasurementChecks;
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
    checks: MeasurementChecks,
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
            checks: MeasurementChecks::new(config),
        }
    }

    /// The stream's clock reads `now` ticks (FPGA clocks at cycle level, the event's
    /// timestamp at event level; never less than before): the time of the events applied
    /// next, and of the FES watchdog ([`crate::measure::checks`]).
    #[inline]
    pub fn observe(&mut self, now: u64) {
        self.checks.observe(now, self.armed);
    }

    /// The CNC's arm line changed. A rising edge starts a measurement cycle: counts,
    /// charge, latches and the decision are cleared. A falling edge ends it; the results
    /// are held for the CNC to read until the next rising edge.
    #[inline]
    pub fn on_arm(&mut self, level: bool) {
        if level && !self.armed {
            self.checks.on_arm(self.contact);
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
    #[inline]
    pub fn on_contact(&mut self, level: bool) {
        self.contact = level;
        if level {
            self.sticky = true;
            if self.armed {
                let position = self.scale.position();
                self.first_contact.capture(position);
                if self.method == DecisionMethod::SinglePulse && self.decision.capture(position) {
                    self.checks.on_decision();
                }
            }
        }
    }

    /// An index pulse (start of a revolution).
    #[inline]
    pub fn on_index(&mut self) {
        if self.armed {
            let closed = self.counter.on_index();
            self.revolutions = self.revolutions.saturating_add(1);
            self.checks.on_index(
                closed,
                self.counter.last_window_count(),
                self.decision.valid(),
                self.revolutions,
            );
        }
    }

    /// An FES pulse: forms the pulse's contact bit by the configured rule, consumes the
    /// sticky bit, and while armed feeds the counter and the capacitor; the configured
    /// detector's decision latches the position.
    #[inline]
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
        self.checks.on_fes(1);
        // Both detectors step on every pulse; the configured one's decision latches the
        // position (single pulse: neither). The method is read only when a detector
        // decides, which is rare.
        let counter_decides = self.counter.on_pulse(bit) && self.method == DecisionMethod::Counter;
        let density_decides = self.density.on_pulse(bit) && self.method == DecisionMethod::Density;
        (counter_decides || density_decides) && self.decide()
    }

    /// A detector decided: latches the position (once per cycle) and starts the
    /// confirmation. Whether it latched.
    #[inline]
    fn decide(&mut self) -> bool {
        let latched = self.decision.capture(self.scale.position());
        if latched {
            self.checks.on_decision();
        }
        latched
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
        self.checks.on_fes(n);
        let rest = self.contact;
        let counter_decides =
            self.counter.on_pulses(first, rest, n) && self.method == DecisionMethod::Counter;
        let density_decides =
            self.density.on_pulses(first, rest, n) && self.method == DecisionMethod::Density;
        (counter_decides || density_decides) && self.decide()
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
    #[inline]
    pub fn on_scale(&mut self, a: bool, b: bool) {
        if self.scale.on_ab(a, b) && self.armed {
            self.checks.on_scale_error();
        }
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

    /// Snapshot of every output at the last observed time ([`Self::observe`]).
    pub fn outputs(&self) -> MeasureOutputs {
        self.outputs_at(self.checks.now())
    }

    /// Snapshot of every output at time `now` (ticks, not before the last observed): the
    /// FES watchdog evaluated at `now`, nothing else changes with time.
    pub fn outputs_at(&self, now: u64) -> MeasureOutputs {
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
            confirmed: self.checks.confirmed(),
            faults: self.checks.faults_at(now, self.armed).0,
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
    /// When the FES watchdog will latch `fes_timeout` if no FES pulse comes first
    /// ([`MeasurementChecks::fes_deadline`]), ticks.
    #[inline]
    pub fn fes_deadline(&self) -> Option<u64> {
        self.checks.fes_deadline(self.armed)
    }

    /// How many more FES pulses raise `index_missing`
    /// ([`MeasurementChecks::pulses_to_index_missing`]).
    #[inline]
    pub fn fes_to_index_missing(&self) -> Option<u32> {
        self.checks.pulses_to_index_missing(self.armed)
    }

    /// The measurement status's checks (read-only).
    pub fn checks(&self) -> &MeasurementChecks {
        &self.checks
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for Measurement {
    /// The pulse counter's (the density detector's charge, the positions and the counts
    /// are outputs; the rest are single bits).
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        crate::internals::Internals::internals(&self.counter, f);
        crate::internals::Internals::internals(&self.checks, f);
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod worked_examples;
