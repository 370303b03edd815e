//! The measurement kernel at event level, `TtMeasurement` (firmware semantics: one event
//! per call).

use super::*;

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

pub(crate) fn measure_event(e: &TtMeasureEvent) -> Result<MeasureEvent, Failure> {
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
