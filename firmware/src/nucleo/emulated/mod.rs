//! The Nucleo's board code under QEMU's `netduinoplus2` (the `emulated` feature): the
//! registers that machine does not emulate, held in memory ([`registers`], one function
//! per seam, which `pins`, `timers` and `adc` call in place of the register access), and
//! the defmt logger that writes the frames defmt-rtt would send to a semihosting file
//! (`defmt_log`). The co-simulation driver that sets the seams' inputs is the RTIC
//! application's (`src/bin/nucleo/emulated/`).

#[cfg(not(feature = "panic-check"))]
mod defmt_log;
pub mod registers;
