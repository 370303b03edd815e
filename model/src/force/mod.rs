//! The force path (docs/domain.md §3 and §4): cutting-force control and tool-wear monitoring from
//! the spindle drive's signals.
//!
//! ```text
//! ADC codes ─ sampling ─ estimator ─ control ─ feed override to the CNC
//!   (1 kHz)   (low-pass,  (F1–F9:    (PI, adaptive F11, fuzzy PI; 20 Hz)
//!              boxcar)     F̂_c)
//!                    └──── wear (spindle power vs. W9's allowed power) ─ alarm
//! ```
//!
//! Layers, each file importing only from the layers before it:
//!
//! 1. the parts, each with its settings, defaults and range checks: [`sampling`] (ADC
//!    codes to per-period averages in SI units), [`estimator`] (F1–F9 on those averages),
//!    [`control`] (the three controllers behind one trait), [`wear`];
//! 2. [`config`], the parts' settings assembled and validated once, and [`events`], the
//!    path's inputs;
//! 3. [`kernel`], the event-level [`kernel::ForceKernel`] the firmware calls per ADC
//!    sample, control tick and CNC command.
//!
//! Units (I32F32) come from [`crate::units`], range checks from [`crate::validation`]; the
//! wire encodings of configuration, events and outputs are in [`crate::wire`], which this
//! room does not import.

pub mod config;
pub mod control;
pub mod estimator;
pub mod events;
pub mod kernel;
pub mod sampling;
pub mod wear;
