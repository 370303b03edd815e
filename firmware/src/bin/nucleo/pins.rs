//! The board's digital pins and their EXTI lines (RM0390 "General-purpose I/Os (GPIO)",
//! "System configuration controller (SYSCFG)", "External interrupt/event controller
//! (EXTI)"); the pin map is in the crate doc.
//!
//! The inputs are in input mode with pull-downs, so an unconnected line reads 0 (PC13,
//! the B1 button, has the board's pull-up instead). EXTI line n is pin n of any one port
//! (SYSCFG_EXTICRx selects the port), which is why the pins are where they are. The
//! analog inputs are the ADC's (`adc`), PB3 and PB6 the timers' (`timers`).

use core::sync::atomic::{AtomicU32, Ordering};
use stm32f4::stm32f446 as pac;
use tooltouch_firmware::model::force::events::ForceEvent;

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

/// "Register now" (PA5, also LD2) and the wear alarm (PA6): push-pull outputs, low.
pub fn configure_outputs(gpioa: &pac::GPIOA) {
    gpioa.bsrr().write(|w| w.br5().set_bit().br6().set_bit());
    gpioa
        .moder()
        .modify(|_, w| w.moder5().output().moder6().output());
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

fn gpioa() -> &'static pac::gpioa::RegisterBlock {
    // SAFETY: the tasks only read IDR / ODR and write BSRR, which sets or resets single
    // pins atomically.
    unsafe { &*pac::GPIOA::ptr() }
}

fn exti() -> &'static pac::exti::RegisterBlock {
    // SAFETY: the tasks only read PR and write 1s to their own lines (write 1 to clear:
    // other lines are unaffected).
    unsafe { &*pac::EXTI::ptr() }
}

/// Level of the CNC's arm line (PA0).
#[inline(always)]
pub fn arm() -> bool {
    gpioa().idr().read().idr0().is_high()
}

/// Level of the contact line (PA1).
#[inline(always)]
pub fn contact() -> bool {
    gpioa().idr().read().idr1().is_high()
}

/// Levels of the scale's A and B lines (PB8, PB9).
#[inline(always)]
pub fn scale() -> (bool, bool) {
    // SAFETY: a read of the input data register; no side effect.
    let idr = unsafe { (*pac::GPIOB::ptr()).idr().read() };
    (idr.idr8().is_high(), idr.idr9().is_high())
}

/// Drives "register now" (PA5).
#[inline(always)]
pub fn set_register_now(on: bool) {
    gpioa().bsrr().write(|w| w.bs5().bit(on).br5().bit(!on));
}

/// The level "register now" is driven at (PA5's output data bit).
#[inline(always)]
pub fn register_now() -> bool {
    gpioa().odr().read().odr5().is_high()
}

/// Drives the wear alarm (PA6).
#[inline(always)]
pub fn set_wear_alarm(on: bool) {
    gpioa().bsrr().write(|w| w.bs6().bit(on).br6().bit(!on));
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
    let exti = exti();
    let pr = exti.pr().read();
    exti.pr().write(|w| {
        w.pr11()
            .bit(pr.pr11().is_pending())
            .pr12()
            .bit(pr.pr12().is_pending())
            .pr13()
            .bit(pr.pr13().is_pending())
    });
    PENDING_COMMANDS.fetch_or(pr.bits() & COMMAND_LINES, Ordering::Relaxed);
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
    // SAFETY: a read of the input data register; no side effect.
    let idr = unsafe { (*pac::GPIOC::ptr()).idr().read() };
    match line {
        CONTROL => Some(ForceEvent::Control(idr.idr11().is_high())),
        IDENTIFY => Some(ForceEvent::Identify(idr.idr12().is_high())),
        TOOL_CHANGED => Some(ForceEvent::ToolChanged),
        _ => None,
    }
}
