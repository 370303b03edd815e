//! The force path (docs/domain.md §3 and §4): cutting-force control and tool-wear monitoring from the
//! spindle drive's signals.
//!
//! ```text
//! ADC codes ─ sampling ─ estimator ─ control ─ feed override to the CNC
//!   (1 kHz)   (low-pass,  (F1–F9:    (PI, adaptive F11, fuzzy PI; 20 Hz)
//!              boxcar)     F̂_c)
//!                    └──── wear (spindle power vs. W9's allowed power) ─ alarm
//! ```
//!
//! Layers, each importing only those below it: [`config`] (all settings, validated once)
//! and [`events`] on top of the parts; the parts [`sampling`] → [`estimator`] →
//! [`control`] and [`wear`]; [`kernel`] combines them into one event-level
//! [`kernel::ForceKernel`] that the firmware calls per ADC sample, control tick and CNC
//! command. Units (I32F32) come from [`crate::units`], range checks from
//! [`crate::validation`]; the wire encodings of configuration, events and outputs are in
//! [`crate::wire`].

pub mod config;
pub mod control;
pub mod estimator;
pub mod events;
pub mod kernel;
pub mod sampling;
pub mod wear;
