//! The force path's event-level kernel, `TtForce`: samples, ticks and commands in, the
//! force outputs out.

use super::*;

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

pub(crate) fn force_event(e: &TtForceEvent) -> Result<ForceEvent, Failure> {
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
            wear_blind: o.wear_blind.into(),
            force_estimate: o.force_estimate.to_bits(),
            force_measured: o.force_measured.to_bits(),
            wear_power: o.wear_power.to_bits(),
            wear_allowed: o.wear_allowed.to_bits(),
            coulomb: o.coulomb.to_bits(),
        };
        Ok(())
    })
}
