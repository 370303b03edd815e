//! A compact, physically shaped random event generator for the co-simulation (until the
//! lathe simulator's streams are wired in): a spindle turning at a given speed (FES pulses
//! and an index per revolution), a cross-slide feeding toward the workpiece (scale
//! quadrature steps), intermittent contact bursts that grow denser each revolution until
//! contact is permanent (docs/domain.md §2.2, §2.6), the CNC arming a measurement cycle, retracting
//! after "register now" and re-arming for the next Z step (docs/domain.md §2.5) — plus the fault
//! cases: missing index pulses, a spindle that stops (the CNC times out and aborts, no
//! decision), encoder glitches, contact chatter, a broken FES line (revolution counter
//! saturates). Beside it runs the force path ([`crate::force_scenario`]): a random
//! spindle-drive plant from [`tooltouch_plant::drive`] closed around the golden force kernel under
//! a random force configuration (controller kind and gains, set point, filters, estimator,
//! wear thresholds), with ADC saturation as its fault.
//!
//! The measurement stream is integer arithmetic on ticks of [`TICK_HZ`]; the randomness comes from one
//! seed, so a case is reproduced from its seed alone.

use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tooltouch_model::force::config::{ForceConfig, ForceSettings};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::testing;
use tooltouch_model::{MeasureConfig, MeasureEvent, MeasureSettings, Measurement, TimedEvent};

/// Tick rate of generated streams: the FPGA clock, 50 MHz (20 ns per tick).
pub const TICK_HZ: u32 = 50_000_000;

/// Which fault a scenario injects.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fault {
    /// None: a clean measurement cycle.
    None,
    /// Some index pulses are missing (always the second revolution's): `index_missing`.
    MissingIndex,
    /// The spindle stops mid-measurement; the CNC times out and aborts (no decision):
    /// `fes_timeout`.
    SpindleStopped,
    /// Extra FES pulses between the real ones and illegal (double) scale transitions:
    /// `scale_error`.
    EncoderGlitches,
    /// Every contact edge bounces several times, some bounces shorter than one tick apart.
    ContactChatter,
    /// The FES line is broken: index pulses only, 65 536 + of them, so the revolution
    /// counter saturates (16 bits).
    BrokenFesLine,
    /// The spindle-drive ADC channels clip at 0 and 4095 for part of the cut.
    AdcSaturation,
    /// The FES pulse count (32 bits, wrapping) passes 2^32 during the measurement: a
    /// `PresetPulses` test event right after arm sets it a few pulses short of the wrap.
    CounterWrap,
    /// The contact is closed when the first cycle arms (a coolant bridge, the tool
    /// already touching): `contact_at_arm`.
    ContactAtArm,
    /// Every third FES pulse is lost (encoder or cable): `pulses_lost`.
    LostPulses,
    /// No contact ever (a broken contact wire, the tool out of reach): the CNC turns until
    /// `no_decision`.
    NoContact,
    /// A chip under the tool: contact held from the first cycle's arm until the decision,
    /// then none while the tool is still in the air: `unconfirmed`.
    ChipBurst,
}

impl Fault {
    /// Every fault, for cases that must cover each.
    pub const ALL: [Fault; 12] = [
        Fault::None,
        Fault::MissingIndex,
        Fault::SpindleStopped,
        Fault::EncoderGlitches,
        Fault::ContactChatter,
        Fault::BrokenFesLine,
        Fault::AdcSaturation,
        Fault::CounterWrap,
        Fault::ContactAtArm,
        Fault::LostPulses,
        Fault::NoContact,
        Fault::ChipBurst,
    ];
}

/// One co-simulation case: a configuration and the event stream made with it.
#[derive(Clone, Debug)]
pub struct Case {
    /// A name saying how the case was made (seed, fault, speed).
    pub name: String,
    /// The configuration the firmware configures itself with.
    pub config: MeasureConfig,
    /// Ticks per second of the event times.
    pub tick_hz: u32,
    /// The events, in time order (same-time events in canonical order).
    pub events: Vec<TimedEvent>,
    /// The force path's configuration (sent to the firmware in the stream's
    /// `FORCE_CONFIG_CHUNK` records); `None` for a stream without force events.
    pub force: Option<ForceConfig>,
    /// Force-path events, in time order (a sample before a same-time tick).
    pub force_events: Vec<(u64, ForceEvent)>,
}

/// A random valid configuration, drawn by the model's test kit with its lathe
/// co-simulation profile (16–1024 pulses per revolution to keep cases short, `i_def` at
/// 20–80 % of the window) from one `u64` of `rng`.
pub fn random_settings(rng: &mut impl Rng) -> MeasureSettings {
    let strategy = testing::measure_settings(&testing::MeasureProfile::LATHE_COSIM);
    testing::draw(&strategy, rng.random())
}

/// Quadrature phase order for positive motion: A leads B (00, 10, 11, 01).
const PHASES: [(bool, bool); 4] = [(false, false), (true, false), (true, true), (false, true)];

/// Builds the event list; sorts it into time order with same-time events in canonical
/// order (the sort is stable, so same-time, same-kind events keep their order).
struct Builder {
    events: Vec<(u64, u64, MeasureEvent)>,
    seq: u64,
    scale_phase: usize,
    /// The contact level of the last contact event.
    contact: bool,
    /// A CNC that watches "register now" like the real one: the golden model run alongside,
    /// over the events before `cnc_upto`.
    cnc: Measurement,
    cnc_upto: u64,
}

impl Builder {
    fn push(&mut self, time: u64, event: MeasureEvent) {
        self.events.push((time, self.seq, event));
        self.seq += 1;
    }

    /// One quadrature step forward (`+1`) or back (`-1`).
    fn scale_step(&mut self, time: u64, forward: bool) {
        self.scale_phase = if forward {
            (self.scale_phase + 1) % 4
        } else {
            (self.scale_phase + 3) % 4
        };
        let (a, b) = PHASES[self.scale_phase];
        self.push(time, MeasureEvent::Scale { a, b });
    }

    /// An illegal transition: both lines change at once.
    fn scale_glitch(&mut self, time: u64) {
        self.scale_phase = (self.scale_phase + 2) % 4;
        let (a, b) = PHASES[self.scale_phase];
        self.push(time, MeasureEvent::Scale { a, b });
    }

    /// Applies the events not yet applied with `time < until` to the CNC's model in stream
    /// order, each at its time.
    fn run_cnc_until(&mut self, until: u64) {
        let from = self.cnc_upto;
        let mut due: Vec<_> = self
            .events
            .iter()
            .filter(|(time, _, _)| *time >= from && *time < until)
            .copied()
            .collect();
        due.sort_by_key(|&(time, seq, event)| (time, event.kind(), seq));
        for (time, _, e) in due {
            self.cnc.apply_at(time, e);
        }
        self.cnc_upto = until;
    }

    fn finish(mut self) -> Vec<TimedEvent> {
        self.events
            .sort_by_key(|&(time, seq, event)| (time, event.kind(), seq));
        self.events
            .into_iter()
            .map(|(time, _, event)| TimedEvent { time, event })
            .collect()
    }
}

/// A contact interval within one revolution, ticks from the revolution's start.
#[derive(Clone, Copy)]
struct Burst {
    start: u64,
    end: u64,
}

/// The spindle of a case: pulses per revolution and their period, ticks.
#[derive(Clone, Copy)]
struct Spindle {
    ppr: u64,
    fes_period: u64,
    rev_ticks: u64,
}

/// How the contact comes during a measurement cycle: the approach's contact lobes per
/// revolution and the revolutions from the first touch to permanent contact.
#[derive(Clone, Copy)]
struct Approach {
    lobes: u64,
    revs_to_permanent: u64,
}

/// `settings` with the check that latches `fault`'s condition turned on (the random
/// settings may have it off), its threshold reachable by the case: the contact at arm, the
/// revolution and scale checks, a probe fail within 8 revolutions, an FES watchdog of 8
/// FES periods (far below the stopped spindle's 0.1 s), a confirmation of 2 windows at
/// least a quarter full.
fn with_fault_check(
    mut settings: MeasureSettings,
    fault: Fault,
    fes_period: u64,
) -> MeasureSettings {
    let c = &mut settings.checks;
    match fault {
        Fault::ContactAtArm => c.contact_at_arm = true,
        Fault::LostPulses | Fault::MissingIndex => c.revolutions = true,
        Fault::EncoderGlitches => c.scale_errors = true,
        Fault::NoContact if c.probe_revs == 0 => c.probe_revs = 8,
        Fault::SpindleStopped if c.fes_timeout_cycles == 0 => {
            c.fes_timeout_cycles = u32::try_from(8 * fes_period).unwrap_or(u32::MAX);
        }
        Fault::ChipBurst => {
            c.confirm_windows = c.confirm_windows.max(2);
            c.confirm_percent = c.confirm_percent.max(25);
        }
        _ => {}
    }
    settings
}

/// One measurement cycle from time `t` (cycle number `cycle`, the case's `last`): the
/// arm, revolutions of FES pulses and index with the contact approaching and the feed
/// stepping the scale, until the CNC sees "register now" (or gives up), then the arm
/// falling and the retract. Returns the time after it.
fn measurement_cycle(
    b: &mut Builder,
    rng: &mut ChaCha8Rng,
    config: &MeasureConfig,
    (spindle, approach): (Spindle, Approach),
    fault: Fault,
    (cycle, last): (u32, bool),
    mut t: u64,
) -> u64 {
    let Spindle { ppr, rev_ticks, .. } = spindle;
    let checks = config.settings().checks;
    let window_revs = u64::from(config.settings().window_revs);
    t += rng.random_range(1..5000);
    if fault == Fault::ContactAtArm && cycle == 0 {
        // A coolant bridge or the tool already touching: the contact closed before arm.
        b.push(t - 1, MeasureEvent::Contact(true));
        b.contact = true;
    }
    b.push(t, MeasureEvent::Arm(true));
    if fault == Fault::CounterWrap {
        // Short of the wrap by less than one revolution's pulses.
        let short = rng.random_range(1..=ppr as u32);
        b.push(t, MeasureEvent::PresetPulses(u32::MAX - short + 1));
    }
    if fault == Fault::EncoderGlitches && cycle == 0 {
        // Disturbed scale lines: a double change right after arm (more come at random).
        b.scale_glitch(t + 1);
    }
    if fault == Fault::BrokenFesLine {
        for _ in 0..(65_536 + rng.random_range(1..600)) {
            t += rev_ticks.min(1 << 20);
            b.push(t, MeasureEvent::Index);
        }
        t += 100;
        b.push(t, MeasureEvent::Arm(false));
        return t;
    }
    let approach_revs: u64 = rng.random_range(0..3);
    // A chip under the tool decides; the revolutions after it show the tool in the air.
    let chip = fault == Fault::ChipBurst && cycle == 0;
    let mut max_revs = approach_revs + approach.revs_to_permanent + 4 * window_revs + 3;
    if fault == Fault::NoContact {
        // The CNC waits for the probe fail.
        max_revs = max_revs.max(u64::from(checks.probe_revs) + 1);
    }
    if chip {
        max_revs = u64::MAX;
    }
    let stop_after = if fault == Fault::SpindleStopped && last {
        rng.random_range(0..=approach_revs + approach.revs_to_permanent / 2)
    } else {
        u64::MAX
    };
    // Feed: a scale step every `feed_period` ticks toward the workpiece.
    let feed_period = rng.random_range(rev_ticks / 8..=rev_ticks * 2).max(1);
    let mut next_feed = t + feed_period;
    let mut decided_at: Option<u64> = None;
    let rev0 = t + rng.random_range(0..rev_ticks);
    let mut rev = 0u64;
    // Revolutions the CNC still turns after the decision.
    let after_decision = if chip { 1 + 2 * window_revs } else { 1 };
    loop {
        if rev >= max_revs || rev >= stop_after {
            break;
        }
        if decided_at.is_some_and(|r| rev > r + after_decision) {
            break;
        }
        let start = rev0 + rev * rev_ticks;
        // Contact density this revolution, per mille: 0 before the first touch, rising
        // to 1000 (permanent) over `revs_to_permanent` revolutions.
        let density = if fault == Fault::NoContact || rev < approach_revs {
            0
        } else {
            ((rev - approach_revs + 1) * 1000 / approach.revs_to_permanent).min(1000)
        };
        let density = match (chip, decided_at) {
            (true, None) => 1000,
            (true, Some(_)) => {
                if b.contact {
                    b.push(start, MeasureEvent::Contact(false));
                    b.contact = false;
                }
                0
            }
            (false, _) => density,
        };
        contact_edges(b, rng, spindle, approach, fault, start, density);
        next_feed = revolution_pulses(
            b,
            rng,
            spindle,
            fault,
            (rev, start),
            (next_feed, feed_period),
        );
        // The CNC sees "register now" (the model run alongside, up to this revolution's end).
        b.run_cnc_until(start + rev_ticks);
        if decided_at.is_none() && b.cnc.register_now() {
            decided_at = Some(rev);
        }
        rev += 1;
        if rev > 200 {
            break;
        }
    }
    // End of this cycle: the time after the last revolution.
    t = rev0 + rev * rev_ticks + rng.random_range(1..1000);
    if fault == Fault::SpindleStopped && last {
        // CNC timeout: no FES for a while, then abort.
        t += u64::from(TICK_HZ) / 10;
    }
    b.push(t, MeasureEvent::Arm(false));
    // Retract: a few steps back, then the next cycle starts after a Z step.
    if b.contact {
        t += rng.random_range(10..1000);
        b.push(t, MeasureEvent::Contact(false));
        b.contact = false;
    }
    for _ in 0..rng.random_range(0..20) {
        t += rng.random_range(50..2000);
        b.scale_step(t, false);
    }
    b.run_cnc_until(t + 1);
    t
}

/// The contact edges of the revolution starting at `start` with contact density
/// `density` per mille: bursts around the approach's lobes and short noise spikes, merged
/// where they overlap, permanent at 1000 (chattering under [`Fault::ContactChatter`]).
fn contact_edges(
    b: &mut Builder,
    rng: &mut ChaCha8Rng,
    Spindle {
        rev_ticks,
        fes_period,
        ..
    }: Spindle,
    Approach { lobes, .. }: Approach,
    fault: Fault,
    start: u64,
    density: u64,
) {
    let mut bursts = Vec::new();
    if density >= 1000 {
        bursts.push(Burst {
            start: 0,
            end: rev_ticks,
        });
    } else if density > 0 {
        let width = rev_ticks * density / 1000 / lobes;
        for lobe in 0..lobes {
            let center = rev_ticks * lobe / lobes + rng.random_range(0..rev_ticks / lobes / 4 + 1);
            let w = (width * rng.random_range(50..=150) / 100).max(1);
            let s = center.saturating_sub(w / 2).max(1);
            let e = (s + w).min(rev_ticks - 1);
            if e > s {
                bursts.push(Burst { start: s, end: e });
            }
        }
        // Noise spikes: contact shorter than one FES period.
        for _ in 0..rng.random_range(0..3) {
            let s = rng.random_range(1..rev_ticks - 2);
            let e = (s + rng.random_range(1..fes_period.max(2))).min(rev_ticks - 1);
            bursts.push(Burst { start: s, end: e });
        }
        bursts.sort_by_key(|x| x.start);
    }
    // Contact edges of this revolution, merged where bursts overlap.
    let mut edges: Vec<(u64, bool)> = Vec::new();
    let mut open_until = 0u64;
    for burst in bursts {
        if burst.start <= open_until && !edges.is_empty() {
            if burst.end > open_until {
                if let Some(last) = edges.last_mut() {
                    last.0 = start + burst.end;
                }
                open_until = burst.end;
            }
            continue;
        }
        edges.push((start + burst.start, true));
        edges.push((start + burst.end, false));
        open_until = burst.end;
    }
    if density >= 1000 {
        // Permanent: one rising edge (if not in contact yet), no falling edge.
        edges.retain(|e| e.1);
    }
    for (time, level) in edges {
        if level == b.contact {
            continue;
        }
        b.contact = level;
        if fault == Fault::ContactChatter {
            for _ in 0..rng.random_range(1..4) {
                b.push(time, MeasureEvent::Contact(level));
                let d = rng.random_range(0..3);
                b.push(time + d, MeasureEvent::Contact(!level));
            }
            b.push(time + 3, MeasureEvent::Contact(level));
        } else {
            b.push(time, MeasureEvent::Contact(level));
        }
    }
}

/// The spindle's pulses of revolution `rev`, starting at `start` — the index at its start
/// (sometimes missing under [`Fault::MissingIndex`], always in the second revolution),
/// one FES per pulse period (every third lost under [`Fault::LostPulses`], extra ones
/// under [`Fault::EncoderGlitches`]) — and the feed's scale steps due meanwhile (`feed`:
/// the next step's time and the feed period). Returns the next step's time.
fn revolution_pulses(
    b: &mut Builder,
    rng: &mut ChaCha8Rng,
    Spindle {
        ppr, fes_period, ..
    }: Spindle,
    fault: Fault,
    (rev, start): (u64, u64),
    (mut next_feed, feed_period): (u64, u64),
) -> u64 {
    let drop_index = fault == Fault::MissingIndex && (rng.random_bool(0.4) || rev == 1);
    if !drop_index {
        b.push(start, MeasureEvent::Index);
    }
    for p in 0..ppr {
        let tp = start + p * fes_period;
        if !(fault == Fault::LostPulses && p % 3 == 2) {
            b.push(tp, MeasureEvent::Fes);
        }
        if fault == Fault::EncoderGlitches && rng.random_bool(0.01) {
            b.push(tp + rng.random_range(1..fes_period), MeasureEvent::Fes);
        }
        while next_feed <= tp {
            if fault == Fault::EncoderGlitches && rng.random_bool(0.05) {
                b.scale_glitch(next_feed);
            } else {
                b.scale_step(next_feed, true);
            }
            next_feed += feed_period;
        }
    }
    next_feed
}

/// Generates one case from `seed` with `fault`.
pub fn generate(seed: u64, fault: Fault) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let settings = random_settings(&mut rng);
    // random_settings draws every field inside its range; fall back to the defaults if a
    // future range change makes that false, so the case still runs.
    let config = settings.validate().unwrap_or_default();
    let ppr = u64::from(config.pulses_per_rev());
    // Spindle speed, rpm: the papers' 600–1000, sometimes the 12 000 rpm target.
    let rpm: u64 = if rng.random_bool(0.2) {
        12_000
    } else {
        rng.random_range(600..=1000)
    };
    let rev_ticks = u64::from(TICK_HZ) * 60 / rpm;
    let fes_period = (rev_ticks / ppr).max(2);
    let spindle = Spindle {
        ppr,
        fes_period,
        rev_ticks: fes_period * ppr,
    };
    let config = with_fault_check(*config.settings(), fault, fes_period)
        .validate()
        .unwrap_or(config);
    let approach = Approach {
        lobes: rng.random_range(1..=5),
        revs_to_permanent: rng.random_range(2..=12),
    };
    let cycles: u32 = if fault == Fault::BrokenFesLine {
        1
    } else {
        rng.random_range(1..=3)
    };
    let mut b = Builder {
        events: Vec::new(),
        seq: 0,
        scale_phase: 0,
        contact: false,
        cnc: Measurement::new(&config),
        cnc_upto: 0,
    };
    let mut t: u64 = rng.random_range(0..1000);
    // Rapid approach: the cross-slide moves some counts before the cycle starts.
    for _ in 0..rng.random_range(0..40) {
        t += rng.random_range(50..2000);
        b.scale_step(t, true);
    }
    for cycle in 0..cycles {
        let last = cycle + 1 == cycles;
        t = measurement_cycle(
            &mut b,
            &mut rng,
            &config,
            (spindle, approach),
            fault,
            (cycle, last),
            t,
        );
        if fault == Fault::BrokenFesLine {
            break;
        }
    }
    let events = b.finish();
    // The force path runs beside the measurement for about the same time span (2 to 5
    // s, at most 8000 ADC samples so the broken-FES case stays short): a random plant
    // from tooltouch_plant::drive closed around the golden kernel under a random force
    // configuration fitted to it.
    let plant = crate::force_scenario::random_plant(&mut rng);
    let settings = crate::force_scenario::random_force_settings(&mut rng, &plant);
    // random_force_settings draws every field inside its range (a unit test checks it);
    // fall back to the defaults if a future range change makes that false.
    let fc = settings
        .validate()
        .or_else(|_| ForceSettings::default().validate());
    let (force, force_events) = match fc {
        Ok(fc) => {
            let span = events.last().map_or(0, |e| e.time) as f64 / f64::from(TICK_HZ);
            let max_s = 8000.0 / f64::from(fc.settings().sample_hz.max(1));
            let duration = span.clamp(2.0, 5.0).min(max_s);
            let fe = crate::force_scenario::force_events(
                &mut rng,
                &fc,
                &plant,
                TICK_HZ,
                duration,
                fault == Fault::AdcSaturation,
            );
            (Some(fc), fe)
        }
        Err(_) => (None, Vec::new()),
    };
    Case {
        name: format!(
            "seed {seed:#018x}, fault {fault:?}, {rpm} rpm, {ppr} ppr, {:?}, force: {}",
            config.settings().method,
            force.as_ref().map_or("none".to_string(), |f| {
                let s = f.settings();
                format!(
                    "{} controller, {} Hz / {} samples, {} N {:?}",
                    s.controller.name(),
                    s.sample_hz,
                    s.samples_per_period,
                    s.reference,
                    s.force_source
                )
            })
        ),
        config,
        tick_hz: TICK_HZ,
        events,
        force,
        force_events,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::fault;

    /// Every fault bit latched at some point of `case`'s golden outputs (the events
    /// replayed at their times).
    fn faults_seen(case: &Case) -> u8 {
        let mut m = Measurement::new(&case.config);
        let mut seen = 0;
        for e in &case.events {
            m.apply_at(e.time, e.event);
            seen |= m.outputs().faults;
        }
        seen
    }

    /// Each fault case latches its condition, whatever the seed's random settings.
    #[test]
    fn every_fault_case_reaches_its_condition() {
        let cases = [
            (Fault::ContactAtArm, fault::CONTACT_AT_ARM),
            (Fault::LostPulses, fault::PULSES_LOST),
            (Fault::MissingIndex, fault::INDEX_MISSING),
            (Fault::EncoderGlitches, fault::SCALE_ERROR),
            (Fault::NoContact, fault::NO_DECISION),
            (Fault::SpindleStopped, fault::FES_TIMEOUT),
            (Fault::ChipBurst, fault::UNCONFIRMED),
        ];
        for seed in 0..8 {
            for (f, bit) in cases {
                let case = generate(seed, f);
                let seen = faults_seen(&case);
                assert!(
                    seen & bit != 0,
                    "{}: {} never latched (seen: {})",
                    case.name,
                    tooltouch_model::Faults(bit),
                    tooltouch_model::Faults(seen)
                );
            }
        }
    }
}
