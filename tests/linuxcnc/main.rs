//! Integration tests of the LinuxCNC HAL component (`host/linuxcnc/hal/tooltouch.comp`) under
//! `halrun` (docs/linuxcnc.md): the component bit for bit against the golden model through
//! LinuxCNC's `streamer` and `sampler`, its refusals, and the measure-then-correct size
//! loop with its measurements made in HAL.
//!
//! `cargo test --release --test linuxcnc`; they need `cargo xtask setup` (linuxcnc-uspace,
//! linuxcnc-uspace-dev) and root (the component is installed into LinuxCNC's module folder,
//! and `halrun` runs as the unprivileged user [`hal::HAL_USER`], created when missing).

#[path = "../common/mod.rs"]
mod common;

mod bit_for_bit;
mod gcode;
mod hal;
mod refusal;
mod size_loop;
