//! tooltouch-firmware: the golden model's measurement kernels on Cortex-M interrupts.
//!
//! The library is the board-independent part: the interrupt handlers' bodies
//! ([`handlers`]), the configuration baked into the image ([`baked`]), the co-simulation driver that replays a binary event stream
//! ([`cosim`]), the measurement tasks' IRQ numbers per board ([`interrupts`]), the lathe player's
//! schedule for the two-board bench ([`player`]) and the
//! stack watermark (`stack`, on the boards). The two RTIC applications, one folder per
//! board in `src/bin/` (QEMU's lm3s6965evb and a Nucleo-F446RE: the board's setup and
//! pins in modules beside the app), only bind these handlers to their interrupts and
//! implement [`board::Board`] (pin levels in, "register now" out).
//!
//! Nothing here may panic: the `panic-check` feature links a panic handler that refers to
//! an undefined symbol, so a release build fails to link if any panic path remains.
//!
//! The board-independent part builds on the host too (the boards' crates are thumb-only
//! dependencies): `tests/handlers` replays event streams through the handlers on a
//! simulated board in each board's interrupt order ([`interrupts`]) against the golden
//! model.
#![no_std]
#![deny(missing_docs)]

pub mod baked;
pub mod board;
pub mod cosim;
pub mod handlers;
pub mod interrupts;
#[cfg(all(feature = "nucleo", target_os = "none"))]
pub mod nucleo;
#[cfg(target_os = "none")]
mod panic;
#[cfg(all(any(feature = "qemu", feature = "emulated"), target_os = "none"))]
pub mod pend;
pub use tooltouch_player as player;
#[cfg(all(any(feature = "qemu", feature = "emulated"), target_os = "none"))]
pub mod semihosting;
#[cfg(all(any(feature = "qemu", feature = "emulated"), target_os = "none"))]
pub mod stack;

pub use tooltouch_model as model;
