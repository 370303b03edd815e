//! The measurement tasks' IRQ numbers on each board.
//!
//! The measurement tasks share one priority, so when several of their interrupts are
//! pending together the NVIC takes the lowest IRQ number first: these numbers decide the
//! order in which simultaneous edges reach the handlers, and the boards differ (QEMU's
//! follow the model's canonical same-clock order; on the Nucleo the FES compare, TIM2,
//! comes after the scale, EXTI9_5). The RTIC applications bind their tasks by interrupt
//! name and check those names against this table at compile time; the host tests replay
//! event streams through the handlers in these orders.

/// IRQ numbers of the measurement tasks of one board (all at one priority).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeasureInterrupts {
    /// CNC arm / abort ([`crate::handlers::cnc_command`]).
    pub arm: u16,
    /// Contact edge ([`crate::handlers::contact`]).
    pub contact: u16,
    /// Index pulse ([`crate::handlers::index`]).
    pub index: u16,
    /// FES counter compare ([`crate::handlers::fes_compare`]).
    pub fes_compare: u16,
    /// Scale edge ([`crate::handlers::scale`]).
    pub scale: u16,
    /// Pulse-count preset, a co-simulation test event ([`crate::handlers::preset_pulses`]);
    /// `None` on a board without it.
    pub preset_pulses: Option<u16>,
    /// Output snapshot ([`crate::handlers::observe`]), pended by lower-priority code.
    pub observe: u16,
    /// The measurement clock's alarm ([`crate::handlers::time_alarm`]).
    pub time_alarm: u16,
}

/// QEMU's lm3s6965evb: GPIOA–GPIOE, UART0, UART1, SSI0 stand in for the pins' edges and the
/// driver's requests, in the model's canonical same-clock order.
pub const QEMU: MeasureInterrupts = MeasureInterrupts {
    arm: 0,
    contact: 1,
    index: 2,
    fes_compare: 3,
    scale: 4,
    preset_pulses: Some(5),
    observe: 6,
    time_alarm: 7,
};

/// The Nucleo-F446RE: EXTI0, EXTI1, EXTI2, TIM2, EXTI9_5, TIM7, TIM5.
pub const NUCLEO: MeasureInterrupts = MeasureInterrupts {
    arm: 6,
    contact: 7,
    index: 8,
    fes_compare: 28,
    scale: 23,
    preset_pulses: None,
    observe: 55,
    time_alarm: 50,
};
