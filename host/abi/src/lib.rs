//! tooltouch-abi: the golden model behind a C ABI, for C and C++ programs, SystemVerilog
//! benches (DPI-C) and Icarus (VPI).
//!
//! Everything is reached through opaque handles made from a configuration:
//!
//! | handle | model | made by | stepped by |
//! | --- | --- | --- | --- |
//! | [`TtConfig`] | `MeasureConfig` + `ForceConfig` | [`tt_config_from_bytes`], [`tt_config_from_file`] | — |
//! | [`TtFrontEnd`] | cycle level, `FrontEnd` | [`tt_frontend_new`] | [`tt_frontend_clock`], [`tt_frontend_advance`] |
//! | [`TtMeasurement`] | event level, `Measurement` | [`tt_measurement_new`] | [`tt_measurement_apply`] |
//! | [`TtForce`] | force kernel, `ForceKernel` | [`tt_force_new`] | [`tt_force_apply`] |
//!
//! The configuration comes from a settings file's canonical bytes: the file
//! `tooltouch cosim config --config settings.toml --out config.ttc` writes (`TTFWCFG1`, then
//! the measurement and the force configuration's canonical bytes, each after its length as
//! a little-endian u16), or the 31 bytes of the measurement configuration alone (the force
//! path then runs the default force settings).
//!
//! Rules every function keeps: it returns a [`TtStatus`] (0 is success) and writes its
//! results through out-pointers; a failure leaves a message naming the culprit for
//! [`tt_last_error`] (per thread); no function panics or unwinds into the caller (each body
//! runs under `catch_unwind`, a caught panic is [`TtStatus::Panic`]); only the `*_new` and
//! `*_from_*` functions allocate (the handle itself), the stepping and reading functions
//! never do. Handles are not thread-safe: use one from one thread at a time.
//! [`tt_abi_version`] is [`TT_ABI_VERSION`]; a change that breaks a caller bumps it.
//!
//! One module per handle family: `config` ([`TtConfig`]), `cycle` ([`TtFrontEnd`], the outputs
//! and the MCU register words), `event` ([`TtMeasurement`]), `force` ([`TtForce`]); this page
//! holds the constants, the C structures, the status and error machinery every call shares.
//!
//! Depends on `tooltouch-model` only: no host library and not the command line, so a C,
//! DPI-C or VPI build links the model and nothing else.
#![deny(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]

use core::ffi::{c_char, CStr};
use core::fmt::{self, Write};
use std::cell::RefCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use tooltouch_model::force::config::{ForceConfig, ForceSettings};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::force::sampling::AdcCodes;
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::wire::force_config::decode_force_settings;
use tooltouch_model::wire::kind;
use tooltouch_model::wire::measure_config::{decode_config, CANONICAL_CONFIG_LEN};
use tooltouch_model::{FrontEnd, MeasureConfig, MeasureEvent, MeasureOutputs, Measurement, Pins};

/// Version of this ABI (functions, structures, constants); [`tt_abi_version`] returns it.
pub const TT_ABI_VERSION: u32 = 1;

/// Number of measurement outputs ([`TtMeasureOutputs`] fields, [`tt_frontend_registers`]
/// entries), in the model's order ([`tt_output_name`] names them).
pub const TT_OUTPUT_COUNT: u32 = 17;

/// Number of MCU register addresses (`mcu_addr` is 4 bits wide).
pub const TT_MCU_ADDRESSES: u32 = 16;

/// The first bytes of the configuration file `tooltouch cosim config` writes.
const CONFIG_FILE_MAGIC: &[u8; 8] = b"TTFWCFG1";
/// The largest configuration file read, bytes (the file is about 200 bytes).
const CONFIG_FILE_MAX: u64 = 4096;

/// Pin bits of [`tt_frontend_clock`]'s `pins`: arm.
pub const TT_PIN_ARM: u8 = 1 << 0;
/// Pin bit: contact.
pub const TT_PIN_CONTACT: u8 = 1 << 1;
/// Pin bit: index.
pub const TT_PIN_INDEX: u8 = 1 << 2;
/// Pin bit: FES.
pub const TT_PIN_FES: u8 = 1 << 3;
/// Pin bit: scale line A.
pub const TT_PIN_SCALE_A: u8 = 1 << 4;
/// Pin bit: scale line B.
pub const TT_PIN_SCALE_B: u8 = 1 << 5;

/// [`TtMeasureEvent::kind`]: the arm line changed to `level` (the wire kind byte).
pub const TT_MEASURE_EVENT_ARM: u8 = 0x02;
/// The contact line changed to `level`.
pub const TT_MEASURE_EVENT_CONTACT: u8 = 0x03;
/// Rising edge of the index pulse.
pub const TT_MEASURE_EVENT_INDEX: u8 = 0x04;
/// Rising edge of an FES pulse.
pub const TT_MEASURE_EVENT_FES: u8 = 0x05;
/// One or both scale lines changed to `scale_a`, `scale_b`.
pub const TT_MEASURE_EVENT_SCALE: u8 = 0x06;
/// Test event: the FES pulse count since arm becomes `pulses`.
pub const TT_MEASURE_EVENT_PRESET_PULSES: u8 = 0x07;

/// [`TtForceEvent::kind`]: one ADC sample of every channel, `adc` (the wire kind byte).
pub const TT_FORCE_EVENT_SAMPLE: u8 = 0x20;
/// Control period tick.
pub const TT_FORCE_EVENT_TICK: u8 = 0x21;
/// No-load identification on (`on` = 1) or off.
pub const TT_FORCE_EVENT_IDENTIFY: u8 = 0x22;
/// Force control on (`on` = 1) or off.
pub const TT_FORCE_EVENT_CONTROL: u8 = 0x23;
/// The cutting conditions changed to condition set `conditions`.
pub const TT_FORCE_EVENT_CONDITIONS: u8 = 0x24;
/// A new tool was put in.
pub const TT_FORCE_EVENT_TOOL_CHANGED: u8 = 0x25;

// The constants above are literals so that cbindgen writes them into the header; they are
// the model's, checked here at compile time.
const _: () = {
    assert!(TT_PIN_ARM == pin::ARM);
    assert!(TT_PIN_CONTACT == pin::CONTACT);
    assert!(TT_PIN_INDEX == pin::INDEX);
    assert!(TT_PIN_FES == pin::FES);
    assert!(TT_PIN_SCALE_A == pin::SCALE_A);
    assert!(TT_PIN_SCALE_B == pin::SCALE_B);
    assert!(TT_MEASURE_EVENT_ARM == kind::ARM);
    assert!(TT_MEASURE_EVENT_CONTACT == kind::CONTACT);
    assert!(TT_MEASURE_EVENT_INDEX == kind::INDEX);
    assert!(TT_MEASURE_EVENT_FES == kind::FES);
    assert!(TT_MEASURE_EVENT_SCALE == kind::SCALE);
    assert!(TT_MEASURE_EVENT_PRESET_PULSES == kind::PRESET_PULSES);
    assert!(TT_FORCE_EVENT_SAMPLE == kind::SAMPLE);
    assert!(TT_FORCE_EVENT_TICK == kind::TICK);
    assert!(TT_FORCE_EVENT_IDENTIFY == kind::IDENTIFY);
    assert!(TT_FORCE_EVENT_CONTROL == kind::CONTROL);
    assert!(TT_FORCE_EVENT_CONDITIONS == kind::CONDITIONS);
    assert!(TT_FORCE_EVENT_TOOL_CHANGED == kind::TOOL_CHANGED);
    assert!(TT_OUTPUT_COUNT as usize == MeasureOutputs::FIELD_COUNT);
};

/// What a call did: 0 success, otherwise why not ([`tt_last_error`] says more).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TtStatus {
    /// Done.
    Ok = 0,
    /// A pointer argument was NULL.
    NullPointer = 1,
    /// The configuration bytes do not decode or do not validate.
    BadConfig = 2,
    /// An argument is out of its range (a pin bit above bit 5, an unknown event kind, …).
    BadArgument = 3,
    /// A file could not be read.
    Io = 4,
    /// An internal error: a panic was caught at the boundary (a bug; please report it).
    Panic = 5,
}

/// A validated configuration: the measurement front end's and the force path's.
pub struct TtConfig {
    measure: MeasureConfig,
    force: ForceConfig,
}

/// The cycle-level front end (RTL semantics: one [`tt_frontend_clock`] per FPGA clock).
pub struct TtFrontEnd {
    config: MeasureConfig,
    /// `config.hash()`, computed once (the MCU's CONFIG_HASH words).
    hash: u64,
    front_end: FrontEnd,
}

/// The measurement kernel at event level (firmware semantics: one event per call).
pub struct TtMeasurement {
    config: MeasureConfig,
    measurement: Measurement,
}

/// The force path's event-level kernel.
pub struct TtForce {
    config: ForceConfig,
    kernel: ForceKernel,
}

/// Every measurement output, as the model holds it. Flags are 0 or 1; positions are counts,
/// `scale_bits` two's complement sign-extended to 32 bits; widths in
/// [`tt_config_output_width`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TtMeasureOutputs {
    /// A measurement cycle is running.
    pub armed: u8,
    /// Filtered contact level.
    pub contact: u8,
    /// "Position reached, register now".
    pub register_now: u8,
    /// A contact edge has been seen since arm.
    pub first_contact: u8,
    /// The density detector is armed.
    pub density_armed: u8,
    /// The density detector has fired since arm.
    pub density_fired: u8,
    /// Illegal scale transitions, saturating at 255.
    pub scale_errors: u8,
    /// Scale position latched at the decision, counts.
    pub decision_position: i32,
    /// Scale position latched at the first contact, counts.
    pub first_contact_position: i32,
    /// Live scale position, counts.
    pub position: i32,
    /// Contact pulses in the current window.
    pub count: u32,
    /// Contact pulses in the previous window.
    pub last_window_count: u32,
    /// Capacitor charge, LSBs.
    pub charge: u32,
    /// Index pulses since arm, saturating at 65535.
    pub revolutions: u16,
    /// FES pulses since arm, wrapping at 2^32.
    pub pulses: u32,
}

/// One event-level measurement input.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TtMeasureEvent {
    /// `TT_MEASURE_EVENT_*`.
    pub kind: u8,
    /// Arm, contact: the new level, 0 or 1.
    pub level: u8,
    /// Scale: line A's new level, 0 or 1.
    pub scale_a: u8,
    /// Scale: line B's new level, 0 or 1.
    pub scale_b: u8,
    /// Preset pulses: the new FES pulse count.
    pub pulses: u32,
}

/// One ADC sample of every channel, 12-bit codes (unipolar speed and power, the others
/// bipolar around 2048).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TtAdcCodes {
    /// Motor speed.
    pub speed: u16,
    /// Measured drive power.
    pub power: u16,
    /// Dynamometer cutting force.
    pub force: u16,
    /// Phase voltages u, v, w.
    pub volts: [u16; 3],
    /// Phase currents u, v.
    pub amps: [u16; 2],
}

/// One event of the force path.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TtForceEvent {
    /// `TT_FORCE_EVENT_*`.
    pub kind: u8,
    /// Identify, control: on (1) or off (0).
    pub on: u8,
    /// Conditions: the condition set's index.
    pub conditions: u8,
    /// Sample: the codes.
    pub adc: TtAdcCodes,
}

/// Every force output. The physical values are the model's I32F32 fixed point as its raw
/// bits (value = bits / 2^32, SI units), so they compare bit for bit.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TtForceOutputs {
    /// Feed override to the CNC, %.
    pub override_pct: u8,
    /// The controller's demand was outside 0..=255 in the last period.
    pub saturated: u8,
    /// The fast electrical estimate was selected in the last period.
    pub fast_estimate: u8,
    /// Force control is on.
    pub control_enabled: u8,
    /// No-load identification is running.
    pub identifying: u8,
    /// Friction comes from an identification.
    pub identified: u8,
    /// The wear monitor's power is at or above its threshold.
    pub wear_over: u8,
    /// Wear alarm latched.
    pub wear_alarm: u8,
    /// Bad CNC commands, saturating at 255.
    pub bad_events: u8,
    /// Estimated cutting force, N, I32F32 bits.
    pub force_estimate: i64,
    /// Dynamometer force (period average), N, I32F32 bits.
    pub force_measured: i64,
    /// Low-passed mean spindle power, W, I32F32 bits.
    pub wear_power: i64,
    /// Allowed power, W, I32F32 bits.
    pub wear_allowed: i64,
    /// Coulomb friction in use, N·m, I32F32 bits.
    pub coulomb: i64,
}

// ---------------------------------------------------------------------------------------
// Errors: a per-thread message in a fixed buffer (no allocation), a status per call.

/// Length of the per-thread error message buffer, bytes (NUL included).
const ERROR_CAPACITY: usize = 512;

struct ErrorText {
    bytes: [u8; ERROR_CAPACITY],
    len: usize,
}

impl Write for ErrorText {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        // Keep one byte for the NUL; cut at a character boundary.
        for c in s.chars() {
            let mut utf8 = [0u8; 4];
            let encoded = c.encode_utf8(&mut utf8).as_bytes();
            let end = self.len + encoded.len();
            if end >= ERROR_CAPACITY {
                return Ok(());
            }
            self.bytes[self.len..end].copy_from_slice(encoded);
            self.len = end;
        }
        Ok(())
    }
}

thread_local! {
    static LAST_ERROR: RefCell<ErrorText> = const {
        RefCell::new(ErrorText { bytes: [0; ERROR_CAPACITY], len: 0 })
    };
}

/// A failed call: its status, the message already recorded.
struct Failure(TtStatus);

/// Records `message` as this thread's last error and returns the failure.
fn fail(status: TtStatus, message: fmt::Arguments<'_>) -> Failure {
    LAST_ERROR.with(|cell| {
        if let Ok(mut text) = cell.try_borrow_mut() {
            text.len = 0;
            let _ = text.write_fmt(message);
            let len = text.len;
            text.bytes[len] = 0;
        }
    });
    Failure(status)
}

/// Runs a body at the boundary: its error as a status, a panic caught.
fn guard(body: impl FnOnce() -> Result<(), Failure>) -> TtStatus {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => TtStatus::Ok,
        Ok(Err(Failure(status))) => status,
        Err(_) => {
            fail(
                TtStatus::Panic,
                format_args!("internal error: the golden model panicked (a bug; please report it)"),
            );
            TtStatus::Panic
        }
    }
}

/// `pointer` as a reference, or a NullPointer failure naming `what`.
///
/// # Safety
/// `pointer` is NULL or points to a live `T`.
unsafe fn deref<'a, T>(pointer: *const T, what: &str) -> Result<&'a T, Failure> {
    // SAFETY: the caller's contract.
    unsafe { pointer.as_ref() }
        .ok_or_else(|| fail(TtStatus::NullPointer, format_args!("{what} is NULL")))
}

/// `pointer` as a mutable reference, or a NullPointer failure naming `what`.
///
/// # Safety
/// `pointer` is NULL or points to a live `T` nobody else uses during the call.
unsafe fn deref_mut<'a, T>(pointer: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    // SAFETY: the caller's contract.
    unsafe { pointer.as_mut() }
        .ok_or_else(|| fail(TtStatus::NullPointer, format_args!("{what} is NULL")))
}

/// A 0/1 flag of an input structure.
fn flag(value: u8, what: &str) -> Result<bool, Failure> {
    match value {
        0 => Ok(false),
        1 => Ok(true),
        v => Err(fail(
            TtStatus::BadArgument,
            format_args!("{what} is {v}; it must be 0 or 1"),
        )),
    }
}

// ---------------------------------------------------------------------------------------
// Version and errors.

/// The ABI version, [`TT_ABI_VERSION`]: check it against the header's at start-up.
#[no_mangle]
pub extern "C" fn tt_abi_version() -> u32 {
    TT_ABI_VERSION
}

/// The message of this thread's last failed call (NUL-terminated UTF-8, empty if none has
/// failed). The text stays valid until the next failing call on this thread.
#[no_mangle]
pub extern "C" fn tt_last_error() -> *const c_char {
    static EMPTY: &CStr = c"";
    LAST_ERROR
        .try_with(|cell| match cell.try_borrow() {
            Ok(text) => text.bytes.as_ptr().cast::<c_char>(),
            Err(_) => EMPTY.as_ptr(),
        })
        .unwrap_or(EMPTY.as_ptr())
}

/// Bytes of a name in [`OUTPUT_NAMES`]: the longest output name and its NUL fit.
const OUTPUT_NAME_BYTES: usize = 32;

/// Every output's name as in `MeasureOutputs::LAYOUT` (the model's one list), NUL-padded.
static OUTPUT_NAMES: [[u8; OUTPUT_NAME_BYTES]; MeasureOutputs::FIELD_COUNT] = output_names();

/// [`OUTPUT_NAMES`], made at compile time (a name too long fails the build).
const fn output_names() -> [[u8; OUTPUT_NAME_BYTES]; MeasureOutputs::FIELD_COUNT] {
    let mut out = [[0u8; OUTPUT_NAME_BYTES]; MeasureOutputs::FIELD_COUNT];
    let mut i = 0;
    while i < MeasureOutputs::FIELD_COUNT {
        let name = MeasureOutputs::LAYOUT[i].0.as_bytes();
        assert!(name.len() < OUTPUT_NAME_BYTES, "an output name is too long");
        let mut j = 0;
        while j < name.len() {
            out[i][j] = name[j];
            j += 1;
        }
        i += 1;
    }
    out
}

/// The name of output `index` (`0..TT_OUTPUT_COUNT`, the order of [`TtMeasureOutputs`]) as
/// in the Verilog ports and VCD signals, NUL-terminated and static; NULL if out of range.
#[no_mangle]
pub extern "C" fn tt_output_name(index: u32) -> *const c_char {
    usize::try_from(index)
        .ok()
        .and_then(|i| OUTPUT_NAMES.get(i))
        .map_or(core::ptr::null(), |name| name.as_ptr().cast::<c_char>())
}

mod config;
mod cycle;
mod event;
mod force;

pub use config::*;
pub use cycle::*;
pub use event::*;
pub use force::*;

#[cfg(test)]
mod tests;
