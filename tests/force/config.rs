//! Bad force-path settings are errors naming the field and its allowed range.

use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::force::control::adaptive::DEFAULT_ADAPTIVE;
use tooltouch_model::force::control::fuzzy::DEFAULT_FUZZY;
use tooltouch_model::force::control::fuzzy::{NO_RULE, SETS};
use tooltouch_model::force::control::pi::DEFAULT_PI;
use tooltouch_model::force::control::{
    AdaptiveSettings, ControllerSettings, FuzzySettings, PiSettings,
};
use tooltouch_model::force::wear::Threshold;
use tooltouch_model::units::Fx;

fn field_of(s: ForceSettings) -> String {
    let e = s.validate().expect_err("settings must be rejected");
    let msg = e.to_string();
    assert!(msg.contains(e.field), "{msg}");
    assert!(msg.contains("allowed"), "{msg}");
    e.field.to_string()
}

fn with(c: ControllerSettings) -> ForceSettings {
    ForceSettings {
        controller: c,
        ..Default::default()
    }
}

#[test]
fn zero_or_negative_gains_name_the_gain() {
    for (kp, ki, field) in [
        (Fx::ZERO, DEFAULT_PI.ki, "pi.kp"),
        (Fx::from_num(-1), DEFAULT_PI.ki, "pi.kp"),
        (DEFAULT_PI.kp, Fx::ZERO, "pi.ki"),
        (DEFAULT_PI.kp, Fx::from_num(-2), "pi.ki"),
    ] {
        let s = with(ControllerSettings::Pi(PiSettings {
            kp,
            ki,
            ..DEFAULT_PI
        }));
        assert_eq!(field_of(s), field);
    }
    let s = with(ControllerSettings::Adaptive(AdaptiveSettings {
        open_loop_gain: Fx::ZERO,
        ..DEFAULT_ADAPTIVE
    }));
    assert_eq!(field_of(s), "adaptive.open_loop_gain");
    let s = with(ControllerSettings::Adaptive(AdaptiveSettings {
        gain_min: Fx::ZERO,
        ..DEFAULT_ADAPTIVE
    }));
    assert_eq!(field_of(s), "adaptive.gain_min");
    for (ge, gde, gdu, field) in [
        (Fx::ZERO, Fx::ONE, Fx::ONE, "fuzzy.ge"),
        (Fx::ONE, Fx::from_num(-1), Fx::ONE, "fuzzy.gde"),
        (Fx::ONE, Fx::ONE, Fx::ZERO, "fuzzy.gdu"),
    ] {
        let s = with(ControllerSettings::Fuzzy(FuzzySettings {
            ge,
            gde,
            gdu,
            ..DEFAULT_FUZZY
        }));
        assert_eq!(field_of(s), field);
    }
}

#[test]
fn empty_or_bad_rule_table_is_rejected() {
    let s = with(ControllerSettings::Fuzzy(FuzzySettings {
        rules: [[NO_RULE; SETS]; SETS],
        ..DEFAULT_FUZZY
    }));
    assert_eq!(field_of(s), "fuzzy.rules");
    let mut rules = DEFAULT_FUZZY.rules;
    rules[2][5] = 4;
    let s = with(ControllerSettings::Fuzzy(FuzzySettings {
        rules,
        ..DEFAULT_FUZZY
    }));
    assert_eq!(field_of(s), "fuzzy.rules");
}

#[test]
fn efficiency_at_or_below_zero_is_rejected() {
    for eta in [Fx::ZERO, Fx::from_num(-1), Fx::from_num(2)] {
        let mut s = ForceSettings::default();
        s.wear.efficiency = eta;
        assert_eq!(field_of(s), "wear.efficiency");
    }
    let mut s = ForceSettings::default();
    s.wear.threshold = Threshold::Constant(Fx::ZERO);
    assert_eq!(field_of(s), "wear.threshold");
    let mut s = ForceSettings::default();
    s.wear.set_count = 0;
    assert_eq!(field_of(s), "wear.set_count");
}

#[test]
fn estimator_and_sampling_fields_are_named() {
    let mut s = ForceSettings::default();
    s.estimator.inertia = Fx::ZERO;
    assert_eq!(field_of(s), "estimator.inertia");
    let mut s = ForceSettings::default();
    s.estimator.viscous_nominal = Fx::from_num(100);
    assert_eq!(field_of(s), "estimator.viscous_nominal");
    let s = ForceSettings {
        samples_per_period: 0,
        ..Default::default()
    };
    assert_eq!(field_of(s), "samples_per_period");
    let mut s = ForceSettings::default();
    s.scales.amps_per_lsb = Fx::ZERO;
    assert_eq!(field_of(s), "scales.amps_per_lsb");
    let s = ForceSettings {
        reference: Fx::from_num(-500),
        ..Default::default()
    };
    assert_eq!(field_of(s), "reference");
}
