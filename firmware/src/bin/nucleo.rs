//! The real board: a Nucleo-F446RE (STM32F446RE, Cortex-M4F). The pins' edges raise EXTI
//! interrupts bound to the same shared handlers as the QEMU board; defmt logs over RTT
//! (probe-rs prints them).
//!
//! Pin map (Arduino / Morpho header names in brackets; README has the wiring):
//!
//! | pin  | header   | signal                         | interrupt        | edges   |
//! |------|----------|--------------------------------|------------------|---------|
//! | PA0  | A0       | FES encoder pulse (in)         | EXTI0, prio 15   | rising  |
//! | PA1  | A1       | index pulse (in)               | EXTI1, prio 14   | rising  |
//! | PA4  | A2       | tool–workpiece contact (in)    | EXTI4, prio 14   | both    |
//! | PB8  | D15      | linear scale A (in)            | EXTI9_5, prio 14 | both    |
//! | PB9  | D14      | linear scale B (in)            | EXTI9_5, prio 14 | both    |
//! | PC10 | CN7-1    | CNC arm / abort (in)           | EXTI15_10, pr 12 | both    |
//! | PA5  | D13, LD2 | "register now" to the CNC (out)| —                | —       |
//!
//! The core runs from the 16 MHz HSI (reset clock): the handlers' cost is counted in
//! instructions, see README for the rates this allows.
#![no_std]
#![no_main]

#[cfg(not(feature = "panic-check"))]
use defmt_rtt as _;

/// The `panic-check` build's defmt logger: discards every frame. defmt-rtt's logger
/// panics when it is taken re-entrantly (a misuse this firmware cannot commit: it logs
/// only from `idle`), which would keep a panic path in the image; everything else in the
/// check build is the shipped firmware.
#[cfg(feature = "panic-check")]
mod null_logger {
    #[defmt::global_logger]
    struct Null;

    // SAFETY: stateless; every method is a no-op, so any call order is sound.
    unsafe impl defmt::Logger for Null {
        fn acquire() {}
        unsafe fn flush() {}
        unsafe fn release() {}
        unsafe fn write(_bytes: &[u8]) {}
    }
}
use stm32f4::stm32f446 as pac;
use tooltouch_firmware::board::Board;

/// GPIO bits.
const FES: u32 = 1 << 0;
const INDEX: u32 = 1 << 1;
const CONTACT: u32 = 1 << 4;
const SCALE_A: u32 = 1 << 8;
const SCALE_B: u32 = 1 << 9;
const ARM: u32 = 1 << 10;
const REGISTER_NOW: u32 = 1 << 5;

/// The Nucleo-F446RE.
pub struct Nucleo;

fn idr_a() -> u32 {
    // SAFETY: a read of the input data register; no side effect.
    unsafe { (*pac::GPIOA::ptr()).idr().read().bits() }
}
fn idr_b() -> u32 {
    // SAFETY: as above.
    unsafe { (*pac::GPIOB::ptr()).idr().read().bits() }
}
fn idr_c() -> u32 {
    // SAFETY: as above.
    unsafe { (*pac::GPIOC::ptr()).idr().read().bits() }
}

impl Board for Nucleo {
    fn arm() -> bool {
        idr_c() & ARM != 0
    }
    fn contact() -> bool {
        idr_a() & CONTACT != 0
    }
    fn scale() -> (bool, bool) {
        let b = idr_b();
        (b & SCALE_A != 0, b & SCALE_B != 0)
    }
    fn set_register_now(on: bool) {
        let bits = if on { REGISTER_NOW } else { REGISTER_NOW << 16 };
        // SAFETY: BSRR is write-only and atomic per bit: sets or resets PA5 alone.
        unsafe { (*pac::GPIOA::ptr()).bsrr().write(|w| w.bits(bits)) };
    }
}

/// Acknowledges EXTI lines `mask` (write 1 to clear).
fn ack(mask: u32) {
    // SAFETY: PR is write-1-to-clear; other lines are unaffected.
    unsafe { (*pac::EXTI::ptr()).pr().write(|w| w.bits(mask)) };
}

#[rtic::app(device = stm32f4::stm32f446, peripherals = true)]
mod app {
    use super::{ack, Nucleo, ARM, CONTACT, FES, INDEX, REGISTER_NOW, SCALE_A, SCALE_B};
    use tooltouch_firmware::handlers::{self, Counters};
    use tooltouch_firmware::model::{MeasureConfig, Measurement};

    #[shared]
    struct Shared {
        meas: Measurement,
        counters: Counters,
    }

    #[local]
    struct Local {}

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        let dp = cx.device;
        // SAFETY (all `bits` writes below): values built from the reference manual's
        // (RM0390) bit positions; reserved bits are left as read.
        unsafe {
            // Clocks: GPIOA, GPIOB, GPIOC (AHB1), SYSCFG (APB2).
            dp.RCC.ahb1enr().modify(|r, w| w.bits(r.bits() | 0b111));
            dp.RCC.apb2enr().modify(|r, w| w.bits(r.bits() | 1 << 14));
            // PA5 push-pull output, low; the inputs keep their reset mode (input) with
            // pull-downs so an unconnected line reads 0.
            dp.GPIOA.bsrr().write(|w| w.bits(REGISTER_NOW << 16));
            dp.GPIOA
                .moder()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 10)) | 0b01 << 10));
            dp.GPIOA.pupdr().modify(|r, w| {
                w.bits((r.bits() & !(0b11 | 0b11 << 2 | 0b11 << 8)) | 0b10 | 0b10 << 2 | 0b10 << 8)
            });
            dp.GPIOB
                .pupdr()
                .modify(|r, w| w.bits((r.bits() & !(0b1111 << 16)) | 0b1010 << 16));
            dp.GPIOC
                .pupdr()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 20)) | 0b10 << 20));
            // EXTI line sources: 0, 1, 4 = port A (reset value); 8, 9 = port B; 10 = port C.
            dp.SYSCFG
                .exticr3()
                .modify(|r, w| w.bits((r.bits() & !0xfff) | 0x1 | 0x1 << 4 | 0x2 << 8));
            let lines = FES | INDEX | CONTACT | SCALE_A | SCALE_B | ARM;
            dp.EXTI.rtsr().modify(|r, w| w.bits(r.bits() | lines));
            dp.EXTI
                .ftsr()
                .modify(|r, w| w.bits(r.bits() | CONTACT | SCALE_A | SCALE_B | ARM));
            dp.EXTI.pr().write(|w| w.bits(lines));
            dp.EXTI.imr().modify(|r, w| w.bits(r.bits() | lines));
        }
        defmt::info!("tooltouch firmware on Nucleo-F446RE: waiting for the CNC's arm line (PC10)");
        (
            Shared {
                meas: Measurement::new(&MeasureConfig::default()),
                counters: Counters::default(),
            },
            Local {},
        )
    }

    /// Logs every change of "register now" with the latched position; sleeps otherwise.
    #[idle(shared = [meas])]
    fn idle(mut cx: idle::Context) -> ! {
        let mut reported = false;
        loop {
            let o = cx.shared.meas.lock(|m| m.outputs());
            if o.register_now != reported {
                reported = o.register_now;
                if reported {
                    defmt::info!(
                        "register now: position {} counts, first contact at {}, {} revolutions",
                        o.decision_position,
                        o.first_contact_position,
                        o.revolutions
                    );
                } else {
                    defmt::info!("measurement cycle armed");
                }
            }
            rtic::export::wfi();
        }
    }

    /// FES pulse: the most frequent edge, highest priority.
    #[task(binds = EXTI0, priority = 15, shared = [meas])]
    fn fes(mut cx: fes::Context) {
        ack(FES);
        cx.shared.meas.lock(handlers::fes::<Nucleo>);
    }

    /// Index pulse.
    #[task(binds = EXTI1, priority = 14, shared = [meas])]
    fn index(mut cx: index::Context) {
        ack(INDEX);
        cx.shared.meas.lock(handlers::index::<Nucleo>);
    }

    /// Contact edge.
    #[task(binds = EXTI4, priority = 14, shared = [meas])]
    fn contact(mut cx: contact::Context) {
        ack(CONTACT);
        cx.shared.meas.lock(handlers::contact::<Nucleo>);
    }

    /// Scale edge on A or B.
    #[task(binds = EXTI9_5, priority = 14, shared = [meas])]
    fn scale(mut cx: scale::Context) {
        ack(SCALE_A | SCALE_B);
        cx.shared.meas.lock(handlers::scale::<Nucleo>);
    }

    /// CNC command (arm / abort).
    #[task(binds = EXTI15_10, priority = 12, shared = [meas, counters])]
    fn cnc_command(mut cx: cnc_command::Context) {
        ack(ARM);
        cx.shared.meas.lock(handlers::cnc_command::<Nucleo>);
    }
}
