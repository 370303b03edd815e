//! proptest strategies: small measurement configurations that decide within a few dozen
//! pulses (every decision method, contact rule and charge law), FES counter start values
//! biased to the 2^32 wrap, and bursts of events (see [`Burst`]) shaped to reach the
//! cases the fold and compare scheduling exist for: a deciding pulse pending with an
//! edge, runs past the fold limit, pulses that pass a new compare value in a handler.

use crate::sim::Burst;
use proptest::prelude::*;
use tooltouch_firmware::model::{MeasureConfig, MeasureEvent};
use tooltouch_model::testing;

/// A valid configuration with short windows and low thresholds, from the model's test kit
/// (its firmware-handlers profile: every field drawn inside its range, so none is rejected).
pub fn config() -> impl Strategy<Value = MeasureConfig> {
    testing::measure_configs(&testing::MeasureProfile::FIRMWARE_HANDLERS)
}

/// The FES counter's value at start: anywhere, or close to the 2^32 wrap.
pub fn start_count() -> impl Strategy<Value = u32> {
    prop_oneof![any::<u32>(), (u32::MAX - 300)..=u32::MAX, 0u32..=300,]
}

/// A count of FES pulses: mostly none or a few, sometimes past the fold limit.
fn pulses() -> impl Strategy<Value = u32> {
    prop_oneof![
        4 => Just(0u32),
        4 => 1u32..=4,
        2 => 5u32..=40,
        1 => 60u32..=140,
    ]
}

/// An edge: mostly contact and scale changes, sometimes the arm line, the index, the
/// pulse-count preset (near the 2^32 wrap), or none.
fn edge() -> impl Strategy<Value = Option<MeasureEvent>> {
    prop_oneof![
        2 => any::<bool>().prop_map(|b| Some(MeasureEvent::Arm(b))),
        1 => Just(Some(MeasureEvent::Arm(true))),
        6 => any::<bool>().prop_map(|level| Some(MeasureEvent::Contact(level))),
        2 => Just(Some(MeasureEvent::Index)),
        6 => any::<(bool, bool)>().prop_map(|(a, b)| Some(MeasureEvent::Scale { a, b })),
        1 => prop_oneof![any::<u32>(), (u32::MAX - 100)..=u32::MAX]
            .prop_map(|n| Some(MeasureEvent::PresetPulses(n))),
        3 => Just(None),
    ]
}

/// One burst.
pub fn burst() -> impl Strategy<Value = Burst> {
    (
        pulses(),
        edge(),
        prop_oneof![6 => Just(0u32), 3 => pulses()],
        any::<bool>(),
    )
        .prop_map(|(pulses_before, edge, pulses_in_handler, observe)| Burst {
            pulses_before,
            edge,
            pulses_in_handler,
            observe,
        })
}

/// A stream: armed first, then `1..=len` bursts.
pub fn stream(len: usize) -> impl Strategy<Value = Vec<Burst>> {
    prop::collection::vec(burst(), 1..=len).prop_map(|mut bursts| {
        bursts.insert(0, Burst::edge(MeasureEvent::Arm(true)));
        bursts
    })
}
