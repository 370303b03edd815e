//! The thin board layer: what the handlers read from and drive on a board.
//!
//! Each board implements [`Board`] with associated functions (no state: the pins are
//! memory-mapped registers, or on QEMU the virtual pins the co-simulation driver sets
//! before it pends an interrupt), so the same handler code runs on every board.

/// Pin levels the handlers read and the outputs they drive.
pub trait Board {
    /// Level of the CNC's arm (measurement-cycle start / abort) input.
    fn arm() -> bool;
    /// Level of the tool–workpiece contact input.
    fn contact() -> bool;
    /// Levels of the linear scale's A and B lines.
    fn scale() -> (bool, bool);
    /// Drives the "position reached, register now" output to the CNC.
    fn set_register_now(on: bool);
}
