//! The thin board layer: what the handlers read from and drive on a board.
//!
//! Each board implements [`Board`] with associated functions (no state: the pins are
//! memory-mapped registers, or on QEMU the virtual pins the co-simulation driver sets
//! before it pends an interrupt), so the same handler code runs on every board.

use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::sampling::AdcCodes;

/// Pin levels the handlers read and the outputs they drive.
pub trait Board {
    /// Level of the CNC's arm (measurement-cycle start / abort) input.
    fn arm() -> bool;
    /// Level of the tool–workpiece contact input.
    fn contact() -> bool;
    /// Levels of the linear scale's A and B lines.
    fn scale() -> (bool, bool);
    /// The hardware count of FES rising edges, wrapping at 2^32 (a timer in external clock
    /// mode; on QEMU, the co-simulation driver's count).
    fn fes_count() -> u32;
    /// Sets the FES counter's compare interrupt to fire when the count reaches `at`.
    fn set_fes_compare(at: u32);
    /// Pends the FES counter's compare interrupt now (for a compare value the count has
    /// already passed).
    fn pend_fes_compare();
    /// The board's clock, ticks of the stream's clock (the unit of `fes_timeout_cycles`),
    /// wrapping at 2^32: a free-running timer (the Nucleo's TIM5 at 1 MHz; on QEMU the
    /// co-simulation driver's time, the event's time stamp).
    fn time() -> u32;
    /// Sets the clock's alarm (a compare interrupt) to fire when [`Board::time`] reaches
    /// `at`, or turns it off (`None`).
    fn set_time_alarm(at: Option<u32>);
    /// Pends the clock's alarm interrupt now (for an alarm already due).
    fn pend_time_alarm();
    /// Drives the "position reached, register now" output to the CNC.
    fn set_register_now(on: bool);
    /// The measurement's status changed or may have: drives the fault output to the CNC's
    /// alarm input (high while the `faults` word, [`tooltouch_model::fault`], is not zero)
    /// and publishes `faults` and `confirmed` for lower-priority code (the Nucleo's log).
    fn set_status(faults: u8, confirmed: bool);
    /// The latest conversion of every spindle-drive channel, 12-bit codes.
    fn adc() -> AdcCodes;
    /// The CNC's force-path command that raised the command interrupt, if any
    /// (identify, control on/off, cutting conditions, tool changed).
    fn force_command() -> Option<ForceEvent>;
    /// Drives the feed override to the CNC, % (`0..=255`, docs/domain.md §3).
    fn set_feed_override(percent: u8);
    /// Drives the wear alarm output (eq. W9, docs/domain.md: change the tool).
    fn set_wear_alarm(on: bool);
}
