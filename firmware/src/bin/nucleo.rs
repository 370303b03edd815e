//! The real board: a Nucleo-F446RE (STM32F446RE, Cortex-M4F). The pins' edges raise EXTI
//! interrupts bound to the same shared handlers as the QEMU board; defmt logs over RTT
//! (probe-rs prints them).
//!
//! Pin map (Arduino / Morpho header names in brackets; README has the wiring):
//!
//! | pin  | header   | signal                         | interrupt        | edges   |
//! |------|----------|--------------------------------|------------------|---------|
//! | PA0  | A0       | CNC arm / abort (in)           | EXTI0, prio 15   | both    |
//! | PA1  | A1       | tool–workpiece contact (in)    | EXTI1, prio 15   | both    |
//! | PB2  | CN10-22  | index pulse (in)               | EXTI2, prio 15   | rising  |
//! | PB3  | D3       | FES encoder pulse (in)         | EXTI3, prio 15   | rising  |
//! | PB8  | D15      | linear scale A (in)            | EXTI9_5, prio 15 | both    |
//! | PB9  | D14      | linear scale B (in)            | EXTI9_5, prio 15 | both    |
//! | —    | —        | observe (idle's output snapshot)| TIM7, prio 15   | —       |
//! | PC11 | CN7-2    | CNC force control on (in)      | EXTI15_10, pr 12 | both    |
//! | PC12 | CN7-3    | CNC no-load identification (in)| EXTI15_10, pr 12 | both    |
//! | PC13 | B1 button| tool changed (in, active low)  | EXTI15_10, pr 12 | falling |
//! | PC0–PC5, PB0, PB1 | A5, A4, CN7-35, CN7-37, CN10-34, CN10-6, A3, CN10-24 | ADC1 IN10–IN15, IN8, IN9: speed, power, force, v_u, v_v, v_w, i_u, i_v | TIM2 1 kHz, pr 8 | — |
//! | —    | —        | 20 Hz control period           | TIM3, prio 4     | —       |
//! | PA5  | D13, LD2 | "register now" to the CNC (out)| —                | —       |
//! | PA6  | D12      | wear alarm (out)               | —                | —       |
//! | PB6  | D10      | feed override, PWM duty = % / 255 (TIM4_CH1) | — | —  |
//!
//! The measurement edges share the highest priority with their IRQ numbers (EXTI0 = 6,
//! EXTI1 = 7, EXTI2 = 8, EXTI3 = 9, EXTI9_5 = 23, TIM7 = 55) in the model's canonical
//! same-clock order arm, contact, index, FES, scale: Cortex-M takes same-priority pending
//! interrupts lowest number first, so simultaneous edges are handled in that order, and
//! none preempts another, so the measurement kernel needs no lock. The pins are chosen
//! for their EXTI lines (line n is pin n of any one port); PB3 leaves its reset function
//! (JTDO/SWO; probe-rs needs only SWD) for a plain input.
//!
//! The core runs from the 16 MHz HSI (reset clock): the handlers' cost is counted in
//! instructions, see README for the rates this allows. The cutting-conditions command
//! has no pin: condition set 0 is used on this board.
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
use core::sync::atomic::{AtomicU32, Ordering};
use stm32f4::stm32f446 as pac;
use tooltouch_firmware::board::Board;
use tooltouch_firmware::model::force::ForceEvent;
use tooltouch_firmware::model::sampling::AdcCodes;

/// GPIO bits (= EXTI lines) of the inputs: arm PA0, contact PA1, index PB2, FES PB3,
/// scale PB8 / PB9, force commands PC11–PC13; outputs PA5, PA6.
const ARM: u32 = 1 << 0;
const CONTACT: u32 = 1 << 1;
const INDEX: u32 = 1 << 2;
const FES: u32 = 1 << 3;
const SCALE_A: u32 = 1 << 8;
const SCALE_B: u32 = 1 << 9;
const REGISTER_NOW: u32 = 1 << 5;
const WEAR_ALARM: u32 = 1 << 6;
const CONTROL: u32 = 1 << 11;
const IDENTIFY: u32 = 1 << 12;
const TOOL_CHANGED: u32 = 1 << 13;
const FORCE_LINES: u32 = CONTROL | IDENTIFY | TOOL_CHANGED;
/// ADC1 channels in [`AdcCodes`] order: speed, power, force, v_u, v_v, v_w, i_u, i_v.
const ADC_CHANNELS: [u32; 8] = [10, 11, 12, 13, 14, 15, 8, 9];

/// EXTI lines of force-path commands not yet handled (set by the EXTI15_10 handler).
static PENDING_COMMANDS: AtomicU32 = AtomicU32::new(0);

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
        idr_a() & ARM != 0
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
    fn adc() -> AdcCodes {
        let mut c = [0u16; 8];
        for (code, channel) in c.iter_mut().zip(ADC_CHANNELS) {
            *code = convert(channel);
        }
        AdcCodes {
            speed: c[0],
            power: c[1],
            force: c[2],
            volts: [c[3], c[4], c[5]],
            amps: [c[6], c[7]],
        }
    }
    fn force_command() -> Option<ForceEvent> {
        // One command per call, lowest line first; the task calls again while any remain.
        let pending = PENDING_COMMANDS.load(Ordering::Relaxed);
        let line = pending & pending.wrapping_neg();
        PENDING_COMMANDS.fetch_and(!line, Ordering::Relaxed);
        match line {
            CONTROL => Some(ForceEvent::Control(idr_c() & CONTROL != 0)),
            IDENTIFY => Some(ForceEvent::Identify(idr_c() & IDENTIFY != 0)),
            TOOL_CHANGED => Some(ForceEvent::ToolChanged),
            _ => None,
        }
    }
    fn set_feed_override(percent: u8) {
        // SAFETY: CCR1 of TIM4 takes any 16-bit compare value; ARR = 255.
        unsafe {
            (*pac::TIM4::ptr())
                .ccr1()
                .write(|w| w.bits(u32::from(percent)))
        };
    }
    fn set_wear_alarm(on: bool) {
        let bits = if on { WEAR_ALARM } else { WEAR_ALARM << 16 };
        // SAFETY: as for "register now" (PA6).
        unsafe { (*pac::GPIOA::ptr()).bsrr().write(|w| w.bits(bits)) };
    }
}

/// One software-started ADC1 conversion of `channel` (about 2 µs at 8 MHz ADC clock);
/// 0 if it does not complete within a bounded wait (never blocks forever).
fn convert(channel: u32) -> u16 {
    // SAFETY: ADC1 is owned by the 1 kHz sample task alone; SQR3 selects one channel,
    // CR2 bit 30 starts it, SR bit 1 (EOC) is cleared by reading DR.
    unsafe {
        let adc = &*pac::ADC1::ptr();
        adc.sqr3().write(|w| w.bits(channel & 0x1f));
        adc.cr2().modify(|r, w| w.bits(r.bits() | 1 << 30));
        for _ in 0..1000u32 {
            if adc.sr().read().bits() & 1 << 1 != 0 {
                return (adc.dr().read().bits() & 0x0fff) as u16;
            }
        }
    }
    0
}

/// Acknowledges EXTI lines `mask` (write 1 to clear).
fn ack(mask: u32) {
    // SAFETY: PR is write-1-to-clear; other lines are unaffected.
    unsafe { (*pac::EXTI::ptr()).pr().write(|w| w.bits(mask)) };
}

#[rtic::app(device = stm32f4::stm32f446, peripherals = true)]
mod app {
    use super::{
        ack, pac, Nucleo, ARM, CONTACT, FES, FORCE_LINES, INDEX, PENDING_COMMANDS, REGISTER_NOW,
        SCALE_A, SCALE_B, WEAR_ALARM,
    };
    use core::sync::atomic::Ordering;
    use tooltouch_firmware::board::Board;
    use tooltouch_firmware::handlers::{
        self, Counters, SampleConsumer, SampleProducer, SampleQueue,
    };
    use tooltouch_firmware::model::force::{ForceKernel, ForceSettings};
    use tooltouch_firmware::model::{MeasureConfig, MeasureOutputs, Measurement};

    /// The interrupt of [`observe`] (TIM7 stays disabled: only software pends it).
    const OBSERVE: pac::Interrupt = pac::Interrupt::TIM7;

    #[shared]
    struct Shared {
        /// The measurement kernel. Lock-free: only the measurement tasks touch it, and
        /// they all run at one priority, so none can preempt another.
        #[lock_free]
        meas: Measurement,
        /// The kernel's outputs as of the last [`observe`], for idle's log.
        snapshot: MeasureOutputs,
        force: ForceKernel,
        counters: Counters,
    }

    #[local]
    struct Local {
        samples_in: SampleProducer<'static>,
        samples_out: SampleConsumer<'static>,
    }

    #[init(local = [queue: SampleQueue = SampleQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let dp = cx.device;
        // SAFETY (all `bits` writes below): values built from the reference manual's
        // (RM0390) bit positions; reserved bits are left as read.
        unsafe {
            // Clocks: GPIOA, GPIOB, GPIOC (AHB1), SYSCFG (APB2).
            dp.RCC.ahb1enr().modify(|r, w| w.bits(r.bits() | 0b111));
            dp.RCC.apb2enr().modify(|r, w| w.bits(r.bits() | 1 << 14));
            // PA5 push-pull output, low; the inputs in input mode (PB3 leaves its reset
            // function, JTDO/SWO) with pull-downs so an unconnected line reads 0.
            dp.GPIOA.bsrr().write(|w| w.bits(REGISTER_NOW << 16));
            dp.GPIOA
                .moder()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 10)) | 0b01 << 10));
            dp.GPIOA
                .pupdr()
                .modify(|r, w| w.bits((r.bits() & !0b1111) | 0b1010));
            dp.GPIOB
                .moder()
                .modify(|r, w| w.bits(r.bits() & !(0b1111 << 4)));
            dp.GPIOB.pupdr().modify(|r, w| {
                w.bits((r.bits() & !(0b1111 << 4 | 0b1111 << 16)) | 0b1010 << 4 | 0b1010 << 16)
            });
            dp.GPIOC
                .pupdr()
                .modify(|r, w| w.bits((r.bits() & !(0b1111 << 22)) | 0b1010 << 22));
            // EXTI line sources: 0, 1 = port A (reset value); 2, 3, 8, 9 = port B.
            dp.SYSCFG
                .exticr1()
                .modify(|r, w| w.bits((r.bits() & !0xff00) | 0x1 << 8 | 0x1 << 12));
            dp.SYSCFG
                .exticr3()
                .modify(|r, w| w.bits((r.bits() & !0xff) | 0x1 | 0x1 << 4));
            let lines = ARM | CONTACT | INDEX | FES | SCALE_A | SCALE_B;
            dp.EXTI.rtsr().modify(|r, w| w.bits(r.bits() | lines));
            dp.EXTI
                .ftsr()
                .modify(|r, w| w.bits(r.bits() | ARM | CONTACT | SCALE_A | SCALE_B));
            dp.EXTI.pr().write(|w| w.bits(lines));
            dp.EXTI.imr().modify(|r, w| w.bits(r.bits() | lines));
            // Force-path command lines PC11, PC12 (both edges), PC13 (button, falling).
            dp.SYSCFG
                .exticr3()
                .modify(|r, w| w.bits((r.bits() & !(0xf << 12)) | 0x2 << 12));
            dp.SYSCFG
                .exticr4()
                .modify(|r, w| w.bits((r.bits() & !0xff) | 0x2 | 0x2 << 4));
            dp.EXTI
                .rtsr()
                .modify(|r, w| w.bits(r.bits() | super::CONTROL | super::IDENTIFY));
            dp.EXTI.ftsr().modify(|r, w| w.bits(r.bits() | FORCE_LINES));
            dp.EXTI.pr().write(|w| w.bits(FORCE_LINES));
            dp.EXTI.imr().modify(|r, w| w.bits(r.bits() | FORCE_LINES));
            // PA6 wear alarm: output, low.
            dp.GPIOA.bsrr().write(|w| w.bits(WEAR_ALARM << 16));
            dp.GPIOA
                .moder()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 12)) | 0b01 << 12));
            // ADC inputs analog: PC0–PC5, PB0, PB1. ADC1 on, clock PCLK2/2 = 8 MHz (reset).
            dp.GPIOC.moder().modify(|r, w| w.bits(r.bits() | 0xfff));
            dp.GPIOB.moder().modify(|r, w| w.bits(r.bits() | 0xf));
            dp.RCC.apb2enr().modify(|r, w| w.bits(r.bits() | 1 << 8));
            dp.ADC1.cr2().modify(|r, w| w.bits(r.bits() | 1));
            // TIM2: 1 kHz sample tick; TIM3: 20 Hz control period; TIM4: override PWM.
            dp.RCC.apb1enr().modify(|r, w| w.bits(r.bits() | 0b111));
            dp.TIM2.psc().write(|w| w.bits(16 - 1));
            dp.TIM2.arr().write(|w| w.bits(1000 - 1));
            dp.TIM3.psc().write(|w| w.bits(1600 - 1));
            dp.TIM3.arr().write(|w| w.bits(500 - 1));
            // PB6 alternate function 2 (TIM4_CH1), PWM mode 1, ARR 255 (62.7 kHz).
            dp.GPIOB
                .moder()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 12)) | 0b10 << 12));
            dp.GPIOB
                .afrl()
                .modify(|r, w| w.bits((r.bits() & !(0xf << 24)) | 0x2 << 24));
            dp.TIM4.arr().write(|w| w.bits(255));
            dp.TIM4
                .ccmr1_output()
                .write(|w| w.bits(0b110 << 4 | 1 << 3));
            dp.TIM4.ccer().write(|w| w.bits(1));
            dp.TIM4.cr1().write(|w| w.bits(1 << 7 | 1));
            dp.TIM2.dier().write(|w| w.bits(1));
            dp.TIM3.dier().write(|w| w.bits(1));
            dp.TIM2.cr1().write(|w| w.bits(1));
            dp.TIM3.cr1().write(|w| w.bits(1));
        }
        defmt::info!("tooltouch firmware on Nucleo-F446RE: waiting for the CNC's arm line (PA0)");
        let (samples_in, samples_out) = cx.local.queue.split();
        // The default force configuration is valid (model::force tests it); should it
        // ever not be, the board halts here with a log line rather than run unconfigured.
        let force = match ForceSettings::default().validate() {
            Ok(c) => ForceKernel::new(&c),
            Err(_) => {
                defmt::error!("the default force configuration does not validate");
                loop {
                    rtic::export::wfi();
                }
            }
        };
        Nucleo::set_feed_override(force.outputs().override_pct);
        let meas = Measurement::new(&MeasureConfig::default());
        (
            Shared {
                meas,
                snapshot: meas.outputs(),
                force,
                counters: Counters::default(),
            },
            Local {
                samples_in,
                samples_out,
            },
        )
    }

    /// Logs every change of "register now" with the latched position; sleeps otherwise.
    /// The pin is read from the output data register; the rest of the outputs, which only
    /// the measurement tasks may read, through [`observe`], and only on a change, so the
    /// FES pulses that wake idle cost no snapshot.
    #[idle(shared = [snapshot])]
    fn idle(mut cx: idle::Context) -> ! {
        let mut reported = false;
        loop {
            // SAFETY: a read of GPIOA's output data register; no side effect.
            let odr = unsafe { (*pac::GPIOA::ptr()).odr().read().bits() };
            let register_now = odr & REGISTER_NOW != 0;
            if register_now != reported {
                reported = register_now;
                rtic::pend(OBSERVE);
                cortex_m::asm::dsb();
                cortex_m::asm::isb();
                let o = cx.shared.snapshot.lock(|s| *s);
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

    // The measurement tasks: one priority (15, the highest), IRQ numbers in the model's
    // canonical same-clock order (arm, contact, index, FES, scale), so simultaneous
    // edges are handled in that order and none preempts another: the kernel needs no
    // lock.

    /// CNC arm / abort (PA0).
    #[task(binds = EXTI0, priority = 15, shared = [meas])]
    fn cnc_command(cx: cnc_command::Context) {
        ack(ARM);
        handlers::cnc_command::<Nucleo>(cx.shared.meas);
    }

    /// Contact edge (PA1).
    #[task(binds = EXTI1, priority = 15, shared = [meas])]
    fn contact(cx: contact::Context) {
        ack(CONTACT);
        handlers::contact::<Nucleo>(cx.shared.meas);
    }

    /// Index pulse (PB2).
    #[task(binds = EXTI2, priority = 15, shared = [meas])]
    fn index(cx: index::Context) {
        ack(INDEX);
        handlers::index::<Nucleo>(cx.shared.meas);
    }

    /// FES pulse (PB3): the most frequent edge.
    #[task(binds = EXTI3, priority = 15, shared = [meas])]
    fn fes(cx: fes::Context) {
        ack(FES);
        handlers::fes::<Nucleo>(cx.shared.meas);
    }

    /// Scale edge on A or B (PB8, PB9).
    #[task(binds = EXTI9_5, priority = 15, shared = [meas])]
    fn scale(cx: scale::Context) {
        ack(SCALE_A | SCALE_B);
        handlers::scale::<Nucleo>(cx.shared.meas);
    }

    /// Idle's snapshot of the outputs; after any edge pending with it.
    #[task(binds = TIM7, priority = 15, shared = [meas, snapshot])]
    fn observe(cx: observe::Context) {
        let o = cx.shared.meas.outputs();
        let mut snapshot = cx.shared.snapshot;
        snapshot.lock(|s| *s = o);
    }

    /// CNC force-path commands (PC11–PC13).
    #[task(binds = EXTI15_10, priority = 12, shared = [force])]
    fn cnc_force_command(mut cx: cnc_force_command::Context) {
        // SAFETY: a read of the pending register.
        let pr = unsafe { (*pac::EXTI::ptr()).pr().read().bits() };
        ack(pr & FORCE_LINES);
        PENDING_COMMANDS.fetch_or(pr & FORCE_LINES, Ordering::Relaxed);
        while PENDING_COMMANDS.load(Ordering::Relaxed) != 0 {
            cx.shared.force.lock(handlers::force_command::<Nucleo>);
        }
    }
    /// 1 kHz ADC sample (TIM2 update): convert the eight channels, queue them.
    #[task(binds = TIM2, priority = 8, shared = [counters], local = [samples_in])]
    fn adc_sample(mut cx: adc_sample::Context) {
        // SAFETY: clears TIM2's update flag (write 0 to UIF; other flags unused).
        unsafe { (*pac::TIM2::ptr()).sr().write(|w| w.bits(0)) };
        if !handlers::adc_sample::<Nucleo>(cx.local.samples_in) {
            cx.shared
                .counters
                .lock(|c| c.overflowed = c.overflowed.saturating_add(1));
        }
    }

    /// 20 Hz control period (TIM3 update): samples, estimate, control, wear.
    #[task(binds = TIM3, priority = 4, shared = [force], local = [samples_out])]
    fn control_period(mut cx: control_period::Context) {
        // SAFETY: clears TIM3's update flag.
        unsafe { (*pac::TIM3::ptr()).sr().write(|w| w.bits(0)) };
        let queue = cx.local.samples_out;
        cx.shared
            .force
            .lock(|k| handlers::control_period::<Nucleo>(k, queue));
    }
}
