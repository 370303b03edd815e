//! tooltouch-model: the golden model of the tooltouch controller.
//!
//! `no_std`, no floating point, no allocation: the firmware links these kernels as they
//! are, and hdl-gen derives the Verilog from [`config`]. Three timings share one logic:
//!
//! - **kernels** — [`pulse_counter`], [`density`], [`quadrature`], [`latch`], combined in
//!   [`measurement`]: pure state machines over integers;
//! - **cycle level** — [`frontend`]: `clock(pins)` once per FPGA clock (RTL semantics);
//! - **event level** — [`events`]: the kernels driven by timestamped events (firmware
//!   semantics).
//!
//! [`wire`] is the binary vector format both the host and the firmware read.
#![no_std]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod config;
pub mod control;
pub mod density;
pub mod estimator;
pub mod events;
pub mod force;
pub mod frontend;
pub mod latch;
pub mod measurement;
pub mod pulse_counter;
pub mod quadrature;
pub mod sampling;
pub mod wear;
pub mod wire;

pub use config::{MeasureConfig, MeasureSettings};
pub use events::{MeasureEvent, TimedEvent};
pub use frontend::{FrontEnd, Pins};
pub use measurement::{MeasureOutputs, Measurement};
