//! tooltouch-model: the golden model of the tooltouch controller.
//!
//! `no_std`, no floating point, no allocation: the firmware links these kernels as they
//! are, and hdl-gen derives the Verilog from [`measure::config`]. Two paths share the
//! crate, each in its own room:
//!
//! - **[`measure`]**, the measurement path (contact, FES pulses, index, linear scale →
//!   "position reached, register now" and the latched position). Three timings share one
//!   logic: the **kernels** ([`measure::pulse_counter`], [`measure::density`],
//!   [`measure::quadrature`], [`measure::latch`], combined in [`measure::kernel`]) are pure
//!   state machines over integers; the **cycle level** ([`measure::frontend`]) clocks them
//!   once per FPGA clock (RTL semantics); the **event level** ([`measure::events`]) drives
//!   them by timestamped events (firmware semantics).
//! - **[`force`]**, the force path (spindle-drive signals → feed override and wear alarm):
//!   [`force::sampling`] (1 kHz ADC codes, low-pass, per-period averages) →
//!   [`force::estimator`] (cutting force from the drive's electrical power) →
//!   [`force::control`] (PI, adaptive or fuzzy PI: the CNC's feed override) →
//!   [`force::wear`] (spindle power against the allowed power), combined in the
//!   event-level [`force::kernel`].
//!
//! Below both, leaves that import nothing above them: [`units`] (the I32F32 format and its
//! SI aliases), [`validation`] (range checks and the configuration errors) and [`fnv`]
//! (the configuration hash). Above both, [`wire`]: the binary vector format both the host
//! and the firmware read — a 28-byte header carrying both configurations' hashes, then
//! timestamped records whose kinds are registered in [`wire::kind`], one file per payload
//! with its encoder and decoder. Imports point down only (wire → paths → leaves), so the
//! module graph has no cycle.
#![no_std]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod fnv;
pub mod force;
pub mod measure;
pub mod units;
pub mod validation;
pub mod wire;

#[cfg(feature = "testing")]
extern crate std;
#[cfg(feature = "testing")]
pub mod testing;

pub use measure::config::{MeasureConfig, MeasureSettings};
pub use measure::events::{MeasureEvent, TimedEvent};
pub use measure::frontend::{FrontEnd, Pins};
pub use measure::kernel::Measurement;
pub use measure::outputs::MeasureOutputs;
