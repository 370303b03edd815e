//! The real board: a Nucleo-F446RE (STM32F446RE, Cortex-M4F). The pins' edges raise EXTI
//! interrupts bound to the same shared handlers as the QEMU board, and TIM2 counts the FES
//! pulses; defmt logs over RTT (probe-rs prints them).
//!
//! Pin map (Arduino / Morpho header names in brackets; docs/firmware.md has the wiring):
//!
//! | pin  | header   | signal                         | interrupt        | edges   |
//! |------|----------|--------------------------------|------------------|---------|
//! | PA0  | A0       | CNC arm / abort (in)           | EXTI0, prio 15   | both    |
//! | PA1  | A1       | tool–workpiece contact (in)    | EXTI1, prio 15   | both    |
//! | PB2  | CN10-22  | index pulse (in)               | EXTI2, prio 15   | rising  |
//! | PB3  | D3       | FES encoder pulse (in; AF1 = TIM2_CH2, counted by TIM2) | TIM2 compare, prio 15 | rising |
//! | PB8  | D15      | linear scale A (in)            | EXTI9_5, prio 15 | both    |
//! | PB9  | D14      | linear scale B (in)            | EXTI9_5, prio 15 | both    |
//! | —    | —        | observe (idle's output snapshot)| TIM7, prio 15   | —       |
//! | PC11 | CN7-2    | CNC force control on (in)      | EXTI15_10, pr 12 | both    |
//! | PC12 | CN7-3    | CNC no-load identification (in)| EXTI15_10, pr 12 | both    |
//! | PC13 | B1 button| tool changed (in, active low)  | EXTI15_10, pr 12 | falling |
//! | PC0–PC5, PB0, PB1 | A5, A4, CN7-35, CN7-37, CN10-34, CN10-6, A3, CN10-24 | ADC1 IN10–IN15, IN8, IN9: speed, power, force, v_u, v_v, v_w, i_u, i_v | TIM6 1 kHz, pr 8 | — |
//! | —    | —        | 20 Hz control period           | TIM3, prio 4     | —       |
//! | PA5  | D13, LD2 | "register now" to the CNC (out)| —                | —       |
//! | PA6  | D12      | wear alarm (out)               | —                | —       |
//! | PA7  | D11      | fault, to the CNC's alarm input (out) | —         | —       |
//! | —    | —        | the measurement's clock alarm (TIM5, 1 MHz) | TIM5, prio 15 | — |
//! | PB6  | D10      | feed override, PWM 15.625 kHz, duty = % / 256 (TIM4_CH1) | — | — |
//!
//! The measurement tasks share the highest priority, so none preempts another and the
//! measurement domain needs no lock. Their IRQ numbers (EXTI0 = 6, EXTI1 = 7, EXTI2 = 8,
//! EXTI9_5 = 23, TIM2 = 28, TIM7 = 55; [`interrupts::NUCLEO`] holds them for the host
//! tests) decide the order of simultaneous edges (Cortex-M takes same-priority pending
//! interrupts lowest number first): arm, contact, index as the model's canonical
//! same-clock order has them; the FES compare comes after the scale here, so the scale
//! task first folds the counted pulses whenever the counter has reached its compare
//! value (`handlers::scale`), and a deciding pulse counted before a scale edge latches
//! the position from before it, as in the model. The pins are chosen for their EXTI lines
//! (line n is pin n of any one port) and, for the FES line, its timer channel: PB3 leaves
//! its reset function (JTDO/SWO; probe-rs needs only SWD) for alternate function 1,
//! TIM2_CH2 (STM32F446 datasheet, alternate-function table).
//!
//! FES pulses raise no interrupt. TIM2 counts every rising edge of PB3 (external clock
//! mode 1 on TI2FP2, 32 bits, wrapping like the kernel's pulse count), and its channel 1
//! compare interrupt fires on the pulse that would decide or at most
//! `handlers::FES_FOLD_LIMIT` pulses after the last fold (`handlers::MeasureDomain`).
//! The timer's input filter (IC2F = 0011) counts a level that holds for 8 of its 84 MHz
//! clocks, so it rejects spikes under 95 ns and counts FES rates up to about 5 MHz, no
//! longer bounded by an interrupt per pulse; docs/firmware.md gives the cycle budget. The
//! channel is an input (CC2S = 01), so the pin is never driven; channel 1 is an output
//! compare in frozen mode (OC1M = 000, CC1E = 0) that drives no pin either.
//!
//! `init` sets the board up in named steps, one module each of the library's board code
//! (`tooltouch_firmware::nucleo`, shared with the on-target tests): the clock tree first
//! (`clocks`: SYSCLK 168 MHz from the PLL fed by the HSI; every setting below derived
//! from it at compile time and checked by `const` assertions), then the pins and their
//! EXTI lines (`pins`), the ADC (`adc`) and the timers (`timers`). Every wait of the
//! setup is bounded; should one run out, the board logs the step with defmt and stays on
//! the reset clocks (HSI 16 MHz, every bus /1) with timer and ADC settings derived for
//! those, so the 1 kHz and 20 Hz periods and the 15.625 kHz PWM stay exact and only the
//! FES-rate budget shrinks. The handlers' cost is counted in instructions and cycles, see
//! docs/firmware.md for the rates 168 MHz allows. The cutting-conditions command has no pin:
//! condition set 0 is used on this board.
#![no_std]
#![no_main]

#[cfg(feature = "emulated")]
mod emulated;

#[cfg(not(any(feature = "panic-check", feature = "emulated")))]
use defmt_rtt as _;

// The `panic-check` build's defmt logger is the library's (`nucleo::null_logger`).

use stm32f4::stm32f446 as pac;
use tooltouch_firmware::interrupts;
use tooltouch_firmware::model::MeasureOutputs;
#[cfg(feature = "cpu-load")]
use tooltouch_firmware::nucleo::cpu_load;
#[cfg(not(feature = "emulated"))]
use tooltouch_firmware::nucleo::pins;

/// The interrupt of the `observe` task (TIM7 stays disabled: only software pends it).
const OBSERVE: pac::Interrupt = pac::Interrupt::TIM7;

/// Idle on the board: logs every change of "register now" (PA5's output data bit) with
/// the outputs `observe` snapshots, and every other change of the measurement's status
/// (a fault latched, the decision confirmed: `pins::status`), and sleeps; with `cpu-load`, spins and reports the
/// interrupts' CPU load once per second (`sysclk_hz`, the core clock).
#[cfg(not(feature = "emulated"))]
fn report_decisions(
    mut snapshot: impl rtic::Mutex<T = MeasureOutputs>,
    mut counters: impl rtic::Mutex<T = tooltouch_firmware::handlers::Counters>,
    sysclk_hz: u32,
) -> ! {
    let mut reported = false;
    let report = match tooltouch_firmware::baked::measure() {
        Ok(config) => tooltouch_firmware::baked::reported_decision(&config),
        Err(_) => tooltouch_firmware::baked::reported_decision(&Default::default()),
    };
    #[cfg(feature = "cpu-load")]
    let mut load = cpu_load::CpuLoad::new(cpu_load::cycles(), sysclk_hz);
    #[cfg(not(feature = "cpu-load"))]
    let _ = sysclk_hz;
    let mut logged = pins::status_word(0, false);
    loop {
        let register_now = pins::register_now();
        let status = pins::status();
        if register_now != reported || status != logged {
            rtic::pend(OBSERVE);
            cortex_m::asm::dsb();
            cortex_m::asm::isb();
            let o = snapshot.lock(|s| *s);
            if register_now != reported {
                reported = register_now;
                let dropped = counters.lock(|c| c.overflowed);
                log_register_now(reported, &o, dropped, &report);
            } else {
                log_status(&o);
            }
            logged = pins::status_word(o.faults, o.confirmed);
        }
        #[cfg(feature = "cpu-load")]
        if let Some(permille) = load.turn(cpu_load::cycles()) {
            defmt::info!(
                "CPU load {}.{} % (interrupts; idle turn {} cycles)",
                permille / 10,
                permille % 10,
                load.shortest
            );
        }
        #[cfg(not(feature = "cpu-load"))]
        cortex_m::asm::wfi();
    }
}

/// The latched faults' names joined by `+` (`Faults`'s display), or `none`.
fn fault_names(faults: u8) -> heapless::String<96> {
    let mut s = heapless::String::new();
    let faults = tooltouch_firmware::model::Faults(faults);
    if faults.is_empty() {
        let _ = s.push_str("none");
    }
    for (i, name) in faults.names().enumerate() {
        if i > 0 {
            let _ = s.push('+');
        }
        let _ = s.push_str(name);
    }
    s
}

/// Whether a decision is confirmed, as the lines say it.
const fn confirmation(confirmed: bool) -> &'static str {
    if confirmed {
        "confirmed"
    } else {
        "not confirmed"
    }
}

/// Logs a change of the measurement's status after its decision (a fault latched, the
/// decision confirmed) or before it (a fault with no decision).
fn log_status(o: &MeasureOutputs) {
    defmt::info!(
        "status: faults {=str}, {=str}",
        fault_names(o.faults).as_str(),
        confirmation(o.confirmed)
    );
}

/// Logs a change of "register now" (to `on`) with the outputs `o` of the observe task
/// and the ADC samples dropped so far: idle's report (and the emulated driver's, after
/// every event), with the decision position corrected by the baked calibration (`report`).
fn log_register_now(
    on: bool,
    o: &MeasureOutputs,
    dropped: u32,
    report: &tooltouch_firmware::handlers::ReportedDecision,
) {
    if on {
        defmt::info!(
            "register now: position {} counts, calibrated {} counts (offset {}), first \
             contact at {}, {} revolutions, {} FES pulses, faults {=str}, {=str}; {} ADC \
             samples dropped",
            o.decision_position,
            report.position(o),
            report.offset(),
            o.first_contact_position,
            o.revolutions,
            o.pulses,
            fault_names(o.faults).as_str(),
            confirmation(o.confirmed),
            dropped
        );
    } else {
        defmt::info!("measurement cycle armed; {} ADC samples dropped", dropped);
    }
}

// The measurement tasks' bindings below are the ones the host tests replay events in
// (`interrupts::NUCLEO`): a rebinding must change both.
const _: () = {
    let irqs = interrupts::NUCLEO;
    assert!(pac::Interrupt::EXTI0 as u16 == irqs.arm);
    assert!(pac::Interrupt::EXTI1 as u16 == irqs.contact);
    assert!(pac::Interrupt::EXTI2 as u16 == irqs.index);
    assert!(pac::Interrupt::TIM2 as u16 == irqs.fes_compare);
    assert!(pac::Interrupt::EXTI9_5 as u16 == irqs.scale);
    assert!(pac::Interrupt::TIM7 as u16 == irqs.observe);
    assert!(pac::Interrupt::TIM5 as u16 == irqs.time_alarm);
    assert!(irqs.preset_pulses.is_none());
    assert!(OBSERVE as u16 == irqs.observe);
};

#[rtic::app(device = stm32f4::stm32f446, peripherals = true)]
mod app {
    use tooltouch_firmware::baked;
    use tooltouch_firmware::board::Board;
    use tooltouch_firmware::handlers::{
        self, Counters, MeasureDomain, SampleConsumer, SampleProducer, SampleQueue,
    };
    use tooltouch_firmware::model::force::kernel::ForceKernel;
    use tooltouch_firmware::model::MeasureOutputs;
    use tooltouch_firmware::nucleo::board::Nucleo;
    use tooltouch_firmware::nucleo::{pins, timers};

    #[shared]
    struct Shared {
        /// The measurement kernel and TIM2's FES count as of its last fold. Lock-free:
        /// only the measurement tasks touch it, and they all run at one priority, so none
        /// can preempt another.
        #[lock_free]
        meas: MeasureDomain,
        /// The kernel's outputs as of the last [`observe`], for idle's log.
        snapshot: MeasureOutputs,
        force: ForceKernel,
        counters: Counters,
    }

    #[local]
    struct Local {
        samples_in: SampleProducer<'static>,
        samples_out: SampleConsumer<'static>,
        /// The core clock `init` set up, Hz (idle's load window with `cpu-load`).
        sysclk_hz: u32,
    }

    #[init(local = [queue: SampleQueue = SampleQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let dp = cx.device;
        #[cfg(feature = "cpu-load")]
        {
            let mut core = cx.core;
            tooltouch_firmware::nucleo::cpu_load::start_cycle_counter(&mut core.DCB, &mut core.DWT);
        }
        let timing = tooltouch_firmware::nucleo::bring_up(&dp);
        defmt::info!(
            "tooltouch firmware on Nucleo-F446RE, SYSCLK {} Hz, feed-override PWM {} Hz: \
             waiting for the CNC's arm line (PA0)",
            timing.sysclk_hz,
            timers::FEED_PWM_HZ
        );
        let (samples_in, samples_out) = cx.local.queue.split();
        // The configuration baked into the image (`cargo xtask firmware --config`, else
        // the defaults). build.rs validated it, so the error arm never runs; should it,
        // the board halts here with a log line rather than run unconfigured.
        let (measure, force) = match (baked::measure(), baked::force()) {
            (Ok(m), Ok(f)) => (m, ForceKernel::new(&f)),
            _ => {
                defmt::error!("the baked configuration does not decode");
                loop {
                    cortex_m::asm::wfi();
                }
            }
        };
        defmt::info!(
            "configuration measure_hash={=u64:016x} force_hash={=u64:016x}",
            baked::MEASURE_HASH,
            baked::FORCE_HASH
        );
        // The baked calibration, as `tooltouch cosim config` names it (none: no line).
        if let Ok(Some(c)) = baked::calibration() {
            defmt::info!(
                "calibration calibration_hash={=u64:016x} offset={=i32} counts",
                c.hash(),
                c.offset_counts
            );
        }
        Nucleo::set_feed_override(force.outputs().override_pct);
        // TIM2 is counting: the domain starts at its count and sets the first compare.
        let meas = MeasureDomain::start::<Nucleo>(&measure);
        (
            Shared {
                meas,
                snapshot: meas.kernel().outputs(),
                force,
                counters: Counters::default(),
            },
            Local {
                samples_in,
                samples_out,
                sysclk_hz: timing.sysclk_hz,
            },
        )
    }

    /// Logs every change of "register now" with the latched position and the ADC samples
    /// dropped; sleeps otherwise. The pin is read from the output data register; the rest
    /// of the outputs, which only the measurement tasks may read, through [`observe`], and
    /// only on a change.
    #[idle(shared = [snapshot, counters, force], local = [sysclk_hz])]
    fn idle(cx: idle::Context) -> ! {
        // Emulated: the co-simulation driver replays the stream instead (and logs each
        // change of "register now" as the board does), then ends the QEMU run.
        #[cfg(feature = "emulated")]
        {
            let _ = cx.local.sysclk_hz;
            crate::emulated::run(cx.shared.snapshot, cx.shared.force, cx.shared.counters)
        }
        #[cfg(not(feature = "emulated"))]
        {
            let _ = cx.shared.force;
            crate::report_decisions(cx.shared.snapshot, cx.shared.counters, *cx.local.sysclk_hz)
        }
    }

    // The measurement tasks: one priority (15, the highest), so none preempts another:
    // the measurement domain needs no lock (module doc: the order of simultaneous edges).

    /// CNC arm / abort (PA0).
    #[task(binds = EXTI0, priority = 15, shared = [meas])]
    fn cnc_command(cx: cnc_command::Context) {
        pins::ack_arm();
        handlers::cnc_command::<Nucleo>(cx.shared.meas);
    }

    /// Contact edge (PA1).
    #[task(binds = EXTI1, priority = 15, shared = [meas])]
    fn contact(cx: contact::Context) {
        pins::ack_contact();
        handlers::contact::<Nucleo>(cx.shared.meas);
    }

    /// Index pulse (PB2).
    #[task(binds = EXTI2, priority = 15, shared = [meas])]
    fn index(cx: index::Context) {
        pins::ack_index();
        handlers::index::<Nucleo>(cx.shared.meas);
    }

    /// Scale edge on A or B (PB8, PB9).
    #[task(binds = EXTI9_5, priority = 15, shared = [meas])]
    fn scale(cx: scale::Context) {
        pins::ack_scale();
        handlers::scale::<Nucleo>(cx.shared.meas);
    }

    /// TIM2 channel 1: the FES count reached the compare value (the pulse that may
    /// decide, or the fold limit). The flag is cleared first, so a match after the new
    /// compare value is set raises the interrupt again.
    #[task(binds = TIM2, priority = 15, shared = [meas])]
    fn fes_compare(cx: fes_compare::Context) {
        timers::ack_fes_compare();
        handlers::fes_compare::<Nucleo>(cx.shared.meas);
    }

    /// TIM5 channel 1: the measurement clock's alarm (the FES watchdog's fold).
    #[task(binds = TIM5, priority = 15, shared = [meas])]
    fn time_alarm(cx: time_alarm::Context) {
        timers::ack_time_alarm();
        handlers::time_alarm::<Nucleo>(cx.shared.meas);
    }

    /// Idle's snapshot of the outputs (folding the counted FES pulses first); after any
    /// edge pending with it.
    #[task(binds = TIM7, priority = 15, shared = [meas, snapshot])]
    fn observe(cx: observe::Context) {
        // Emulated: the driver's fresh kernel for the next stream, installed here (the
        // domain is the measurement tasks' alone).
        #[cfg(feature = "emulated")]
        if let Some(fresh) = crate::emulated::registers::take_reset() {
            *cx.shared.meas = MeasureDomain::start::<Nucleo>(&fresh);
        }
        let outputs = handlers::observe::<Nucleo>(cx.shared.meas);
        let mut snapshot = cx.shared.snapshot;
        snapshot.lock(|s| *s = outputs);
    }

    /// CNC force-path commands (PC11–PC13).
    #[task(binds = EXTI15_10, priority = 12, shared = [force])]
    fn cnc_force_command(mut cx: cnc_force_command::Context) {
        pins::take_pending_commands();
        while pins::commands_pending() {
            cx.shared.force.lock(handlers::force_command::<Nucleo>);
        }
    }

    /// 1 kHz ADC sample (TIM6 update): convert the eight channels, queue them.
    #[task(binds = TIM6_DAC, priority = 8, shared = [counters], local = [samples_in])]
    fn adc_sample(mut cx: adc_sample::Context) {
        timers::ack_sample_tick();
        if !handlers::adc_sample::<Nucleo>(cx.local.samples_in) {
            cx.shared
                .counters
                .lock(|c| c.overflowed = c.overflowed.saturating_add(1));
        }
    }

    /// 20 Hz control period (TIM3 update): samples, estimate, control, wear.
    #[task(binds = TIM3, priority = 4, shared = [force], local = [samples_out])]
    fn control_period(mut cx: control_period::Context) {
        timers::ack_control_period();
        let queue = cx.local.samples_out;
        cx.shared
            .force
            .lock(|k| handlers::control_period::<Nucleo>(k, queue));
    }
}
