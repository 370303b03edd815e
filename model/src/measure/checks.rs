//! The measurement status: fault conditions latched per measurement cycle (cleared at arm),
//! and the confirmation of a decision by the contact pattern that follows it.
//!
//! Every embodiment decides exactly as the kernel does, and the kernel decides right when
//! every pin behaves. These checks tell the CNC when a pin did not, so that a reading the
//! controller cannot trust is never passed on as a good one:
//!
//! | fault | raised when (while armed) | on the machine |
//! | --- | --- | --- |
//! | `contact_at_arm` | the contact is closed when the arm rises | coolant bridge, tool already touching, a shorted wire |
//! | `pulses_lost` | an index pulse ends a revolution of fewer than `pulses_per_rev − pulse_tolerance` FES pulses (counted from the first index after arm) | FES pulses lost (encoder, cable, a too-long glitch filter) or an early/extra index |
//! | `index_missing` | more than `pulses_per_rev + pulse_tolerance` FES pulses without an index | the index lost, or extra FES pulses |
//! | `scale_error` | the scale decoder sees an illegal transition | scale lines lost or disturbed |
//! | `no_decision` | `probe_revs` index pulses since arm and no decision | broken contact wire, tool out of reach (probe fail) |
//! | `fes_timeout` | `fes_timeout_cycles` clock ticks without an FES pulse | encoder lost, spindle stopped |
//! | `unconfirmed` | one of the `confirm_windows` counting windows closed after the decision counts fewer contact pulses than the confirmation level | a chip or a burst decided, then the contact fell back |
//!
//! `confirmed` rises when all `confirm_windows` windows closed after the decision (the
//! first being the deciding window itself) counted at least the confirmation level:
//! `confirm_percent` % of the window's pulses for the counter and density methods, one
//! contact pulse for the single-pulse method (which decides at the first touch, where the
//! density is still low). With `confirm_windows = 0` the decision is confirmed at once.
//!
//! "Register now" is not withheld: it stays the latency-critical signal to latch the
//! position, exactly as without the checks. The CNC accepts a measurement when `confirmed`
//! is high and `faults` is zero, and alarms on any fault (docs/CONTRACT.md).
//!
//! Time: the FES watchdog counts ticks of the stream's clock (FPGA clocks at cycle level,
//! the event timestamps at event level). The kernel is told the time before each event
//! ([`crate::Measurement::observe`]); the watchdog is evaluated lazily, so reading the
//! outputs at time `t` ([`crate::Measurement::outputs_at`]) shows `fes_timeout` exactly
//! when `t − t_fes ≥ fes_timeout_cycles`, `t_fes` being the time of the last FES pulse (or
//! of the arm, if none came since).

pub use crate::measure::config::MeasureChecks;
use crate::measure::config::MeasureConfig;

/// The fault bits of the `faults` output word, and their names.
pub mod fault {
    /// The contact was closed when the arm rose.
    pub const CONTACT_AT_ARM: u8 = 1 << 0;
    /// A revolution (index to index) of too few FES pulses.
    pub const PULSES_LOST: u8 = 1 << 1;
    /// Too many FES pulses without an index pulse.
    pub const INDEX_MISSING: u8 = 1 << 2;
    /// An illegal scale transition since arm.
    pub const SCALE_ERROR: u8 = 1 << 3;
    /// No decision within `probe_revs` revolutions of the arm.
    pub const NO_DECISION: u8 = 1 << 4;
    /// No FES pulse for `fes_timeout_cycles` ticks.
    pub const FES_TIMEOUT: u8 = 1 << 5;
    /// The contact fell back in a confirmation window after the decision.
    pub const UNCONFIRMED: u8 = 1 << 6;
    /// Number of fault conditions (the width of the `faults` word, bits).
    pub const COUNT: usize = 7;
    /// Every fault bit.
    pub const ALL: u8 = 0x7f;
    /// The faults' names, by bit position, as in docs, reports and the defmt line.
    pub const NAMES: [&str; COUNT] = [
        "contact_at_arm",
        "pulses_lost",
        "index_missing",
        "scale_error",
        "no_decision",
        "fes_timeout",
        "unconfirmed",
    ];
}

/// A `faults` word: which fault conditions are latched.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Faults(pub u8);

impl Faults {
    /// No fault.
    pub const NONE: Faults = Faults(0);

    /// Whether no fault is latched.
    pub fn is_empty(self) -> bool {
        self.0 & fault::ALL == 0
    }

    /// Whether the fault bit `bit` ([`fault`]) is set.
    pub fn contains(self, bit: u8) -> bool {
        self.0 & bit != 0
    }

    /// The names of the latched faults, in bit order.
    pub fn names(self) -> impl Iterator<Item = &'static str> {
        fault::NAMES
            .iter()
            .enumerate()
            .filter(move |(i, _)| self.0 & (1 << i) != 0)
            .map(|(_, name)| *name)
    }

    /// The fault bit named `name`, if there is one.
    pub fn bit_named(name: &str) -> Option<u8> {
        fault::NAMES
            .iter()
            .position(|n| *n == name)
            .map(|i| 1u8 << i)
    }
}

impl core::fmt::Display for Faults {
    /// `none`, or the latched faults' names joined by `+` (`pulses_lost+no_decision`).
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.is_empty() {
            return f.write_str("none");
        }
        for (i, name) in self.names().enumerate() {
            if i > 0 {
                f.write_str("+")?;
            }
            f.write_str(name)?;
        }
        Ok(())
    }
}

/// The checks' state in the kernel: the latched faults, the revolution's FES count, the
/// watchdog's last FES time and the confirmation's progress.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MeasurementChecks {
    /// Fault bits the configuration enables (a disabled check never sets its bit).
    enabled: u8,
    /// Fewest FES pulses of a whole revolution: `pulses_per_rev − pulse_tolerance`.
    fewest: u32,
    /// Most FES pulses without an index: `pulses_per_rev + pulse_tolerance`.
    most: u32,
    probe_revs: u16,
    fes_timeout: u64,
    confirm_windows: u8,
    /// Contact pulses a confirming window must count.
    confirm_count: u32,
    /// Latched faults since arm.
    faults: u8,
    /// FES pulses since the last index pulse (or arm), saturating at `most + 1`.
    rev_pulses: u32,
    /// An index pulse has come since arm (so `rev_pulses` counts a whole revolution).
    index_seen: bool,
    /// Time of the last FES pulse, or of the arm, ticks.
    fes_at: u64,
    /// Time now, ticks (the last [`Self::observe`]).
    now: u64,
    /// Windows still to close before the decision is confirmed (0 when not pending).
    confirm_left: u8,
    /// The decision is confirmed.
    confirmed: bool,
}

impl MeasurementChecks {
    /// Power-on state for `config`: no fault, nothing pending.
    pub fn new(config: &MeasureConfig) -> Self {
        let s = config.settings();
        let c = s.checks;
        let mut enabled = 0;
        for (on, bit) in [
            (c.contact_at_arm, fault::CONTACT_AT_ARM),
            (c.revolutions, fault::PULSES_LOST | fault::INDEX_MISSING),
            (c.scale_errors, fault::SCALE_ERROR),
            (c.probe_revs != 0, fault::NO_DECISION),
            (c.fes_timeout_cycles != 0, fault::FES_TIMEOUT),
            (c.confirm_windows != 0, fault::UNCONFIRMED),
        ] {
            if on {
                enabled |= bit;
            }
        }
        let ppr = u32::from(s.pulses_per_rev);
        let tolerance = u32::from(c.pulse_tolerance);
        MeasurementChecks {
            enabled,
            fewest: ppr - tolerance,
            most: ppr + tolerance,
            probe_revs: c.probe_revs,
            fes_timeout: c.fes_timeout_cycles.into(),
            confirm_windows: c.confirm_windows,
            confirm_count: config.confirm_count(),
            faults: 0,
            rev_pulses: 0,
            index_seen: false,
            fes_at: 0,
            now: 0,
            confirm_left: 0,
            confirmed: false,
        }
    }

    /// Sets the faults in `bits` that the configuration enables.
    #[inline(always)]
    fn raise(&mut self, bits: u8) {
        self.faults |= bits & self.enabled;
    }

    /// The watchdog's verdict at `now` while armed.
    #[inline(always)]
    fn fes_expired(&self, now: u64) -> bool {
        self.fes_timeout != 0 && now.wrapping_sub(self.fes_at) >= self.fes_timeout
    }

    /// The stream's clock reads `now` ticks (never less than before). Latches the FES
    /// watchdog if it expired while `armed`.
    #[inline]
    pub fn observe(&mut self, now: u64, armed: bool) {
        if armed && self.fes_expired(now) {
            self.raise(fault::FES_TIMEOUT);
        }
        self.now = now;
    }

    /// The arm rose with the contact at `contact`: a new measurement cycle.
    #[inline]
    pub fn on_arm(&mut self, contact: bool) {
        self.faults = 0;
        if contact {
            self.raise(fault::CONTACT_AT_ARM);
        }
        self.rev_pulses = 0;
        self.index_seen = false;
        self.fes_at = self.now;
        self.confirm_left = 0;
        self.confirmed = false;
    }

    /// `n ≥ 1` FES pulses while armed, with no other event between them.
    #[inline(always)]
    pub fn on_fes(&mut self, n: u32) {
        self.fes_at = self.now;
        self.rev_pulses = self.rev_pulses.saturating_add(n);
        if self.rev_pulses > self.most {
            self.rev_pulses = self.most + 1;
            self.raise(fault::INDEX_MISSING);
        }
    }

    /// An index pulse while armed. `window_closed`: it ended a counting window, which
    /// counted `window_count` contact pulses; `decided`: a decision is latched;
    /// `revolutions`: index pulses since arm, this one included.
    #[inline]
    pub fn on_index(
        &mut self,
        window_closed: bool,
        window_count: u32,
        decided: bool,
        revolutions: u16,
    ) {
        if self.index_seen && self.rev_pulses < self.fewest {
            self.raise(fault::PULSES_LOST);
        }
        self.rev_pulses = 0;
        self.index_seen = true;
        if window_closed && self.confirm_left > 0 {
            if window_count < self.confirm_count {
                self.raise(fault::UNCONFIRMED);
                self.confirm_left = 0;
            } else {
                self.confirm_left -= 1;
                self.confirmed = self.confirm_left == 0;
            }
        }
        if !decided && self.probe_revs != 0 && revolutions >= self.probe_revs {
            self.raise(fault::NO_DECISION);
        }
    }

    /// The decision latched the position (once per measurement cycle).
    #[inline]
    pub fn on_decision(&mut self) {
        if self.confirm_windows == 0 {
            self.confirmed = true;
        } else {
            self.confirm_left = self.confirm_windows;
        }
    }

    /// An illegal scale transition while armed.
    #[inline]
    pub fn on_scale_error(&mut self) {
        self.raise(fault::SCALE_ERROR);
    }

    /// The latched faults, with the watchdog evaluated at `now` if `armed`.
    #[inline]
    pub fn faults_at(&self, now: u64, armed: bool) -> Faults {
        let mut faults = self.faults;
        if armed && self.fes_expired(now) {
            faults |= fault::FES_TIMEOUT & self.enabled;
        }
        Faults(faults)
    }

    /// When the FES watchdog will latch `fes_timeout` if no FES pulse comes first, ticks:
    /// `fes_at + fes_timeout_cycles` while `armed`, the watchdog on and not yet latched;
    /// `None` otherwise. A caller that skips time (a settled front end, a firmware alarm)
    /// schedules itself for this instant.
    #[inline]
    pub fn fes_deadline(&self, armed: bool) -> Option<u64> {
        let latched = self.faults & fault::FES_TIMEOUT != 0;
        (armed && self.fes_timeout != 0 && self.enabled & fault::FES_TIMEOUT != 0 && !latched)
            .then(|| self.fes_at.saturating_add(self.fes_timeout))
    }

    /// How many more FES pulses, with no index pulse between them, raise
    /// `index_missing`: `Some(k)`, `k >= 1`, while `armed`, the revolution check on and the
    /// fault not yet raised; `None` otherwise.
    #[inline]
    pub fn pulses_to_index_missing(&self, armed: bool) -> Option<u32> {
        let on = self.enabled & fault::INDEX_MISSING != 0;
        (armed && on && self.faults & fault::INDEX_MISSING == 0)
            .then(|| (self.most + 1).saturating_sub(self.rev_pulses).max(1))
    }

    /// Whether the decision is confirmed.
    #[inline]
    pub fn confirmed(&self) -> bool {
        self.confirmed
    }
    /// Time now, ticks (the last observed).
    #[inline]
    pub fn now(&self) -> u64 {
        self.now
    }
    /// FES pulses since the last index pulse (or arm), saturating at
    /// `pulses_per_rev + pulse_tolerance + 1`.
    pub fn rev_pulses(&self) -> u32 {
        self.rev_pulses
    }
    /// Whether an index pulse has come since arm.
    pub fn index_seen(&self) -> bool {
        self.index_seen
    }
    /// Windows still to close before the decision is confirmed.
    pub fn confirm_left(&self) -> u8 {
        self.confirm_left
    }
    /// Time of the last FES pulse (or of the arm), ticks.
    pub fn fes_at(&self) -> u64 {
        self.fes_at
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for MeasurementChecks {
    /// `checks.rev_pulses` (`u32`, saturating at `pulses_per_rev + pulse_tolerance + 1`)
    /// and `checks.confirm_left` (`u8`, `0..=confirm_windows`).
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        f(Register::new(
            "checks.rev_pulses",
            Format::unsigned(32),
            self.rev_pulses.into(),
        ));
        f(Register::new(
            "checks.confirm_left",
            Format::unsigned(8),
            self.confirm_left.into(),
        ));
    }
}

#[cfg(test)]
mod tests;
