//! tooltouch's vector files and their verdict: the golden model run over a [`Stimulus`], the events and outputs it
//! gives, and their files — VCD for people and EDA tools ([`vcd`]), the compact binary
//! stream for the firmware ([`binary`], over `tooltouch_model::wire`).
//!
//! The two timings meet here. [`events_from_stimulus`] runs the cycle level
//! ([`FrontEnd`]) and lists the events its kernel acted on, timestamped with the clock
//! index (clock `k` = the `k`-th rising edge, from 0); same-clock events come in the
//! canonical order. [`outputs_after_each_event`] replays such a list at event level
//! ([`Measurement::apply_at`]: each event at its time, the FES watchdog's clock) and records every output after each event: the firmware must
//! reproduce exactly these, and after the last event of clock `k` they equal the cycle
//! level's outputs registered after clock `k` (`tests/measure/levels_agree.rs`).
//!
//! The formats live here, each writer beside its reader: VCD ([`vcd`]), the binary event and
//! output streams ([`binary`]), `$readmemh` words for the testbench ([`hex`]), run-length pins
//! and the stimulus files `vectors` reads ([`stimulus_file`]), the golden set a device is
//! checked with ([`golden_set`]); [`check`] compares a device's trace with it and returns a
//! typed verdict; [`output`] writes output folders whole or not at all.
//!
//! Depends on the golden model, hdl-gen (the testbench's word formats) and the plants'
//! stimulus; must not depend on settings files, the co-simulation runners, tuning, plots or
//! the command line.

pub mod binary;
pub mod check;
pub mod cocotb_coverage;
pub mod coverage;
pub mod firmware_error;
pub mod force_run;
pub mod fst;
pub mod golden_set;
pub mod hex;
pub mod output;
pub mod signals;
pub mod stimulus_file;
pub mod vcd;

use tooltouch_model::measure::checks::fault;
use tooltouch_model::measure::frontend::Pins;
use tooltouch_model::{FrontEnd, MeasureConfig, MeasureOutputs, Measurement, TimedEvent};
use tooltouch_plant::stimulus::Stimulus;

/// Runs the cycle-level model from reset over `stimulus` and calls `f(k, pins, front
/// end, edges)` after every clock `k` that was actually clocked. Settled clocks (where
/// [`FrontEnd::is_settled`] holds, so the clock would change nothing but the time) are
/// skipped, their time added to the front end's clock count, so `f` misses only clocks
/// that change no register — but the clock at which the FES watchdog expires is clocked
/// even when settled, since the `faults` output changes there without an edge
/// ([`watchdog_expires_at`] tells it). Returns the number of clocks clocked.
pub fn clock_through(
    stimulus: &Stimulus,
    config: &MeasureConfig,
    f: impl FnMut(u64, Pins, &FrontEnd, tooltouch_model::measure::frontend::Edges),
) -> u64 {
    clock_through_to_end(stimulus, config, f).1
}

/// [`clock_through`], returning the front end after the stimulus's last clock (its clock
/// count = the stimulus's clocks) and the number of clocks clocked.
pub(crate) fn clock_through_to_end(
    stimulus: &Stimulus,
    config: &MeasureConfig,
    mut f: impl FnMut(u64, Pins, &FrontEnd, tooltouch_model::measure::frontend::Edges),
) -> (FrontEnd, u64) {
    let mut fe = FrontEnd::new(config);
    let mut k = 0u64;
    let mut clocked = 0u64;
    for seg in &stimulus.segments {
        let end = k + u64::from(seg.cycles);
        while k < end {
            if fe.is_settled(seg.pins) {
                // Only the time moves on: to the watchdog's expiry if it falls in this
                // segment (clocked below), else to the segment's end.
                let to = watchdog_expiry(&fe).filter(|t| (k..end).contains(t));
                let next = to.unwrap_or(end);
                fe.advance(seg.pins, next - k, |_, _| {});
                k = next;
                if to.is_none() {
                    break;
                }
            }
            let edges = fe.clock(seg.pins);
            f(k, seg.pins, &fe, edges);
            clocked += 1;
            k += 1;
        }
    }
    (fe, clocked)
}

/// The clock after which the FES watchdog of `fe` will show `fes_timeout`, if it is
/// armed, running and not yet expired (the model's [`Measurement::fes_deadline`]).
fn watchdog_expiry(fe: &FrontEnd) -> Option<u64> {
    let m = fe.measurement();
    let shown = fe.outputs().faults & fault::FES_TIMEOUT != 0;
    m.fes_deadline().filter(|_| !shown)
}

/// Whether the FES watchdog of `fe` expired at clock `k` (the front end's last clock):
/// `faults` after clock `k` differs from after clock `k − 1` though the kernel may have
/// acted on no edge. Besides the edges the kernel acted on, the only way an output changes
/// from one clock to the next.
pub fn watchdog_expires_at(fe: &FrontEnd, k: u64) -> bool {
    let m = fe.measurement();
    k > 0 && m.checks().fes_at() < k && {
        let armed = m.outputs_at(k).armed;
        m.checks().faults_at(k, armed) != m.checks().faults_at(k - 1, armed)
    }
}

/// Runs the cycle-level model over every clock of `stimulus`, one `clock` call each, no
/// skipping (the reference the skipping runs are checked against; slow for long runs).
pub fn clock_every_cycle(
    stimulus: &Stimulus,
    config: &MeasureConfig,
    mut f: impl FnMut(u64, &FrontEnd, tooltouch_model::measure::frontend::Edges),
) {
    let mut fe = FrontEnd::new(config);
    let mut k = 0u64;
    for seg in &stimulus.segments {
        for _ in 0..seg.cycles {
            let edges = fe.clock(seg.pins);
            f(k, &fe, edges);
            k += 1;
        }
    }
}

/// The events the cycle-level kernel acted on over `stimulus`, timestamped with the clock
/// index at which it acted (FPGA clocks from 0), same-clock events in canonical order
/// (arm, contact, index, FES, scale). This is the firmware's input stream for the
/// scenario; replaying it with [`outputs_after_each_event`] reproduces every output.
pub fn events_from_stimulus(stimulus: &Stimulus, config: &MeasureConfig) -> Vec<TimedEvent> {
    let mut events = Vec::new();
    clock_through(stimulus, config, |k, _, _, edges| {
        edges.for_each_event(|event| events.push(TimedEvent { time: k, event }));
    });
    events
}

/// Replays `events` at event level from reset and returns, for each event, its time and
/// every output after it (the expected response of a device driven by events).
pub fn outputs_after_each_event(
    events: &[TimedEvent],
    config: &MeasureConfig,
) -> Vec<(u64, MeasureOutputs)> {
    let mut m = Measurement::new(config);
    events
        .iter()
        .map(|e| {
            m.apply_at(e.time, e.event);
            (e.time, m.outputs())
        })
        .collect()
}

/// The cycle-level outputs after every clock at which they changed: `(clock, outputs)`,
/// starting with the outputs after the first clock clocked (clock 0 unless the stimulus
/// starts settled).
pub fn output_changes(stimulus: &Stimulus, config: &MeasureConfig) -> Vec<(u64, MeasureOutputs)> {
    let mut out: Vec<(u64, MeasureOutputs)> = Vec::new();
    clock_through(stimulus, config, |k, _, fe, edges| {
        if out.is_empty() || !edges.is_empty() || watchdog_expires_at(fe, k) {
            let o = fe.outputs();
            if out.last().is_none_or(|l| l.1 != o) {
                out.push((k, o));
            }
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::measure::frontend::pin;
    use tooltouch_model::MeasureEvent;

    #[test]
    fn arm_then_contact_events_carry_the_latency() {
        let config = MeasureConfig::default();
        let mut s = Stimulus::new(50_000_000);
        s.push(Pins(0), 10);
        s.push(Pins(pin::ARM), 100);
        s.push(Pins(pin::ARM | pin::CONTACT), 100);
        let ev = events_from_stimulus(&s, &config);
        let l = u64::from(config.latency_cycles());
        assert_eq!(
            ev,
            vec![
                TimedEvent {
                    time: 10 + l,
                    event: MeasureEvent::Arm(true)
                },
                TimedEvent {
                    time: 110 + l,
                    event: MeasureEvent::Contact(true)
                }
            ]
        );
        let outs = outputs_after_each_event(&ev, &config);
        assert!(outs[1].1.first_contact);
    }
}
