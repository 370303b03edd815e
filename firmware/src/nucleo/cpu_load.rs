//! Interrupt load measured from `idle` (feature `cpu-load`), for checking the FES budget
//! on a board: idle spins instead of sleeping and reads the DWT cycle counter once per
//! turn.

use cortex_m::peripheral::{DCB, DWT};

/// The cycle counter's value now.
#[inline(always)]
pub fn cycles() -> u32 {
    DWT::cycle_count()
}

/// Starts the DWT cycle counter [`CpuLoad`] reads.
pub fn start_cycle_counter(dcb: &mut DCB, dwt: &mut DWT) {
    dcb.enable_trace();
    dwt.enable_cycle_counter();
}

/// The interrupts' share of the CPU, from idle's turns: a turn longer than the shortest
/// one seen was preempted, and its excess is time spent in interrupts; once per `period`
/// cycles the busy share is reported, in ‰.
pub struct CpuLoad {
    /// Cycle count at the previous turn.
    last: u32,
    /// Shortest turn seen, cycles: idle's own loop.
    pub shortest: u32,
    /// Cycles taken by interrupts in this window.
    busy: u64,
    /// Cycles in this window.
    window: u64,
    /// Window length, cycles (one second of SYSCLK).
    period: u64,
}

impl CpuLoad {
    /// Starts at cycle count `now`, reporting once per `period` cycles.
    pub fn new(now: u32, period: u32) -> Self {
        CpuLoad {
            last: now,
            shortest: u32::MAX,
            busy: 0,
            window: 0,
            period: u64::from(period).max(1),
        }
    }

    /// One idle turn at cycle count `now`; the window's load in ‰ when it is complete.
    pub fn turn(&mut self, now: u32) -> Option<u32> {
        let turn = now.wrapping_sub(self.last);
        self.last = now;
        self.shortest = self.shortest.min(turn);
        self.busy = self
            .busy
            .saturating_add(u64::from(turn.saturating_sub(self.shortest)));
        self.window = self.window.saturating_add(u64::from(turn));
        if self.window < self.period {
            return None;
        }
        let permille = self
            .busy
            .saturating_mul(1000)
            .checked_div(self.window)
            .unwrap_or(0);
        self.busy = 0;
        self.window = 0;
        Some(u32::try_from(permille).unwrap_or(u32::MAX))
    }
}
