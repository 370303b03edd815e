//! The co-simulation board: QEMU's lm3s6965evb (Cortex-M3). The input pins are virtual:
//! the co-simulation driver in `idle` sets their levels, then pends the event's
//! interrupt, exactly as an edge on a real pin would. The handlers are the shared ones.
//!
//! Interrupt map (the LM3S6965's GPIO port interrupts stand in for the pins' edges):
//! GPIOA = FES, GPIOB = index, GPIOC = contact, GPIOD = scale A/B, GPIOE = CNC arm/abort,
//! GPIOF = CNC force-path command, ADC0 sequence 0 = 1 kHz ADC sample, TIMER0A = 20 Hz
//! control period. The ADC's result registers and the command lines are virtual too.
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, Ordering};
use tooltouch_firmware::board::Board;
use tooltouch_firmware::model::force::ForceEvent;
use tooltouch_firmware::model::sampling::AdcCodes;

/// Virtual pin bits in [`PINS`].
const ARM: u8 = 1;
const CONTACT: u8 = 2;
const SCALE_A: u8 = 4;
const SCALE_B: u8 = 8;

/// Levels of the virtual input pins, written by the driver before each pend.
static PINS: AtomicU8 = AtomicU8::new(0);
/// The "register now" output.
static REGISTER_NOW: AtomicBool = AtomicBool::new(false);
/// The virtual ADC's result registers: speed, power, force, v_u, v_v, v_w, i_u, i_v,
/// two 16-bit codes per word.
static ADC: [AtomicU32; 4] = [
    AtomicU32::new(0),
    AtomicU32::new(0),
    AtomicU32::new(0),
    AtomicU32::new(0),
];
/// The pending CNC force-path command: 0 none, else `1 + index` of [`encode_command`].
static COMMAND: AtomicU32 = AtomicU32::new(0);
/// The value of the pending pulse-count preset (test event).
static PRESET: AtomicU32 = AtomicU32::new(0);
/// The feed override output, %.
static FEED_OVERRIDE: AtomicU8 = AtomicU8::new(0);
/// The wear alarm output.
static WEAR_ALARM: AtomicBool = AtomicBool::new(false);

/// A CNC command as the command register holds it: kind in bits 8..16, argument in 0..8,
/// bit 16 set (so 0 means "none").
fn encode_command(event: ForceEvent) -> u32 {
    let (kind, arg) = match event {
        ForceEvent::Identify(on) => (1, u32::from(on)),
        ForceEvent::Control(on) => (2, u32::from(on)),
        ForceEvent::Conditions(i) => (3, u32::from(i)),
        ForceEvent::ToolChanged => (4, 0),
        // Samples and ticks have their own interrupts.
        ForceEvent::Sample(_) | ForceEvent::Tick => (0, 0),
    };
    1 << 16 | kind << 8 | arg
}

fn decode_command(word: u32) -> Option<ForceEvent> {
    if word & 1 << 16 == 0 {
        return None;
    }
    let arg = (word & 0xff) as u8;
    match (word >> 8) & 0xff {
        1 => Some(ForceEvent::Identify(arg != 0)),
        2 => Some(ForceEvent::Control(arg != 0)),
        3 => Some(ForceEvent::Conditions(arg)),
        4 => Some(ForceEvent::ToolChanged),
        _ => None,
    }
}

fn set_adc(codes: &AdcCodes) {
    let words = [
        (codes.speed, codes.power),
        (codes.force, codes.volts[0]),
        (codes.volts[1], codes.volts[2]),
        (codes.amps[0], codes.amps[1]),
    ];
    for (reg, (lo, hi)) in ADC.iter().zip(words) {
        reg.store(u32::from(lo) | u32::from(hi) << 16, Ordering::Relaxed);
    }
}

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
    fn adc() -> AdcCodes {
        let w: [u32; 4] = [
            ADC[0].load(Ordering::Relaxed),
            ADC[1].load(Ordering::Relaxed),
            ADC[2].load(Ordering::Relaxed),
            ADC[3].load(Ordering::Relaxed),
        ];
        let lo = |x: u32| (x & 0xffff) as u16;
        let hi = |x: u32| (x >> 16) as u16;
        AdcCodes {
            speed: lo(w[0]),
            power: hi(w[0]),
            force: lo(w[1]),
            volts: [hi(w[1]), lo(w[2]), hi(w[2])],
            amps: [lo(w[3]), hi(w[3])],
        }
    }
    fn force_command() -> Option<ForceEvent> {
        decode_command(COMMAND.swap(0, Ordering::Relaxed))
    }
    fn set_feed_override(percent: u8) {
        FEED_OVERRIDE.store(percent, Ordering::Relaxed);
    }
    fn set_wear_alarm(on: bool) {
        WEAR_ALARM.store(on, Ordering::Relaxed);
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
    use super::{
        encode_command, set_adc, Qemu, ARM, COMMAND, CONTACT, FEED_OVERRIDE, PINS, PRESET,
        REGISTER_NOW, SCALE_A, SCALE_B, WEAR_ALARM,
    };
    use core::sync::atomic::Ordering;
    use cortex_m::peripheral::{syst::SystClkSource, NVIC, SYST};
    use cortex_m_semihosting::debug;
    use lm3s6965::Interrupt;
    use tooltouch_firmware::cosim::{self, Input, Target};
    use tooltouch_firmware::handlers::{
        self, Counters, SampleConsumer, SampleProducer, SampleQueue,
    };
    use tooltouch_firmware::model::force::{
        ForceConfig, ForceEvent, ForceKernel, ForceOutputs, ForceSettings,
    };
    use tooltouch_firmware::model::{MeasureConfig, MeasureEvent, MeasureOutputs, Measurement};
    use tooltouch_firmware::{semihosting, stack};

    #[shared]
    struct Shared {
        meas: Measurement,
        force: ForceKernel,
        counters: Counters,
    }

    #[local]
    struct Local {
        calibration: (u32, u32),
        samples_in: SampleProducer<'static>,
        samples_out: SampleConsumer<'static>,
    }

    #[init(local = [queue: SampleQueue = SampleQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        stack::paint(256);
        // QEMU's lm3s6965evb derives the system clock (and so SysTick) from RCC.SYSDIV:
        // a period of 5 ns × (SYSDIV + 1), 80 ns at reset. SYSDIV = 0 gives 5 ns, i.e.
        // 5 instructions per tick under `-icount shift=0`, for a finer profile.
        const RCC: *mut u32 = 0x400f_e060 as *mut u32;
        // SAFETY: the system control block's RCC register, written once before anything
        // depends on the clock; only QEMU's board model reads SYSDIV this way.
        unsafe {
            let rcc = core::ptr::read_volatile(RCC);
            core::ptr::write_volatile(RCC, rcc & !(0xf << 23));
        }
        let mut syst = cx.core.SYST;
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(0x00ff_ffff);
        syst.clear_current();
        syst.enable_counter();
        let calibration = super::calibrate();
        let (samples_in, samples_out) = cx.local.queue.split();
        // The default force configuration is valid (model::force tests it); a failure
        // would only leave the force kernel at the smallest valid state.
        let force = match ForceSettings::default().validate() {
            Ok(c) => ForceKernel::new(&c),
            Err(_) => loop {
                debug::exit(debug::EXIT_FAILURE);
            },
        };
        (
            Shared {
                meas: Measurement::new(&MeasureConfig::default()),
                force,
                counters: Counters::default(),
            },
            Local {
                calibration,
                samples_in,
                samples_out,
            },
        )
    }

    /// Drives the firmware from idle (priority 0): every pend preempts it at once.
    struct Driver<M, F, C> {
        meas: M,
        force: F,
        counters: C,
        calibration: (u32, u32),
    }

    impl<M, F, C> Target for Driver<M, F, C>
    where
        M: rtic::Mutex<T = Measurement>,
        F: rtic::Mutex<T = ForceKernel>,
        C: rtic::Mutex<T = Counters>,
    {
        fn configure(&mut self, config: &MeasureConfig, force: &ForceConfig) {
            PINS.store(0, Ordering::Relaxed);
            REGISTER_NOW.store(false, Ordering::Relaxed);
            COMMAND.store(0, Ordering::Relaxed);
            self.meas.lock(|m| *m = Measurement::new(config));
            // A previous stream may have left samples queued after its last control
            // period: run one period into the old kernel to drain them, then replace it.
            rtic::pend(Interrupt::TIMER_0A);
            cortex_m::asm::dsb();
            cortex_m::asm::isb();
            let kernel = ForceKernel::new(force);
            self.force.lock(|k| *k = kernel);
            FEED_OVERRIDE.store(kernel.outputs().override_pct, Ordering::Relaxed);
            WEAR_ALARM.store(false, Ordering::Relaxed);
            self.counters.lock(|c| *c = Counters::default());
        }

        fn inject(&mut self, input: Input) -> u32 {
            let event = match input {
                Input::Measure(event) => event,
                Input::Force(event) => return self.inject_force(event),
            };
            let pins = PINS.load(Ordering::Relaxed);
            let (irq, pins) = match event {
                MeasureEvent::Arm(on) => (Interrupt::GPIOE, set(pins, ARM, on)),
                MeasureEvent::Contact(on) => (Interrupt::GPIOC, set(pins, CONTACT, on)),
                MeasureEvent::Index => (Interrupt::GPIOB, pins),
                MeasureEvent::Fes => (Interrupt::GPIOA, pins),
                MeasureEvent::PresetPulses(n) => {
                    PRESET.store(n, Ordering::Relaxed);
                    (Interrupt::UART1, pins)
                }
                MeasureEvent::Scale { a, b } => {
                    (Interrupt::GPIOD, set(set(pins, SCALE_A, a), SCALE_B, b))
                }
            };
            PINS.store(pins, Ordering::Relaxed);
            // QEMU takes a pended interrupt only between translated blocks: without the
            // barriers (in pend_and_time), back-to-back pends merge into one interrupt.
            self.pend_and_time(irq)
        }

        fn outputs(&mut self) -> MeasureOutputs {
            self.meas.lock(|m| m.outputs())
        }

        fn force_outputs(&mut self) -> ForceOutputs {
            self.force.lock(|k| k.outputs())
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

    impl<M, F, C> Driver<M, F, C>
    where
        M: rtic::Mutex<T = Measurement>,
        F: rtic::Mutex<T = ForceKernel>,
        C: rtic::Mutex<T = Counters>,
    {
        fn inject_force(&mut self, event: ForceEvent) -> u32 {
            let irq = match event {
                ForceEvent::Sample(codes) => {
                    set_adc(&codes);
                    Interrupt::ADC0_SEQUENCE_0
                }
                ForceEvent::Tick => Interrupt::TIMER_0A,
                command => {
                    COMMAND.store(encode_command(command), Ordering::Relaxed);
                    Interrupt::GPIOF
                }
            };
            self.pend_and_time(irq)
        }

        /// Pends `irq` and returns the SysTick ticks until it has run.
        fn pend_and_time(&mut self, irq: Interrupt) -> u32 {
            if NVIC::is_pending(irq) {
                self.counters.lock(|c| c.lost = c.lost.saturating_add(1));
            }
            let t0 = SYST::get_current();
            rtic::pend(irq);
            cortex_m::asm::dsb();
            cortex_m::asm::isb();
            let t1 = SYST::get_current();
            t0.wrapping_sub(t1) & 0x00ff_ffff
        }
    }

    fn set(pins: u8, bit: u8, on: bool) -> u8 {
        if on {
            pins | bit
        } else {
            pins & !bit
        }
    }

    #[idle(shared = [meas, force, counters], local = [calibration])]
    fn idle(cx: idle::Context) -> ! {
        let mut driver = Driver {
            meas: cx.shared.meas,
            force: cx.shared.force,
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

    /// Test event: preset the FES pulse count (UART1 stands in for a debug request).
    #[task(binds = UART1, priority = 7, shared = [meas])]
    fn preset_pulses(mut cx: preset_pulses::Context) {
        let n = PRESET.load(Ordering::Relaxed);
        cx.shared.meas.lock(|m| handlers::preset_pulses(m, n));
    }

    /// CNC command (arm / abort).
    #[task(binds = GPIOE, priority = 5, shared = [meas])]
    fn cnc_command(mut cx: cnc_command::Context) {
        cx.shared.meas.lock(handlers::cnc_command::<Qemu>);
    }

    /// CNC force-path command (identify, control on/off, conditions, tool changed).
    #[task(binds = GPIOF, priority = 5, shared = [force])]
    fn cnc_force_command(mut cx: cnc_force_command::Context) {
        cx.shared.force.lock(handlers::force_command::<Qemu>);
    }

    /// 1 kHz ADC sample: queue the codes, count a full queue.
    #[task(binds = ADC0_SEQUENCE_0, priority = 4, shared = [counters], local = [samples_in])]
    fn adc_sample(mut cx: adc_sample::Context) {
        if !handlers::adc_sample::<Qemu>(cx.local.samples_in) {
            cx.shared
                .counters
                .lock(|c| c.overflowed = c.overflowed.saturating_add(1));
        }
    }

    /// 20 Hz control period: the queued samples, then estimate, control, wear.
    #[task(binds = TIMER_0A, priority = 2, shared = [force], local = [samples_out])]
    fn control_period(mut cx: control_period::Context) {
        let queue = cx.local.samples_out;
        cx.shared
            .force
            .lock(|k| handlers::control_period::<Qemu>(k, queue));
    }
}
