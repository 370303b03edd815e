//! The LinuxCNC HAL component (`host/abi/hal/tooltouch.comp`) against the golden model
//! (docs/linuxcnc.md): its period semantics over the model ([`period`]), the golden
//! stimulus ([`stimulus`]), and the files of a `halrun` session — the streamer's input, the
//! samplers' output read back as Outputs streams that `tooltouch check` compares
//! ([`files`]), and the component's pins and header generated from the model's tables
//! ([`component`]).

pub mod component;
pub mod files;
pub mod period;
pub mod size_loop;
pub mod stimulus;
