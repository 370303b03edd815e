//! Integration tests of the firmware under QEMU against the model: co-simulation, a baked configuration, `cargo run` by convention, the Nucleo image under netduinoplus2, the on-target tests and the lathe player under netduinoplus2.
//!
//! One test binary per area (`cargo test --release --test firmware`); one module per topic
//! (`cargo test --release --test firmware <topic>::`).

#[path = "../common/mod.rs"]
mod common;

mod calibrated;
mod configured;
mod convention;
mod cosim;
mod gates;
mod nucleo;
mod on_target;
mod player;
