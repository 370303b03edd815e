//! The co-simulation driver's hold on the QEMU board ([`Target`] for
//! `tooltouch_firmware::cosim`): it runs in `idle` (priority 0), sets the virtual pins and
//! registers of an event, pends the event's interrupt and times the handler with SysTick;
//! every pend preempts it at once.
//!
//! The measurement kernel is the measurement tasks' alone (lock-free at their priority),
//! so the driver reaches it through mailboxes: it queues a fresh kernel and pends
//! `observe`, which installs it; `observe` queues the kernel's outputs back. Lock-free
//! single-producer single-consumer queues, one element deep (the driver waits for each
//! observe), so neither side takes a lock.

use crate::board::{
    encode_command, set_adc, ARM, COMMAND, CONTACT, FAULT, FEED_OVERRIDE, FES_COMPARE, FES_COUNT,
    PINS, PRESET, REGISTER_NOW, SCALE_A, SCALE_B, TIME, TIME_ALARM, TIME_ALARM_ON, WEAR_ALARM,
};
use core::sync::atomic::Ordering;
use cortex_m::interrupt::InterruptNumber;
use cortex_m::peripheral::NVIC;
use heapless::spsc::{Consumer, Producer, Queue};
use lm3s6965::Interrupt;
use tooltouch_firmware::cosim::{Input, Target};
use tooltouch_firmware::handlers::Counters;
use tooltouch_firmware::model::force::config::ForceConfig;
use tooltouch_firmware::model::force::events::ForceEvent;
use tooltouch_firmware::model::force::kernel::{ForceKernel, ForceOutputs};
use tooltouch_firmware::model::{MeasureConfig, MeasureEvent, MeasureOutputs};
use tooltouch_firmware::{pend, stack};

/// Depth of the mailboxes.
pub const MAILBOX: usize = 2;
/// Configurations of fresh kernels, driver to `observe`.
pub type Resets = Queue<MeasureConfig, MAILBOX>;
/// Output snapshots, `observe` to the driver.
pub type Snapshots = Queue<MeasureOutputs, MAILBOX>;

/// The interrupt of the `observe` task: after every measurement edge's (higher IRQ
/// number, same priority).
pub const OBSERVE: Interrupt = Interrupt::UART1;
/// The interrupt each measurement event's edge raises (the FES event's is the counter's
/// compare, raised only on a match).
pub const fn measure_interrupt(event: &MeasureEvent) -> Interrupt {
    match event {
        MeasureEvent::Arm(_) => Interrupt::GPIOA,
        MeasureEvent::Contact(_) => Interrupt::GPIOB,
        MeasureEvent::Index => Interrupt::GPIOC,
        MeasureEvent::Fes => Interrupt::GPIOD,
        MeasureEvent::Scale { .. } => Interrupt::GPIOE,
        MeasureEvent::PresetPulses(_) => Interrupt::UART0,
    }
}
/// The interrupt of the clock's alarm (the FES watchdog's).
pub const TIME_ALARM_IRQ: Interrupt = Interrupt::SSI0;
/// The 1 kHz ADC sample's interrupt.
pub const ADC_SAMPLE: Interrupt = Interrupt::ADC0_SEQUENCE_0;
/// The 20 Hz control period's interrupt.
pub const CONTROL_PERIOD: Interrupt = Interrupt::TIMER_0A;
/// The CNC force-path command's interrupt.
pub const FORCE_COMMAND: Interrupt = Interrupt::GPIOF;

/// Runs a loop of a known instruction count and returns `(instructions, SysTick ticks)`
/// (`tooltouch_firmware::pend::calibrate`).
pub fn calibrate() -> (u32, u32) {
    pend::calibrate()
}

/// Drives the firmware from idle (priority 0): every pend preempts it at once.
pub struct Driver<F, C> {
    resets: &'static mut Producer<'static, MeasureConfig>,
    snapshots: &'static mut Consumer<'static, MeasureOutputs>,
    /// The last snapshot (returned again should `observe` not have run: a mismatch
    /// the host reports).
    last: MeasureOutputs,
    force: F,
    counters: C,
    calibration: (u32, u32),
    /// The stream's time, ticks ([`TIME`] holds its low 32 bits).
    now: u64,
}

/// Pends `irq` with the barriers QEMU needs to take it at once: QEMU takes a pended
/// interrupt only between translated blocks, and without them back-to-back pends
/// merge into one interrupt. Returns after the handler (idle is preempted).
fn run_now(irq: Interrupt) {
    rtic::pend(irq);
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}

fn set(pins: u8, bit: u8, on: bool) -> u8 {
    if on {
        pins | bit
    } else {
        pins & !bit
    }
}

impl<F, C> Driver<F, C>
where
    F: rtic::Mutex<T = ForceKernel>,
    C: rtic::Mutex<T = Counters>,
{
    /// The driver over the mailboxes' ends, idle's locks on the force kernel and the
    /// counters, and `init`'s SysTick calibration.
    pub fn new(
        resets: &'static mut Producer<'static, MeasureConfig>,
        snapshots: &'static mut Consumer<'static, MeasureOutputs>,
        force: F,
        counters: C,
        calibration: (u32, u32),
    ) -> Self {
        Driver {
            resets,
            snapshots,
            last: MeasureOutputs::default(),
            force,
            counters,
            calibration,
            now: 0,
        }
    }

    fn inject_force(&mut self, event: ForceEvent) -> Option<u32> {
        let irq = match event {
            ForceEvent::Sample(codes) => {
                set_adc(&codes);
                ADC_SAMPLE
            }
            ForceEvent::Tick => CONTROL_PERIOD,
            command => {
                COMMAND.store(encode_command(command), Ordering::Relaxed);
                FORCE_COMMAND
            }
        };
        Some(self.pend_and_time(irq))
    }

    /// Pends `irq` and returns the SysTick ticks until it has run
    /// (`tooltouch_firmware::pend::pend_and_time`). An edge whose interrupt is still
    /// pending would be lost (merged into the pending one): it is counted in
    /// [`Counters::lost`].
    fn pend_and_time(&mut self, irq: Interrupt) -> u32 {
        if NVIC::is_pending(irq) {
            self.counters.lock(|c| c.lost = c.lost.saturating_add(1));
        }
        pend::pend_and_time(irq.number())
    }
}

impl<F, C> Target for Driver<F, C>
where
    F: rtic::Mutex<T = ForceKernel>,
    C: rtic::Mutex<T = Counters>,
{
    fn configure(&mut self, config: &MeasureConfig, force: &ForceConfig) {
        PINS.store(0, Ordering::Relaxed);
        REGISTER_NOW.store(false, Ordering::Relaxed);
        FAULT.store(false, Ordering::Relaxed);
        COMMAND.store(0, Ordering::Relaxed);
        self.now = 0;
        TIME.store(0, Ordering::Relaxed);
        // The kernel is the measurement tasks' alone: observe installs the new one.
        // (The queue is empty: observe ran after the previous reset.)
        let _ = self.resets.enqueue(*config);
        run_now(OBSERVE);
        let _ = self.snapshots.dequeue();
        // A previous stream may have left samples queued after its last control
        // period: run one period into the old kernel to drain them, then replace it.
        run_now(CONTROL_PERIOD);
        let kernel = ForceKernel::new(force);
        self.force.lock(|k| *k = kernel);
        FEED_OVERRIDE.store(kernel.outputs().override_pct, Ordering::Relaxed);
        WEAR_ALARM.store(false, Ordering::Relaxed);
        self.counters.lock(|c| *c = Counters::default());
    }

    fn advance(&mut self, time: u64) {
        // The alarm compares the clock's 32 bits: it matches when the clock next reaches
        // its value (a value equal to the clock now was pended by hand, if due).
        while TIME_ALARM_ON.load(Ordering::Relaxed) {
            let ahead = TIME_ALARM
                .load(Ordering::Relaxed)
                .wrapping_sub(self.now as u32);
            let at = self.now.saturating_add(u64::from(ahead));
            if ahead == 0 || at > time {
                break;
            }
            self.now = at;
            TIME.store(at as u32, Ordering::Relaxed);
            self.pend_and_time(TIME_ALARM_IRQ);
        }
        self.now = time;
        TIME.store(time as u32, Ordering::Relaxed);
    }

    fn inject(&mut self, input: Input) -> Option<u32> {
        let event = match input {
            Input::Measure(event) => event,
            Input::Force(event) => return self.inject_force(event),
        };
        let pins = PINS.load(Ordering::Relaxed);
        let pins = match event {
            MeasureEvent::Arm(on) => set(pins, ARM, on),
            MeasureEvent::Contact(on) => set(pins, CONTACT, on),
            MeasureEvent::Index => pins,
            MeasureEvent::Fes => {
                // The counter counts the edge; only a compare match interrupts.
                let count = FES_COUNT.load(Ordering::Relaxed).wrapping_add(1);
                FES_COUNT.store(count, Ordering::Relaxed);
                if count != FES_COMPARE.load(Ordering::Relaxed) {
                    return None;
                }
                pins
            }
            MeasureEvent::Scale { a, b } => set(set(pins, SCALE_A, a), SCALE_B, b),
            MeasureEvent::PresetPulses(n) => {
                PRESET.store(n, Ordering::Relaxed);
                pins
            }
        };
        PINS.store(pins, Ordering::Relaxed);
        Some(self.pend_and_time(measure_interrupt(&event)))
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
        // The fault line as the CNC sees it must agree with the faults word: a
        // disagreement sets the word's unused bit 7, which the host reports.
        if FAULT.load(Ordering::Relaxed) == (o.faults == 0) {
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
