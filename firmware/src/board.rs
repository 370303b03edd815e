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
    /// Drives the "position reached, register now" output to the CNC.
    fn set_register_now(on: bool);
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
