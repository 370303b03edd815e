//! Random force-path settings of the test kit: [`force_settings`] (a proptest strategy) and
//! [`draw_force`] (one seeded draw), both over [`settings_from`], which maps raw words to
//! valid settings for every controller kind (PI, adaptive, fuzzy with rules removed or
//! changed), force source, 1–8 wear condition sets and both wear thresholds.
//!
//! Every field is drawn, as full struct literals without `..Default::default()`, so a new
//! field does not compile until it is drawn here. Each value lies in the range its
//! `validate` checks; fields whose range depends on another (viscous friction on J/(2h),
//! the adaptive gain on 1/h, the upper clamps on the lower ones) are drawn after it. The
//! host's plant-fitted co-simulation (`cosim::force_scenario`) starts from this draw and
//! overrides only what its simulated plant dictates.

use crate::force::config::{ForceSettings, ForceSource};
use crate::force::control::fuzzy::{NO_RULE, SETS, STANDARD_RULES};
use crate::force::control::{
    AdaptiveSettings, ControllerSettings, FuzzySettings, PiSettings, OVERRIDE_MAX_FX,
};
use crate::force::estimator::settings::{viscous_max, EstimatorSettings};
use crate::force::sampling::AdcScales;
use crate::force::wear::{ConditionSet, Threshold, WearSettings, MAX_CONDITION_SETS};
use crate::units::Fx;
use proptest::prelude::*;

/// Raw words read in order; a missing word reads as 0 (every field at its lower end).
struct Words<'a> {
    words: &'a [u64],
    next: usize,
}

impl Words<'_> {
    fn word(&mut self) -> u64 {
        self.next += 1;
        self.words.get(self.next - 1).copied().unwrap_or(0)
    }

    /// An integer in `lo..=hi`: each end one word in eight, else uniform.
    fn int(&mut self, lo: u64, hi: u64) -> u64 {
        let x = self.word();
        match x % 8 {
            0 => lo,
            1 => hi,
            _ => lo + (x >> 3) % (hi - lo + 1),
        }
    }

    fn u8(&mut self, lo: u8, hi: u8) -> u8 {
        self.int(u64::from(lo), u64::from(hi)) as u8
    }

    fn u16(&mut self, lo: u16, hi: u16) -> u16 {
        self.int(u64::from(lo), u64::from(hi)) as u16
    }

    /// An I32F32 in `[lo, hi]`: each end one word in eight, else spread over magnitudes
    /// (the span shifted right by 0..=63 bits, then uniform), so values just above `lo`
    /// come up as often as values near `hi`.
    fn fx(&mut self, lo: Fx, hi: Fx) -> Fx {
        let x = self.word();
        let span = hi.to_bits().abs_diff(lo.to_bits());
        let offset = match x % 8 {
            0 => 0,
            1 => span,
            _ => (x >> 9) % ((span >> ((x >> 3) % 64)) + 1),
        };
        Fx::from_bits(lo.to_bits().wrapping_add(offset as i64))
    }

    /// An I32F32 in `(0, hi]`.
    fn positive(&mut self, hi: Fx) -> Fx {
        self.fx(Fx::DELTA, hi)
    }

    /// True one word in `n`.
    fn one_in(&mut self, n: u64) -> bool {
        self.word().is_multiple_of(n)
    }
}

fn int(n: i32) -> Fx {
    Fx::from_num(n)
}

/// Valid force settings from raw words `w` (missing words read as 0); `kind % 3` picks the
/// controller (PI, adaptive, fuzzy). Every field is drawn inside the range its `validate`
/// documents.
pub fn settings_from(kind: u8, w: &[u64]) -> ForceSettings {
    let mut w = Words { words: w, next: 0 };
    let sample_hz = w.u16(100, 10_000);
    let samples_per_period = w.u16(1, 1000);
    // The control period exactly as `ForceSettings::validate` derives it.
    let h = Fx::from_num(samples_per_period)
        .checked_div(Fx::from_num(sample_hz))
        .unwrap_or(Fx::ZERO);
    let lowpass_shift = w.u8(1, 8);
    let scales = AdcScales {
        speed_per_lsb: w.positive(Fx::ONE),
        power_per_lsb: w.positive(int(100)),
        force_per_lsb: w.positive(int(100)),
        volts_per_lsb: w.positive(int(10)),
        amps_per_lsb: w.positive(Fx::ONE),
    };
    let inertia = w.positive(int(100));
    let friction_limit = Fx::lit("0.01");
    let estimator = EstimatorSettings {
        stator_resistance: w.fx(Fx::ZERO, int(100)),
        inertia,
        viscous_nominal: w.fx(Fx::ZERO, viscous_max(inertia, h)),
        coulomb_nominal: w.fx(Fx::ZERO, int(1000)),
        friction_f: [
            w.fx(Fx::lit("-0.5"), Fx::ONE),
            w.fx(-friction_limit, friction_limit),
        ],
        friction_g: [
            w.fx(-Fx::ONE, Fx::ONE),
            w.fx(-friction_limit, friction_limit),
        ],
        min_speed: w.positive(int(100)),
        switch_threshold: w.positive(int(10)),
        slip_gain: w.positive(int(2)),
        slip_hold_periods: w.u8(1, 100),
        workpiece_radius: w.positive(Fx::ONE),
    };
    let force_source = if w.one_in(2) {
        ForceSource::Estimated
    } else {
        ForceSource::Measured
    };
    let reference = w.positive(int(100_000));
    let manual_override = w.u8(0, 255);
    let controller = match kind % 3 {
        0 => {
            let integrator_min = w.fx(Fx::ZERO, OVERRIDE_MAX_FX - Fx::ONE);
            ControllerSettings::Pi(PiSettings {
                kp: w.positive(int(100)),
                ki: w.positive(int(1000)),
                integrator_min,
                integrator_max: w.fx(integrator_min + Fx::DELTA, OVERRIDE_MAX_FX),
            })
        }
        1 => {
            let open_loop_limit = Fx::ONE.checked_div(h).unwrap_or(Fx::ZERO);
            let gain_limit = int(10_000);
            let gain_min = w.positive(gain_limit);
            let gain_max = w.fx(gain_min, gain_limit);
            ControllerSettings::Adaptive(AdaptiveSettings {
                open_loop_gain: w.positive(open_loop_limit),
                gain_min,
                gain_max,
                initial_gain: w.fx(gain_min, gain_max),
                gain_filter_shift: w.u8(0, 8),
                min_override: w.positive(OVERRIDE_MAX_FX),
                min_force: w.positive(int(100_000)),
            })
        }
        _ => {
            // The standard table with about one entry in eight removed and one in eight
            // pointing at another output set; the centre rule stays, so a rule fires.
            let mut rules = STANDARD_RULES;
            let centre = SETS * SETS / 2;
            for (i, r) in rules.iter_mut().flatten().enumerate() {
                let x = w.word();
                match x % 8 {
                    _ if i == centre => {}
                    0 => *r = NO_RULE,
                    1 => *r = ((x >> 3) % 7) as i8 - 3,
                    _ => {}
                }
            }
            let scaling_limit = int(1_000_000);
            ControllerSettings::Fuzzy(FuzzySettings {
                ge: w.positive(scaling_limit),
                gde: w.positive(scaling_limit),
                gdu: w.positive(int(100)),
                rules,
            })
        }
    };
    let set_count = w.u8(1, MAX_CONDITION_SETS as u8);
    let mut sets = [ConditionSet::default(); MAX_CONDITION_SETS];
    let mega = int(1_000_000);
    for set in sets.iter_mut().take(usize::from(set_count)) {
        *set = ConditionSet {
            mean_power_limit: w.positive(mega),
            idle_power: w.fx(Fx::ZERO, mega),
        };
    }
    let wear = WearSettings {
        sets,
        set_count,
        efficiency: w.positive(Fx::ONE),
        lowpass_shift: w.u8(0, 8),
        debounce_periods: w.u8(1, 255),
        threshold: if w.one_in(2) {
            Threshold::Updating
        } else {
            Threshold::Constant(w.positive(mega))
        },
        settle_periods: w.u8(0, 255),
        power_lag_gain: if w.one_in(2) {
            None
        } else {
            Some(w.positive(Fx::ONE))
        },
    };
    ForceSettings {
        sample_hz,
        samples_per_period,
        lowpass_shift,
        scales,
        estimator,
        force_source,
        reference,
        manual_override,
        controller,
        wear,
    }
}

/// Raw words [`settings_from`] reads at most (the fuzzy table's 49 entries included).
const WORDS: usize = 128;

/// Valid force settings: a controller kind and raw words through [`settings_from`].
pub fn force_settings() -> impl Strategy<Value = ForceSettings> {
    (0u8..3, proptest::collection::vec(any::<u64>(), WORDS))
        .prop_map(|(kind, words)| settings_from(kind, &words))
}

/// The force settings that `seed` draws.
pub fn draw_force(seed: u64) -> ForceSettings {
    super::draw(&force_settings(), seed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::strategy::ValueTree;
    use std::collections::BTreeSet;
    use std::format;
    use std::string::String;

    #[test]
    fn draws_validate_and_reach_every_controller_source_and_threshold() {
        let strategy = force_settings();
        let mut runner = super::super::seeded_runner(0xf0_4ce);
        let mut seen = BTreeSet::<String>::new();
        for _ in 0..500 {
            let s = strategy.new_tree(&mut runner).unwrap().current();
            if let Err(e) = s.validate() {
                panic!("invalid draw {s:?}: {e}");
            }
            let kind = match s.controller {
                ControllerSettings::Pi(_) => "pi",
                ControllerSettings::Adaptive(_) => "adaptive",
                ControllerSettings::Fuzzy(_) => "fuzzy",
            };
            seen.insert(String::from(kind));
            seen.insert(format!("{:?}", s.force_source));
            seen.insert(String::from(match s.wear.threshold {
                Threshold::Updating => "updating",
                Threshold::Constant(_) => "constant",
            }));
            seen.insert(format!("sets={}", s.wear.set_count));
        }
        for want in [
            "pi",
            "adaptive",
            "fuzzy",
            "Estimated",
            "Measured",
            "updating",
            "constant",
        ] {
            assert!(seen.contains(want), "never drew {want}: {seen:?}");
        }
        for n in 1..=8 {
            assert!(
                seen.contains(&format!("sets={n}")),
                "never drew {n} condition sets"
            );
        }
    }
}
