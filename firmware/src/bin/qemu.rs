//! The co-simulation board: QEMU's lm3s6965evb (Cortex-M3). The input pins are virtual:
//! the co-simulation driver in `idle` sets their levels, then pends the event's
//! interrupt, exactly as an edge on a real pin would. The handlers are the shared ones.
//!
//! Interrupt map (the LM3S6965's GPIO port interrupts stand in for the pins' edges):
//! GPIOA = FES, GPIOB = index, GPIOC = contact, GPIOD = scale A/B, GPIOE = CNC arm/abort.
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use tooltouch_firmware::board::Board;

/// Virtual pin bits in [`PINS`].
const ARM: u8 = 1;
const CONTACT: u8 = 2;
const SCALE_A: u8 = 4;
const SCALE_B: u8 = 8;

/// Levels of the virtual input pins, written by the driver before each pend.
static PINS: AtomicU8 = AtomicU8::new(0);
/// The "register now" output.
static REGISTER_NOW: AtomicBool = AtomicBool::new(false);

/// The QEMU board.
pub struct Qemu;

impl Board for Qemu {
    fn arm() -> bool {
        PINS.load(Ordering::Relaxed) & ARM != 0
    }
    fn contact() -> bool {
        PINS.load(Ordering::Relaxed) & CONTACT != 0
    }
    fn scale() -> (bool, bool) {
        let p = PINS.load(Ordering::Relaxed);
        (p & SCALE_A != 0, p & SCALE_B != 0)
    }
    fn set_register_now(on: bool) {
        REGISTER_NOW.store(on, Ordering::Relaxed);
    }
}

/// Instructions of the calibration loop: `subs` + `bne` per iteration.
const CALIBRATION_ITERATIONS: u32 = 100_000;

/// Runs a loop of a known instruction count and returns `(instructions, SysTick ticks)`.
/// Under `-icount shift=0` every instruction takes the same virtual time, so this ratio
/// converts the profile's ticks to instructions.
fn calibrate() -> (u32, u32) {
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

#[rtic::app(device = lm3s6965, peripherals = false)]
mod app {
    use super::{Qemu, ARM, CONTACT, PINS, REGISTER_NOW, SCALE_A, SCALE_B};
    use core::sync::atomic::Ordering;
    use cortex_m::peripheral::{syst::SystClkSource, NVIC, SYST};
    use cortex_m_semihosting::debug;
    use lm3s6965::Interrupt;
    use tooltouch_firmware::cosim::{self, Target};
    use tooltouch_firmware::handlers::{self, Counters};
    use tooltouch_firmware::model::{MeasureConfig, MeasureEvent, MeasureOutputs, Measurement};
    use tooltouch_firmware::{semihosting, stack};

    #[shared]
    struct Shared {
        meas: Measurement,
        counters: Counters,
    }

    #[local]
    struct Local {
        calibration: (u32, u32),
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        stack::paint(256);
        let mut syst = cx.core.SYST;
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(0x00ff_ffff);
        syst.clear_current();
        syst.enable_counter();
        let calibration = super::calibrate();
        (
            Shared {
                meas: Measurement::new(&MeasureConfig::default()),
                counters: Counters::default(),
            },
            Local { calibration },
        )
    }

    /// Drives the firmware from idle (priority 0): every pend preempts it at once.
    struct Driver<M, C> {
        meas: M,
        counters: C,
        calibration: (u32, u32),
    }

    impl<M, C> Target for Driver<M, C>
    where
        M: rtic::Mutex<T = Measurement>,
        C: rtic::Mutex<T = Counters>,
    {
        fn configure(&mut self, config: &MeasureConfig) {
            PINS.store(0, Ordering::Relaxed);
            REGISTER_NOW.store(false, Ordering::Relaxed);
            self.meas.lock(|m| *m = Measurement::new(config));
            self.counters.lock(|c| *c = Counters::default());
        }

        fn inject(&mut self, event: MeasureEvent) -> u32 {
            let pins = PINS.load(Ordering::Relaxed);
            let (irq, pins) = match event {
                MeasureEvent::Arm(on) => (Interrupt::GPIOE, set(pins, ARM, on)),
                MeasureEvent::Contact(on) => (Interrupt::GPIOC, set(pins, CONTACT, on)),
                MeasureEvent::Index => (Interrupt::GPIOB, pins),
                MeasureEvent::Fes => (Interrupt::GPIOA, pins),
                MeasureEvent::Scale { a, b } => {
                    (Interrupt::GPIOD, set(set(pins, SCALE_A, a), SCALE_B, b))
                }
            };
            PINS.store(pins, Ordering::Relaxed);
            if NVIC::is_pending(irq) {
                // The previous edge of this line has not been served: it is lost.
                self.counters.lock(|c| c.lost = c.lost.saturating_add(1));
            }
            let t0 = SYST::get_current();
            rtic::pend(irq);
            // QEMU takes a pended interrupt only between translated blocks: without the
            // barriers, back-to-back pends merge into one interrupt.
            cortex_m::asm::dsb();
            cortex_m::asm::isb();
            let t1 = SYST::get_current();
            t0.wrapping_sub(t1) & 0x00ff_ffff
        }

        fn outputs(&mut self) -> MeasureOutputs {
            self.meas.lock(|m| m.outputs())
        }

        fn counters(&mut self) -> Counters {
            self.counters.lock(|c| *c)
        }

        fn calibration(&self) -> (u32, u32) {
            self.calibration
        }

        fn stack_used(&self) -> u32 {
            stack::used()
        }
    }

    fn set(pins: u8, bit: u8, on: bool) -> u8 {
        if on {
            pins | bit
        } else {
            pins & !bit
        }
    }

    #[idle(shared = [meas, counters], local = [calibration])]
    fn idle(cx: idle::Context) -> ! {
        let mut driver = Driver {
            meas: cx.shared.meas,
            counters: cx.shared.counters,
            calibration: *cx.local.calibration,
        };
        let ok = match semihosting::Files::open() {
            Some(mut files) => {
                let ran = cosim::run(&mut files, &mut driver).is_ok();
                files.close() && ran
            }
            None => false,
        };
        // Every output was written (synchronous semihosting calls) before the exit.
        debug::exit(if ok {
            debug::EXIT_SUCCESS
        } else {
            debug::EXIT_FAILURE
        });
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// FES pulse: the most frequent edge, highest priority.
    #[task(binds = GPIOA, priority = 7, shared = [meas])]
    fn fes(mut cx: fes::Context) {
        cx.shared.meas.lock(handlers::fes::<Qemu>);
    }

    /// Index pulse.
    #[task(binds = GPIOB, priority = 6, shared = [meas])]
    fn index(mut cx: index::Context) {
        cx.shared.meas.lock(handlers::index::<Qemu>);
    }

    /// Contact edge.
    #[task(binds = GPIOC, priority = 6, shared = [meas])]
    fn contact(mut cx: contact::Context) {
        cx.shared.meas.lock(handlers::contact::<Qemu>);
    }

    /// Scale edge.
    #[task(binds = GPIOD, priority = 6, shared = [meas])]
    fn scale(mut cx: scale::Context) {
        cx.shared.meas.lock(handlers::scale::<Qemu>);
    }

    /// CNC command (arm / abort).
    #[task(binds = GPIOE, priority = 5, shared = [meas])]
    fn cnc_command(mut cx: cnc_command::Context) {
        cx.shared.meas.lock(handlers::cnc_command::<Qemu>);
    }
}
