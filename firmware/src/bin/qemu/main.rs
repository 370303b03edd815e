//! The co-simulation board: QEMU's lm3s6965evb (Cortex-M3). The input pins are virtual:
//! the co-simulation driver in `idle` sets their levels, then pends the event's
//! interrupt, exactly as an edge on a real pin would. The handlers are the shared ones.
//!
//! Interrupt map (the LM3S6965's GPIO port interrupts stand in for the pins' edges). The
//! measurement tasks share the highest priority, 7, with IRQ numbers in the model's
//! canonical same-clock order (Cortex-M takes same-priority pending interrupts lowest
//! number first): GPIOA (0) = CNC arm/abort, GPIOB (1) = contact, GPIOC (2) = index,
//! GPIOD (3) = FES counter compare, GPIOE (4) = scale A/B, UART0 (5) = pulse-count preset
//! (test event), UART1 (6) = observe (the driver's reset of and snapshot from the
//! kernel). Below them:
//! GPIOF = CNC force-path command (5), ADC0 sequence 0 = 1 kHz ADC sample (4), TIMER0A =
//! 20 Hz control period (2). The ADC's result registers and the command lines are virtual
//! too; "register now" is a variable the driver reads back as the trace's output.
//!
//! The FES counter is virtual as well (QEMU's Stellaris timers have no edge-count mode):
//! the driver counts each FES event in [`FES_COUNT`] and, when the count reaches the
//! compare value the handlers set, pends the compare interrupt, as a timer's compare
//! match would; other FES events raise no interrupt.
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, Ordering};
use heapless::spsc::{Consumer, Producer, Queue};
use tooltouch_firmware::board::Board;
use tooltouch_firmware::model::force::events::ForceEvent;
use tooltouch_firmware::model::force::sampling::AdcCodes;
use tooltouch_firmware::model::{MeasureOutputs, Measurement};

/// Virtual pin bits in [`PINS`].
const ARM: u8 = 1;
const CONTACT: u8 = 2;
const SCALE_A: u8 = 4;
const SCALE_B: u8 = 8;

/// Levels of the virtual input pins, written by the driver before each pend.
static PINS: AtomicU8 = AtomicU8::new(0);
/// The virtual FES counter: FES events so far (wrapping).
static FES_COUNT: AtomicU32 = AtomicU32::new(0);
/// The virtual FES counter's compare value.
static FES_COMPARE: AtomicU32 = AtomicU32::new(0);
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

/// The driver's window on the measurement kernel, which only the measurement tasks may
/// touch (it is lock-free at their priority): the driver queues a fresh kernel and pends
/// `observe`, which installs it; `observe` queues the kernel's outputs back. Lock-free
/// single-producer single-consumer queues, one element deep (the driver waits for each
/// observe), so neither side takes a lock.
const MAILBOX: usize = 2;
/// Fresh kernels, driver to `observe`.
type Resets = Queue<Measurement, MAILBOX>;
/// Output snapshots, `observe` to the driver.
type Snapshots = Queue<MeasureOutputs, MAILBOX>;

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
    fn fes_count() -> u32 {
        FES_COUNT.load(Ordering::Relaxed)
    }
    fn set_fes_compare(at: u32) {
        FES_COMPARE.store(at, Ordering::Relaxed);
    }
    fn pend_fes_compare() {
        rtic::pend(lm3s6965::Interrupt::GPIOD);
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
        encode_command, set_adc, Consumer, Producer, Qemu, Resets, Snapshots, ARM, COMMAND,
        CONTACT, FEED_OVERRIDE, FES_COMPARE, FES_COUNT, MAILBOX, PINS, PRESET, REGISTER_NOW,
        SCALE_A, SCALE_B, WEAR_ALARM,
    };
    use core::sync::atomic::Ordering;
    use cortex_m::interrupt::InterruptNumber;
    use cortex_m::peripheral::{syst::SystClkSource, NVIC};
    use cortex_m_semihosting::debug;
    use lm3s6965::Interrupt;
    use tooltouch_firmware::cosim::{self, Input, Target};
    use tooltouch_firmware::handlers::{
        self, Counters, MeasureDomain, SampleConsumer, SampleProducer, SampleQueue,
    };
    use tooltouch_firmware::model::force::config::{ForceConfig, ForceSettings};
    use tooltouch_firmware::model::force::events::ForceEvent;
    use tooltouch_firmware::model::force::kernel::{ForceKernel, ForceOutputs};
    use tooltouch_firmware::model::{MeasureConfig, MeasureEvent, MeasureOutputs, Measurement};
    use tooltouch_firmware::{semihosting, stack};

    /// The interrupt of [`observe`]: after every measurement edge's (higher IRQ number,
    /// same priority).
    const OBSERVE: Interrupt = Interrupt::UART1;

    #[shared]
    struct Shared {
        /// The measurement kernel and its FES pulse count. Lock-free: only the
        /// measurement tasks touch it, and they all run at one priority, so none can
        /// preempt another.
        #[lock_free]
        meas: MeasureDomain,
        force: ForceKernel,
        counters: Counters,
    }

    #[local]
    struct Local {
        calibration: (u32, u32),
        samples_in: SampleProducer<'static>,
        samples_out: SampleConsumer<'static>,
        resets_in: Producer<'static, Measurement, MAILBOX>,
        resets_out: Consumer<'static, Measurement, MAILBOX>,
        snapshots_in: Producer<'static, MeasureOutputs, MAILBOX>,
        snapshots_out: Consumer<'static, MeasureOutputs, MAILBOX>,
    }

    #[init(local = [
        queue: SampleQueue = SampleQueue::new(),
        resets: Resets = Resets::new(),
        snapshots: Snapshots = Snapshots::new(),
    ])]
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
        let (resets_in, resets_out) = cx.local.resets.split();
        let (snapshots_in, snapshots_out) = cx.local.snapshots.split();
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
                meas: MeasureDomain::start::<Qemu>(Measurement::new(&MeasureConfig::default())),
                force,
                counters: Counters::default(),
            },
            Local {
                calibration,
                samples_in,
                samples_out,
                resets_in,
                resets_out,
                snapshots_in,
                snapshots_out,
            },
        )
    }

    /// Drives the firmware from idle (priority 0): every pend preempts it at once.
    struct Driver<F, C> {
        resets: &'static mut Producer<'static, Measurement, MAILBOX>,
        snapshots: &'static mut Consumer<'static, MeasureOutputs, MAILBOX>,
        /// The last snapshot (returned again should `observe` not have run: a mismatch
        /// the host reports).
        last: MeasureOutputs,
        force: F,
        counters: C,
        calibration: (u32, u32),
    }

    /// Pends `irq` with the barriers QEMU needs to take it at once: QEMU takes a pended
    /// interrupt only between translated blocks, and without them back-to-back pends
    /// merge into one interrupt. Returns after the handler (idle is preempted).
    fn run_now(irq: Interrupt) {
        rtic::pend(irq);
        cortex_m::asm::dsb();
        cortex_m::asm::isb();
    }

    impl<F, C> Target for Driver<F, C>
    where
        F: rtic::Mutex<T = ForceKernel>,
        C: rtic::Mutex<T = Counters>,
    {
        fn configure(&mut self, config: &MeasureConfig, force: &ForceConfig) {
            PINS.store(0, Ordering::Relaxed);
            REGISTER_NOW.store(false, Ordering::Relaxed);
            COMMAND.store(0, Ordering::Relaxed);
            // The kernel is the measurement tasks' alone: observe installs the new one.
            // (The queue is empty: observe ran after the previous reset.)
            let _ = self.resets.enqueue(Measurement::new(config));
            run_now(OBSERVE);
            let _ = self.snapshots.dequeue();
            // A previous stream may have left samples queued after its last control
            // period: run one period into the old kernel to drain them, then replace it.
            run_now(Interrupt::TIMER_0A);
            let kernel = ForceKernel::new(force);
            self.force.lock(|k| *k = kernel);
            FEED_OVERRIDE.store(kernel.outputs().override_pct, Ordering::Relaxed);
            WEAR_ALARM.store(false, Ordering::Relaxed);
            self.counters.lock(|c| *c = Counters::default());
        }

        fn inject(&mut self, input: Input) -> Option<u32> {
            let event = match input {
                Input::Measure(event) => event,
                Input::Force(event) => return self.inject_force(event),
            };
            let pins = PINS.load(Ordering::Relaxed);
            let (irq, pins) = match event {
                MeasureEvent::Arm(on) => (Interrupt::GPIOA, set(pins, ARM, on)),
                MeasureEvent::Contact(on) => (Interrupt::GPIOB, set(pins, CONTACT, on)),
                MeasureEvent::Index => (Interrupt::GPIOC, pins),
                MeasureEvent::Fes => {
                    // The counter counts the edge; only a compare match interrupts.
                    let count = FES_COUNT.load(Ordering::Relaxed).wrapping_add(1);
                    FES_COUNT.store(count, Ordering::Relaxed);
                    if count != FES_COMPARE.load(Ordering::Relaxed) {
                        return None;
                    }
                    (Interrupt::GPIOD, pins)
                }
                MeasureEvent::Scale { a, b } => {
                    (Interrupt::GPIOE, set(set(pins, SCALE_A, a), SCALE_B, b))
                }
                MeasureEvent::PresetPulses(n) => {
                    PRESET.store(n, Ordering::Relaxed);
                    (Interrupt::UART0, pins)
                }
            };
            PINS.store(pins, Ordering::Relaxed);
            Some(self.pend_and_time(irq))
        }

        fn outputs(&mut self) -> MeasureOutputs {
            run_now(OBSERVE);
            if let Some(o) = self.snapshots.dequeue() {
                self.last = o;
            }
            let mut o = self.last;
            // "Register now" as the CNC sees it: the output pin the handlers drive, so
            // the trace checks the pin, not only the kernel's flag.
            o.register_now = REGISTER_NOW.load(Ordering::Relaxed);
            o
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

    impl<F, C> Driver<F, C>
    where
        F: rtic::Mutex<T = ForceKernel>,
        C: rtic::Mutex<T = Counters>,
    {
        fn inject_force(&mut self, event: ForceEvent) -> Option<u32> {
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
            Some(self.pend_and_time(irq))
        }

        /// Pends `irq` and returns the SysTick ticks until it has run. An edge whose
        /// interrupt is still pending would be lost (merged into the pending one): it
        /// is counted in [`Counters::lost`].
        ///
        /// The timed sequence is fixed assembly, so the harness's share of the profile
        /// does not move with the compiler's scheduling: between the two SysTick reads
        /// run the pend's store, `dsb`, `isb`, the handler (exception entry and exit
        /// execute no instruction under QEMU) and the second read: 4 instructions plus
        /// the handler's.
        fn pend_and_time(&mut self, irq: Interrupt) -> u32 {
            if NVIC::is_pending(irq) {
                self.counters.lock(|c| c.lost = c.lost.saturating_add(1));
            }
            let n = u32::from(irq.number());
            // NVIC_ISPRn, one bit per interrupt.
            let ispr = 0xe000_e200_u32.wrapping_add((n >> 5) << 2);
            let bit = 1_u32 << (n & 31);
            let (t0, t1): (u32, u32);
            // SAFETY: a write-one-to-set of the interrupt's pending bit (what
            // `rtic::pend` does) between two reads of SysTick's current value register;
            // the handler it runs is an RTIC task like any pended one.
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
    }

    fn set(pins: u8, bit: u8, on: bool) -> u8 {
        if on {
            pins | bit
        } else {
            pins & !bit
        }
    }

    #[idle(shared = [force, counters], local = [calibration, resets_in, snapshots_out])]
    fn idle(cx: idle::Context) -> ! {
        let mut driver = Driver {
            resets: cx.local.resets_in,
            snapshots: cx.local.snapshots_out,
            last: MeasureOutputs::default(),
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

    // The measurement tasks: one priority (7, the highest), IRQ numbers in the model's
    // canonical same-clock order (arm, contact, index, FES, scale), so simultaneous
    // edges are handled in that order and none preempts another: the kernel needs no
    // lock.

    /// CNC command (arm / abort).
    #[task(binds = GPIOA, priority = 7, shared = [meas])]
    fn cnc_command(cx: cnc_command::Context) {
        handlers::cnc_command::<Qemu>(cx.shared.meas);
    }

    /// Contact edge.
    #[task(binds = GPIOB, priority = 7, shared = [meas])]
    fn contact(cx: contact::Context) {
        handlers::contact::<Qemu>(cx.shared.meas);
    }

    /// Index pulse.
    #[task(binds = GPIOC, priority = 7, shared = [meas])]
    fn index(cx: index::Context) {
        handlers::index::<Qemu>(cx.shared.meas);
    }

    /// FES counter compare: the pulse that may decide, or the fold limit.
    #[task(binds = GPIOD, priority = 7, shared = [meas])]
    fn fes_compare(cx: fes_compare::Context) {
        handlers::fes_compare::<Qemu>(cx.shared.meas);
    }

    /// Scale edge.
    #[task(binds = GPIOE, priority = 7, shared = [meas])]
    fn scale(cx: scale::Context) {
        handlers::scale::<Qemu>(cx.shared.meas);
    }

    /// Test event: preset the FES pulse count (UART0 stands in for a debug request).
    #[task(binds = UART0, priority = 7, shared = [meas])]
    fn preset_pulses(cx: preset_pulses::Context) {
        handlers::preset_pulses::<Qemu>(cx.shared.meas, PRESET.load(Ordering::Relaxed));
    }

    /// The driver's access to the kernel (UART1 stands in for a debug request): installs
    /// a queued fresh kernel, then queues a snapshot of the outputs (folding the counted
    /// FES pulses first). Runs after any edge pending with it.
    #[task(binds = UART1, priority = 7, shared = [meas], local = [resets_out, snapshots_in])]
    fn observe(cx: observe::Context) {
        let meas = cx.shared.meas;
        if let Some(fresh) = cx.local.resets_out.dequeue() {
            *meas = MeasureDomain::start::<Qemu>(fresh);
        }
        let outputs = handlers::observe::<Qemu>(meas);
        // Full only if the driver skipped a snapshot; it then reads the older one.
        let _ = cx.local.snapshots_in.enqueue(outputs);
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
