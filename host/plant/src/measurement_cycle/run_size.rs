//! The size of a measurement run, checked before it starts: its event vectors are held in
//! memory, so settings that would make more than [`MAX_EVENTS`] events (a tiny feed over a
//! large clearance, thousands of repeats) are refused with the figures that make them.

use crate::lathe::LatheScenario;
use tooltouch_model::MeasureConfig;

/// Most input events a run may make: about [`BYTES_PER_EVENT`] each in memory across the
/// stimulus, the event list, the expected outputs and their encodings (measured: 93 MB
/// peak for 664 000 events), so 16 million events are about 2 GB.
pub const MAX_EVENTS: f64 = 16e6;

/// Memory a run holds per input event, bytes (see [`MAX_EVENTS`]).
pub const BYTES_PER_EVENT: f64 = 125.0;

/// A run that would make more events than [`MAX_EVENTS`]; the message gives its figures and
/// which settings to change.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct RunTooLarge(String);

/// Refuses a run whose event vectors would not fit in memory, before it starts: the
/// estimate is the FES pulses of every measurement's approach (bounded by
/// `max_approach_revs`), retract and Z dwell, about one input event each.
pub fn check_run_size(
    scenario: &LatheScenario,
    config: &MeasureConfig,
) -> Result<f64, RunTooLarge> {
    let c = &scenario.cycle;
    let feed_um_per_rev = scenario.feed_mm_per_rev * 1000.0;
    let window = f64::from(config.settings().window_revs);
    let approach_revs = (c.clearance_um / feed_um_per_rev + 2.0 * window + 4.0)
        .min(f64::from(c.max_approach_revs) + 2.0 * window + 4.0);
    let revs_per_s = scenario.rpm / 60.0;
    let retract_s = (c.clearance_um * 1e-3 + 0.1) / c.retract_mm_per_s;
    let other_revs = revs_per_s * (c.z_dwell_ms * 1e-3 + retract_s);
    let revs = f64::from(c.repeats) * (approach_revs + other_revs);
    let events = revs * f64::from(config.pulses_per_rev());
    if events > MAX_EVENTS {
        return Err(RunTooLarge(format!(
            "this run would make about {events:.3e} events ({revs:.3e} revolutions × {} pulses_per_rev; \
             per measurement up to {approach_revs:.0} revolutions of approach: clearance_um {} / feed_mm_per_rev {} \
             capped by max_approach_revs {}; repeats {}), about {:.1} GB of vectors in memory: \
             the limit is {MAX_EVENTS:.0} events. Lower --repeats, --max-approach-revs or --clearance-um, \
             or raise --feed-mm-per-rev",
            config.pulses_per_rev(),
            c.clearance_um,
            scenario.feed_mm_per_rev,
            c.max_approach_revs,
            c.repeats,
            events * BYTES_PER_EVENT / 1e9
        )));
    }
    Ok(events)
}
