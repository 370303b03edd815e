//! The cycle level `TtFrontEnd` (one call per FPGA clock) and the outputs and MCU register
//! words both levels read: `TtMeasureOutputs` from the model's, the register map's words.

use super::*;

pub(crate) fn c_outputs(o: &MeasureOutputs) -> TtMeasureOutputs {
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
        confirmed: o.confirmed.into(),
        faults: o.faults,
    }
}

/// The MCU register file's word at `addr`: the model's register map
/// (`tooltouch_model::measure::mcu_registers`), the diagnostic counters 0 unless
/// `diagnostics`, 0 at an unlisted address.
pub(crate) fn mcu_word(
    config: &MeasureConfig,
    hash: u64,
    o: &MeasureOutputs,
    addr: u32,
    diagnostics: bool,
) -> u32 {
    tooltouch_model::measure::mcu_registers::mcu_word(
        config,
        hash,
        &o.register_bits(config),
        addr,
        diagnostics,
    )
}

pub(crate) fn check_mcu_addr(addr: u32) -> Result<(), Failure> {
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
pub(crate) unsafe fn write_registers(
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

pub(crate) fn pins_of(pins: u8) -> Result<Pins, Failure> {
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
