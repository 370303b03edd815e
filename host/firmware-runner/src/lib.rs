//! tooltouch's firmware runners: the RTIC firmware under QEMU against the event-level
//! golden model (this page, [`qemu`], [`trace`]), the Nucleo image under QEMU's
//! netduinoplus2 ([`nucleo`], [`on_target`]), the lathe player's image ([`player`]) and the
//! two-board bench over probe-rs ([`bench`]). The cases are `tooltouch-stimuli`'s.
//!
//! Depends on the golden model, the vector formats, the settings and the random streams of
//! `tooltouch-stimuli`; must not depend on the RTL runners, the formal proof, LinuxCNC,
//! tuning, plots or the command line.
//!
//! ## The firmware under QEMU
//!
//! The host writes each case's event stream in the binary vector format
//! (`model::wire`: an `Events` header, the `MEASURE_CONFIG` record so the firmware
//! configures itself, the force configuration in `FORCE_CONFIG_CHUNK` records when the
//! case has a force path, the events, `END`), concatenates many cases into one file so that
//! one QEMU boot replays them all, boots the firmware, reads its output trace (a
//! `MEASURE_OUTPUTS` record after every event) and compares every output of every event
//! with [`tooltouch_model::Measurement::apply_at`] (each event at its time; with FES runs
//! folded, each FES pulse at the time the firmware folds it: [`golden_observing`]),
//! reporting the first difference with the case, event index, time, signal and both
//! values.

pub mod bench;
pub mod error;
pub mod nucleo;
pub mod on_target;
pub mod player;
pub mod qemu;
pub mod trace;

use std::time::Duration;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::{ForceKernel, ForceOutputs};
use tooltouch_model::measure::calibration::{
    applied_offset, corrected_position, CalibrationRecord,
};
use tooltouch_model::wire::force_chunks::force_config_chunks;
use tooltouch_model::wire::force_event::encode_force_event;
use tooltouch_model::wire::measure_config::encode_config;
use tooltouch_model::wire::measure_event::encode_event;
use tooltouch_model::wire::{self, Header, Record, StreamKind};
use tooltouch_model::{MeasureConfig, MeasureEvent, MeasureOutputs, Measurement};
use tooltouch_vectors::signals::force_signals;

pub use error::{CosimError, Mismatch};
pub use tooltouch_stimuli::{generate, Case, Fault};

/// Which measurement events the firmware writes an outputs record after.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Observe {
    /// After every event: every output of every event is compared, and each FES pulse is
    /// folded into the kernel on its own (the snapshot folds it), so the compare
    /// interrupt is seen to fire on the exact deciding pulse.
    #[default]
    EveryEvent,
    /// After every event but FES pulses: runs of pulses reach the kernel many at a time,
    /// folded by the compare interrupt and the other edges' tasks as on a board, and the
    /// profile shows a board's interrupt costs. Every output is compared after every
    /// other event.
    SkipFes,
}

impl Observe {
    /// Whether the event at hand gets an outputs record.
    pub fn records(self, event: &MeasureEvent) -> bool {
        self == Observe::EveryEvent || *event != MeasureEvent::Fes
    }
}
pub use trace::{Profile, ReportedDecision, StreamTrace};

/// Every output as `(name, value)`, names as in `MeasureOutputs` (docs/CONTRACT.md).
pub fn signals(o: &MeasureOutputs) -> [(&'static str, i64); MeasureOutputs::FIELD_COUNT] {
    o.fields()
}

/// The golden force model's outputs after each force event except samples, with the
/// event's index in `case.force_events`.
pub fn golden_force(case: &Case) -> Vec<(usize, ForceOutputs)> {
    let Some(config) = &case.force else {
        return Vec::new();
    };
    let mut k = ForceKernel::new(config);
    let mut out = Vec::new();
    for (i, (_, e)) in case.force_events.iter().enumerate() {
        k.apply(*e);
        if !matches!(e, ForceEvent::Sample(_)) {
            out.push((i, k.outputs()));
        }
    }
    out
}

/// Appends `case` as one event stream to `out`, every event observed.
pub fn encode_case(case: &Case, out: &mut Vec<u8>) {
    encode_case_observing(case, Observe::EveryEvent, out);
}

/// Appends `case` as one event stream to `out`, with outputs records after the events
/// `observe` names.
pub fn encode_case_observing(case: &Case, observe: Observe, out: &mut Vec<u8>) {
    let header = Header {
        stream: StreamKind::Events,
        tick_hz: case.tick_hz,
        measure_hash: case.config.hash(),
        force_hash: case.force.as_ref().map_or(0, |f| f.hash()),
    };
    out.extend_from_slice(&header.encode());
    let mut buf = [0u8; wire::RECORD_HEADER_LEN + wire::MAX_PAYLOAD];
    let mut put = |r: &Record, out: &mut Vec<u8>| {
        let n = r.encode(&mut buf).unwrap_or(0);
        out.extend_from_slice(&buf[..n]);
    };
    put(&encode_config(&case.config), out);
    // The force configuration, in chunks, before any event (model::wire).
    if let Some(force) = &case.force {
        for r in force_config_chunks(force, 0) {
            put(&r, out);
        }
    }
    if observe != Observe::EveryEvent {
        put(&Record::new(trace::kind::FIRMWARE_OBSERVE, 0, &[0]), out);
    }
    // Merge the two paths by time; on equal times measurement events first (the two
    // kernels are independent, so any tie order gives the same outputs).
    let mut last = 0;
    let (mut i, mut j) = (0, 0);
    while i < case.events.len() || j < case.force_events.len() {
        let m = case.events.get(i);
        let f = case.force_events.get(j);
        let take_measure = match (m, f) {
            (Some(m), Some(f)) => m.time <= f.0,
            (Some(_), None) => true,
            _ => false,
        };
        if let (true, Some(m)) = (take_measure, m) {
            put(&encode_event(m.time, m.event), out);
            last = m.time;
            i += 1;
        } else if let Some((time, e)) = f {
            put(&encode_force_event(*time, e), out);
            last = *time;
            j += 1;
        }
    }
    put(&Record::new(wire::kind::END, last, &[]), out);
}

/// The golden model's outputs after each event of `case`, each applied at its time
/// (`Measurement::apply_at`: the model's event level).
pub fn golden(case: &Case) -> Vec<MeasureOutputs> {
    let mut m = Measurement::new(&case.config);
    case.events
        .iter()
        .map(|e| {
            m.apply_at(e.time, e.event);
            m.outputs()
        })
        .collect()
}

/// The firmware's fold limit (`tooltouch_firmware::handlers::FES_FOLD_LIMIT`): the FES
/// counter's compare is set at most this many pulses past the last fold.
pub const FES_FOLD_LIMIT: u32 = 64;
/// The firmware's watchdog step (`handlers::FES_WATCHDOG_STEP_SHIFT`): while armed, the
/// clock's alarm folds at most `fes_timeout_cycles >> 3` ticks after the last fold.
pub const FES_WATCHDOG_STEP_SHIFT: u32 = 3;

/// The golden model's outputs after each event of `case` as the firmware sees the events
/// when `observe` names them: after every event, each FES pulse is folded into the
/// kernel at its own time, so this is [`golden`]. With FES pulses unobserved
/// ([`Observe::SkipFes`]) the firmware folds runs of pulses and the kernel's time of an
/// FES pulse is the time of its fold (the pulses carry no time stamp: the FES watchdog's
/// resolution, docs/firmware.md): the model is replayed with every FES pulse at the time
/// the firmware folds it — at the pulse the counter's compare fires on (the deciding one,
/// the one raising `index_missing`, or [`FES_FOLD_LIMIT`] past the last fold), at the next other measurement event, or at
/// the clock's alarm ([`FES_WATCHDOG_STEP_SHIFT`], the watchdog's deadline) — so the
/// comparison is exact. Only the watchdog sees the difference; every output but
/// `faults`' `fes_timeout` bit is the same either way.
pub fn golden_observing(case: &Case, observe: Observe) -> Vec<MeasureOutputs> {
    if observe == Observe::EveryEvent {
        return golden(case);
    }
    replay_as_firmware(case, observe, false)
}

/// The firmware's kernel outputs as its log sees them: after every event of `case` and
/// after every fold of the clock's alarm (the FES watchdog's), in time order — the
/// emulated Nucleo's driver logs a change of "register now" or of the status at each of
/// them, as the board's idle would (an alarm may latch `fes_timeout` before the event
/// that shows it in the trace, and that event may add another fault).
pub fn firmware_steps(case: &Case, observe: Observe) -> Vec<MeasureOutputs> {
    replay_as_firmware(case, observe, true)
}

/// The golden model replayed as the firmware folds `case`'s events with `observe`
/// ([`golden_observing`]): the outputs after every event, and after every alarm fold
/// when `alarms`.
fn replay_as_firmware(case: &Case, observe: Observe, alarms: bool) -> Vec<MeasureOutputs> {
    let checks = case.config.settings().checks;
    let timeout = u64::from(checks.fes_timeout_cycles);
    let step = (timeout >> FES_WATCHDOG_STEP_SHIFT).max(1);
    let mut m = Measurement::new(&case.config);
    let mut armed = false;
    // Pulses counted since the last fold, and when the compare interrupt fires.
    let mut pending = 0u32;
    let mut due = FES_FOLD_LIMIT;
    let mut alarm: Option<u64> = None;
    // One measurement task at time `t`: the time, the fold, (the event), the schedule.
    let fold = |m: &mut Measurement, pending: &mut u32, t: u64| {
        m.observe(t);
        m.on_fes_run(*pending);
        *pending = 0;
    };
    let schedule = |m: &Measurement, armed: bool, t: u64| {
        let faults = m.outputs().faults;
        let mut due = m.fes_to_decision(FES_FOLD_LIMIT).unwrap_or(FES_FOLD_LIMIT);
        if armed {
            if let Some(k) = m.fes_to_index_missing() {
                due = due.min(k);
            }
        }
        let expired = faults & tooltouch_model::fault::FES_TIMEOUT != 0;
        let alarm = m
            .fes_deadline()
            .filter(|_| armed && !expired)
            .map(|deadline| deadline.min(t + step).max(t));
        (due, alarm)
    };
    let mut out = Vec::with_capacity(case.events.len());
    for e in &case.events {
        while let Some(at) = alarm.filter(|&at| at <= e.time) {
            fold(&mut m, &mut pending, at);
            (due, alarm) = schedule(&m, armed, at);
            if alarms {
                out.push(m.outputs());
            }
        }
        match e.event {
            MeasureEvent::Fes => {
                pending += 1;
                if pending == due {
                    fold(&mut m, &mut pending, e.time);
                    (due, alarm) = schedule(&m, armed, e.time);
                }
            }
            event => {
                fold(&mut m, &mut pending, e.time);
                m.apply(event);
                if let MeasureEvent::Arm(level) = event {
                    armed = level;
                }
                (due, alarm) = schedule(&m, armed, e.time);
            }
        }
        // The snapshot after an observed event folds (and schedules) at its time.
        if observe.records(&e.event) {
            fold(&mut m, &mut pending, e.time);
            (due, alarm) = schedule(&m, armed, e.time);
        }
        out.push(m.outputs());
    }
    out
}

/// The firmware's decision report, as the golden model gives it: fed the outputs records
/// of one stream in order, it yields a decision for the first record that shows "register
/// now" when the previous one did not — the latched position corrected by the offset the
/// image applies to the stream's configuration (model::measure::calibration; 0 without a
/// calibration or for another configuration).
#[derive(Clone, Copy, Debug)]
pub struct DecisionReporter {
    offset: i32,
    scale_bits: u8,
    reported: bool,
}

impl DecisionReporter {
    /// A stream in `config` on an image built with `calibration`.
    pub fn new(config: &MeasureConfig, calibration: Option<&CalibrationRecord>) -> Self {
        DecisionReporter {
            offset: applied_offset(calibration, config),
            scale_bits: config.settings().scale_bits,
            reported: false,
        }
    }

    /// The decision reported after the outputs record `o`, if any.
    pub fn next(&mut self, o: &MeasureOutputs) -> Option<ReportedDecision> {
        let new = o.register_now && !self.reported;
        self.reported = o.register_now;
        new.then(|| ReportedDecision {
            position: corrected_position(o.decision_position, self.offset, self.scale_bits),
            offset: self.offset,
        })
    }
}

/// The decisions the firmware must report for `case` when `calibration` is baked into the
/// image, with the index of the event after which each is reported ([`DecisionReporter`]
/// over the outputs records `observe` names).
pub fn golden_decisions(
    case: &Case,
    observe: Observe,
    calibration: Option<&CalibrationRecord>,
) -> Vec<(usize, ReportedDecision)> {
    let mut reporter = DecisionReporter::new(&case.config, calibration);
    golden_observing(case, observe)
        .iter()
        .enumerate()
        .filter(|(i, _)| observe.records(&case.events[*i].event))
        .filter_map(|(i, o)| reporter.next(o).map(|d| (i, d)))
        .collect()
}

/// Compares one case's firmware trace with the golden model, every output of every event.
pub fn compare(index: usize, case: &Case, stream: &StreamTrace) -> Result<(), Box<Mismatch>> {
    compare_observing(index, case, Observe::EveryEvent, stream)
}

/// Compares one case's firmware trace with the golden model, every output of every event
/// `observe` names, of an image built without a calibration.
pub fn compare_observing(
    index: usize,
    case: &Case,
    observe: Observe,
    stream: &StreamTrace,
) -> Result<(), Box<Mismatch>> {
    compare_calibrated(index, case, observe, None, stream)
}

/// Compares one case's firmware trace with the golden model, every output of every event
/// `observe` names and every reported decision ([`golden_decisions`]) of an image built
/// with `calibration`.
pub fn compare_calibrated(
    index: usize,
    case: &Case,
    observe: Observe,
    calibration: Option<&CalibrationRecord>,
    stream: &StreamTrace,
) -> Result<(), Box<Mismatch>> {
    let mismatch =
        |event: Option<usize>, time: u64, signal: &str, model: String, firmware: String| {
            Box::new(Mismatch {
                case: index,
                name: case.name.clone(),
                event,
                time,
                signal: signal.to_string(),
                model,
                firmware,
            })
        };
    if stream.measure_hash != case.config.hash() {
        return Err(mismatch(
            None,
            0,
            "measure_hash",
            format!("{:#018x}", case.config.hash()),
            format!("{:#018x}", stream.measure_hash),
        ));
    }
    let expected: Vec<(usize, MeasureOutputs)> = golden_observing(case, observe)
        .into_iter()
        .enumerate()
        .filter(|(i, _)| observe.records(&case.events[*i].event))
        .collect();
    for (record, (i, model)) in expected.iter().enumerate() {
        let (i, event) = (*i, &case.events[*i]);
        let Some((time, fw)) = stream.outputs.get(record) else {
            return Err(mismatch(
                Some(i),
                event.time,
                "outputs record",
                "present".into(),
                "missing".into(),
            ));
        };
        if *time != event.time {
            return Err(mismatch(
                Some(i),
                event.time,
                "time",
                event.time.to_string(),
                time.to_string(),
            ));
        }
        for ((name, want), (_, got)) in signals(model).iter().zip(signals(fw).iter()) {
            if want != got {
                return Err(mismatch(
                    Some(i),
                    event.time,
                    name,
                    want.to_string(),
                    got.to_string(),
                ));
            }
        }
    }
    let decisions = golden_decisions(case, observe, calibration);
    for (k, (i, want)) in decisions.iter().enumerate() {
        let time = case.events[*i].time;
        let Some((fw_time, got)) = stream.decisions.get(k) else {
            return Err(mismatch(
                Some(*i),
                time,
                "decision record",
                "present".into(),
                "missing".into(),
            ));
        };
        if *fw_time != time {
            return Err(mismatch(
                Some(*i),
                time,
                "decision time",
                time.to_string(),
                fw_time.to_string(),
            ));
        }
        for (name, w, g) in [
            ("decision.corrected_position", want.position, got.position),
            ("decision.offset", want.offset, got.offset),
        ] {
            if w != g {
                return Err(mismatch(Some(*i), time, name, w.to_string(), g.to_string()));
            }
        }
    }
    let expected_force = golden_force(case);
    for ((i, model), got) in expected_force.iter().zip(&stream.force_outputs) {
        let time = case.force_events.get(*i).map_or(0, |e| e.0);
        let (fw_time, fw) = got;
        if *fw_time != time {
            return Err(mismatch(
                Some(*i),
                time,
                "force event time",
                time.to_string(),
                fw_time.to_string(),
            ));
        }
        for ((name, want), (_, got)) in force_signals(model).iter().zip(force_signals(fw).iter()) {
            if want != got {
                return Err(mismatch(
                    Some(*i),
                    time,
                    &format!("force.{name}"),
                    want.to_string(),
                    got.to_string(),
                ));
            }
        }
    }
    let p = &stream.profile;
    let all_events = (case.events.len() + case.force_events.len()) as u64;
    let checks = [
        (
            "outputs records",
            expected.len() as u64,
            stream.outputs.len() as u64,
        ),
        (
            "decision records",
            decisions.len() as u64,
            stream.decisions.len() as u64,
        ),
        (
            "force outputs records",
            expected_force.len() as u64,
            stream.force_outputs.len() as u64,
        ),
        ("events replayed", all_events, u64::from(p.events)),
        ("lost events", 0, u64::from(p.lost)),
        ("overflowed events", 0, u64::from(p.overflowed)),
    ];
    for (signal, want, got) in checks {
        if want != got {
            return Err(mismatch(None, 0, signal, want.to_string(), got.to_string()));
        }
    }
    Ok(())
}

/// The result of one batch.
#[derive(Clone, Debug)]
pub struct Report {
    /// Cases run.
    pub cases: usize,
    /// Events replayed in all cases.
    pub events: u64,
    /// QEMU's wall time for the whole batch (boot included).
    pub qemu_time: Duration,
    /// Each case's firmware profile.
    pub profiles: Vec<Profile>,
}

impl Report {
    /// Events per second of QEMU wall time.
    pub fn events_per_second(&self) -> f64 {
        self.events as f64 / self.qemu_time.as_secs_f64().max(1e-9)
    }

    /// Mean instructions per event of kind `k` over all cases (pend to return; see
    /// [`Profile::instructions_per_event`]).
    pub fn instructions_per_event(&self, k: usize) -> Option<f64> {
        let (mut n, mut instr) = (0f64, 0f64);
        for p in &self.profiles {
            if let Some(&(count, ticks)) = p.per_kind.get(k) {
                n += f64::from(count);
                instr += f64::from(ticks) * p.instructions_per_tick();
            }
        }
        (n > 0.0).then(|| instr / n)
    }

    /// The deepest stack the firmware used, bytes.
    pub fn stack_bytes(&self) -> u32 {
        self.profiles
            .iter()
            .map(|p| p.stack_bytes)
            .max()
            .unwrap_or(0)
    }
}

/// Runs every case in one QEMU boot of `image` and compares each with the golden model,
/// every output of every event.
pub fn run_batch(image: &std::path::Path, cases: &[Case]) -> Result<Report, CosimError> {
    run_batch_observing(image, cases, Observe::EveryEvent)
}

/// Runs every case in one QEMU boot of `image` and compares each with the golden model,
/// every output after every event `observe` names.
pub fn run_batch_observing(
    image: &std::path::Path,
    cases: &[Case],
    observe: Observe,
) -> Result<Report, CosimError> {
    let (trace, qemu_time) = qemu::run_image(image, &encode_batch(cases, observe))?;
    check_batch(cases, observe, &trace, qemu_time)
}

/// [`run_batch_observing`] on an image built with `calibration` baked in.
pub fn run_calibrated_batch(
    image: &std::path::Path,
    cases: &[Case],
    observe: Observe,
    calibration: Option<&CalibrationRecord>,
) -> Result<Report, CosimError> {
    let (trace, qemu_time) = qemu::run_image(image, &encode_batch(cases, observe))?;
    check_calibrated_batch(cases, observe, calibration, &trace, qemu_time)
}

/// Every case as one event stream after another (one QEMU boot replays them all), with
/// outputs records after the events `observe` names.
pub fn encode_batch(cases: &[Case], observe: Observe) -> Vec<u8> {
    let mut input = Vec::new();
    for case in cases {
        encode_case_observing(case, observe, &mut input);
    }
    input
}

/// Compares the firmware's `trace` of [`encode_batch`]'s streams with the golden model,
/// every output after every event `observe` names, case by case; `qemu_time` is the run's
/// wall time, for the report.
pub fn check_batch(
    cases: &[Case],
    observe: Observe,
    trace: &[u8],
    qemu_time: Duration,
) -> Result<Report, CosimError> {
    check_calibrated_batch(cases, observe, None, trace, qemu_time)
}

/// [`check_batch`] for an image built with `calibration`: the reported decisions are
/// compared with [`golden_decisions`] of that calibration.
pub fn check_calibrated_batch(
    cases: &[Case],
    observe: Observe,
    calibration: Option<&CalibrationRecord>,
    trace: &[u8],
    qemu_time: Duration,
) -> Result<Report, CosimError> {
    let streams = trace::parse(trace)?;
    if streams.len() != cases.len() {
        return Err(CosimError::Mismatch(Box::new(Mismatch {
            case: streams.len().min(cases.len()),
            name: String::new(),
            event: None,
            time: 0,
            signal: "streams in the trace".into(),
            model: cases.len().to_string(),
            firmware: streams.len().to_string(),
        })));
    }
    for (i, (case, stream)) in cases.iter().zip(&streams).enumerate() {
        compare_calibrated(i, case, observe, calibration, stream).map_err(CosimError::Mismatch)?;
    }
    Ok(Report {
        cases: cases.len(),
        events: cases
            .iter()
            .map(|c| (c.events.len() + c.force_events.len()) as u64)
            .sum(),
        qemu_time,
        profiles: streams.iter().map(|s| s.profile).collect(),
    })
}
