//! The configuration handle `TtConfig`: decoded from the canonical bytes or the file
//! `tooltouch cosim config` writes, and what it tells (hashes, output widths, latency, force rates).

use super::*;

/// Decodes a configuration from `bytes`: the file `tooltouch cosim config` writes, or the
/// measurement configuration's 42 canonical bytes alone (`CANONICAL_CONFIG_LEN`) (force path: default settings).
/// `origin` prefixes every message (a file's name and a colon, or nothing).
pub(crate) fn decode_configuration(bytes: &[u8], origin: &str) -> Result<TtConfig, Failure> {
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
/// file `tooltouch cosim config` writes, or a measurement configuration's 42 canonical
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
