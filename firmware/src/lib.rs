//! tooltouch-firmware: the golden model's measurement kernels on Cortex-M interrupts.
//!
//! The library is the board-independent part: the interrupt handlers' bodies
//! ([`handlers`]), the co-simulation driver that replays a binary event stream
//! ([`cosim`]), and the stack watermark ([`stack`]). The two RTIC applications in
//! `src/bin/` (QEMU's lm3s6965evb and a Nucleo-F446RE) only bind these handlers to their
//! interrupts and implement [`board::Board`] (pin levels in, "register now" out).
//!
//! Nothing here may panic: the `panic-check` feature links a panic handler that refers to
//! an undefined symbol, so a release build fails to link if any panic path remains.
#![no_std]
#![deny(missing_docs)]

pub mod board;
pub mod cosim;
pub mod handlers;
pub mod interrupts;
mod panic;
#[cfg(feature = "qemu")]
pub mod semihosting;
pub mod stack;

pub use tooltouch_model as model;
