//! Units of the force path: one fixed-point format, I32F32 ([`Fx`]: 32 integer bits, 32
//! fractional bits, range ±2^31, resolution 2^−32), named once per SI unit.
//!
//! A leaf: every module that computes with physical quantities imports its vocabulary from
//! here, and this module imports nothing from the crate. The aliases are the same type, so
//! they document a value's unit without conversions; every operation on them in this crate
//! saturates.

use fixed::types::I32F32;

/// Generic fixed-point quantity, I32F32 (range ±2^31, resolution 2^−32).
pub type Fx = I32F32;
/// Force, newtons, I32F32.
pub type Newtons = I32F32;
/// Torque, newton-metres, I32F32.
pub type NewtonMetres = I32F32;
/// Power, watts, I32F32.
pub type Watts = I32F32;
/// Angular speed, rad/s, I32F32.
pub type RadPerSec = I32F32;
/// Voltage, volts, I32F32.
pub type Volts = I32F32;
/// Current, amperes, I32F32.
pub type Amps = I32F32;
/// Resistance, ohms, I32F32.
pub type Ohms = I32F32;
/// Time, seconds, I32F32.
pub type Seconds = I32F32;
/// Length, metres, I32F32.
pub type Metres = I32F32;
/// Moment of inertia, kg·m², I32F32.
pub type KilogramSquareMetres = I32F32;
/// Viscous friction coefficient B, N·m·s/rad, I32F32.
pub type NmsPerRad = I32F32;
