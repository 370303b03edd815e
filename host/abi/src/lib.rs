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
pub const TT_OUTPUT_COUNT: u32 = 15;

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

// ---------------------------------------------------------------------------------------
// Configuration.

/// Decodes a configuration from `bytes`: the file `tooltouch cosim config` writes, or the
/// measurement configuration's 31 canonical bytes alone (force path: default settings).
/// `origin` prefixes every message (a file's name and a colon, or nothing).
fn decode_configuration(bytes: &[u8], origin: &str) -> Result<TtConfig, Failure> {
    let bad = |m: fmt::Arguments<'_>| fail(TtStatus::BadConfig, format_args!("{origin}{m}"));
    let default_force = || {
        ForceSettings::default().validate().map_err(|e| {
            bad(format_args!(
                "the default force settings do not validate: {e}"
            ))
        })
    };
    let measure_of = |part: &[u8]| {
        decode_config(part).map_err(|e| bad(format_args!("measurement configuration: {e}")))
    };
    if bytes.len() == CANONICAL_CONFIG_LEN && !bytes.starts_with(CONFIG_FILE_MAGIC) {
        return Ok(TtConfig {
            measure: measure_of(bytes)?,
            force: default_force()?,
        });
    }
    let Some(mut rest) = bytes.strip_prefix(CONFIG_FILE_MAGIC) else {
        return Err(bad(format_args!(
            "{} bytes that are neither a configuration file (it starts with \"TTFWCFG1\"; \
             `tooltouch cosim config` writes one) nor the {CANONICAL_CONFIG_LEN} canonical bytes \
             of a measurement configuration",
            bytes.len()
        )));
    };
    let mut part = |name: &str| -> Result<&[u8], Failure> {
        let (len, tail) = match rest {
            [lo, hi, tail @ ..] => (usize::from(u16::from_le_bytes([*lo, *hi])), tail),
            _ => {
                return Err(bad(format_args!(
                    "the configuration file ends before the {name} configuration's length"
                )))
            }
        };
        if tail.len() < len {
            return Err(bad(format_args!(
                "the configuration file's {name} configuration says {len} bytes, {} are left",
                tail.len()
            )));
        }
        let (part, tail) = tail.split_at(len);
        rest = tail;
        Ok(part)
    };
    let measure = measure_of(part("measurement")?)?;
    let force_bytes = part("force")?;
    let force_settings = decode_force_settings(force_bytes).map_err(|e| {
        bad(format_args!(
            "force configuration: unknown encoding at byte {}",
            e.at
        ))
    })?;
    let force = force_settings
        .validate()
        .map_err(|e| bad(format_args!("force configuration: {e}")))?;
    if !rest.is_empty() {
        return Err(bad(format_args!(
            "{} bytes after the force configuration",
            rest.len()
        )));
    }
    Ok(TtConfig { measure, force })
}

/// Makes a configuration from `len` bytes at `bytes` (see the crate documentation: the
/// file `tooltouch cosim config` writes, or a measurement configuration's 31 canonical
/// bytes) and stores its handle in `*out`; free it with [`tt_config_free`].
///
/// # Safety
/// `bytes` points to `len` readable bytes; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_config_from_bytes(
    bytes: *const u8,
    len: usize,
    out: *mut *mut TtConfig,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let out = unsafe { deref_mut(out, "out") }?;
        if bytes.is_null() {
            return Err(fail(TtStatus::NullPointer, format_args!("bytes is NULL")));
        }
        // SAFETY: the caller's contract: `len` readable bytes.
        let bytes = unsafe { core::slice::from_raw_parts(bytes, len) };
        *out = Box::into_raw(Box::new(decode_configuration(bytes, "")?));
        Ok(())
    })
}

/// Reads the configuration file at `path` (NUL-terminated; as [`tt_config_from_bytes`]
/// takes it, at most 4096 bytes) and stores its handle in `*out`.
///
/// # Safety
/// `path` is NULL or a NUL-terminated string; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_config_from_file(
    path: *const c_char,
    out: *mut *mut TtConfig,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let out = unsafe { deref_mut(out, "out") }?;
        if path.is_null() {
            return Err(fail(TtStatus::NullPointer, format_args!("path is NULL")));
        }
        // SAFETY: the caller's contract: a NUL-terminated string.
        let path = unsafe { CStr::from_ptr(path) };
        let Ok(name) = path.to_str() else {
            return Err(fail(
                TtStatus::BadArgument,
                format_args!("the configuration path is not UTF-8"),
            ));
        };
        let io = |e: std::io::Error| fail(TtStatus::Io, format_args!("{name}: {e}"));
        let file = std::fs::File::open(name).map_err(io)?;
        let mut bytes = Vec::new();
        use std::io::Read;
        file.take(CONFIG_FILE_MAX + 1)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if bytes.len() as u64 > CONFIG_FILE_MAX {
            return Err(fail(
                TtStatus::BadConfig,
                format_args!(
                    "{name}: more than {CONFIG_FILE_MAX} bytes; not a configuration file \
                     (`tooltouch cosim config --config SETTINGS --out FILE` writes one)"
                ),
            ));
        }
        let config = decode_configuration(&bytes, &format!("{name}: "))?;
        *out = Box::into_raw(Box::new(config));
        Ok(())
    })
}

/// Frees a configuration (NULL is ignored). Handles made from it stay valid.
///
/// # Safety
/// `config` is NULL or a handle from this library not yet freed.
#[no_mangle]
pub unsafe extern "C" fn tt_config_free(config: *mut TtConfig) {
    if !config.is_null() {
        // SAFETY: the caller's contract: a live handle made by Box::into_raw.
        drop(unsafe { Box::from_raw(config) });
    }
}

/// The measurement configuration's hash (the `CONFIG_HASH` of the generated Verilog and of
/// every vector file's header) into `*out`.
///
/// # Safety
/// `config` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_config_measure_hash(
    config: *const TtConfig,
    out: *mut u64,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (config, out) = unsafe { (deref(config, "config")?, deref_mut(out, "out")?) };
        *out = config.measure.hash();
        Ok(())
    })
}

/// The force configuration's hash into `*out`.
///
/// # Safety
/// `config` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_config_force_hash(config: *const TtConfig, out: *mut u64) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (config, out) = unsafe { (deref(config, "config")?, deref_mut(out, "out")?) };
        *out = config.force.hash();
        Ok(())
    })
}

/// The width in bits of output `index` (`0..TT_OUTPUT_COUNT`) for this configuration, the
/// width of its Verilog port, into `*out`.
///
/// # Safety
/// `config` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_config_output_width(
    config: *const TtConfig,
    index: u32,
    out: *mut u32,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (config, out) = unsafe { (deref(config, "config")?, deref_mut(out, "out")?) };
        let widths = MeasureOutputs::widths(&config.measure);
        let (_, width) = usize::try_from(index)
            .ok()
            .and_then(|i| widths.get(i))
            .ok_or_else(|| {
                fail(
                    TtStatus::BadArgument,
                    format_args!("output index {index}; there are {TT_OUTPUT_COUNT}"),
                )
            })?;
        *out = *width;
        Ok(())
    })
}

/// The latency from a pin to the outputs, clocks (`3 + glitch_cycles`), into `*out`.
///
/// # Safety
/// `config` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_config_latency_cycles(
    config: *const TtConfig,
    out: *mut u32,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (config, out) = unsafe { (deref(config, "config")?, deref_mut(out, "out")?) };
        *out = config.measure.latency_cycles();
        Ok(())
    })
}

/// The force path's sampling: the ADC sample rate, Hz, into `*sample_hz` and the samples
/// per control period (one tick after every that many samples) into `*samples_per_period`
/// (the settings file's `[force]` rates; a HAL component derives its tick from them).
///
/// # Safety
/// `config` is NULL or a live handle; `sample_hz` and `samples_per_period` are NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn tt_config_force_rates(
    config: *const TtConfig,
    sample_hz: *mut u32,
    samples_per_period: *mut u32,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (config, sample_hz, samples_per_period) = unsafe {
            (
                deref(config, "config")?,
                deref_mut(sample_hz, "sample_hz")?,
                deref_mut(samples_per_period, "samples_per_period")?,
            )
        };
        let s = config.force.settings();
        *sample_hz = u32::from(s.sample_hz);
        *samples_per_period = u32::from(s.samples_per_period);
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------
// Outputs.

fn c_outputs(o: &MeasureOutputs) -> TtMeasureOutputs {
    TtMeasureOutputs {
        armed: o.armed.into(),
        contact: o.contact.into(),
        register_now: o.register_now.into(),
        first_contact: o.first_contact.into(),
        density_armed: o.density_armed.into(),
        density_fired: o.density_fired.into(),
        scale_errors: o.scale_errors,
        decision_position: o.decision_position,
        first_contact_position: o.first_contact_position,
        position: o.position,
        count: o.count,
        last_window_count: o.last_window_count,
        charge: o.charge,
        revolutions: o.revolutions,
        pulses: o.pulses,
    }
}

/// The MCU register file's word at `addr` (the map of `tooltouch_hdl_gen::MCU_REGISTERS`:
/// status, positions sign-extended from `scale_bits`, counts, charge, diagnostic counters
/// (0 unless `diagnostics`), scale errors, configuration hash; 0 elsewhere).
fn mcu_word(
    config: &MeasureConfig,
    hash: u64,
    o: &MeasureOutputs,
    addr: u32,
    diagnostics: bool,
) -> u32 {
    let bits = o.register_bits(config);
    let scale_bits = u32::from(config.settings().scale_bits);
    let sign_extend = |raw: u64| -> u32 {
        if scale_bits >= 32 {
            raw as u32
        } else {
            let shift = 32 - scale_bits;
            (((raw as u32) << shift) as i32 >> shift) as u32
        }
    };
    let status = u32::from(o.armed)
        | u32::from(o.contact) << 1
        | u32::from(o.register_now) << 2
        | u32::from(o.first_contact) << 3
        | u32::from(o.density_armed) << 4
        | u32::from(o.density_fired) << 5;
    match addr {
        0 => status,
        1 => sign_extend(bits[6]),
        2 => sign_extend(bits[3]),
        3 => sign_extend(bits[5]),
        4 => bits[8] as u32,
        5 => bits[9] as u32,
        6 => bits[10] as u32,
        7 if diagnostics => u32::from(o.revolutions),
        8 if diagnostics => o.pulses,
        9 => u32::from(o.scale_errors),
        10 => hash as u32,
        11 => (hash >> 32) as u32,
        _ => 0,
    }
}

fn check_mcu_addr(addr: u32) -> Result<(), Failure> {
    if addr < TT_MCU_ADDRESSES {
        Ok(())
    } else {
        Err(fail(
            TtStatus::BadArgument,
            format_args!("MCU address {addr}; mcu_addr is 4 bits, 0..=15"),
        ))
    }
}

/// # Safety
/// `out` is NULL or points to `TT_OUTPUT_COUNT` writable `u64`s.
unsafe fn write_registers(
    config: &MeasureConfig,
    o: &MeasureOutputs,
    out: *mut u64,
) -> Result<(), Failure> {
    // SAFETY: the caller's contract.
    let out = unsafe { deref_mut(out.cast::<[u64; TT_OUTPUT_COUNT as usize]>(), "out") }?;
    *out = o.register_bits(config);
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Cycle level.

/// A front end in its reset state for `config`, into `*out`; free it with
/// [`tt_frontend_free`].
///
/// # Safety
/// `config` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_frontend_new(
    config: *const TtConfig,
    out: *mut *mut TtFrontEnd,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (config, out) = unsafe { (deref(config, "config")?, deref_mut(out, "out")?) };
        *out = Box::into_raw(Box::new(TtFrontEnd {
            config: config.measure,
            hash: config.measure.hash(),
            front_end: FrontEnd::new(&config.measure),
        }));
        Ok(())
    })
}

/// Frees a front end (NULL is ignored).
///
/// # Safety
/// `front_end` is NULL or a live handle from this library.
#[no_mangle]
pub unsafe extern "C" fn tt_frontend_free(front_end: *mut TtFrontEnd) {
    if !front_end.is_null() {
        // SAFETY: the caller's contract: a live handle made by Box::into_raw.
        drop(unsafe { Box::from_raw(front_end) });
    }
}

/// Back to the reset state (the Verilog's synchronous `rst`).
///
/// # Safety
/// `front_end` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn tt_frontend_reset(front_end: *mut TtFrontEnd) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let fe = unsafe { deref_mut(front_end, "front_end") }?;
        fe.front_end = FrontEnd::new(&fe.config);
        Ok(())
    })
}

fn pins_of(pins: u8) -> Result<Pins, Failure> {
    if pins & !pin::ALL != 0 {
        return Err(fail(
            TtStatus::BadArgument,
            format_args!("pins 0x{pins:02x}: only bits 0..=5 are pins (TT_PIN_*)"),
        ));
    }
    Ok(Pins(pins))
}

/// One rising clock edge with the pins `pins` (`TT_PIN_*` bits) sampled.
///
/// # Safety
/// `front_end` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn tt_frontend_clock(front_end: *mut TtFrontEnd, pins: u8) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let fe = unsafe { deref_mut(front_end, "front_end") }?;
        fe.front_end.clock(pins_of(pins)?);
        Ok(())
    })
}

/// `cycles` clocks with `pins` held, skipping exactly the clocks in which nothing can
/// change; the clocks simulated one by one into `*simulated` (NULL: not wanted). The state
/// afterwards is that of `cycles` calls of [`tt_frontend_clock`].
///
/// # Safety
/// `front_end` is NULL or a live handle; `simulated` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_frontend_advance(
    front_end: *mut TtFrontEnd,
    pins: u8,
    cycles: u64,
    simulated: *mut u64,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let fe = unsafe { deref_mut(front_end, "front_end") }?;
        let n = fe.front_end.advance(pins_of(pins)?, cycles, |_, _| {});
        // SAFETY: the caller's contract.
        if let Some(out) = unsafe { simulated.as_mut() } {
            *out = n;
        }
        Ok(())
    })
}

/// Every output, as registered after the last clock, into `*out`.
///
/// # Safety
/// `front_end` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_frontend_outputs(
    front_end: *const TtFrontEnd,
    out: *mut TtMeasureOutputs,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (fe, out) = unsafe { (deref(front_end, "front_end")?, deref_mut(out, "out")?) };
        *out = c_outputs(&fe.front_end.outputs());
        Ok(())
    })
}

/// Every output as the unsigned bits of its Verilog register (`TT_OUTPUT_COUNT` words in
/// the order of [`TtMeasureOutputs`], positions truncated to `scale_bits`) into `out[]`.
///
/// # Safety
/// `front_end` is NULL or a live handle; `out` is NULL or points to `TT_OUTPUT_COUNT`
/// writable `uint64_t`s.
#[no_mangle]
pub unsafe extern "C" fn tt_frontend_registers(
    front_end: *const TtFrontEnd,
    out: *mut u64,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let fe = unsafe { deref(front_end, "front_end") }?;
        // SAFETY: the caller's contract.
        unsafe { write_registers(&fe.config, &fe.front_end.outputs(), out) }
    })
}

/// The MCU register word at `addr` (0..=15) as `tt_frontend`'s `mcu_rdata` reads it after
/// the last clock, into `*out`. `diagnostics`: the design was generated with
/// `--mcu-diagnostics` (REVOLUTIONS and PULSES readable).
///
/// # Safety
/// `front_end` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_frontend_mcu_read(
    front_end: *const TtFrontEnd,
    addr: u32,
    diagnostics: bool,
    out: *mut u32,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (fe, out) = unsafe { (deref(front_end, "front_end")?, deref_mut(out, "out")?) };
        check_mcu_addr(addr)?;
        *out = mcu_word(
            &fe.config,
            fe.hash,
            &fe.front_end.outputs(),
            addr,
            diagnostics,
        );
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------
// Event level.

/// The measurement kernel at event level in its power-on state, into `*out`; free it with
/// [`tt_measurement_free`].
///
/// # Safety
/// `config` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_measurement_new(
    config: *const TtConfig,
    out: *mut *mut TtMeasurement,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (config, out) = unsafe { (deref(config, "config")?, deref_mut(out, "out")?) };
        *out = Box::into_raw(Box::new(TtMeasurement {
            config: config.measure,
            measurement: Measurement::new(&config.measure),
        }));
        Ok(())
    })
}

/// Frees a measurement kernel (NULL is ignored).
///
/// # Safety
/// `measurement` is NULL or a live handle from this library.
#[no_mangle]
pub unsafe extern "C" fn tt_measurement_free(measurement: *mut TtMeasurement) {
    if !measurement.is_null() {
        // SAFETY: the caller's contract: a live handle made by Box::into_raw.
        drop(unsafe { Box::from_raw(measurement) });
    }
}

fn measure_event(e: &TtMeasureEvent) -> Result<MeasureEvent, Failure> {
    Ok(match e.kind {
        TT_MEASURE_EVENT_ARM => MeasureEvent::Arm(flag(e.level, "level")?),
        TT_MEASURE_EVENT_CONTACT => MeasureEvent::Contact(flag(e.level, "level")?),
        TT_MEASURE_EVENT_INDEX => MeasureEvent::Index,
        TT_MEASURE_EVENT_FES => MeasureEvent::Fes,
        TT_MEASURE_EVENT_SCALE => MeasureEvent::Scale {
            a: flag(e.scale_a, "scale_a")?,
            b: flag(e.scale_b, "scale_b")?,
        },
        TT_MEASURE_EVENT_PRESET_PULSES => MeasureEvent::PresetPulses(e.pulses),
        k => {
            return Err(fail(
                TtStatus::BadArgument,
                format_args!(
                "measurement event kind 0x{k:02x}; the kinds are 0x02..=0x07 (TT_MEASURE_EVENT_*)"
            ),
            ))
        }
    })
}

/// Applies one event.
///
/// # Safety
/// `measurement` is NULL or a live handle; `event` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn tt_measurement_apply(
    measurement: *mut TtMeasurement,
    event: *const TtMeasureEvent,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (m, e) = unsafe {
            (
                deref_mut(measurement, "measurement")?,
                deref(event, "event")?,
            )
        };
        m.measurement.apply(measure_event(e)?);
        Ok(())
    })
}

/// Every output after the last event, into `*out`.
///
/// # Safety
/// `measurement` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_measurement_outputs(
    measurement: *const TtMeasurement,
    out: *mut TtMeasureOutputs,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (m, out) = unsafe { (deref(measurement, "measurement")?, deref_mut(out, "out")?) };
        *out = c_outputs(&m.measurement.outputs());
        Ok(())
    })
}

/// Every output as register bits (as [`tt_frontend_registers`]) into `out[]`.
///
/// # Safety
/// `measurement` is NULL or a live handle; `out` is NULL or points to `TT_OUTPUT_COUNT`
/// writable `uint64_t`s.
#[no_mangle]
pub unsafe extern "C" fn tt_measurement_registers(
    measurement: *const TtMeasurement,
    out: *mut u64,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let m = unsafe { deref(measurement, "measurement") }?;
        // SAFETY: the caller's contract.
        unsafe { write_registers(&m.config, &m.measurement.outputs(), out) }
    })
}

// ---------------------------------------------------------------------------------------
// Force kernel.

/// The force kernel for `config` (control off at the manual override), into `*out`; free
/// it with [`tt_force_free`].
///
/// # Safety
/// `config` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_force_new(config: *const TtConfig, out: *mut *mut TtForce) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (config, out) = unsafe { (deref(config, "config")?, deref_mut(out, "out")?) };
        *out = Box::into_raw(Box::new(TtForce {
            config: config.force,
            kernel: ForceKernel::new(&config.force),
        }));
        Ok(())
    })
}

/// Frees a force kernel (NULL is ignored).
///
/// # Safety
/// `force` is NULL or a live handle from this library.
#[no_mangle]
pub unsafe extern "C" fn tt_force_free(force: *mut TtForce) {
    if !force.is_null() {
        // SAFETY: the caller's contract: a live handle made by Box::into_raw.
        drop(unsafe { Box::from_raw(force) });
    }
}

/// Back to the state [`tt_force_new`] gives.
///
/// # Safety
/// `force` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn tt_force_reset(force: *mut TtForce) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let f = unsafe { deref_mut(force, "force") }?;
        f.kernel = ForceKernel::new(&f.config);
        Ok(())
    })
}

fn force_event(e: &TtForceEvent) -> Result<ForceEvent, Failure> {
    Ok(match e.kind {
        TT_FORCE_EVENT_SAMPLE => ForceEvent::Sample(AdcCodes {
            speed: e.adc.speed,
            power: e.adc.power,
            force: e.adc.force,
            volts: e.adc.volts,
            amps: e.adc.amps,
        }),
        TT_FORCE_EVENT_TICK => ForceEvent::Tick,
        TT_FORCE_EVENT_IDENTIFY => ForceEvent::Identify(flag(e.on, "on")?),
        TT_FORCE_EVENT_CONTROL => ForceEvent::Control(flag(e.on, "on")?),
        TT_FORCE_EVENT_CONDITIONS => ForceEvent::Conditions(e.conditions),
        TT_FORCE_EVENT_TOOL_CHANGED => ForceEvent::ToolChanged,
        k => {
            return Err(fail(
                TtStatus::BadArgument,
                format_args!(
                    "force event kind 0x{k:02x}; the kinds are 0x20..=0x25 (TT_FORCE_EVENT_*)"
                ),
            ))
        }
    })
}

/// Applies one event.
///
/// # Safety
/// `force` is NULL or a live handle; `event` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn tt_force_apply(
    force: *mut TtForce,
    event: *const TtForceEvent,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (f, e) = unsafe { (deref_mut(force, "force")?, deref(event, "event")?) };
        f.kernel.apply(force_event(e)?);
        Ok(())
    })
}

/// Every force output after the last event, into `*out`.
///
/// # Safety
/// `force` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_force_outputs(
    force: *const TtForce,
    out: *mut TtForceOutputs,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (f, out) = unsafe { (deref(force, "force")?, deref_mut(out, "out")?) };
        let o = f.kernel.outputs();
        *out = TtForceOutputs {
            override_pct: o.override_pct,
            saturated: o.saturated.into(),
            fast_estimate: o.fast_estimate.into(),
            control_enabled: o.control_enabled.into(),
            identifying: o.identifying.into(),
            identified: o.identified.into(),
            wear_over: o.wear_over.into(),
            wear_alarm: o.wear_alarm.into(),
            bad_events: o.bad_events,
            force_estimate: o.force_estimate.to_bits(),
            force_measured: o.force_measured.to_bits(),
            wear_power: o.wear_power.to_bits(),
            wear_allowed: o.wear_allowed.to_bits(),
            coulomb: o.coulomb.to_bits(),
        };
        Ok(())
    })
}

#[cfg(test)]
mod tests;
