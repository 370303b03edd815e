//! The interrupt handlers' bodies, shared by every board: each reads its pins through
//! [`Board`], steps the golden model's [`Measurement`] kernel once (the event level of
//! the model, one call per event) and drives the "register now" output.
//!
//! The RTIC applications call these inside a lock of the shared `Measurement`; their
//! priorities (highest first): FES, then index / contact / scale, then the CNC command.
//! The FES pulse is the most frequent and the one whose loss would corrupt a count, so it
//! preempts everything; the CNC's arm line changes once per measurement cycle.

use crate::board::Board;
use tooltouch_model::Measurement;

/// FES pulse (rising edge): count the pulse's contact bit, charge the capacitor, decide.
#[inline]
pub fn fes<B: Board>(m: &mut Measurement) {
    m.on_fes();
    B::set_register_now(m.register_now());
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
    B::set_register_now(m.register_now());
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

/// Counters of events the firmware could not handle, reported with the outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Edges lost because their interrupt was still pending when the next one came
    /// (saturating at `u32::MAX`).
    pub lost: u32,
    /// Samples dropped because a queue was full (saturating at `u32::MAX`).
    pub overflowed: u32,
}
