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
//!
//! ## Cargo features
//!
//! None is on by default, and the firmware images enable none of them (its host tests use
//! `testing`).
//!
//! - `serde`: `Serialize`/`Deserialize` for the settings types (the host's TOML files).
//! - `testing`: the test kit `tooltouch_model::testing` (proptest strategies, seeded draws; needs `std`).
//! - `internals`: `tooltouch_model::internals`, read-only snapshots of the kernels' internal state
//!   registers — the glitch filters' counters, the sampling chain's filters, sums and
//!   averages, the estimator's no-load sums and intermediate powers and torques, the
//!   controllers' accumulators, the wear monitor's filter and counters — each with a stable
//!   name and its format (word, fractional bits, clamp), for `tooltouch ranges`. A leaf like
//!   [`units`]: the kernels implement its trait in `#[cfg(feature = "internals")]` blocks
//!   that only read their fields, so with the feature off nothing of it is compiled and with
//!   it on no kernel computes anything differently. `no_std`.
#![no_std]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod fnv;
pub mod force;
#[cfg(feature = "internals")]
pub mod internals;
pub mod measure;
pub mod units;
pub mod validation;
pub mod wire;

#[cfg(feature = "testing")]
extern crate std;
#[cfg(feature = "testing")]
pub mod testing;

pub use measure::checks::{fault, Faults, MeasureChecks};
pub use measure::config::{MeasureConfig, MeasureSettings};
pub use measure::events::{MeasureEvent, TimedEvent};
pub use measure::frontend::{FrontEnd, Pins};
pub use measure::kernel::Measurement;
pub use measure::outputs::{MeasureOutputs, OutputWidth};
