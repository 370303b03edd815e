//! Tool-wear monitor from spindle power (docs/domain.md §4, paper W): the updating threshold of
//! W8–W9 and, for comparison, a constant threshold.
//!
//! Why precomputed: the mean-power limit `[P̄]` of W7 needs `a^(−x)` with a non-integer x
//! and the engagement angles' arcsines — for each *set of cutting conditions* (depth,
//! width, feed per tooth, speed) it is a constant. The host (`tooltouch::milling`) evaluates
//! W7 with the wear limit `[VB]` for every condition set of the part program, outside the
//! hot path, and loads the results here as I32F32 constants; the CNC selects the current
//! set by index when the conditions change (step 3 of the strategy). The kernel then
//! computes the allowed motor power `[P] = p_i + [P̄]/η` (W9) once per selection, and every
//! control period low-passes the measured mean spindle power (step 6) and compares (step 7).
//!
//! Alarm: `debounce_periods` consecutive periods with `p̄ ≥ [P]` latch the alarm until
//! [`WearMonitor::tool_changed`]. With [`Threshold::Constant`] the allowed power is one
//! number whatever the conditions — valid for one condition set only (the failure mode the
//! `tooltouch wear` scenario shows).
//!
//! Formats: watts I32F32, saturating; low-pass `p̄ += (P − p̄) >> lowpass_shift`.

use crate::units::{Fx, Watts};
use crate::validation::{check_range, positive, ForceConfigError};

/// Most condition sets a configuration holds.
pub const MAX_CONDITION_SETS: usize = 8;

/// One set of cutting conditions, as precomputed on the host.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ConditionSet {
    /// Mean cutting-power limit `[P̄]` from W7 with `[VB]` (W8), W, `(0, 10^6]`.
    pub mean_power_limit: Watts,
    /// Idle power p_i of the spindle at this set's speed, W, `[0, 10^6]`.
    pub idle_power: Watts,
}

/// Which threshold the monitor compares with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Threshold {
    /// `[P] = p_i + [P̄]/η` of the selected condition set (W9).
    Updating,
    /// One constant allowed power, W, `(0, 10^6]`.
    Constant(Watts),
}

/// Wear-monitor settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct WearSettings {
    /// Condition sets; the first `set_count` are used.
    pub sets: [ConditionSet; MAX_CONDITION_SETS],
    /// Number of condition sets in use, `1..=8`.
    pub set_count: u8,
    /// Machine efficiency η, `(0, 1]`.
    pub efficiency: Fx,
    /// Low-pass of the mean power, `0..=8` (0 = none).
    pub lowpass_shift: u8,
    /// Consecutive periods above the threshold before the alarm, `1..=255`.
    pub debounce_periods: u8,
    /// Updating or constant threshold.
    pub threshold: Threshold,
}

impl Default for WearSettings {
    /// The default plant's monitor (`tooltouch control`): one condition set, `[P̄]` =
    /// 1800 W at 300 W idle power, η = 0.8, low-pass 2^−3, 10 periods of debounce, the
    /// updating threshold.
    fn default() -> Self {
        let mut sets = [ConditionSet::default(); MAX_CONDITION_SETS];
        sets[0] = ConditionSet {
            mean_power_limit: Fx::const_from_int(1800),
            idle_power: Fx::const_from_int(300),
        };
        WearSettings {
            sets,
            set_count: 1,
            efficiency: const { Fx::lit("0.8") },
            lowpass_shift: 3,
            debounce_periods: 10,
            threshold: Threshold::Updating,
        }
    }
}

impl WearSettings {
    /// Checks every field (`wear.<field>`).
    pub fn validate(&self) -> Result<(), ForceConfigError> {
        let mega = Fx::const_from_int(1_000_000);
        check_range(
            "wear.set_count",
            Fx::from_num(self.set_count),
            Fx::ONE,
            Fx::from_num(MAX_CONDITION_SETS),
        )?;
        positive("wear.efficiency", self.efficiency, Fx::ONE)?;
        for set in self.sets.iter().take(usize::from(self.set_count)) {
            positive("wear.sets.mean_power_limit", set.mean_power_limit, mega)?;
            check_range("wear.sets.idle_power", set.idle_power, Fx::ZERO, mega)?;
        }
        check_range(
            "wear.lowpass_shift",
            Fx::from_num(self.lowpass_shift),
            Fx::ZERO,
            Fx::const_from_int(8),
        )?;
        check_range(
            "wear.debounce_periods",
            Fx::from_num(self.debounce_periods),
            Fx::ONE,
            Fx::const_from_int(255),
        )?;
        if let Threshold::Constant(p) = self.threshold {
            positive("wear.threshold", p, mega)?;
        }
        Ok(())
    }
}

/// Allowed motor power `[P] = p_i + [P̄]/η` (eq. W9, docs/domain.md), W, I32F32, saturating; `η`
/// must be positive (validated), else `[P̄]` is taken as is.
pub fn allowed_power(set: &ConditionSet, efficiency: Fx) -> Watts {
    let cutting = set
        .mean_power_limit
        .checked_div(efficiency)
        .unwrap_or(set.mean_power_limit);
    set.idle_power.saturating_add(cutting)
}

/// One period's wear status.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct WearStatus {
    /// Low-passed mean spindle power p̄, W.
    pub power: Watts,
    /// The allowed power it is compared with, W.
    pub allowed: Watts,
    /// p̄ ≥ \[P\] this period.
    pub over: bool,
    /// Alarm latched: change the tool.
    pub alarm: bool,
}

/// The wear monitor's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct WearMonitor {
    s: WearSettings,
    allowed: Watts,
    filtered: Option<Watts>,
    over_count: u8,
    alarm: bool,
    over: bool,
}

impl WearMonitor {
    /// A monitor for validated `s`, condition set 0 selected.
    pub fn new(s: &WearSettings) -> WearMonitor {
        let mut m = WearMonitor {
            s: *s,
            allowed: Fx::ZERO,
            filtered: None,
            over_count: 0,
            alarm: false,
            over: false,
        };
        m.select(0);
        m
    }

    /// Selects condition set `index` (step 3); returns false and keeps the current one if
    /// `index` is not below `set_count`.
    pub fn select(&mut self, index: u8) -> bool {
        if index >= self.s.set_count {
            return false;
        }
        let Some(set) = self.s.sets.get(usize::from(index)) else {
            return false;
        };
        self.allowed = match self.s.threshold {
            Threshold::Updating => allowed_power(set, self.s.efficiency),
            Threshold::Constant(p) => p,
        };
        true
    }

    /// Clears the alarm and the debounce count (a new tool).
    pub fn tool_changed(&mut self) {
        self.alarm = false;
        self.over_count = 0;
    }

    /// One period with the period's mean spindle power `power` (W): low-pass, compare,
    /// debounce (saturating count).
    pub fn step(&mut self, power: Watts) -> WearStatus {
        let p = match self.filtered {
            None => power,
            Some(f) => f.saturating_add(power.saturating_sub(f) >> u32::from(self.s.lowpass_shift)),
        };
        self.filtered = Some(p);
        self.over = p >= self.allowed;
        if self.over {
            self.over_count = self.over_count.saturating_add(1);
        } else {
            self.over_count = 0;
        }
        if self.over_count >= self.s.debounce_periods {
            self.alarm = true;
        }
        self.status()
    }

    /// The current status without a step.
    pub fn status(&self) -> WearStatus {
        WearStatus {
            power: self.filtered.unwrap_or(Fx::ZERO),
            allowed: self.allowed,
            over: self.over,
            alarm: self.alarm,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> WearSettings {
        let mut sets = [ConditionSet::default(); MAX_CONDITION_SETS];
        sets[0] = ConditionSet {
            mean_power_limit: Fx::const_from_int(1600),
            idle_power: Fx::const_from_int(300),
        };
        WearSettings {
            sets,
            set_count: 1,
            efficiency: Fx::lit("0.8"),
            lowpass_shift: 0,
            debounce_periods: 3,
            threshold: Threshold::Updating,
        }
    }

    #[test]
    fn allowed_power_is_w9() {
        let m = WearMonitor::new(&settings());
        // 300 + 1600/0.8; 0.8 is not exact in binary: within a few LSBs
        let err = (m.status().allowed - Fx::const_from_int(2300)).abs();
        assert!(err < Fx::lit("0.000001"), "{err}");
    }

    #[test]
    fn alarm_needs_debounce_and_latches() {
        let mut m = WearMonitor::new(&settings());
        let hi = Fx::const_from_int(2400);
        assert!(!m.step(hi).alarm);
        assert!(!m.step(hi).alarm);
        assert!(!m.step(Fx::const_from_int(100)).alarm);
        assert!(!m.step(hi).alarm);
        assert!(!m.step(hi).alarm);
        assert!(m.step(hi).alarm);
        assert!(m.step(Fx::ZERO).alarm);
        m.tool_changed();
        assert!(!m.step(Fx::ZERO).alarm);
    }

    /// η = 1/2 (exact): set 0 allows 200 + 1000/0.5 = 2200 W, set 1 100 + 600/0.5 = 1300 W;
    /// low-pass 2^−1, debounce 2.
    fn two_sets(threshold: Threshold) -> WearMonitor {
        let mut sets = [ConditionSet::default(); MAX_CONDITION_SETS];
        sets[0] = ConditionSet {
            mean_power_limit: Fx::const_from_int(1000),
            idle_power: Fx::const_from_int(200),
        };
        sets[1] = ConditionSet {
            mean_power_limit: Fx::const_from_int(600),
            idle_power: Fx::const_from_int(100),
        };
        WearMonitor::new(&WearSettings {
            sets,
            set_count: 2,
            efficiency: Fx::lit("0.5"),
            lowpass_shift: 1,
            debounce_periods: 2,
            threshold,
        })
    }

    fn status(power: i32, allowed: i32, over: bool, alarm: bool) -> WearStatus {
        WearStatus {
            power: Fx::from_num(power),
            allowed: Fx::from_num(allowed),
            over,
            alarm,
        }
    }

    #[test]
    fn periods_by_hand() {
        let mut m = two_sets(Threshold::Updating);
        assert_eq!(m.status(), status(0, 2200, false, false));
        let w = Fx::from_num::<i32>;
        // The first period is taken as is, then p̄ += (P − p̄)/2.
        assert_eq!(m.step(w(1000)), status(1000, 2200, false, false));
        assert_eq!(m.step(w(3000)), status(2000, 2200, false, false));
        assert_eq!(m.step(w(3000)), status(2500, 2200, true, false));
        assert_eq!(m.step(w(3000)), status(2750, 2200, true, true));
        // A new tool: the alarm and the count clear; two more periods over raise it again.
        m.tool_changed();
        assert_eq!(m.status(), status(2750, 2200, true, false));
        assert_eq!(m.step(w(2750)), status(2750, 2200, true, false));
        assert_eq!(m.step(w(2750)), status(2750, 2200, true, true));
        // Set 1 lowers the threshold; set 2 does not exist and changes nothing.
        assert!(m.select(1));
        assert_eq!(m.status().allowed, w(1300));
        assert!(!m.select(2));
        assert_eq!(m.status().allowed, w(1300));
        assert!(m.select(0));
        assert_eq!(m.status().allowed, w(2200));
    }

    #[test]
    fn equal_power_is_over_and_a_dip_restarts_the_debounce() {
        let mut m = two_sets(Threshold::Updating);
        let w = Fx::from_num::<i32>;
        assert!(m.step(w(2200)).over, "p̄ = [P] counts as over");
        // 2200 → 1100 → back: the count restarts.
        assert!(!m.step(w(0)).over);
        assert_eq!(m.step(w(3300)), status(2200, 2200, true, false));
        assert_eq!(m.step(w(2200)), status(2200, 2200, true, true));
    }

    #[test]
    fn a_constant_threshold_ignores_the_conditions() {
        let mut m = two_sets(Threshold::Constant(Fx::const_from_int(1500)));
        assert_eq!(m.status().allowed, Fx::const_from_int(1500));
        assert!(m.select(1));
        assert_eq!(m.status().allowed, Fx::const_from_int(1500));
    }

    #[test]
    fn zero_efficiency_is_rejected() {
        let s = WearSettings {
            efficiency: Fx::ZERO,
            ..settings()
        };
        assert_eq!(s.validate().unwrap_err().field, "wear.efficiency");
    }
}
