//! The co-simulation board: QEMU's lm3s6965evb (Cortex-M3). The input pins are virtual:
//! the co-simulation driver in `idle` sets their levels, then pends the event's
//! interrupt, exactly as an edge on a real pin would. The handlers are the shared ones.
//!
//! Interrupt map (the LM3S6965's GPIO port interrupts stand in for the pins' edges). The
//! measurement tasks share the highest priority, 7, with IRQ numbers in the model's
//! canonical same-clock order (Cortex-M takes same-priority pending interrupts lowest
//! number first; [`interrupts::QEMU`] holds them for the host tests): GPIOA (0) = CNC
//! arm/abort, GPIOB (1) = contact, GPIOC (2) = index, GPIOD (3) = FES counter compare,
//! GPIOE (4) = scale A/B, UART0 (5) = pulse-count preset (test event), UART1 (6) =
//! observe (the driver's reset of and snapshot from the kernel), SSI0 (7) = the clock's
//! alarm (the FES watchdog's fold). Below them: GPIOF = CNC
//! force-path command (5), ADC0 sequence 0 = 1 kHz ADC sample (4), TIMER0A = 20 Hz
//! control period (2). The ADC's result registers and the command lines are virtual too;
//! "register now" is a variable the driver reads back as the trace's output.
//!
//! Modules: [`board`] the virtual pins, registers and FES counter ([`Board`] for the
//! handlers); [`driver`] the co-simulation driver's side (event in, interrupt pended and
//! timed, outputs back). This file is the RTIC application that binds them.
#![no_std]
#![no_main]

mod board;
mod driver;

use lm3s6965::Interrupt;
use tooltouch_firmware::interrupts;
use tooltouch_firmware::model::MeasureEvent;

/// The IRQ number the driver pends for `event`.
const fn pended(event: &MeasureEvent) -> u16 {
    driver::measure_interrupt(event) as u16
}

// The measurement tasks' bindings below, and the interrupts the driver pends, are the ones
// the host tests replay events in (`interrupts::QEMU`): a rebinding must change all three.
const _: () = {
    let irqs = interrupts::QEMU;
    assert!(Interrupt::GPIOA as u16 == irqs.arm);
    assert!(Interrupt::GPIOB as u16 == irqs.contact);
    assert!(Interrupt::GPIOC as u16 == irqs.index);
    assert!(Interrupt::GPIOD as u16 == irqs.fes_compare);
    assert!(Interrupt::GPIOE as u16 == irqs.scale);
    assert!(matches!(irqs.preset_pulses, Some(n) if n == Interrupt::UART0 as u16));
    assert!(Interrupt::UART1 as u16 == irqs.observe);
    assert!(pended(&MeasureEvent::Arm(true)) == irqs.arm);
    assert!(pended(&MeasureEvent::Contact(true)) == irqs.contact);
    assert!(pended(&MeasureEvent::Index) == irqs.index);
    assert!(pended(&MeasureEvent::Fes) == irqs.fes_compare);
    assert!(pended(&MeasureEvent::Scale { a: true, b: true }) == irqs.scale);
    assert!(matches!(irqs.preset_pulses, Some(n) if n == pended(&MeasureEvent::PresetPulses(0))));
    assert!(driver::OBSERVE as u16 == irqs.observe);
    assert!(matches!(driver::ADC_SAMPLE, Interrupt::ADC0_SEQUENCE_0));
    assert!(matches!(driver::CONTROL_PERIOD, Interrupt::TIMER_0A));
    assert!(matches!(driver::FORCE_COMMAND, Interrupt::GPIOF));
    assert!(matches!(driver::TIME_ALARM_IRQ, Interrupt::SSI0));
};

#[rtic::app(device = lm3s6965, peripherals = false)]
mod app {
    use crate::board::{Qemu, PRESET};
    use crate::driver::{self, Driver, Resets, Snapshots};
    use core::sync::atomic::Ordering;
    use cortex_m::peripheral::syst::SystClkSource;
    use heapless::spsc::{Consumer, Producer};
    use tooltouch_firmware::baked;
    use tooltouch_firmware::handlers::{
        self, Counters, MeasureDomain, SampleConsumer, SampleProducer, SampleQueue,
    };
    use tooltouch_firmware::model::force::kernel::ForceKernel;
    use tooltouch_firmware::model::{MeasureConfig, MeasureOutputs};
    use tooltouch_firmware::semihosting::{self, exit_code, print};

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
        resets_in: Producer<'static, MeasureConfig>,
        resets_out: Consumer<'static, MeasureConfig>,
        snapshots_in: Producer<'static, MeasureOutputs>,
        snapshots_out: Consumer<'static, MeasureOutputs>,
    }

    #[init(local = [
        queue: SampleQueue = SampleQueue::new(),
        resets: Resets = Resets::new(),
        snapshots: Snapshots = Snapshots::new(),
    ])]
    fn init(cx: init::Context) -> (Shared, Local) {
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
        let calibration = driver::calibrate();
        let (samples_in, samples_out) = cx.local.queue.split();
        let (resets_in, resets_out) = cx.local.resets.split();
        let (snapshots_in, snapshots_out) = cx.local.snapshots.split();
        // The image boots with its baked configuration (each replayed stream then sets
        // its own); build.rs validated it, so the error arm never runs.
        let (measure, force) = match (baked::measure(), baked::force()) {
            (Ok(m), Ok(f)) => (m, ForceKernel::new(&f)),
            _ => {
                print(b"tooltouch firmware: the baked configuration does not decode\n");
                semihosting::exit(exit_code::BAD_BAKED_CONFIG)
            }
        };
        print(&baked::boot_line());
        (
            Shared {
                meas: MeasureDomain::start::<Qemu>(&measure),
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

    /// Runs the co-simulation: the event streams from the host file through the
    /// interrupts, the trace back; then exits QEMU with the run's status.
    #[idle(shared = [force, counters], local = [calibration, resets_in, snapshots_out])]
    fn idle(cx: idle::Context) -> ! {
        let mut driver = Driver::new(
            cx.local.resets_in,
            cx.local.snapshots_out,
            cx.shared.force,
            cx.shared.counters,
            *cx.local.calibration,
        );
        let code = semihosting::replay(&mut driver);
        // Every output was written (synchronous semihosting calls) before the exit.
        semihosting::exit(code)
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
            *meas = MeasureDomain::start::<Qemu>(&fresh);
        }
        let outputs = handlers::observe::<Qemu>(meas);
        // Full only if the driver skipped a snapshot; it then reads the older one.
        let _ = cx.local.snapshots_in.enqueue(outputs);
    }

    /// The clock's alarm (SSI0 stands in for a timer compare): the FES watchdog's fold,
    /// after every other measurement task pending with it.
    #[task(binds = SSI0, priority = 7, shared = [meas])]
    fn time_alarm(cx: time_alarm::Context) {
        handlers::time_alarm::<Qemu>(cx.shared.meas);
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
