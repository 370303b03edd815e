//! Device 1, the pulse counter (docs/domain.md §2.3): counts the FES pulses that carry contact and
//! decides when the count exceeds `i_def` within a window of revolutions.
//!
//! The decision is taken on the very pulse that makes the count exceed `i_def` (the last
//! pulse of the series, eq. S9, docs/domain.md), not at the following index pulse: the comparator
//! CU is combinational on the count; the window's last index pulse resets the count at every
//! window end, whether it got there or not. Deciding at the pulse removes up to one revolution of latency and decides on the
//! same pulse an index-time compare would have accepted.

use crate::measure::config::MeasureConfig;

/// Contact-pulse counter over a window of `window_revs` revolutions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PulseCounter {
    i_def: u32,
    window_revs: u8,
    window_pulses: u32,
    /// Contact pulses in the current window, `0..=window_pulses` (saturating, so a missing
    /// index pulse cannot overflow the `count_bits`-wide register).
    count: u32,
    /// The previous window's final count (contact density × window pulses).
    last_window_count: u32,
    /// Index pulses seen in the current window, `0..window_revs`.
    revs_in_window: u8,
    /// The count has exceeded `i_def` since the last reset.
    reached: bool,
}

impl PulseCounter {
    /// A cleared counter for `config`.
    pub fn new(config: &MeasureConfig) -> Self {
        let s = config.settings();
        PulseCounter {
            i_def: s.i_def,
            window_revs: s.window_revs,
            window_pulses: config.window_pulses(),
            count: 0,
            last_window_count: 0,
            revs_in_window: 0,
            reached: false,
        }
    }

    /// Clears counts and the decision (start of a measurement cycle).
    pub fn reset(&mut self) {
        self.count = 0;
        self.last_window_count = 0;
        self.revs_in_window = 0;
        self.reached = false;
    }

    /// One FES pulse; `contact` is the pulse's contact bit. Adds one to the count when in
    /// contact (saturating at `window_pulses`). Returns `true` on the single pulse at which
    /// the count first exceeds `i_def`.
    #[inline]
    pub fn on_pulse(&mut self, contact: bool) -> bool {
        if contact && self.count < self.window_pulses {
            self.count += 1;
            // The count changes only here, by one, or is cleared (index, reset), and a
            // reset clears `reached` with it; so while `reached` is false the count is at
            // most `i_def` between calls, and it can first exceed `i_def` only at an
            // increment: the compare is needed only here (the per-pulse path).
            if self.count > self.i_def && !self.reached {
                self.reached = true;
                return true;
            }
        }
        false
    }

    /// `n` FES pulses with no index pulse between them, the first with contact bit `first`
    /// and the others with `rest` (a run at one contact level, whose first pulse may carry
    /// the sticky bit): the same state and decision as `n` calls of
    /// [`PulseCounter::on_pulse`], in constant time. Returns `true` if one of them decided.
    pub fn on_pulses(&mut self, first: bool, rest: bool, n: u32) -> bool {
        if n == 0 {
            return false;
        }
        let others = if rest { n.saturating_sub(1) } else { 0 };
        let contacts = u32::from(first).saturating_add(others);
        // The count only rises in a run, saturating at `window_pulses`; while `reached` is
        // false it starts at most `i_def` ([`PulseCounter::on_pulse`]), so the run decides
        // exactly when it ends above `i_def`.
        self.count = self.count.saturating_add(contacts).min(self.window_pulses);
        if self.count > self.i_def && !self.reached {
            self.reached = true;
            return true;
        }
        false
    }

    /// How many FES pulses of a run (first with contact bit `first`, then `rest`, no index
    /// pulse) the counter needs to decide: `Some(k)` when the `k`-th would decide (`k >=
    /// 1`), `None` when the run never decides (already decided, or no contact to count).
    pub fn pulses_to_decision(&self, first: bool, rest: bool) -> Option<u32> {
        if self.reached {
            return None;
        }
        // Contact pulses still needed to exceed `i_def` (at least 1: the count is at most
        // `i_def` while not reached, and `i_def < window_pulses`, so saturation at
        // `window_pulses` never stops it).
        let needed = self.i_def.saturating_sub(self.count).saturating_add(1);
        let after_first = needed.saturating_sub(u32::from(first));
        if after_first == 0 {
            Some(1)
        } else if rest {
            Some(after_first.saturating_add(1))
        } else {
            None
        }
    }

    /// One index pulse: at the end of a window the count moves to `last_window_count` and
    /// restarts from zero. Returns whether it ended a window.
    pub fn on_index(&mut self) -> bool {
        self.revs_in_window = self.revs_in_window.saturating_add(1);
        if self.revs_in_window >= self.window_revs {
            self.last_window_count = self.count;
            self.count = 0;
            self.revs_in_window = 0;
            return true;
        }
        false
    }

    /// Contact pulses in the current window.
    pub fn count(&self) -> u32 {
        self.count
    }
    /// The previous window's final count.
    pub fn last_window_count(&self) -> u32 {
        self.last_window_count
    }
    /// Index pulses seen in the current window.
    pub fn revs_in_window(&self) -> u8 {
        self.revs_in_window
    }
    /// Whether the count has exceeded `i_def` since the last reset.
    pub fn reached(&self) -> bool {
        self.reached
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for PulseCounter {
    /// `counter.revs_in_window` (`u8`); its counts are outputs.
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        f(Register::new(
            "counter.revs_in_window",
            Format::unsigned(8),
            self.revs_in_window.into(),
        ));
    }
}

#[cfg(test)]
mod worked_examples;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::config::MeasureSettings;
    use proptest::prelude::*;

    fn counter(i_def: u32, window_revs: u8) -> PulseCounter {
        let c = MeasureSettings {
            pulses_per_rev: 16,
            i_def,
            window_revs,
            ..Default::default()
        };
        PulseCounter::new(&c.validate().unwrap())
    }

    #[test]
    fn decides_on_the_pulse_that_exceeds_i_def() {
        let mut c = counter(8, 1);
        for _ in 0..8 {
            assert!(!c.on_pulse(true));
        }
        assert!(c.on_pulse(true), "ninth contact pulse exceeds 8");
        assert!(!c.on_pulse(true), "decides once");
        assert!(c.reached());
    }

    #[test]
    fn index_resets_a_count_that_did_not_get_there() {
        let mut c = counter(8, 1);
        for _ in 0..8 {
            c.on_pulse(true);
        }
        c.on_index();
        assert_eq!((c.count(), c.last_window_count()), (0, 8));
        assert!(!c.on_pulse(true));
    }

    #[test]
    fn window_of_two_revolutions_spans_two_index_pulses() {
        let mut c = counter(20, 2);
        for _ in 0..12 {
            c.on_pulse(true);
        }
        c.on_index();
        assert_eq!(c.count(), 12);
        for _ in 0..8 {
            assert!(!c.on_pulse(true));
        }
        assert!(c.on_pulse(true), "12 + 9 = 21 exceeds 20");
        c.on_index();
        assert_eq!((c.count(), c.last_window_count()), (0, 21));
    }

    /// docs/domain.md §2.3's counter as first written, comparing the count with `i_def` after every
    /// pulse: the reference for [`PulseCounter::on_pulse`], which compares only after an
    /// increment.
    fn on_pulse_reference(c: &mut PulseCounter, contact: bool) -> bool {
        if contact && c.count < c.window_pulses {
            c.count += 1;
        }
        if !c.reached && c.count > c.i_def {
            c.reached = true;
            return true;
        }
        false
    }

    proptest! {
        #[test]
        fn on_pulse_equals_the_compare_every_pulse_reference(
            pulses_per_rev in 16u16..40, window_revs in 1u8..4, i_def in any::<u32>(),
            ops in proptest::collection::vec(0u8..8, 0..600),
        ) {
            let window = u32::from(pulses_per_rev) * u32::from(window_revs);
            let s = MeasureSettings {
                pulses_per_rev,
                window_revs,
                i_def: i_def % window,
                ..Default::default()
            };
            let mut c = PulseCounter::new(&s.validate().unwrap());
            let mut r = c;
            for (i, op) in ops.into_iter().enumerate() {
                match op {
                    0..=3 => prop_assert_eq!(c.on_pulse(true), on_pulse_reference(&mut r, true), "op {}", i),
                    4 | 5 => prop_assert_eq!(c.on_pulse(false), on_pulse_reference(&mut r, false), "op {}", i),
                    6 => { c.on_index(); r.on_index(); }
                    _ => { c.reset(); r.reset(); }
                }
                prop_assert_eq!(c, r, "state after op {}", i);
            }
        }

        #[test]
        fn count_never_exceeds_window_pulses(ops in proptest::collection::vec(0u8..3, 0..400)) {
            let mut c = counter(15, 1);
            for op in ops {
                match op { 0 => { c.on_pulse(true); } 1 => { c.on_pulse(false); } _ => { c.on_index(); } }
                prop_assert!(c.count() <= 16);
                prop_assert!(c.last_window_count() <= 16);
            }
        }
    }
}
