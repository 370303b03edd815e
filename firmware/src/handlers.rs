//! The interrupt handlers' bodies, shared by every board: each reads its inputs through
//! [`Board`], steps a golden-model kernel once (the model's event level: one call per
//! event) and drives the outputs.
//!
//! Priorities (highest first; RTIC applications bind them): the measurement edges (CNC
//! arm/abort, contact, index, FES, scale) at one priority, their IRQ numbers in the
//! model's canonical same-clock order, so that simultaneous edges are taken in that order
//! (Cortex-M takes same-priority pending interrupts lowest number first) and none
//! preempts another: the measurement kernel is a lock-free resource, and the FES pulse —
//! 204 800 interrupts/s at 1024 ppr and 12 000 rpm — pays no lock. Below them the CNC's
//! force-path commands, the 1 kHz ADC sample and the 20 Hz control period. The control
//! period is long (tens of microseconds) and has 50 ms, so it runs below everything
//! else. The ADC sample does not touch the force kernel: it queues the codes
//! ([`SampleQueue`]) and the control period applies the queued samples before its tick,
//! so the sample interrupt never waits for the control computation.

use crate::board::Board;
use heapless::spsc::{Consumer, Producer, Queue};
use tooltouch_model::force::{ForceEvent, ForceKernel};
use tooltouch_model::sampling::AdcCodes;
use tooltouch_model::Measurement;

/// FES pulse (rising edge): count the pulse's contact bit, charge the capacitor, decide.
///
/// An FES pulse can raise "register now" (a decision) but never lower it (only the arm
/// line does), so the pin is driven only on the pulse that raises it: the common pulse,
/// which decides nothing, costs nothing for the output.
#[inline(always)]
pub fn fes<B: Board>(m: &mut Measurement) {
    if m.on_fes_raises() {
        B::set_register_now(true);
    }
}

/// Index pulse (start of a revolution): closes the counting window.
#[inline]
pub fn index<B: Board>(m: &mut Measurement) {
    m.on_index();
}

/// Contact edge (either direction): the new level is read from the pin. A rising edge
/// sets the sticky bit and latches the first-contact position.
#[inline]
pub fn contact<B: Board>(m: &mut Measurement) {
    m.on_contact(B::contact());
    // Like an FES pulse, a contact edge can only raise "register now" (single-pulse
    // method).
    if m.register_now() {
        B::set_register_now(true);
    }
}

/// Scale edge on A or B (either direction): the quadrature decoder steps.
#[inline]
pub fn scale<B: Board>(m: &mut Measurement) {
    let (a, b) = B::scale();
    m.on_scale(a, b);
}

/// CNC command: the arm line changed. Rising: start a measurement cycle (clears the
/// decision, so "register now" drops); falling: abort / end it, results held.
#[inline]
pub fn cnc_command<B: Board>(m: &mut Measurement) {
    m.on_arm(B::arm());
    B::set_register_now(m.register_now());
}

/// Test event (co-simulation only, no pin): the FES pulse count since arm becomes
/// `pulses`, so the count's 2^32 wrap is reached without 2^32 interrupts.
#[inline]
pub fn preset_pulses(m: &mut Measurement, pulses: u32) {
    m.apply(tooltouch_model::MeasureEvent::PresetPulses(pulses));
}

/// Queued ADC samples: one control period holds `samples_per_period` (50 at the SPEC's
/// 1 kHz / 20 Hz); the capacity leaves room for a control period that starts late.
pub const SAMPLE_QUEUE: usize = 256;
/// The ADC-to-control sample queue (single producer, single consumer, lock-free).
pub type SampleQueue = Queue<AdcCodes, SAMPLE_QUEUE>;
/// The ADC interrupt's end of the queue.
pub type SampleProducer<'a> = Producer<'a, AdcCodes, SAMPLE_QUEUE>;
/// The control period's end of the queue.
pub type SampleConsumer<'a> = Consumer<'a, AdcCodes, SAMPLE_QUEUE>;

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
