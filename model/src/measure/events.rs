//! Event level (firmware semantics): the measurement kernel driven by a stream of
//! timestamped events, one call per event, as the firmware's interrupt handlers do.
//!
//! When several edges are detected in the same FPGA clock, the cycle level applies them in
//! [`MeasureEvent::CANONICAL_ORDER`]; an event stream extracted from a cycle-level run
//! lists them in that order with the same timestamp, so replaying it here reproduces every
//! count, charge and latched position.

use crate::measure::kernel::Measurement;

/// One measurement input event.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeasureEvent {
    /// The CNC's arm (measurement-cycle start / abort) line changed to this level.
    Arm(bool),
    /// The contact line changed to this level.
    Contact(bool),
    /// Rising edge of the index pulse.
    Index,
    /// Rising edge of an FES pulse.
    Fes,
    /// One or both scale lines changed; their new levels.
    Scale {
        /// Line A.
        a: bool,
        /// Line B.
        b: bool,
    },
    /// Test event, no pin (the cycle level never produces it): sets the count of FES
    /// pulses since arm to this value, as if that many pulses had passed, and changes
    /// nothing else. It lets a test reach the count's 2^32 wrap without 2^32 events.
    PresetPulses(u32),
}

/// The kinds of [`MeasureEvent`], in the order same-clock edges are applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MeasureEventKind {
    /// [`MeasureEvent::Arm`].
    Arm,
    /// [`MeasureEvent::Contact`].
    Contact,
    /// [`MeasureEvent::Index`].
    Index,
    /// [`MeasureEvent::Fes`].
    Fes,
    /// [`MeasureEvent::Scale`].
    Scale,
    /// [`MeasureEvent::PresetPulses`] (a test event; after every pin event of its time).
    PresetPulses,
}

impl MeasureEvent {
    /// Order of same-clock events: arm, contact, index, FES, scale. Arm first so an
    /// edge arriving with the arm is counted; index before FES so the pulse at the index
    /// is the new revolution's first; scale last so latches hold the position as it was at
    /// the start of the clock.
    pub const CANONICAL_ORDER: [MeasureEventKind; 5] = [
        MeasureEventKind::Arm,
        MeasureEventKind::Contact,
        MeasureEventKind::Index,
        MeasureEventKind::Fes,
        MeasureEventKind::Scale,
    ];

    /// This event's kind.
    pub fn kind(&self) -> MeasureEventKind {
        match self {
            MeasureEvent::Arm(_) => MeasureEventKind::Arm,
            MeasureEvent::Contact(_) => MeasureEventKind::Contact,
            MeasureEvent::Index => MeasureEventKind::Index,
            MeasureEvent::Fes => MeasureEventKind::Fes,
            MeasureEvent::Scale { .. } => MeasureEventKind::Scale,
            MeasureEvent::PresetPulses(_) => MeasureEventKind::PresetPulses,
        }
    }
}

/// An event with its time, in ticks of the stream's clock (FPGA clock cycles for streams
/// extracted from the cycle level).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TimedEvent {
    /// Time, ticks.
    pub time: u64,
    /// The event.
    pub event: MeasureEvent,
}

impl Measurement {
    /// Applies one event: the event level's whole step.
    #[inline]
    pub fn apply(&mut self, event: MeasureEvent) {
        match event {
            MeasureEvent::Arm(level) => self.on_arm(level),
            MeasureEvent::Contact(level) => self.on_contact(level),
            MeasureEvent::Index => self.on_index(),
            MeasureEvent::Fes => self.on_fes(),
            MeasureEvent::Scale { a, b } => self.on_scale(a, b),
            MeasureEvent::PresetPulses(n) => self.preset_pulses(n),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_order_is_the_kind_order() {
        let mut sorted = MeasureEvent::CANONICAL_ORDER;
        sorted.sort();
        assert_eq!(sorted, MeasureEvent::CANONICAL_ORDER);
    }
}
