//! The board's digital pins and their EXTI lines (RM0390 "General-purpose I/Os (GPIO)",
//! "System configuration controller (SYSCFG)", "External interrupt/event controller
//! (EXTI)"); the pin map is in the crate doc.
//!
//! The inputs are in input mode with pull-downs, so an unconnected line reads 0 (PC13,
//! the B1 button, has the board's pull-up instead). EXTI line n is pin n of any one port
//! (SYSCFG_EXTICRx selects the port), which is why the pins are where they are. The
//! analog inputs are the ADC's (`adc`), PB3 and PB6 the timers' (`timers`).

use crate::model::force::events::ForceEvent;
use core::sync::atomic::{AtomicU32, AtomicU8, Ordering};
use stm32f4::stm32f446 as pac;

/// EXTI line of the force-path command "control on" (PC11), as a bit of EXTI_PR.
const CONTROL: u32 = 1 << 11;
/// EXTI line of the command "no-load identification" (PC12).
const IDENTIFY: u32 = 1 << 12;
/// EXTI line of the command "tool changed" (PC13, the B1 button, active low).
const TOOL_CHANGED: u32 = 1 << 13;
/// Every force-path command line.
const COMMAND_LINES: u32 = CONTROL | IDENTIFY | TOOL_CHANGED;

/// EXTI lines of force-path commands taken from EXTI_PR and not yet handled.
static PENDING_COMMANDS: AtomicU32 = AtomicU32::new(0);

/// "Register now" (PA5, also LD2), the wear alarm (PA6) and the fault line to the CNC's
/// alarm input (PA7): push-pull outputs, low.
pub fn configure_outputs(gpioa: &pac::GPIOA) {
    gpioa
        .bsrr()
        .write(|w| w.br5().set_bit().br6().set_bit().br7().set_bit());
    gpioa
        .moder()
        .modify(|_, w| w.moder5().output().moder6().output().moder7().output());
}

/// The measurement inputs: arm PA0 and contact PA1 (both edges), index PB2 (rising),
/// scale A / B PB8 / PB9 (both edges), and FES PB3 (pull-down; `timers` gives it to
/// TIM2, the pull-down stays). PB2 and PB3 leave their reset functions (PB3 is JTDO/SWO;
/// probe-rs needs only SWD) for input mode.
pub fn configure_measurement_inputs(
    gpioa: &pac::GPIOA,
    gpiob: &pac::GPIOB,
    syscfg: &pac::SYSCFG,
    exti: &pac::EXTI,
) {
    gpioa
        .pupdr()
        .modify(|_, w| w.pupdr0().pull_down().pupdr1().pull_down());
    gpiob
        .moder()
        .modify(|_, w| w.moder2().input().moder3().input());
    gpiob.pupdr().modify(|_, w| {
        w.pupdr2()
            .pull_down()
            .pupdr3()
            .pull_down()
            .pupdr8()
            .pull_down()
            .pupdr9()
            .pull_down()
    });
    // EXTI line sources: 0, 1 = port A (reset value); 2, 8, 9 = port B.
    syscfg.exticr1().modify(|_, w| w.exti2().pb());
    syscfg.exticr3().modify(|_, w| w.exti8().pb().exti9().pb());
    exti.rtsr().modify(|_, w| {
        w.tr0()
            .enabled()
            .tr1()
            .enabled()
            .tr2()
            .enabled()
            .tr8()
            .enabled()
            .tr9()
            .enabled()
    });
    exti.ftsr().modify(|_, w| {
        w.tr0()
            .enabled()
            .tr1()
            .enabled()
            .tr8()
            .enabled()
            .tr9()
            .enabled()
    });
    exti.pr().write(|w| {
        w.pr0()
            .clear()
            .pr1()
            .clear()
            .pr2()
            .clear()
            .pr8()
            .clear()
            .pr9()
            .clear()
    });
    exti.imr().modify(|_, w| {
        w.mr0()
            .unmasked()
            .mr1()
            .unmasked()
            .mr2()
            .unmasked()
            .mr8()
            .unmasked()
            .mr9()
            .unmasked()
    });
}

/// The force-path command inputs: control on PC11 and identification PC12 (both edges,
/// pull-down), tool changed PC13 (the button: falling edge).
pub fn configure_command_inputs(gpioc: &pac::GPIOC, syscfg: &pac::SYSCFG, exti: &pac::EXTI) {
    gpioc
        .pupdr()
        .modify(|_, w| w.pupdr11().pull_down().pupdr12().pull_down());
    syscfg.exticr3().modify(|_, w| w.exti11().pc());
    syscfg
        .exticr4()
        .modify(|_, w| w.exti12().pc().exti13().pc());
    exti.rtsr()
        .modify(|_, w| w.tr11().enabled().tr12().enabled());
    exti.ftsr()
        .modify(|_, w| w.tr11().enabled().tr12().enabled().tr13().enabled());
    exti.pr()
        .write(|w| w.pr11().clear().pr12().clear().pr13().clear());
    exti.imr()
        .modify(|_, w| w.mr11().unmasked().mr12().unmasked().mr13().unmasked());
}

/// The data registers the tasks read and drive: GPIO input and output data, the command
/// lines' EXTI pending bits. The flashable image touches the hardware registers; the
/// emulated one (`netduinoplus2` emulates no GPIO, and its EXTI sets no pending bit from
/// software) the driver's copies in `emulated::registers`, its seam.
#[cfg(not(feature = "emulated"))]
mod data {
    use stm32f4::stm32f446 as pac;

    // SAFETY (every function): the tasks only read IDR / ODR / PR and write BSRR, which
    // sets or resets single pins atomically, and PR, where a written 1 clears that line
    // only.

    /// GPIOA_IDR.
    #[inline(always)]
    pub fn idr_a() -> u32 {
        unsafe { (*pac::GPIOA::ptr()).idr().read().bits() }
    }
    /// GPIOB_IDR.
    #[inline(always)]
    pub fn idr_b() -> u32 {
        unsafe { (*pac::GPIOB::ptr()).idr().read().bits() }
    }
    /// GPIOC_IDR.
    #[inline(always)]
    pub fn idr_c() -> u32 {
        unsafe { (*pac::GPIOC::ptr()).idr().read().bits() }
    }
    /// GPIOA_ODR.
    #[inline(always)]
    pub fn odr_a() -> u32 {
        unsafe { (*pac::GPIOA::ptr()).odr().read().bits() }
    }
    /// GPIOA_BSRR.
    #[inline(always)]
    pub fn bsrr_a(bits: u32) {
        unsafe {
            (*pac::GPIOA::ptr()).bsrr().write(|w| w.bits(bits));
        }
    }
    /// EXTI_PR.
    #[inline(always)]
    pub fn exti_pr() -> u32 {
        unsafe { (*pac::EXTI::ptr()).pr().read().bits() }
    }
    /// EXTI_PR write: a 1 clears its line.
    #[inline(always)]
    pub fn exti_clear(bits: u32) {
        unsafe {
            (*pac::EXTI::ptr()).pr().write(|w| w.bits(bits));
        }
    }
}
#[cfg(feature = "emulated")]
use crate::nucleo::emulated::registers as data;

fn exti() -> &'static pac::exti::RegisterBlock {
    // SAFETY: the tasks only write 1s to their own lines of PR (write 1 to clear: other
    // lines are unaffected).
    unsafe { &*pac::EXTI::ptr() }
}

/// PA5: "register now".
const REGISTER_NOW: u32 = 1 << 5;
/// PA6: the wear alarm.
const WEAR_ALARM: u32 = 1 << 6;
/// PA7: the fault line (the measurement's `faults` word not zero).
const FAULT: u32 = 1 << 7;

/// The BSRR word that drives the pins of `mask` to `on`.
#[inline(always)]
const fn bsrr(mask: u32, on: bool) -> u32 {
    if on {
        mask
    } else {
        mask << 16
    }
}

/// Level of the CNC's arm line (PA0).
#[inline(always)]
pub fn arm() -> bool {
    data::idr_a() & 1 << 0 != 0
}

/// Level of the contact line (PA1).
#[inline(always)]
pub fn contact() -> bool {
    data::idr_a() & 1 << 1 != 0
}

/// Levels of the scale's A and B lines (PB8, PB9).
#[inline(always)]
pub fn scale() -> (bool, bool) {
    let idr = data::idr_b();
    (idr & 1 << 8 != 0, idr & 1 << 9 != 0)
}

/// Drives "register now" (PA5).
#[inline(always)]
pub fn set_register_now(on: bool) {
    data::bsrr_a(bsrr(REGISTER_NOW, on));
}

/// The level "register now" is driven at (PA5's output data bit).
#[inline(always)]
pub fn register_now() -> bool {
    data::odr_a() & REGISTER_NOW != 0
}

/// The measurement's status as the handlers last published it: the `faults` word in
/// bits 0–6, `confirmed` in bit 7 (idle logs its changes).
static STATUS: AtomicU8 = AtomicU8::new(0);

/// Drives the fault line (PA7: `faults` not zero) and publishes the status.
#[inline(always)]
pub fn set_status(faults: u8, confirmed: bool) {
    data::bsrr_a(bsrr(FAULT, faults != 0));
    STATUS.store(status_word(faults, confirmed), Ordering::Relaxed);
}

/// The status word of `faults` and `confirmed` (as [`status`] reads it).
#[inline(always)]
pub const fn status_word(faults: u8, confirmed: bool) -> u8 {
    (faults & 0x7f) | (confirmed as u8) << 7
}

/// The status the handlers last published ([`status_word`]).
#[inline(always)]
pub fn status() -> u8 {
    STATUS.load(Ordering::Relaxed)
}

/// The level the fault line is driven at (PA7's output data bit).
#[inline(always)]
pub fn fault() -> bool {
    data::odr_a() & FAULT != 0
}

/// Drives the wear alarm (PA6).
#[inline(always)]
pub fn set_wear_alarm(on: bool) {
    data::bsrr_a(bsrr(WEAR_ALARM, on));
}

/// Acknowledges the arm line's edge (EXTI0).
#[inline(always)]
pub fn ack_arm() {
    exti().pr().write(|w| w.pr0().clear());
}

/// Acknowledges the contact line's edge (EXTI1).
#[inline(always)]
pub fn ack_contact() {
    exti().pr().write(|w| w.pr1().clear());
}

/// Acknowledges the index pulse (EXTI2).
#[inline(always)]
pub fn ack_index() {
    exti().pr().write(|w| w.pr2().clear());
}

/// Acknowledges the scale lines' edges (EXTI8, EXTI9).
#[inline(always)]
pub fn ack_scale() {
    exti().pr().write(|w| w.pr8().clear().pr9().clear());
}

/// Takes the force-path command lines pending in EXTI_PR (acknowledging them) into the
/// commands not yet handled.
#[inline(always)]
pub fn take_pending_commands() {
    let pending = data::exti_pr() & COMMAND_LINES;
    data::exti_clear(pending);
    PENDING_COMMANDS.fetch_or(pending, Ordering::Relaxed);
}

/// Whether a taken command is not yet handled.
#[inline(always)]
pub fn commands_pending() -> bool {
    PENDING_COMMANDS.load(Ordering::Relaxed) != 0
}

/// The next command not yet handled, lowest line first, with its line's level read now;
/// the task calls again while any remain.
pub fn next_command() -> Option<ForceEvent> {
    let pending = PENDING_COMMANDS.load(Ordering::Relaxed);
    let line = pending & pending.wrapping_neg();
    PENDING_COMMANDS.fetch_and(!line, Ordering::Relaxed);
    let idr = data::idr_c();
    match line {
        CONTROL => Some(ForceEvent::Control(idr & CONTROL != 0)),
        IDENTIFY => Some(ForceEvent::Identify(idr & IDENTIFY != 0)),
        TOOL_CHANGED => Some(ForceEvent::ToolChanged),
        _ => None,
    }
}
