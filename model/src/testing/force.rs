//! Random force-path settings of the test kit: [`force_settings`] (a proptest strategy) and
//! [`draw_force`] (one seeded draw), both over [`settings_from`], which maps raw words to
//! valid settings for every controller kind (PI, adaptive, fuzzy with rules removed), force
//! source, 1–8 wear condition sets and both wear thresholds. Fields it does not draw keep
//! their defaults. (The host's plant-fitted generator, `cosim::force_scenario`, derives its
//! gains from the simulated plant and stays there.)

use crate::force::config::{ForceSettings, ForceSource};
use crate::force::control::adaptive::DEFAULT_ADAPTIVE;
use crate::force::control::fuzzy::{DEFAULT_FUZZY, NO_RULE, STANDARD_RULES};
use crate::force::control::pi::DEFAULT_PI;
use crate::force::control::{AdaptiveSettings, ControllerSettings, FuzzySettings, PiSettings};
use crate::force::wear::Threshold;
use crate::units::Fx;
use proptest::prelude::*;

/// Valid force settings from raw words `w` (missing words read as 0); `kind % 3` picks the
/// controller. Every drawn field is inside its documented range.
pub fn settings_from(kind: u8, w: &[u32]) -> ForceSettings {
    let mut i = 0;
    let mut next = || {
        i += 1;
        w.get(i - 1).copied().unwrap_or(0)
    };
    let frac = |x: u32, lo: i64, hi: i64| Fx::from_bits(lo + (i64::from(x) % (hi - lo + 1)));
    let one = 1i64 << 32;
    let mut s = ForceSettings {
        sample_hz: 500 + (next() % 1500) as u16,
        samples_per_period: 10 + (next() % 90) as u16,
        lowpass_shift: 1 + (next() % 8) as u8,
        manual_override: next() as u8,
        reference: frac(next(), one, 2000 * one),
        force_source: if next() % 2 == 0 {
            ForceSource::Estimated
        } else {
            ForceSource::Measured
        },
        ..ForceSettings::default()
    };
    s.scales.speed_per_lsb = frac(next(), 1, one);
    s.scales.force_per_lsb = frac(next(), 1, 5 * one);
    s.estimator.coulomb_nominal = frac(next(), 0, 3 * one);
    s.estimator.friction_f[1] = frac(next(), -(one / 100), one / 100);
    s.estimator.slip_hold_periods = 1 + (next() % 100) as u8;
    s.controller = match kind % 3 {
        0 => ControllerSettings::Pi(PiSettings {
            kp: frac(next(), 1, 2 * one),
            ki: frac(next(), 1, 10 * one),
            ..DEFAULT_PI
        }),
        1 => ControllerSettings::Adaptive(AdaptiveSettings {
            open_loop_gain: frac(next(), 1, 5 * one),
            gain_filter_shift: (next() % 9) as u8,
            ..DEFAULT_ADAPTIVE
        }),
        _ => {
            let mut rules = STANDARD_RULES;
            for r in rules.iter_mut().flatten() {
                if next() % 5 == 0 {
                    *r = NO_RULE;
                }
            }
            rules[3][3] = 0;
            ControllerSettings::Fuzzy(FuzzySettings {
                gdu: frac(next(), 1, one),
                rules,
                ..DEFAULT_FUZZY
            })
        }
    };
    let count = 1 + (next() % 8) as u8;
    s.wear.set_count = count;
    for set in s.wear.sets.iter_mut().take(usize::from(count)) {
        set.mean_power_limit = frac(next(), 1, 5000 * one);
        set.idle_power = frac(next(), 0, 500 * one);
    }
    s.wear.debounce_periods = 1 + (next() % 255) as u8;
    s.wear.threshold = if next() % 2 == 0 {
        Threshold::Updating
    } else {
        Threshold::Constant(frac(next(), 1, 3000 * one))
    };
    s
}

/// Raw words [`settings_from`] reads at most.
const WORDS: usize = 80;

/// Valid force settings: a controller kind and raw words through [`settings_from`].
pub fn force_settings() -> impl Strategy<Value = ForceSettings> {
    (0u8..3, proptest::collection::vec(any::<u32>(), WORDS))
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
