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
//! [`WearMonitor::tool_changed`].
//!
//! Settling hold: when a selection *lowers* the threshold, the measured power is still the
//! old conditions' for a while (the power transducer's lag, the sampling low-pass, the
//! period average and this monitor's low-pass). For `settle_periods` periods after such a
//! selection the monitor compares with the higher of the previous and the new threshold,
//! so a new tool is never judged by the lighter cut's limit on the heavier cut's power. A
//! higher threshold applies at once (the power rises to it from below). The host derives
//! `settle_periods` from the lag and the filter constants (docs/wear.md, "Settling hold"). With [`Threshold::Constant`] the allowed power is one
//! number whatever the conditions — valid for one condition set only (the failure mode the
//! `tooltouch wear` scenario shows).
//!
//! Tracking (the default, `power_lag_gain` set): instead of holding a threshold, the monitor
//! compares in the power's own frame. The selected `[P]` goes through a replica of the chain
//! the measured power goes through — the transducer's first-order lag per sample
//! (`lag += ([P] − lag)·power_lag_gain`), the sampling low-pass `2^−k` per sample, the
//! period's average and the monitor's low-pass per period — and gives `T̃`, the threshold
//! as the monitored power would show it. The chain is linear, so `p̄ − T̃` is the chain's
//! response to `P − [P]`: positive in every cut for a tool over the limit in every cut,
//! negative for one under it, however short the cuts (a settled comparison needs a cut
//! longer than the chain's settling; docs/wear.md, "Cuts shorter than the hold"). The
//! threshold compared is `T̃ + |[P] − T̃|/2^GUARD_SHIFT`: a guard for a replica that is off
//! (another lag, the meter's ringing), gone once `T̃` has arrived. While the guard is more
//! than `[P]/2^BLIND_SHIFT` the status is `blind`: the monitor cannot judge a tool that
//! close to its limit, and says so. Without tracking the settling hold applies and `blind`
//! is the hold's time (the held threshold that far above `[P]`).
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
    /// Periods after a selection that lowers the threshold during which the previous,
    /// higher threshold is still compared, `0..=255` (0 = none): the power's settling time
    /// to the new conditions in control periods. Used only without tracking
    /// (`power_lag_gain` `None`).
    pub settle_periods: u8,
    /// Tracking: the per-sample gain `1 − e^(−1/(f_s·τ))` of the measured power's
    /// first-order lag τ, `(0, 1]` (1: no lag). `Some`: the threshold is compared in the
    /// power's own frame (module documentation, "Tracking"); `None`: the settling hold.
    pub power_lag_gain: Option<Fx>,
}

impl Default for WearSettings {
    /// The default plant's monitor (`tooltouch control`): one condition set, `[P̄]` =
    /// 1800 W at 300 W idle power, η = 0.8, low-pass 2^−3, 10 periods of debounce, the
    /// updating threshold, and [`DEFAULT_SETTLE_PERIODS`] of hold.
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
            settle_periods: DEFAULT_SETTLE_PERIODS,
            power_lag_gain: Some(DEFAULT_POWER_LAG_GAIN),
        }
    }
}

/// The default plant's power lag (0.3 s at 1 kHz) as the tracking's per-sample gain:
/// `1 − e^(−1/300)` = 0.0033277839…; the host's `tooltouch_plant::milling::power_lag_gain`
/// computes it and a test checks the two agree.
pub const DEFAULT_POWER_LAG_GAIN: Fx = Fx::lit("0.0033277839454767255");

/// The tracked threshold's guard: `1/2^GUARD_SHIFT` of the transition still ahead of it is
/// added to the threshold compared (a quarter: the replica's step response may be off by
/// that much when the plant's lag differs from the configured one by ±30 %).
pub const GUARD_SHIFT: u32 = 3;

/// The monitor cannot judge ([`WearStatus::blind`]) while a tool more than
/// `[P]/2^BLIND_SHIFT` (1/64, 1.6 %) over its limit could pass unseen: tracking, while the
/// guard is larger than that; with the hold, while the threshold compared is that far above
/// the selected set's `[P]`.
pub const BLIND_SHIFT: u32 = 6;

/// The settling hold of the default set-up, periods: the 0.3 s power lag of the default
/// plant, the 2^−1 sampling low-pass at 1 kHz, 50-sample periods and the 2^−3 wear
/// low-pass settle to within 1 % of a step after 46 periods, so 45 periods (2.25 s) are held; the host's
/// `tooltouch_plant::milling::settle_periods` computes it and a test checks the two agree.
pub const DEFAULT_SETTLE_PERIODS: u8 = 45;

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
        if let Some(g) = self.power_lag_gain {
            positive("wear.power_lag_gain", g, Fx::ONE)?;
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
    /// The allowed power it is compared with (during a settling hold the held one), W.
    pub allowed: Watts,
    /// p̄ ≥ \[P\] this period.
    pub over: bool,
    /// Alarm latched: change the tool.
    pub alarm: bool,
    /// The monitor cannot judge: a tool more than `[P]/2^`[`BLIND_SHIFT`] over its limit
    /// could pass this period (while the power still moves to new conditions).
    pub blind: bool,
}

/// The wear monitor's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct WearMonitor {
    s: WearSettings,
    /// The selected set's threshold.
    allowed: Watts,
    /// The threshold in force before the last lowering selection (compared while held).
    held: Watts,
    /// Periods of hold left.
    hold_left: u8,
    filtered: Option<Watts>,
    over_count: u8,
    alarm: bool,
    over: bool,
    track: Tracking,
}

/// The replica of the measuring chain the threshold goes through when tracking (module
/// documentation, "Tracking"): the power lag and the sampling low-pass per sample, the
/// period's sum and count, and the monitor's low-pass per period. W, I32F32.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
struct Tracking {
    /// Sampling low-pass `2^−shift` (the sampler's, `1..=8`).
    sample_shift: u32,
    lag: Watts,
    sampled: Watts,
    sum: Watts,
    count: u16,
    /// The threshold as the monitored power would show it, `T̃`.
    tracked: Watts,
}

impl WearMonitor {
    /// A monitor for validated `s`, condition set 0 selected; `sample_shift` is the
    /// sampling chain's low-pass shift (`1..=8`, the tracking replicates it).
    pub fn new(s: &WearSettings, sample_shift: u8) -> WearMonitor {
        let mut m = WearMonitor {
            s: *s,
            allowed: Fx::ZERO,
            held: Fx::ZERO,
            hold_left: 0,
            filtered: None,
            over_count: 0,
            alarm: false,
            over: false,
            track: Tracking {
                sample_shift: u32::from(sample_shift.clamp(1, 8)),
                ..Tracking::default()
            },
        };
        m.select(0);
        // No hold at power-up: nothing was compared before; the replica starts settled.
        m.hold_left = 0;
        let t = &mut m.track;
        (t.lag, t.sampled, t.tracked) = (m.allowed, m.allowed, m.allowed);
        m
    }

    /// The threshold compared this period. Tracking: the tracked `T̃` plus the guard,
    /// `1/2^GUARD_SHIFT` of `|[P] − T̃|`. Otherwise the selected set's, or during a hold
    /// the higher of it and the one in force before the lowering selection.
    fn compared(&self) -> Watts {
        if self.s.power_lag_gain.is_some() {
            let t = self.track.tracked;
            let ahead = self.allowed.saturating_sub(t).saturating_abs();
            t.saturating_add(ahead >> GUARD_SHIFT)
        } else if self.hold_left > 0 {
            self.allowed.max(self.held)
        } else {
            self.allowed
        }
    }

    /// How far over its limit a tool may be and still pass this period, W: tracking, the
    /// guard; with the hold, how far the threshold compared is above `[P]`.
    fn unseen(&self) -> Watts {
        if self.s.power_lag_gain.is_some() {
            self.allowed
                .saturating_sub(self.track.tracked)
                .saturating_abs()
                >> GUARD_SHIFT
        } else {
            self.compared().saturating_sub(self.allowed).max(Fx::ZERO)
        }
    }

    /// A tool more than `[P]/2^BLIND_SHIFT` over its limit could pass this period.
    fn blind(&self) -> bool {
        self.unseen() > self.allowed >> BLIND_SHIFT
    }

    /// One ADC sample (tracking only): the selected `[P]` through the replica of the power
    /// lag and the sampling low-pass, added to the period's sum.
    pub fn on_sample(&mut self) {
        let Some(gain) = self.s.power_lag_gain else {
            return;
        };
        let t = &mut self.track;
        t.lag = t
            .lag
            .saturating_add(self.allowed.saturating_sub(t.lag).saturating_mul(gain));
        t.sampled = t
            .sampled
            .saturating_add(t.lag.saturating_sub(t.sampled) >> t.sample_shift);
        t.sum = t.sum.saturating_add(t.sampled);
        t.count = t.count.saturating_add(1);
    }

    /// The period's end for the replica: its average through the monitor's low-pass
    /// (a period without samples keeps `T̃`).
    fn track_period(&mut self) {
        let t = &mut self.track;
        // The count as I32F32 (a u16 always fits); 0 samples: no average, T̃ kept.
        let count = Fx::from_bits(i64::from(t.count) << 32);
        if let Some(avg) = t.sum.checked_div(count) {
            t.tracked = t
                .tracked
                .saturating_add(avg.saturating_sub(t.tracked) >> u32::from(self.s.lowpass_shift));
        }
        t.sum = Fx::ZERO;
        t.count = 0;
    }

    /// Selects condition set `index` (step 3); returns false and keeps the current one if
    /// `index` is not below `set_count`. A lower threshold than the one in force starts
    /// the settling hold (module documentation).
    pub fn select(&mut self, index: u8) -> bool {
        if index >= self.s.set_count {
            return false;
        }
        let Some(set) = self.s.sets.get(usize::from(index)) else {
            return false;
        };
        let before = self.compared();
        self.allowed = match self.s.threshold {
            Threshold::Updating => allowed_power(set, self.s.efficiency),
            Threshold::Constant(p) => p,
        };
        if self.allowed < before {
            self.held = before;
            self.hold_left = self.s.settle_periods;
        }
        if self.filtered.is_none() && self.s.power_lag_gain.is_some() {
            // Before the first period nothing was measured under the old conditions: the
            // replica starts settled at the new threshold, as the power starts as it is.
            let t = &mut self.track;
            (t.lag, t.sampled, t.tracked) = (self.allowed, self.allowed, self.allowed);
        }
        true
    }

    /// Clears the alarm and the debounce count (a new tool).
    pub fn tool_changed(&mut self) {
        self.alarm = false;
        self.over_count = 0;
    }

    /// One period with the period's mean spindle power `power` (W): low-pass, compare with
    /// the threshold in force (held or not), count the hold down, debounce (saturating
    /// count). The status's `allowed` is the threshold this period compared with.
    pub fn step(&mut self, power: Watts) -> WearStatus {
        let p = match self.filtered {
            None => power,
            Some(f) => f.saturating_add(power.saturating_sub(f) >> u32::from(self.s.lowpass_shift)),
        };
        self.filtered = Some(p);
        if self.s.power_lag_gain.is_some() {
            self.track_period();
        }
        let limit = self.compared();
        let blind = self.blind();
        self.over = p >= limit;
        self.hold_left = self.hold_left.saturating_sub(1);
        if self.over {
            self.over_count = self.over_count.saturating_add(1);
        } else {
            self.over_count = 0;
        }
        if self.over_count >= self.s.debounce_periods {
            self.alarm = true;
        }
        WearStatus {
            power: p,
            allowed: limit,
            over: self.over,
            alarm: self.alarm,
            blind,
        }
    }

    /// The current status without a step: `allowed` is the threshold the next period
    /// compares with (a step's status holds the one it compared with).
    pub fn status(&self) -> WearStatus {
        WearStatus {
            power: self.filtered.unwrap_or(Fx::ZERO),
            allowed: self.compared(),
            over: self.over,
            alarm: self.alarm,
            blind: self.blind(),
        }
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for WearMonitor {
    /// The low-passed power `wear.filtered` (I32F32; none before the first period), the
    /// selected set's threshold `wear.allowed` and the held one `wear.held` (I32F32), the
    /// settling hold's periods left `wear.hold_left` and the debounce count
    /// `wear.over_count` (`u8`, saturating).
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        f(Register {
            name: "wear.filtered",
            format: Format::I32F32,
            raw: self.filtered.map(|p| p.to_bits().into()),
        });
        f(Register::fx("wear.allowed", Format::I32F32, self.allowed));
        f(Register::fx("wear.held", Format::I32F32, self.held));
        let u8 = Format::unsigned(8);
        f(Register::new("wear.hold_left", u8, self.hold_left.into()));
        f(Register::new("wear.over_count", u8, self.over_count.into()));
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
            settle_periods: 0,
            power_lag_gain: None,
        }
    }

    #[test]
    fn allowed_power_is_w9() {
        let m = WearMonitor::new(&settings(), 1);
        // 300 + 1600/0.8; 0.8 is not exact in binary: within a few LSBs
        let err = (m.status().allowed - Fx::const_from_int(2300)).abs();
        assert!(err < Fx::lit("0.000001"), "{err}");
    }

    #[test]
    fn alarm_needs_debounce_and_latches() {
        let mut m = WearMonitor::new(&settings(), 1);
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
        WearMonitor::new(
            &WearSettings {
                sets,
                set_count: 2,
                efficiency: Fx::lit("0.5"),
                lowpass_shift: 1,
                debounce_periods: 2,
                threshold,
                settle_periods: 0,
                power_lag_gain: None,
            },
            1,
        )
    }

    fn two_sets_held(threshold: Threshold, settle_periods: u8) -> WearMonitor {
        let mut m = two_sets(threshold);
        m.s.settle_periods = settle_periods;
        m
    }

    fn status(power: i32, allowed: i32, over: bool, alarm: bool) -> WearStatus {
        WearStatus {
            power: Fx::from_num(power),
            allowed: Fx::from_num(allowed),
            over,
            alarm,
            blind: false,
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
    fn a_lower_threshold_waits_settle_periods_a_higher_one_does_not() {
        let w = Fx::from_num::<i32>;
        let mut m = two_sets_held(Threshold::Updating, 3);
        // Power settled at 2000 W under set 0 (2200 W): not over.
        assert_eq!(m.step(w(2000)), status(2000, 2200, false, false));
        // Set 1 (1300 W): for 3 periods 2200 W is still compared, then 1300 W.
        // The held 2200 W is more than 1300/64 above 1300 W: blind while it holds.
        assert!(m.select(1));
        assert_eq!(m.status().allowed, w(2200));
        assert!(m.status().blind);
        let held = WearStatus {
            blind: true,
            ..status(2000, 2200, false, false)
        };
        assert_eq!(m.step(w(2000)), held);
        assert_eq!(m.step(w(2000)), held);
        assert_eq!(m.step(w(2000)), held);
        assert_eq!(m.status().allowed, w(1300));
        assert!(!m.status().blind);
        assert_eq!(m.step(w(2000)), status(2000, 1300, true, false));
        assert_eq!(m.step(w(2000)), status(2000, 1300, true, true));
        // Back to set 0: the higher threshold applies at once.
        m.tool_changed();
        assert!(m.select(0));
        assert_eq!(m.status().allowed, w(2200));
        assert_eq!(m.step(w(2000)), status(2000, 2200, false, false));
    }

    #[test]
    fn a_second_lowering_during_a_hold_keeps_the_highest_threshold() {
        let w = Fx::from_num::<i32>;
        let mut m = two_sets_held(Threshold::Updating, 2);
        let held = WearStatus {
            blind: true,
            ..status(2100, 2200, false, false)
        };
        assert!(m.select(1));
        assert_eq!(m.step(w(2100)), held);
        // 1 → 0 → 1 inside the hold: 2200 W stays compared for 2 more periods.
        assert!(m.select(0));
        assert!(m.select(1));
        assert_eq!(m.status().allowed, w(2200));
        assert_eq!(m.step(w(2100)), held);
        assert_eq!(m.step(w(2100)), held);
        assert_eq!(m.step(w(2100)), status(2100, 1300, true, false));
        // A bad index changes nothing, not even the hold.
        assert!(!m.select(5));
        assert_eq!(m.status().allowed, w(1300));
    }

    /// Tracking by hand: no lag (gain 1), the sampling low-pass 2^−1, two samples a
    /// period, the monitor's low-pass 2^−1; every value is a binary fraction.
    #[test]
    fn tracking_by_hand() {
        let w = Fx::from_num::<f64>;
        let mut m = two_sets(Threshold::Updating);
        m.s.power_lag_gain = Some(Fx::ONE);
        let period = |m: &mut WearMonitor, p: f64| {
            m.on_sample();
            m.on_sample();
            m.step(w(p))
        };
        // The replica starts settled: T̃ = [P] = 2200 W, no guard.
        assert_eq!(period(&mut m, 2000.0), status(2000, 2200, false, false));
        // Set 1 (1300 W): the guard is |1300 − 2200|/8 = 112.5 W on T̃ = 2200, blind
        // (112.5 > 1300/64).
        assert!(m.select(1));
        assert_eq!(m.status().allowed, w(2312.5));
        assert!(m.status().blind);
        // Samples 2200 + (1300 − 2200)/2 = 1750, 1750 + (1300 − 1750)/2 = 1525, mean
        // 1637.5; T̃ = 2200 + (1637.5 − 2200)/2 = 1918.75; compared 1918.75 + 618.75/8 =
        // 1996.09375: 2000 W is over it.
        let st = period(&mut m, 2000.0);
        assert_eq!((st.allowed, st.over, st.blind), (w(1996.09375), true, true));
        // Settled: T̃ at 1300 W, the guard gone, no longer blind.
        for _ in 0..60 {
            period(&mut m, 1200.0);
        }
        let st = m.status();
        assert!((st.allowed - w(1300.0)).abs() < w(0.001), "{}", st.allowed);
        assert!(!st.blind);
        // Tracking ignores the hold: with settle periods set, the same.
        let mut h = two_sets_held(Threshold::Updating, 40);
        h.s.power_lag_gain = Some(Fx::ONE);
        period(&mut h, 2000.0);
        assert!(h.select(1));
        assert_eq!(period(&mut h, 2000.0).allowed, w(1996.09375));
    }

    #[test]
    fn the_hold_starts_only_after_a_selection() {
        let mut m = two_sets_held(Threshold::Updating, 5);
        assert_eq!(m.status().allowed, Fx::from_num(2200));
        assert!(m.step(Fx::from_num(2200)).over, "no hold at power-up");
        // Constant: a selection never lowers it, so never holds.
        let mut c = two_sets_held(Threshold::Constant(Fx::from_num(1500)), 5);
        assert!(c.select(1));
        assert!(c.step(Fx::from_num(1500)).over);
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
