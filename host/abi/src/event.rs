//! The measurement kernel at event level, `TtMeasurement` (firmware semantics: one event
//! per call, at its time: the model's `apply_at(time, event)`).

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

/// `time` if it is not before the kernel's time (the last event's or observed), else a
/// BadArgument failure naming both.
fn not_before(m: &TtMeasurement, time: u64, what: &str) -> Result<u64, Failure> {
    let now = m.measurement.checks().now();
    if time < now {
        return Err(fail(
            TtStatus::BadArgument,
            format_args!("{what} {time} is before the time already reached, {now}; time never goes backwards"),
        ));
    }
    Ok(time)
}

/// Applies one event at its `time` (the model's `apply_at(time, event)`: the time is
/// observed first, so the FES watchdog latches if it expired before the event). A time
/// before the last event's or observed time is BadArgument and changes nothing.
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
        let event = measure_event(e)?;
        let time = not_before(m, e.time, "the event's time")?;
        m.measurement.apply_at(time, event);
        Ok(())
    })
}

/// The stream's clock reads `now` ticks, with no event (the model's `observe`): the FES
/// watchdog latches if it expired. A time before the last is BadArgument.
///
/// # Safety
/// `measurement` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn tt_measurement_observe(
    measurement: *mut TtMeasurement,
    now: u64,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let m = unsafe { deref_mut(measurement, "measurement") }?;
        let now = not_before(m, now, "time")?;
        m.measurement.observe(now);
        Ok(())
    })
}

/// Every output at time `now` (ticks, not before the last event's or observed time; the
/// model's `outputs_at`: the FES watchdog evaluated at `now`), into `*out`. Changes nothing.
///
/// # Safety
/// `measurement` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn tt_measurement_outputs_at(
    measurement: *const TtMeasurement,
    now: u64,
    out: *mut TtMeasureOutputs,
) -> TtStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let (m, out) = unsafe { (deref(measurement, "measurement")?, deref_mut(out, "out")?) };
        let now = not_before(m, now, "time")?;
        *out = c_outputs(&m.measurement.outputs_at(now));
        Ok(())
    })
}

/// Every output at the last event's or observed time, into `*out`.
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

/// Every output as register bits (as [`tt_frontend_registers`]) at the last event's or
/// observed time into `out[]`.
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
