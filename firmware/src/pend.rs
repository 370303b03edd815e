//! The co-simulation drivers' pends under QEMU, timed with SysTick: both QEMU boards (the
//! lm3s6965 image and the emulated Nucleo) deliver an event by pending its interrupt from
//! `idle` and time the handler from the pend to its return.

/// Instructions of the calibration loop: `subs` + `bne` per iteration.
const CALIBRATION_ITERATIONS: u32 = 100_000;

/// Runs a loop of a known instruction count and returns `(instructions, SysTick ticks)`
/// (SysTick must be counting down from a 24-bit reload). Under `-icount shift=0` every
/// instruction takes the same virtual time, so this ratio converts the profile's ticks to
/// instructions.
pub fn calibrate() -> (u32, u32) {
    let t0 = cortex_m::peripheral::SYST::get_current();
    let mut n = CALIBRATION_ITERATIONS;
    // SAFETY: a register-only countdown loop.
    unsafe {
        core::arch::asm!("2:", "subs {0}, #1", "bne 2b", inout(reg) n, options(nomem, nostack));
    }
    let t1 = cortex_m::peripheral::SYST::get_current();
    let _ = n;
    (
        CALIBRATION_ITERATIONS.saturating_mul(2),
        t0.wrapping_sub(t1) & 0x00ff_ffff,
    )
}

/// Pends interrupt `irq` (its NVIC number) and returns the SysTick ticks until it has run
/// (the caller runs at a lower priority, so the handler preempts it at once).
///
/// The timed sequence is fixed assembly, so the harness's share of the profile does not
/// move with the compiler's scheduling: between the two SysTick reads run the pend's
/// store, `dsb`, `isb` (QEMU takes a pended interrupt only between translated blocks;
/// without them back-to-back pends merge into one), the handler (exception entry and exit
/// execute no instruction under QEMU) and the second read: 4 instructions plus the
/// handler's.
pub fn pend_and_time(irq: u16) -> u32 {
    let n = u32::from(irq);
    // NVIC_ISPRn, one bit per interrupt.
    let ispr = 0xe000_e200_u32.wrapping_add((n >> 5) << 2);
    let bit = 1_u32 << (n & 31);
    let (t0, t1): (u32, u32);
    // SAFETY: a write-one-to-set of the interrupt's pending bit (what `rtic::pend` does)
    // between two reads of SysTick's current value register; the handler it runs is an
    // RTIC task like any pended one.
    unsafe {
        core::arch::asm!(
            "ldr {t0}, [{cvr}]",
            "str {bit}, [{ispr}]",
            "dsb",
            "isb",
            "ldr {t1}, [{cvr}]",
            cvr = in(reg) 0xe000_e018_u32,
            ispr = in(reg) ispr,
            bit = in(reg) bit,
            t0 = out(reg) t0,
            t1 = out(reg) t1,
            options(nostack, preserves_flags),
        );
    }
    t0.wrapping_sub(t1) & 0x00ff_ffff
}

/// Whether interrupt `irq` is pending (NVIC_ISPRn): a pend now would merge with it.
pub fn is_pending(irq: u16) -> bool {
    let n = u32::from(irq);
    let ispr = 0xe000_e200_u32.wrapping_add((n >> 5) << 2) as *const u32;
    // SAFETY: a read of the NVIC's set-pending register; no side effect.
    unsafe { core::ptr::read_volatile(ispr) & (1 << (n & 31)) != 0 }
}
