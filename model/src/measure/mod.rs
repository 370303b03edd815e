//! The measurement path: deciding "position reached, register now" from the contact signal,
//! the FES encoder pulses, the index pulse and the linear scale, and latching the position.
//!
//! Three layers, each importing only the ones above it in this list:
//!
//! - [`config`]: the validated configuration every kernel, the firmware and hdl-gen read;
//! - **kernels** ([`pulse_counter`], [`density`], [`quadrature`], [`latch`]): pure state
//!   machines over integers, combined by [`kernel`] into one [`kernel::Measurement`] with
//!   the outputs of [`outputs`], read by an MCU through the register map of
//!   [`mcu_registers`];
//! - **timings**: [`frontend`] clocks the kernel once per FPGA clock (cycle level, RTL
//!   semantics), [`events`] drives it by timestamped events (event level, firmware
//!   semantics). Both call the same kernel methods in the same canonical order, so both
//!   reach the same state.

pub mod calibration;
pub mod checks;
pub mod config;
pub mod density;
pub mod events;
pub mod frontend;
pub mod kernel;
pub mod latch;
pub mod mcu_registers;
pub mod outputs;
pub mod pulse_counter;
pub mod quadrature;
