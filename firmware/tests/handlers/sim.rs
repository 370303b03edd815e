//! A simulated board for the handlers: the [`Board`] they read and drive, the wrapping
//! 32-bit FES counter with its compare match, and an NVIC that takes the pending
//! measurement interrupts (one priority, so none preempts another) lowest IRQ number
//! first, with one board's IRQ numbers ([`MeasureInterrupts`]).
//!
//! [`Sim`] replays [`Burst`]s: the events of a burst arrive before the CPU takes any of
//! their interrupts (FES pulses are counted as they arrive; an edge sets its pin and pends
//! its interrupt), then the NVIC serves the pending set. That is where the boards differ:
//! a deciding FES pulse and a scale edge pending together are taken compare first on QEMU
//! and scale first on the Nucleo. The golden model steps the same events one at a time,
//! in arrival order, and after every burst the pin "register now" and, when the burst is
//! observed, every output and the whole kernel state must equal the model's.
//!
//! Which arrivals the firmware promises to handle exactly (its module doc: a pulse that
//! arrives between an edge and its task's fold is folded before that edge) decides the
//! shape of a burst: FES pulses, then at most one edge, then pulses that arrive while the
//! edge's handler runs, right before it writes the compare (or after it returns, if it
//! writes none) — the moment a pulse can pass the new compare value unmatched.

use std::cell::RefCell;
use std::collections::BTreeSet;
use tooltouch_firmware::board::Board;
use tooltouch_firmware::handlers::{self, MeasureDomain, FES_FOLD_LIMIT};
use tooltouch_firmware::interrupts::MeasureInterrupts;
use tooltouch_firmware::model::force::events::ForceEvent;
use tooltouch_firmware::model::force::sampling::AdcCodes;
use tooltouch_firmware::model::{MeasureConfig, MeasureEvent, MeasureOutputs, Measurement};

/// What the handlers did to the board, and what the NVIC did, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// The NVIC took this interrupt (its handler ran).
    Taken(u16),
    /// The compare value was set to `at` with the counter at `count`.
    SetCompare {
        /// The new compare value.
        at: u32,
        /// The count when it was written.
        count: u32,
    },
    /// The compare interrupt was pended by hand.
    HandPend,
    /// "Register now" was driven.
    RegisterNow(bool),
}

/// The board's state: pins, counter, NVIC, outputs.
struct State {
    irqs: MeasureInterrupts,
    arm: bool,
    contact: bool,
    scale: (bool, bool),
    /// FES pulses counted, wrapping at 2^32.
    count: u32,
    /// The counter's compare value (0 at reset, like TIM2's CCR1).
    compare: u32,
    /// Pending interrupts, by IRQ number.
    pending: BTreeSet<u16>,
    /// The interrupt whose handler runs.
    running: Option<u16>,
    register_now: bool,
    /// The fault output.
    fault: bool,
    /// The clock's alarm (its compare value while set). The clock reads 0 throughout:
    /// the co-simulations under QEMU test the time (the FES watchdog).
    alarm: Option<u32>,
    /// The pulse-count preset's value (a co-simulation test event).
    preset: u32,
    /// Pulses that arrive when the handler of `arrive_in` writes the compare.
    in_handler: u32,
    arrive_in: Option<u16>,
    actions: Vec<Action>,
    /// Force path: the ADC's codes, the pending command, the outputs.
    adc: AdcCodes,
    command: Option<ForceEvent>,
    feed_override: u8,
    wear_alarm: bool,
}

impl State {
    fn new(irqs: MeasureInterrupts, count: u32) -> Self {
        State {
            irqs,
            arm: false,
            contact: false,
            scale: (false, false),
            count,
            compare: 0,
            pending: BTreeSet::new(),
            running: None,
            register_now: false,
            fault: false,
            alarm: None,
            preset: 0,
            in_handler: 0,
            arrive_in: None,
            actions: Vec::new(),
            adc: AdcCodes::default(),
            command: None,
            feed_override: 0,
            wear_alarm: false,
        }
    }

    /// An FES rising edge: counted; a match with the compare value pends its interrupt.
    fn count_pulse(&mut self) {
        self.count = self.count.wrapping_add(1);
        if self.count == self.compare {
            self.pending.insert(self.irqs.fes_compare);
        }
    }

    /// The pulses due in the running handler, counted now.
    fn deliver_in_handler_pulses(&mut self) {
        for _ in 0..self.in_handler {
            self.count_pulse();
        }
        self.in_handler = 0;
        self.arrive_in = None;
    }
}

thread_local! {
    /// The board of the [`Sim`] running on this thread (tests run on several threads).
    static STATE: RefCell<Option<State>> = const { RefCell::new(None) };
}

fn with<R>(f: impl FnOnce(&mut State) -> R) -> R {
    STATE.with(|s| f(s.borrow_mut().as_mut().expect("no Sim on this thread")))
}

/// The simulated board as the handlers see it.
pub struct SimBoard;

impl Board for SimBoard {
    fn arm() -> bool {
        with(|s| s.arm)
    }
    fn contact() -> bool {
        with(|s| s.contact)
    }
    fn scale() -> (bool, bool) {
        with(|s| s.scale)
    }
    fn fes_count() -> u32 {
        with(|s| s.count)
    }
    fn set_fes_compare(at: u32) {
        with(|s| {
            if s.running.is_some() && s.running == s.arrive_in {
                // Counted while the old compare value still holds.
                s.deliver_in_handler_pulses();
            }
            s.compare = at;
            s.actions.push(Action::SetCompare { at, count: s.count });
        })
    }
    fn pend_fes_compare() {
        with(|s| {
            s.pending.insert(s.irqs.fes_compare);
            s.actions.push(Action::HandPend);
        })
    }
    fn time() -> u32 {
        0
    }
    fn set_time_alarm(at: Option<u32>) {
        with(|s| s.alarm = at)
    }
    fn pend_time_alarm() {
        with(|s| s.pending.insert(s.irqs.time_alarm));
    }
    fn set_register_now(on: bool) {
        with(|s| {
            s.register_now = on;
            s.actions.push(Action::RegisterNow(on));
        })
    }
    fn set_status(faults: u8, _confirmed: bool) {
        with(|s| s.fault = faults != 0)
    }
    fn adc() -> AdcCodes {
        with(|s| s.adc)
    }
    fn force_command() -> Option<ForceEvent> {
        with(|s| s.command.take())
    }
    fn set_feed_override(percent: u8) {
        with(|s| s.feed_override = percent)
    }
    fn set_wear_alarm(on: bool) {
        with(|s| s.wear_alarm = on)
    }
}

/// Events that arrive before the CPU takes any of their interrupts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Burst {
    /// FES pulses counted first.
    pub pulses_before: u32,
    /// Then one edge (any event but [`MeasureEvent::Fes`]), or none.
    pub edge: Option<MeasureEvent>,
    /// FES pulses that arrive while the edge's handler runs (with no edge: the FES
    /// compare handler's), right before it writes the compare; or after it returns, if
    /// it writes none.
    pub pulses_in_handler: u32,
    /// Whether lower-priority code takes a snapshot of the outputs afterwards (`observe`),
    /// compared field by field with the model's.
    pub observe: bool,
}

impl Burst {
    /// `n` FES pulses, nothing else.
    pub fn pulses(n: u32) -> Self {
        Burst {
            pulses_before: n,
            edge: None,
            pulses_in_handler: 0,
            observe: false,
        }
    }

    /// One edge, nothing else.
    pub fn edge(event: MeasureEvent) -> Self {
        Burst {
            pulses_before: 0,
            edge: Some(event),
            pulses_in_handler: 0,
            observe: false,
        }
    }

    /// With `n` FES pulses counted before the edge.
    pub fn after_pulses(self, n: u32) -> Self {
        Burst {
            pulses_before: n,
            ..self
        }
    }

    /// With `n` FES pulses arriving in the handler.
    pub fn with_pulses_in_handler(self, n: u32) -> Self {
        Burst {
            pulses_in_handler: n,
            ..self
        }
    }

    /// Observed afterwards.
    pub fn observed(self) -> Self {
        Burst {
            observe: true,
            ..self
        }
    }

    /// The burst a board can receive: without the pulse-count preset where the board has
    /// none.
    pub fn for_board(self, irqs: &MeasureInterrupts) -> Self {
        match self.edge {
            Some(MeasureEvent::PresetPulses(_)) if irqs.preset_pulses.is_none() => {
                Burst { edge: None, ..self }
            }
            _ => self,
        }
    }
}

/// The handlers on the simulated board, beside the golden model's event level.
pub struct Sim {
    name: &'static str,
    irqs: MeasureInterrupts,
    domain: MeasureDomain,
    model: Measurement,
    /// The last `observe` snapshot.
    snapshot: Option<MeasureOutputs>,
    /// The configuration's FES watchdog is on.
    watchdog: bool,
    /// Bursts replayed so far (for failure messages).
    bursts: usize,
}

impl Sim {
    /// A fresh kernel for `config` on board `name` (interrupts `irqs`), its FES counter at
    /// `count`; the measurement domain starts as `init` starts it.
    pub fn new(
        name: &'static str,
        irqs: MeasureInterrupts,
        config: &MeasureConfig,
        count: u32,
    ) -> Self {
        STATE.with(|s| *s.borrow_mut() = Some(State::new(irqs, count)));
        Sim {
            name,
            irqs,
            domain: MeasureDomain::start::<SimBoard>(config),
            watchdog: config.settings().checks.fes_timeout_cycles != 0,
            model: Measurement::new(config),
            snapshot: None,
            bursts: 0,
        }
    }

    /// The golden model as stepped so far.
    pub fn model(&self) -> &Measurement {
        &self.model
    }

    /// The FES counter's value.
    pub fn count(&self) -> u32 {
        with(|s| s.count)
    }

    /// The compare value.
    pub fn compare(&self) -> u32 {
        with(|s| s.compare)
    }

    /// The level "register now" is driven at.
    pub fn register_now(&self) -> bool {
        with(|s| s.register_now)
    }

    /// Everything done since the last call.
    pub fn take_actions(&mut self) -> Vec<Action> {
        with(|s| std::mem::take(&mut s.actions))
    }

    /// Replays `burst` (see [`Burst`]) and checks the board against the model.
    pub fn replay(&mut self, burst: Burst) {
        self.bursts += 1;
        let edge_irq = burst.edge.map(|e| self.irq_of(&e));
        with(|s| {
            for _ in 0..burst.pulses_before {
                s.count_pulse();
            }
            if let (Some(edge), Some(irq)) = (burst.edge, edge_irq) {
                match edge {
                    MeasureEvent::Arm(level) => s.arm = level,
                    MeasureEvent::Contact(level) => s.contact = level,
                    MeasureEvent::Scale { a, b } => s.scale = (a, b),
                    MeasureEvent::PresetPulses(n) => s.preset = n,
                    MeasureEvent::Index | MeasureEvent::Fes => {}
                }
                s.pending.insert(irq);
            }
            s.in_handler = burst.pulses_in_handler;
            s.arrive_in = Some(edge_irq.unwrap_or(s.irqs.fes_compare));
        });
        for _ in 0..burst.pulses_before {
            self.model.apply(MeasureEvent::Fes);
        }
        if let Some(edge) = burst.edge {
            self.model.apply(edge);
        }
        for _ in 0..burst.pulses_in_handler {
            self.model.apply(MeasureEvent::Fes);
        }
        self.serve();
        // Pulses whose handler wrote no compare (or never ran) arrive after it.
        let late = with(|s| {
            let n = s.in_handler;
            s.deliver_in_handler_pulses();
            n
        });
        if late > 0 {
            self.serve();
        }
        self.check_pin_and_compare(&burst);
        if burst.observe {
            self.observe(&burst);
        }
    }

    /// Every burst of `bursts`, then a final observation.
    pub fn replay_all(&mut self, bursts: &[Burst]) {
        for burst in bursts {
            self.replay(burst.for_board(&self.irqs));
        }
        self.replay(Burst::pulses(0).observed());
    }

    /// The interrupt an edge pends.
    fn irq_of(&self, event: &MeasureEvent) -> u16 {
        match event {
            MeasureEvent::Arm(_) => self.irqs.arm,
            MeasureEvent::Contact(_) => self.irqs.contact,
            MeasureEvent::Index => self.irqs.index,
            MeasureEvent::Scale { .. } => self.irqs.scale,
            MeasureEvent::PresetPulses(_) => self
                .irqs
                .preset_pulses
                .unwrap_or_else(|| panic!("board {} has no pulse-count preset", self.name)),
            MeasureEvent::Fes => panic!("an FES pulse is counted, not an edge of a burst"),
        }
    }

    /// Takes the pending interrupts, lowest IRQ number first, until none is pending.
    fn serve(&mut self) {
        for _ in 0..10_000 {
            let Some(irq) = with(|s| {
                let irq = s.pending.pop_first()?;
                s.running = Some(irq);
                s.actions.push(Action::Taken(irq));
                Some(irq)
            }) else {
                return;
            };
            self.dispatch(irq);
            with(|s| s.running = None);
        }
        panic!("{}: the handlers keep pending interrupts", self.name);
    }

    /// Runs the task bound to `irq`.
    fn dispatch(&mut self, irq: u16) {
        let irqs = self.irqs;
        let d = &mut self.domain;
        if irq == irqs.arm {
            handlers::cnc_command::<SimBoard>(d);
        } else if irq == irqs.contact {
            handlers::contact::<SimBoard>(d);
        } else if irq == irqs.index {
            handlers::index::<SimBoard>(d);
        } else if irq == irqs.fes_compare {
            handlers::fes_compare::<SimBoard>(d);
        } else if irq == irqs.scale {
            handlers::scale::<SimBoard>(d);
        } else if Some(irq) == irqs.preset_pulses {
            handlers::preset_pulses::<SimBoard>(d, with(|s| s.preset));
        } else if irq == irqs.time_alarm {
            handlers::time_alarm::<SimBoard>(d);
        } else if irq == irqs.observe {
            self.snapshot = Some(handlers::observe::<SimBoard>(d));
        } else {
            panic!("{}: no task is bound to IRQ {irq}", self.name);
        }
    }

    /// After a burst: "register now" as the model has it, and the compare value 1 to
    /// [`FES_FOLD_LIMIT`] pulses ahead of the count (so the deciding pulse and the fold
    /// limit are matched as they are counted).
    fn check_pin_and_compare(&self, burst: &Burst) {
        let (pin, count, compare) = with(|s| (s.register_now, s.count, s.compare));
        let (fault, alarm) = with(|s| (s.fault, s.alarm));
        let faults = self.model.outputs().faults;
        assert_eq!(
            fault,
            faults != 0,
            "{}: the fault output after burst {} {burst:?} (faults {faults:#x})",
            self.name,
            self.bursts
        );
        // The alarm stands for the FES watchdog: set exactly while armed with the
        // watchdog on (the clock stands still here, so it never expires).
        let watchdog_on = self.model.outputs().armed && self.watchdog;
        assert_eq!(
            alarm.is_some(),
            watchdog_on,
            "{}: the clock's alarm after burst {} {burst:?}",
            self.name,
            self.bursts
        );
        assert_eq!(
            pin,
            self.model.register_now(),
            "{}: \"register now\" after burst {} {burst:?}",
            self.name,
            self.bursts
        );
        let ahead = compare.wrapping_sub(count);
        assert!(
            (1..=FES_FOLD_LIMIT).contains(&ahead),
            "{}: after burst {} {burst:?} the compare value {compare} is {ahead} pulses past \
             the count {count}, not 1..={FES_FOLD_LIMIT}",
            self.name,
            self.bursts
        );
    }

    /// `observe` pended by lower-priority code: its snapshot equals the model's outputs,
    /// and the kernel (folded to the count) the model's whole state.
    fn observe(&mut self, burst: &Burst) {
        with(|s| s.pending.insert(s.irqs.observe));
        self.serve();
        let snapshot = self.snapshot.take();
        assert_eq!(
            snapshot,
            Some(self.model.outputs()),
            "{}: outputs after burst {} {burst:?}",
            self.name,
            self.bursts
        );
        assert_eq!(
            self.domain.kernel(),
            &self.model,
            "{}: kernel state after burst {} {burst:?}",
            self.name,
            self.bursts
        );
        self.check_pin_and_compare(burst);
    }
}

/// The force path's handlers on the simulated board (no interrupt order: one task per
/// priority).
pub struct ForceSim;

impl ForceSim {
    /// A fresh board (the measurement side idle).
    pub fn new() -> Self {
        STATE.with(|s| *s.borrow_mut() = Some(State::new(tooltouch_firmware::interrupts::QEMU, 0)));
        ForceSim
    }

    /// Sets the ADC's result registers.
    pub fn set_adc(&self, codes: AdcCodes) {
        with(|s| s.adc = codes);
    }

    /// Sets the pending CNC command.
    pub fn set_command(&self, event: ForceEvent) {
        with(|s| s.command = Some(event));
    }

    /// The feed override and the wear alarm as driven.
    pub fn outputs(&self) -> (u8, bool) {
        with(|s| (s.feed_override, s.wear_alarm))
    }
}
