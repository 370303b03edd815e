//! The LinuxCNC HAL component (`host/linuxcnc/hal/tooltouch.comp`) against the golden model
//! (docs/linuxcnc.md): its period semantics over the model ([`period`]), the golden
//! stimulus ([`stimulus`]), and the files of a `halrun` session — the streamer's input, the
//! samplers' output read back as Outputs streams that `tooltouch check` compares
//! ([`files`]); the component's pins and header generated from the model's tables
//! ([`component`]); the measure-then-correct size loop ([`size_loop`]). Beside the code, the
//! component itself over the C ABI: `hal/tooltouch.comp`, `hal/tooltouch_hal.h` and
//! `hal/Makefile`.
//!
//! Depends on the golden model, the plants, the vector formats and the random streams of
//! `tooltouch-stimuli`; must not depend on the firmware or RTL runners, the formal proof,
//! tuning, plots or the command line.

pub mod component;
pub mod files;
pub mod period;
pub mod size_loop;
pub mod stimulus;
