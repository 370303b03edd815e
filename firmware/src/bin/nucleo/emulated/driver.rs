//! The co-simulation driver of the emulated Nucleo ([`Target`] for
//! `tooltouch_firmware::cosim`): runs in `idle` (priority 0), sets the seams' inputs of an
//! event ([`registers::drive`]), pends the Nucleo's interrupt for it and times the
//! handler with SysTick; every pend preempts it at once. After every measurement event it
//! does what the board's `idle` does on a change of "register now": logs it over defmt
//! with the outputs `observe` snapshots.

use super::registers::drive;
use cortex_m::peripheral::syst::SystClkSource;
use stm32f4::stm32f446::Interrupt;
use tooltouch_firmware::board::Board;
use tooltouch_firmware::cosim::{Input, Target};
use tooltouch_firmware::handlers::Counters;
use tooltouch_firmware::handlers::ReportedDecision;
use tooltouch_firmware::model::force::config::ForceConfig;
use tooltouch_firmware::model::force::events::ForceEvent;
use tooltouch_firmware::model::force::kernel::{ForceKernel, ForceOutputs};
use tooltouch_firmware::model::{MeasureConfig, MeasureEvent, MeasureOutputs};
use tooltouch_firmware::nucleo::adc::ADC_CHANNELS;
use tooltouch_firmware::nucleo::board::Nucleo;
use tooltouch_firmware::nucleo::pins;
use tooltouch_firmware::{pend, stack};

use crate::OBSERVE;
/// The 1 kHz ADC sample's interrupt (TIM6's update on the board).
pub const ADC_SAMPLE: Interrupt = Interrupt::TIM6_DAC;
/// The control period's interrupt (TIM3's update on the board).
pub const CONTROL_PERIOD: Interrupt = Interrupt::TIM3;
/// The measurement clock's alarm interrupt (TIM5's compare on the board).
pub const TIME_ALARM: Interrupt = Interrupt::TIM5;
/// The CNC force-path commands' interrupt (PC11–PC13).
pub const FORCE_COMMAND: Interrupt = Interrupt::EXTI15_10;

/// The interrupt a measurement event's edge raises on the Nucleo (the FES pulse's is
/// TIM2's compare, raised only on a match); `None` for the pulse-count preset, a
/// co-simulation test event the Nucleo has no task for.
pub const fn measure_interrupt(event: &MeasureEvent) -> Option<Interrupt> {
    match event {
        MeasureEvent::Arm(_) => Some(Interrupt::EXTI0),
        MeasureEvent::Contact(_) => Some(Interrupt::EXTI1),
        MeasureEvent::Index => Some(Interrupt::EXTI2),
        MeasureEvent::Fes => Some(Interrupt::TIM2),
        MeasureEvent::Scale { .. } => Some(Interrupt::EXTI9_5),
        MeasureEvent::PresetPulses(_) => None,
    }
}

/// EXTI line of a force-path command, and the level its edge leaves on the pin; `None`
/// for the cutting-conditions command, which has no pin on this board.
const fn command_line(event: &ForceEvent) -> Option<(u32, bool)> {
    match *event {
        ForceEvent::Control(on) => Some((11, on)),
        ForceEvent::Identify(on) => Some((12, on)),
        // B1 pressed: PC13 falls.
        ForceEvent::ToolChanged => Some((13, false)),
        ForceEvent::Conditions(_) | ForceEvent::Sample(_) | ForceEvent::Tick => None,
    }
}

/// Starts SysTick on the core clock, counting down from 2^24 − 1, for the profile.
pub fn start_systick() {
    // SAFETY: only the driver uses SysTick (the board's firmware does not).
    let mut syst = unsafe { cortex_m::Peripherals::steal() }.SYST;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(0x00ff_ffff);
    syst.clear_current();
    syst.enable_counter();
}

/// Pends `irq` and returns after its handler has run (idle is preempted).
fn run_now(irq: Interrupt) {
    rtic::pend(irq);
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}

/// Drives the firmware from idle.
pub struct Driver<S, F, C> {
    snapshot: S,
    force: F,
    counters: C,
    calibration: (u32, u32),
    /// "Register now" as last logged (idle's `reported`).
    reported: bool,
    /// The status as last logged (idle's `logged`, `pins::status_word`).
    logged: u8,
    /// The stream's time, ticks (TIM5_CNT's seam holds its low 32 bits).
    now: u64,
    /// How the stream's decision is reported (the baked calibration for its configuration).
    report: ReportedDecision,
}

impl<S, F, C> Driver<S, F, C>
where
    S: rtic::Mutex<T = MeasureOutputs>,
    F: rtic::Mutex<T = ForceKernel>,
    C: rtic::Mutex<T = Counters>,
{
    /// The driver over idle's locks; starts SysTick and calibrates it.
    pub fn new(snapshot: S, force: F, counters: C) -> Self {
        start_systick();
        Driver {
            snapshot,
            force,
            counters,
            calibration: pend::calibrate(),
            reported: false,
            logged: 0,
            now: 0,
            report: tooltouch_firmware::baked::reported_decision(&Default::default()),
        }
    }

    /// Pends `irq` and returns the SysTick ticks until it has run; an edge whose
    /// interrupt is still pending is counted lost.
    fn pend_and_time(&mut self, irq: Interrupt) -> u32 {
        if pend::is_pending(irq as u16) {
            self.lost();
        }
        pend::pend_and_time(irq as u16)
    }

    fn lost(&mut self) {
        self.counters.lock(|c| c.lost = c.lost.saturating_add(1));
    }

    /// The board's idle on a change of "register now" or of the status: the outputs
    /// through `observe`, logged over defmt.
    fn log_register_now(&mut self) {
        let on = pins::register_now();
        if on == self.reported && pins::status() == self.logged {
            return;
        }
        run_now(OBSERVE);
        let o = self.snapshot.lock(|s| *s);
        if on != self.reported {
            self.reported = on;
            let dropped = self.counters.lock(|c| c.overflowed);
            crate::log_register_now(on, &o, dropped, &self.report);
        } else {
            crate::log_status(&o);
        }
        self.logged = pins::status_word(o.faults, o.confirmed);
    }

    fn inject_force(&mut self, event: ForceEvent) -> Option<u32> {
        let irq = match event {
            ForceEvent::Sample(codes) => {
                for (channel, code) in ADC_CHANNELS.iter().zip(codes.to_array()) {
                    drive::adc(*channel, code);
                }
                ADC_SAMPLE
            }
            ForceEvent::Tick => CONTROL_PERIOD,
            command => match command_line(&command) {
                Some((line, level)) => {
                    drive::command_edge(line, level);
                    FORCE_COMMAND
                }
                None => {
                    // No pin for it on this board: the event cannot be delivered, and
                    // the trace's lost count says so.
                    self.lost();
                    return None;
                }
            },
        };
        Some(self.pend_and_time(irq))
    }
}

impl<S, F, C> Target for Driver<S, F, C>
where
    S: rtic::Mutex<T = MeasureOutputs>,
    F: rtic::Mutex<T = ForceKernel>,
    C: rtic::Mutex<T = Counters>,
{
    fn configure(&mut self, config: &MeasureConfig, force: &ForceConfig) {
        drive::release_all();
        Nucleo::set_register_now(false);
        Nucleo::set_wear_alarm(false);
        Nucleo::set_status(0, false);
        self.reported = false;
        self.logged = 0;
        self.report = tooltouch_firmware::baked::reported_decision(config);
        self.now = 0;
        drive::set_time(0);
        // The kernel is the measurement tasks' alone: observe installs the new one.
        drive::reset(*config);
        run_now(OBSERVE);
        // A previous stream may have left samples queued after its last control period:
        // run one period into the old kernel to drain them, then replace it.
        run_now(CONTROL_PERIOD);
        let kernel = ForceKernel::new(force);
        self.force.lock(|k| *k = kernel);
        Nucleo::set_feed_override(kernel.outputs().override_pct);
        self.counters.lock(|c| *c = Counters::default());
    }

    fn advance(&mut self, time: u64) {
        // The alarm compares TIM5's 32 bits: it matches when the clock next reaches its
        // value (a value equal to the clock now was pended by hand, if due). The board's
        // idle would log a change it makes, so the driver does.
        while let Some(alarm) = drive::time_alarm() {
            let ahead = alarm.wrapping_sub(self.now as u32);
            let at = self.now.saturating_add(u64::from(ahead));
            if ahead == 0 || at > time {
                break;
            }
            self.now = at;
            drive::set_time(at as u32);
            self.pend_and_time(TIME_ALARM);
            self.log_register_now();
        }
        self.now = time;
        drive::set_time(time as u32);
    }

    fn inject(&mut self, input: Input) -> Option<u32> {
        let event = match input {
            Input::Measure(event) => event,
            Input::Force(event) => return self.inject_force(event),
        };
        let Some(irq) = measure_interrupt(&event) else {
            self.lost();
            return None;
        };
        match event {
            MeasureEvent::Arm(on) => drive::arm(on),
            MeasureEvent::Contact(on) => drive::contact(on),
            MeasureEvent::Scale { a, b } => drive::scale(a, b),
            MeasureEvent::Fes => {
                // TIM2 counts the edge; only a compare match interrupts.
                if !drive::fes_edge() {
                    return None;
                }
            }
            MeasureEvent::Index | MeasureEvent::PresetPulses(_) => {}
        }
        let ticks = self.pend_and_time(irq);
        self.log_register_now();
        Some(ticks)
    }

    fn outputs(&mut self) -> MeasureOutputs {
        run_now(OBSERVE);
        let mut o = self.snapshot.lock(|s| *s);
        // "Register now" as the CNC sees it: the PA5 level the handlers drive.
        o.register_now = pins::register_now();
        // The fault line (PA7) must agree with the faults word: a disagreement sets the
        // word's unused bit 7, which the host reports.
        if pins::fault() == (o.faults == 0) {
            o.faults ^= 0x80;
        }
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
