//! The interrupt handlers' bodies, shared by every board: each reads its inputs through
//! [`Board`], steps a golden-model kernel once (the model's event level: one call per
//! event) and drives the outputs.
//!
//! FES pulses raise no interrupt: a hardware counter counts them, and the measurement
//! tasks fold them into the kernel in runs ([`MeasureDomain`]); the counter's compare
//! interrupt fires on the pulse that would decide and at least every [`FES_FOLD_LIMIT`]
//! pulses. At 1024 ppr and 12 000 rpm (204 800 pulses/s) that is 3 200 compare
//! interrupts per second instead of 204 800 pulse interrupts.
//!
//! Priorities (highest first; RTIC applications bind them): the measurement tasks (CNC
//! arm/abort, contact, index, FES compare, scale, observe) at one priority, their IRQ
//! numbers in the model's canonical same-clock order where the board allows it, so that
//! simultaneous edges are taken in that order (Cortex-M takes same-priority pending
//! interrupts lowest number first) and none preempts another: the measurement domain is
//! a lock-free resource. Below them the CNC's
//! force-path commands, the 1 kHz ADC sample and the 20 Hz control period. The control
//! period is long (tens of microseconds) and has 50 ms, so it runs below everything
//! else. The ADC sample does not touch the force kernel: it queues the codes
//! ([`SampleQueue`]) and the control period applies the queued samples before its tick,
//! so the sample interrupt never waits for the control computation.

use crate::board::Board;
use heapless::spsc::{Consumer, Producer, Queue};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::force::sampling::AdcCodes;
use tooltouch_model::measure::calibration::{
    applied_offset, corrected_position, CalibrationRecord,
};
use tooltouch_model::measure::checks::{fault, Faults};
use tooltouch_model::{MeasureConfig, MeasureEvent, MeasureOutputs, Measurement};

/// The most FES pulses folded into the kernel at once: the counter's compare interrupt
/// is set at most this many pulses past the last fold even when none of them can decide.
/// It bounds a fold's work (constant for the linear charge law; one step per pulse for
/// the exponential law: at most this many) and so the delay a fold adds to the other
/// measurement edges, at the cost of one compare interrupt per this many pulses
/// (3 200 per second at 1024 ppr and 12 000 rpm).
pub const FES_FOLD_LIMIT: u32 = 64;

/// The FES watchdog's alarm comes at most this fraction of `fes_timeout_cycles` after the
/// last fold (`T >> FES_WATCHDOG_STEP_SHIFT` ticks, at least 1), so the firmware's last
/// FES time is never more than that behind the last pulse: `fes_timeout` latches between
/// `T` and `T + T/8` ticks after the last FES pulse (docs/firmware.md "The FES
/// watchdog").
pub const FES_WATCHDOG_STEP_SHIFT: u32 = 3;

/// The measurement kernel fed by a hardware FES pulse counter ([`Board::fes_count`]) and
/// told the time by a hardware clock ([`Board::time`]).
///
/// No interrupt per FES pulse: a timer counts them, and every measurement task first
/// tells the kernel the time ([`Measurement::observe`]), then *folds* the pulses counted
/// since the last fold into the kernel ([`Measurement::on_fes_run`], equal to that many
/// single pulses at the fold's time — no other edge came between them, or its task would
/// have folded them), then handles its own event, then sets the counter's compare
/// interrupt at the pulse that would raise "register now"
/// ([`Measurement::fes_to_decision`]) or [`FES_FOLD_LIMIT`] pulses on, whichever comes
/// first, and the clock's alarm for the FES watchdog. The deciding pulse thus interrupts
/// as it did with one interrupt per pulse, and the latched position is the one it saw.
///
/// Time: the kernel counts in ticks of the board's clock ([`Board::time`], 32 bits,
/// extended here to the kernel's 64 by its wrapping difference, so it never goes back).
/// The last FES time the kernel knows is its last fold's time (the pulses carry no time
/// stamp): while armed the alarm ([`Board::set_time_alarm`]) folds at least every
/// `fes_timeout_cycles >> FES_WATCHDOG_STEP_SHIFT` ticks and at the watchdog's deadline,
/// so the fault output rises without any other event.
///
/// Timing: a pulse is counted at its edge but folded when the next measurement task
/// runs; a pulse that arrives between another edge and its task's fold (the interrupt
/// entry, a few dozen cycles) is folded before that edge rather than after it. With one
/// interrupt per pulse the same window existed, in the other direction (same-priority
/// pending interrupts are taken by IRQ number, not by arrival). The FPGA front end
/// orders same-clock edges exactly.
#[derive(Clone, Copy, Debug)]
pub struct MeasureDomain {
    kernel: Measurement,
    /// The counter's value at the last fold.
    folded: u32,
    /// The counter value the compare interrupt is set at.
    compare_at: u32,
    /// The kernel's time, ticks (the board's clock extended to 64 bits).
    now: u64,
    /// The board's clock at the last reading.
    clock: u32,
    /// Time of the last fold, ticks.
    folded_at: u64,
    /// The arm line as the kernel last saw it.
    armed: bool,
    /// `fes_timeout_cycles` (0: the watchdog is off).
    fes_timeout: u64,
}

impl MeasureDomain {
    /// A fresh kernel for `config`, started at the counter's and the clock's current
    /// values (pulses counted before are not its; its time starts at 0), with the compare
    /// interrupt set.
    #[inline]
    pub fn start<B: Board>(config: &MeasureConfig) -> Self {
        let folded = B::fes_count();
        let mut d = MeasureDomain {
            kernel: Measurement::new(config),
            folded,
            compare_at: folded,
            now: 0,
            clock: B::time(),
            folded_at: 0,
            armed: false,
            fes_timeout: config.settings().checks.fes_timeout_cycles.into(),
        };
        d.schedule::<B>();
        d
    }

    /// The kernel as of the last fold.
    pub fn kernel(&self) -> &Measurement {
        &self.kernel
    }

    /// Reads the clock and tells the kernel the time.
    #[inline(always)]
    fn tick<B: Board>(&mut self) {
        let clock = B::time();
        self.now = self
            .now
            .wrapping_add(u64::from(clock.wrapping_sub(self.clock)));
        self.clock = clock;
        self.kernel.observe(self.now);
    }

    /// Reads the clock and tells the kernel the time, then folds the pulses counted since
    /// the last fold; whether one raised "register now".
    #[inline(always)]
    fn fold<B: Board>(&mut self) -> bool {
        self.tick::<B>();
        self.folded_at = self.now;
        let count = B::fes_count();
        let n = count.wrapping_sub(self.folded);
        self.folded = count;
        self.kernel.on_fes_run(n)
    }

    /// Sets the compare interrupt at the pulse that would decide or raise `index_missing`,
    /// or [`FES_FOLD_LIMIT`] pulses past the last fold, and the watchdog's alarm; drives the fault output. A
    /// pulse counted since the fold may already have reached the compare value, which the
    /// timer would then not match until it wraps: the interrupt is pended by hand instead
    /// (a spare compare interrupt only folds nothing); so is an alarm already due.
    #[inline(always)]
    fn schedule<B: Board>(&mut self) {
        let mut due = self
            .kernel
            .fes_to_decision(FES_FOLD_LIMIT)
            .unwrap_or(FES_FOLD_LIMIT);
        if let Some(k) = self.pulses_to_index_missing() {
            due = due.min(k);
        }
        self.compare_at = self.folded.wrapping_add(due);
        B::set_fes_compare(self.compare_at);
        if B::fes_count().wrapping_sub(self.folded) >= due {
            B::pend_fes_compare();
        }
        let faults = self.publish_status::<B>();
        match self.alarm(faults) {
            Some(at) => {
                B::set_time_alarm(Some(
                    self.clock.wrapping_add(at.wrapping_sub(self.now) as u32),
                ));
                if at <= self.now {
                    B::pend_time_alarm();
                }
            }
            None => B::set_time_alarm(None),
        }
    }

    /// How many more FES pulses raise `index_missing` (so the compare interrupt fires on
    /// that pulse and the fault output rises with it): the kernel's prediction.
    #[inline(always)]
    fn pulses_to_index_missing(&self) -> Option<u32> {
        self.kernel.fes_to_index_missing()
    }

    /// Drives the fault output and publishes the status ([`Board::set_status`]); the
    /// faults word now.
    #[inline(always)]
    fn publish_status<B: Board>(&self) -> Faults {
        let faults = self.kernel.checks().faults_at(self.now, self.armed);
        B::set_status(faults.0, self.kernel.checks().confirmed());
        faults
    }

    /// When the watchdog's alarm must next fold, ticks of the kernel's time: while armed
    /// with the watchdog on and not yet expired, the earlier of its deadline (last FES
    /// time + `fes_timeout_cycles`) and one step ([`FES_WATCHDOG_STEP_SHIFT`]) past the
    /// last fold.
    #[inline(always)]
    fn alarm(&self, faults: Faults) -> Option<u64> {
        if faults.contains(fault::FES_TIMEOUT) {
            return None;
        }
        let deadline = self.kernel.fes_deadline()?;
        let step = (self.fes_timeout >> FES_WATCHDOG_STEP_SHIFT).max(1);
        Some(deadline.min(self.folded_at.wrapping_add(step)))
    }

    /// Whether the counter has reached the compare value: a counted pulse not yet folded
    /// may decide (its compare interrupt is pending).
    #[inline(always)]
    fn compare_reached<B: Board>(&self) -> bool {
        let due = self.compare_at.wrapping_sub(self.folded);
        B::fes_count().wrapping_sub(self.folded) >= due
    }
}

/// FES counter compare: the pulse that may decide, or [`FES_FOLD_LIMIT`] pulses since the
/// last fold. Drives "register now" from the kernel's state, not from this fold alone:
/// another task may have folded the deciding pulse first (`observe` does not drive it).
#[inline]
pub fn fes_compare<B: Board>(d: &mut MeasureDomain) {
    d.fold::<B>();
    if d.kernel.register_now() {
        B::set_register_now(true);
    }
    d.schedule::<B>();
}

/// The clock's alarm (the FES watchdog's): folds at the time it fires, so the kernel
/// knows whether FES pulses came, latches `fes_timeout` if none came for
/// `fes_timeout_cycles`, and drives the fault output with no other event.
#[inline]
pub fn time_alarm<B: Board>(d: &mut MeasureDomain) {
    fes_compare::<B>(d);
}

/// Index pulse (start of a revolution): closes the counting window.
#[inline]
pub fn index<B: Board>(d: &mut MeasureDomain) {
    if d.fold::<B>() {
        B::set_register_now(true);
    }
    d.kernel.on_index();
    d.schedule::<B>();
}

/// Contact edge (either direction): the new level is read from the pin. A rising edge
/// sets the sticky bit and latches the first-contact position.
#[inline]
pub fn contact<B: Board>(d: &mut MeasureDomain) {
    d.fold::<B>();
    d.kernel.on_contact(B::contact());
    // A fold or a contact edge can only raise "register now" (single-pulse method).
    if d.kernel.register_now() {
        B::set_register_now(true);
    }
    d.schedule::<B>();
}

/// Scale edge on A or B (either direction): the quadrature decoder steps. Scale edges
/// change no count, so they fold only when a counted pulse may have decided: its
/// position is the one before this edge, whichever interrupt the NVIC takes first.
/// Otherwise they only tell the kernel the time (an illegal transition latches
/// `scale_error`, which the fault output shows at once).
#[inline]
pub fn scale<B: Board>(d: &mut MeasureDomain) {
    d.tick::<B>();
    if d.compare_reached::<B>() {
        fes_compare::<B>(d);
    }
    let (a, b) = B::scale();
    d.kernel.on_scale(a, b);
    d.publish_status::<B>();
}

/// CNC command: the arm line changed. Rising: start a measurement cycle (clears the
/// decision and the faults, so "register now" and the fault output drop); falling: abort /
/// end it, results and faults held.
#[inline]
pub fn cnc_command<B: Board>(d: &mut MeasureDomain) {
    d.fold::<B>();
    let arm = B::arm();
    d.kernel.on_arm(arm);
    d.armed = arm;
    B::set_register_now(d.kernel.register_now());
    d.schedule::<B>();
}

/// Test event (co-simulation only, no pin): the FES pulse count since arm becomes
/// `pulses`, so the count's 2^32 wrap is reached without 2^32 pulses.
#[inline]
pub fn preset_pulses<B: Board>(d: &mut MeasureDomain, pulses: u32) {
    if d.fold::<B>() {
        B::set_register_now(true);
    }
    d.kernel.apply(MeasureEvent::PresetPulses(pulses));
    d.schedule::<B>();
}

/// Snapshot of every output for lower-priority code (idle's log, the co-simulation
/// trace) at the time it runs: folds the counted pulses first, so the snapshot is exact.
/// It does not drive "register now": the compare interrupt, pending whenever a counted
/// pulse decided and taken before this task, does (a co-simulation trace checks the pin,
/// so a missed compare shows).
#[inline]
pub fn observe<B: Board>(d: &mut MeasureDomain) -> MeasureOutputs {
    d.fold::<B>();
    d.schedule::<B>();
    d.kernel.outputs()
}

/// The decision as the firmware reports it: the position the FPGA (here the kernel) latched
/// at "register now", corrected by the baked reference-part calibration
/// (model::measure::calibration: `decision_position − offset`, wrapped to `scale_bits`).
/// Set once per configuration: the offset is the calibration's for the configuration it
/// was made with, 0 for another one or without a calibration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReportedDecision {
    offset: i32,
    scale_bits: u8,
}

impl ReportedDecision {
    /// The report for runs in `config` with `calibration` baked.
    pub fn new(calibration: Option<&CalibrationRecord>, config: &MeasureConfig) -> Self {
        ReportedDecision {
            offset: applied_offset(calibration, config),
            scale_bits: config.settings().scale_bits,
        }
    }

    /// The offset subtracted, scale counts.
    pub fn offset(&self) -> i32 {
        self.offset
    }

    /// The corrected decision position of the outputs `o`, scale counts.
    pub fn position(&self, o: &MeasureOutputs) -> i32 {
        corrected_position(o.decision_position, self.offset, self.scale_bits)
    }
}

/// Queued ADC samples: one control period holds `samples_per_period` (50 at docs/domain.md §3:
/// 1 kHz / 20 Hz); the capacity leaves room for a control period that starts late.
pub const SAMPLE_QUEUE: usize = 256;
/// The ADC-to-control sample queue (single producer, single consumer, lock-free).
pub type SampleQueue = Queue<AdcCodes, SAMPLE_QUEUE>;
/// The ADC interrupt's end of the queue.
pub type SampleProducer<'a> = Producer<'a, AdcCodes>;
/// The control period's end of the queue.
pub type SampleConsumer<'a> = Consumer<'a, AdcCodes>;

/// ADC sample (1 kHz): queue the codes. Returns false when the queue was full and the
/// sample is dropped (count it in [`Counters::overflowed`]).
#[inline]
pub fn adc_sample<B: Board>(queue: &mut SampleProducer<'_>) -> bool {
    queue.enqueue(B::adc()).is_ok()
}

/// Control period (20 Hz): apply the queued samples in order, then the tick (estimate,
/// control, wear), and drive the feed override and the wear alarm.
#[inline]
pub fn control_period<B: Board>(k: &mut ForceKernel, queue: &mut SampleConsumer<'_>) {
    while let Some(codes) = queue.dequeue() {
        k.apply(ForceEvent::Sample(codes));
    }
    k.apply(ForceEvent::Tick);
    drive_force_outputs::<B>(k);
}

/// CNC force-path command (identify, control on/off, conditions, tool changed).
#[inline]
pub fn force_command<B: Board>(k: &mut ForceKernel) {
    if let Some(event) = B::force_command() {
        k.apply(event);
    }
    drive_force_outputs::<B>(k);
}

fn drive_force_outputs<B: Board>(k: &ForceKernel) {
    let o = k.outputs();
    B::set_feed_override(o.override_pct);
    B::set_wear_alarm(o.wear_alarm);
}

/// Counters of events the firmware could not handle, reported with the outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Edges lost because their interrupt was still pending when the next one came
    /// (saturating at `u32::MAX`).
    pub lost: u32,
    /// ADC samples dropped because the sample queue was full (saturating at `u32::MAX`).
    pub overflowed: u32,
}
