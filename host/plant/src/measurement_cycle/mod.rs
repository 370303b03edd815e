//! The closed-loop measurement cycle (docs/domain.md §2.5): approach at f_r → decide (the golden
//! model's `register_now`) → latch → retract → step in Z → repeat N times → statistics.
//!
//! The driver plays the CNC. It asks the [`Lathe`] for the pins of the next span of clocks
//! (one revolution during an approach), clocks [`FrontEnd`] through them, and reacts to the
//! outputs: when "register now" rises it stops the feed `cnc_reaction_us` later (or, with
//! [`RetractAt::PermanentContact`], once contact has been permanent for a revolution),
//! retracts, lowers the arm line and steps in Z. The pins of a span are cut at the clock
//! where the CNC acted, so the returned [`Stimulus`] is exactly what the front end saw.
//!
//! The CNC reads the measurement status as docs/CONTRACT.md says: it accepts a
//! measurement only when `confirmed` rises with `faults == 0`. With
//! [`RetractAt::Decision`] the feed stops at the reaction after "register now" and the tool
//! stays there until `confirmed` or a fault, then retracts (a reaction later); with
//! [`RetractAt::PermanentContact`] it retracts at permanent contact once the decision is
//! confirmed. A fault alarms at any time: the feed stops a reaction after it and the tool
//! retracts. A measurement that is not accepted reports no diameter
//! ([`MeasurementReport::diameter_mm`]; the latched one stays for diagnosis) and is left
//! out of the statistics. The decisions of a clean run (no fault) are those of the run
//! without the checks, clock for clock: the status only moves the retract.
//!
//! Clocks inside long constant segments are skipped exactly with
//! [`FrontEnd::is_settled`]: a settled front end is unchanged by a clock, so a default run
//! (about 10^9 clocks) clocks only the few clocks after each pin change.

mod report;
mod run_size;
mod stats;

pub use report::MeasurementReport;
pub use run_size::{check_run_size, RunTooLarge, BYTES_PER_EVENT, MAX_EVENTS};
pub use stats::{Spread, Summary};

use crate::lathe::{
    Chunk, CycleSettings, Lathe, LatheScenario, Motion, RetractAt, ScenarioError, Spindle,
};
use crate::stimulus::{Segment, Stimulus};
use tooltouch_model::measure::frontend::Edges;
use tooltouch_model::{Faults, FrontEnd, MeasureConfig};

/// A whole closed-loop run.
#[derive(Clone, Debug)]
pub struct CycleRun {
    /// Every clock's pins, run-length encoded, from power-on to the end of the last
    /// measurement.
    pub stimulus: Stimulus,
    /// One report per measurement.
    pub measurements: Vec<MeasurementReport>,
    /// Statistics over the measurements.
    pub summary: Summary,
    /// Clocks actually clocked (the rest were skipped as settled).
    pub clocked_cycles: u64,
    /// The approach start point's scale count (the count at power-on).
    pub home_count: i64,
}

struct Driver {
    lathe: Lathe,
    fe: FrontEnd,
    stimulus: Stimulus,
    clocked: u64,
    /// Next clock to simulate.
    now: u64,
}

/// What the CNC watches during a span of clocks.
#[derive(Default)]
struct Watch {
    first_contact: Option<u64>,
    decision: Option<u64>,
    /// Clock after which the model's `confirmed` output was first high (while armed).
    confirmed: Option<u64>,
    /// Clock after which the model's `faults` word was first non-zero (while armed).
    fault: Option<u64>,
    window_counts: Vec<u32>,
    /// Last clock to simulate in this span, if the CNC acts before its end.
    stop_after: Option<u64>,
    reaction: u64,
    /// Stop `reaction` clocks after the decision.
    stop_on_decision: bool,
    /// Stop `reaction` clocks after `confirmed` rises.
    stop_on_confirm: bool,
    /// Watch the measurement status: record `confirmed` and the first fault, and stop
    /// `reaction` clocks after a fault (the CNC's alarm).
    status: bool,
}

impl Watch {
    /// Stops the span `reaction` clocks after clock `k`, or earlier if already due.
    fn stop_reacting_to(&mut self, k: u64) {
        let s = k + self.reaction;
        self.stop_after = Some(self.stop_after.map_or(s, |t| t.min(s)));
    }

    fn on_edges(&mut self, k: u64, fe: &FrontEnd, edges: Edges) {
        let m = fe.measurement();
        let out = m.outputs();
        if !out.armed {
            return;
        }
        if self.first_contact.is_none() && out.first_contact {
            self.first_contact = Some(k);
        }
        if self.decision.is_none() && out.register_now {
            self.decision = Some(k);
            if self.stop_on_decision {
                self.stop_after = Some(k + self.reaction);
            }
        }
        if self.status {
            if self.confirmed.is_none() && out.confirmed {
                self.confirmed = Some(k);
                if self.stop_on_confirm {
                    self.stop_reacting_to(k);
                }
            }
            if self.fault.is_none() && out.faults != 0 {
                self.fault = Some(k);
                self.stop_reacting_to(k);
            }
        }
        let index = tooltouch_model::measure::frontend::pin::INDEX;
        if edges.changed & edges.levels & index != 0 {
            self.window_counts.push(m.counter().last_window_count());
        }
    }

    /// The faults that rise with time alone (the FES watchdog) during clocks `from..=to`,
    /// in which no event is applied: records the first clock showing one and stops the
    /// span `reaction` clocks after it.
    fn on_time(&mut self, from: u64, to: u64, fe: &FrontEnd) {
        if !self.status || self.fault.is_some() {
            return;
        }
        let m = fe.measurement();
        // Held faults of the previous measurement (the arm low) are not this one's.
        let faulted = |t: u64| {
            let out = m.outputs_at(t);
            out.armed && out.faults != 0
        };
        if !faulted(to) {
            return;
        }
        // The watchdog's verdict only ever turns on as time passes: bisect for its start.
        let (mut lo, mut hi) = (from, to);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if faulted(mid) {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        self.fault = Some(lo);
        self.stop_reacting_to(lo);
    }
}

impl Driver {
    /// Clocks the front end through `chunk` from its start, stopping after the clock
    /// `watch.stop_after` if that comes first; appends the used pins to the stimulus and
    /// commits the lathe. Returns one past the last clock used.
    fn run(&mut self, chunk: &Chunk, watch: &mut Watch) -> u64 {
        debug_assert_eq!(chunk.start, self.now);
        let mut k = chunk.start;
        'segments: for seg in &chunk.segments {
            let end = k + u64::from(seg.cycles);
            while k < end {
                if watch.stop_after.is_some_and(|s| k > s) {
                    break 'segments;
                }
                if self.fe.is_settled(seg.pins) {
                    let limit =
                        |watch: &Watch| watch.stop_after.map_or(end, |s| end.min(s + 1)).max(k + 1);
                    watch.on_time(k, limit(watch) - 1, &self.fe);
                    let skip_to = limit(watch);
                    // Settled clocks change no register; the front end's time moves on.
                    self.fe.advance(seg.pins, skip_to - k, |_, _| {});
                    k = skip_to;
                    continue;
                }
                let edges = self.fe.clock(seg.pins);
                self.clocked += 1;
                if !edges.is_empty() {
                    watch.on_edges(k, &self.fe, edges);
                } else {
                    watch.on_time(k, k, &self.fe);
                }
                k += 1;
            }
        }
        let used = k.min(chunk.end);
        for s in chunk.truncated_segments(used - chunk.start) {
            self.stimulus.push(s.pins, s.cycles.into());
        }
        self.lathe.commit(chunk, used);
        self.now = used;
        used
    }

    /// Holds the slide at `x_um` with the arm at `arm` until clock `until`.
    fn hold(&mut self, until: u64, x_um: f64, arm: bool) {
        if until > self.now {
            let chunk = self
                .lathe
                .chunk(self.now, until, &Motion::hold(x_um), arm, false);
            self.run(&chunk, &mut Watch::default());
        }
    }
}

/// Unwraps a `bits`-wide two's-complement position to the value nearest `reference`.
pub fn unwrap_position(position: i32, bits: u8, reference: i64) -> i64 {
    let modulus = 1i64 << bits;
    let p = i64::from(position);
    let k = (reference - p + modulus / 2).div_euclid(modulus);
    p + k * modulus
}

/// What one approach saw.
struct ApproachSeen {
    /// First clock of the run of contact that became permanent (a whole revolution).
    permanent: Option<u64>,
    /// Fraction of each revolution in contact.
    contact_fraction: Vec<f64>,
    /// The lathe's scale count at the decision's latch, and at the first contact's.
    decision_count: Option<i64>,
    first_contact_count: Option<i64>,
}

impl Driver {
    /// Feeds in along `approach` one revolution at a time from revolution `r0`, watching
    /// with `watch`, until the CNC stops the feed (at `cycle.retract_at`) or
    /// `cycle.max_approach_revs` pass.
    fn approach(
        &mut self,
        spindle: &Spindle,
        cycle: &CycleSettings,
        approach: &Motion,
        r0: u64,
        watch: &mut Watch,
    ) -> ApproachSeen {
        let mut contact_since: Option<u64> = None;
        let mut permanent: Option<u64> = None;
        let mut contact_fraction = Vec::new();
        let mut decision_count: Option<i64> = None;
        let mut first_contact_count: Option<i64> = None;
        let mut r = r0;
        loop {
            let (a, b) = (spindle.index_rise(r), spindle.index_rise(r + 1));
            let chunk = self.lathe.chunk(a, b, approach, true, true);
            let count_before = self.lathe.count();
            let used = self.run(&chunk, watch);
            // The lathe's scale count at the latching clocks, to unwrap the latched
            // `scale_bits`-wide positions.
            let count_at = |k: u64| {
                chunk
                    .count_changes
                    .iter()
                    .rev()
                    .find(|c| c.0 <= k)
                    .map_or(count_before, |c| c.1)
            };
            for (event, count) in [
                (watch.decision, &mut decision_count),
                (watch.first_contact, &mut first_contact_count),
            ] {
                if let Some(k) = event.filter(|&k| k >= a && k < used) {
                    count.get_or_insert(count_at(k));
                }
            }
            // A piece of a revolution fed only while waiting for the confirmation (permanent
            // contact seen, the decision's reaction long past) is no revolution of the
            // approach's pattern: left out, so the last fraction stays the permanent one.
            let awaiting_confirmation = permanent.is_some()
                && used < b
                && watch.decision.is_some_and(|k| k + watch.reaction < a);
            if !awaiting_confirmation {
                contact_fraction.push(
                    crate::lathe::electrics::covered(&chunk.contact, a, used) as f64
                        / (b - a) as f64,
                );
            }
            if used < b || watch.stop_after.is_some_and(|s| s < used) {
                break;
            }
            // Track the current run of contact across revolutions.
            let mut since =
                contact_since.filter(|_| chunk.contact.first().is_some_and(|&(s, _)| s == a));
            for &(s, e) in &chunk.contact {
                if !(s == a && since.is_some()) {
                    since = Some(s);
                }
                if e < b {
                    since = None;
                }
            }
            contact_since = since;
            if permanent.is_none() && chunk.contact == [(a, b)] {
                permanent = contact_since;
                if cycle.retract_at == RetractAt::PermanentContact {
                    // From now on the CNC retracts once the decision is confirmed.
                    watch.stop_on_confirm = true;
                }
            }
            if let (Some(_), Some(k_c), RetractAt::PermanentContact) =
                (permanent, watch.confirmed, cycle.retract_at)
            {
                if k_c + watch.reaction < b {
                    break;
                }
                watch.stop_after = Some(k_c + watch.reaction);
            }
            r += 1;
            if r - r0 >= u64::from(cycle.max_approach_revs) {
                break;
            }
        }
        ApproachSeen {
            permanent,
            contact_fraction,
            decision_count,
            first_contact_count,
        }
    }

    /// Holds the tool at `x_um` (the feed stopped, the arm high), one revolution at a
    /// time, until the model confirms the decision or raises a fault, then `reaction`
    /// clocks more (the CNC's reaction), or `max_revs` revolutions pass.
    fn await_status(&mut self, spindle: &Spindle, x_um: f64, max_revs: u32, watch: &mut Watch) {
        watch.stop_after = None;
        watch.stop_on_decision = false;
        watch.stop_on_confirm = true;
        let hold = Motion::hold(x_um);
        for _ in 0..max_revs {
            let end = spindle.index_rise(spindle.next_revolution(self.now + 1));
            let chunk = self.lathe.chunk(self.now, end, &hold, true, true);
            let used = self.run(&chunk, watch);
            if used < end || watch.stop_after.is_some_and(|s| s < used) {
                break;
            }
        }
    }

    /// Retracts from where `approach` stopped to `home` µm at `retract` µm per clock, then
    /// holds the arm low for the Z step, `dwell` clocks (at least 64).
    fn retract_and_dwell(&mut self, approach: &Motion, home: f64, retract: f64, dwell: u64) {
        let stop = self.now;
        // Retract to the start point, then lower the arm and step in Z.
        let x_stop = approach.at(stop as f64);
        let retract_cycles = ((home - x_stop).max(0.0) / retract).ceil() as u64 + 1;
        let retract_motion = Motion {
            t0: stop as f64,
            start_um: x_stop,
            speed_um_per_cycle: retract,
        };
        let chunk = self
            .lathe
            .chunk(stop, stop + retract_cycles, &retract_motion, true, false);
        self.run(&chunk, &mut Watch::default());
        self.hold(self.now + dwell.max(64), home, false);
    }
}

/// Runs the whole measurement cycle of `scenario` on the golden model configured by
/// `config`. `progress` is called with the number of measurements done after each one.
pub fn run(
    scenario: &LatheScenario,
    config: &MeasureConfig,
    progress: &mut dyn FnMut(usize),
) -> Result<CycleRun, ScenarioError> {
    let lathe = Lathe::new(scenario, config)?;
    let spindle = *lathe.spindle();
    let cycles_per_us = lathe.cycles_per_us();
    let home_count = lathe.home_count();
    let home = lathe.home_um();
    let res = scenario.scale_resolution_um;
    let cycle = scenario.cycle;
    let mut d = Driver {
        lathe,
        fe: FrontEnd::new(config),
        stimulus: Stimulus::new(scenario.clock_hz),
        clocked: 0,
        now: 0,
    };
    let feed = -scenario.feed_mm_per_rev * 1000.0 / spindle.cycles_per_rev;
    let retract = scenario.cycle.retract_mm_per_s * 1000.0 / f64::from(scenario.clock_hz);
    let reaction = (cycle.cnc_reaction_us * cycles_per_us).round() as u64;
    let dwell = (cycle.z_dwell_ms * 1000.0 * cycles_per_us).round() as u64;
    let bits = config.settings().scale_bits;
    let diameter = |count: i64| 2.0 * (count as f64 + 0.5) * res / 1000.0;
    let mut measurements = Vec::new();

    let per_z = cycle.averages_per_z.max(1) as usize;
    for m in 0..cycle.repeats as usize {
        let z_index = m / per_z;
        if m % per_z == 0 {
            d.lathe.set_z(z_index as u64);
        } else {
            d.lathe.clear_first_touch();
        }
        let true_mean = 2.0 * d.lathe.surface().mean_radius_um() / 1000.0;
        let true_largest = 2.0 * d.lathe.surface().largest_radius_um() / 1000.0;
        // Wait at the start point for the next index pulse (at least 64 clocks after
        // power-on so the synchronizers hold defined levels); the approach starts with it,
        // like a spindle-synchronised (threading-type) feed.
        let r0 = spindle.next_revolution(d.now.max(64));
        let k0 = spindle.index_rise(r0);
        d.hold(k0, home, false);
        d.lathe.start_approach(k0);

        let approach = Motion {
            t0: k0 as f64,
            start_um: home,
            speed_um_per_cycle: feed,
        };
        let mut watch = Watch {
            reaction,
            stop_on_decision: cycle.retract_at == RetractAt::Decision,
            status: true,
            ..Default::default()
        };
        let ApproachSeen {
            permanent,
            contact_fraction,
            decision_count,
            first_contact_count,
        } = d.approach(&spindle, &cycle, &approach, r0, &mut watch);
        let stop = d.now;
        // The CNC retracts once the decision is confirmed or a fault alarms: with
        // `RetractAt::Decision` the feed stopped at the reaction after "register now" and the
        // tool waits there for the status.
        let mut from = approach;
        if watch.decision.is_some() && watch.confirmed.is_none() && watch.fault.is_none() {
            from = Motion::hold(approach.at(stop as f64));
            d.await_status(&spindle, from.start_um, cycle.max_approach_revs, &mut watch);
        }
        let retract_cycle = d.now;
        d.retract_and_dwell(&from, home, retract, dwell);

        let out = d.fe.outputs();
        let decision_position =
            decision_count.map(|c| unwrap_position(out.decision_position, bits, c - home_count));
        let first_contact_position = first_contact_count
            .map(|c| unwrap_position(out.first_contact_position, bits, c - home_count));
        let faults = Faults(out.faults);
        let accepted = decision_position.is_some() && out.confirmed && faults.is_empty();
        let latched_diameter_mm = decision_position.map(|p| diameter(home_count + p));
        // A reading the CNC does not accept is never reported as a measured diameter.
        let diameter_mm = latched_diameter_mm.filter(|_| accepted);
        let revs = |k: Option<u64>| match (k, watch.first_contact) {
            (Some(k), Some(f)) => Some((k as f64 - f as f64) / spindle.cycles_per_rev),
            _ => None,
        };
        measurements.push(MeasurementReport {
            index: m,
            z_mm: z_index as f64 * cycle.z_step_mm,
            arm_cycle: k0,
            first_contact_cycle: watch.first_contact,
            decision_cycle: watch.decision,
            permanent_contact_cycle: permanent,
            stop_cycle: stop,
            confirmed_cycle: watch.confirmed,
            fault_cycle: watch.fault,
            retract_cycle,
            end_cycle: d.now,
            revs_to_decision: revs(watch.decision),
            revs_to_permanent: revs(permanent),
            decision_position,
            first_contact_position,
            confirmed: out.confirmed,
            faults: faults.0,
            fault_names: faults.names().collect(),
            accepted,
            diameter_mm,
            latched_diameter_mm,
            first_contact_diameter_mm: first_contact_position.map(|p| diameter(home_count + p)),
            true_mean_diameter_mm: true_mean,
            true_largest_diameter_mm: true_largest,
            error_vs_mean_um: diameter_mm.map(|x| (x - true_mean) * 1000.0),
            error_vs_largest_um: diameter_mm.map(|x| (x - true_largest) * 1000.0),
            window_counts: watch.window_counts,
            contact_fraction,
        });
        progress(m + 1);
    }
    let summary = Summary::of(&measurements, res);
    Ok(CycleRun {
        stimulus: d.stimulus,
        measurements,
        summary,
        clocked_cycles: d.clocked,
        home_count,
    })
}

/// The closed-loop stimulus of `scenario` alone (see [`run`]).
pub fn closed_loop_stimulus(
    scenario: &LatheScenario,
    config: &MeasureConfig,
) -> Result<Stimulus, ScenarioError> {
    Ok(run(scenario, config, &mut |_| {})?.stimulus)
}

/// Segments of `stimulus` covering clocks `[start, end)`.
pub fn slice(stimulus: &Stimulus, start: u64, end: u64) -> Vec<Segment> {
    let mut out = Vec::new();
    let mut k = 0u64;
    for s in &stimulus.segments {
        let (a, b) = (k, k + u64::from(s.cycles));
        k = b;
        let (a, b) = (a.max(start), b.min(end));
        if a < b {
            out.push(Segment {
                pins: s.pins,
                cycles: (b - a) as u32,
            });
        }
        if k >= end {
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_cycle_decides_every_measurement() {
        let scenario = LatheScenario {
            cycle: crate::lathe::CycleSettings {
                repeats: 3,
                ..Default::default()
            },
            ..Default::default()
        };
        let config = MeasureConfig::default();
        let run = run(&scenario, &config, &mut |_| {}).unwrap();
        for m in &run.measurements {
            // Decided between first contact and permanent contact, and the latched
            // diameter lies between the true mean-ish and largest diameters.
            assert!(m.revs_to_decision.unwrap() < m.revs_to_permanent.unwrap());
            assert!(m.diameter_mm.unwrap() < m.true_largest_diameter_mm);
            assert!(!m.window_counts.is_empty());
            // A clean machine: confirmed, no fault, accepted.
            assert!(m.confirmed && m.faults == 0 && m.accepted, "{m:?}");
            assert!(m.confirmed_cycle.unwrap() >= m.decision_cycle.unwrap());
        }
        assert_eq!(run.summary.faulted, 0);
        assert!(run.clocked_cycles * 50 < run.stimulus.total_cycles());
        assert_eq!(run.summary.decided, 3);
    }
}
