//! Tests of [`super`]: the kernel against single-pulse stepping and its decision prediction.

use super::*;
use crate::measure::config::MeasureSettings;
use proptest::prelude::*;

fn measurement(method: DecisionMethod, rule: ContactRule) -> Measurement {
    let s = MeasureSettings {
        pulses_per_rev: 16,
        i_def: 8,
        method,
        contact_rule: rule,
        ..Default::default()
    };
    Measurement::new(&s.validate().unwrap())
}

#[test]
fn sticky_rule_counts_a_burst_between_pulses_sampled_does_not() {
    for (rule, expected) in [(ContactRule::Sticky, 1), (ContactRule::Sampled, 0)] {
        let mut m = measurement(DecisionMethod::Counter, rule);
        m.on_arm(true);
        m.on_contact(true);
        m.on_contact(false);
        m.on_fes();
        assert_eq!(m.outputs().count, expected, "{rule:?}");
        m.on_fes();
        assert_eq!(m.outputs().count, expected, "{rule:?}: consumed");
    }
}

#[test]
fn counter_decision_latches_the_position_before_a_same_clock_scale_edge() {
    let mut m = measurement(DecisionMethod::Counter, ContactRule::Sampled);
    m.on_arm(true);
    m.on_scale(true, false);
    m.on_contact(true);
    assert_eq!(m.outputs().first_contact_position, 1);
    for _ in 0..9 {
        m.on_fes();
    }
    m.on_scale(true, true);
    let o = m.outputs();
    assert!(o.register_now);
    assert_eq!((o.decision_position, o.position), (1, 2));
}

#[test]
fn register_bits_truncate_positions_to_scale_bits() {
    let config = MeasureConfig::default();
    let mut m = Measurement::new(&config);
    m.on_scale(false, true);
    let o = m.outputs();
    assert_eq!(o.position, -1);
    let bits = o.register_bits(&config);
    let widths = MeasureOutputs::widths(&config);
    assert_eq!(widths[6], ("position", 24));
    assert_eq!(bits[6], 0xff_ffff, "position -1 in 24 bits");
    assert_eq!(bits[11], 1, "density_armed at reset");
}

#[test]
fn disarm_holds_results_and_rearm_clears_them() {
    let mut m = measurement(DecisionMethod::SinglePulse, ContactRule::Sampled);
    m.on_arm(true);
    m.on_contact(true);
    assert!(m.register_now());
    m.on_arm(false);
    m.on_fes();
    assert!(m.register_now());
    assert_eq!(m.outputs().pulses, 0, "no counting while disarmed");
    m.on_arm(true);
    assert!(!m.register_now());
}

/// A random valid configuration over every method, rule and charge law, small enough that
/// runs of a few hundred pulses cross every threshold (the test kit's kernel profile).
fn any_config() -> impl Strategy<Value = MeasureConfig> {
    crate::testing::measure_configs(&crate::testing::MeasureProfile::KERNEL)
}

/// A random event: arm, contact, index, scale, or a run of FES pulses (`Err(n)`).
fn apply_op(m: &mut Measurement, op: u8) -> Result<(), u32> {
    match op % 16 {
        0 => m.on_arm(true),
        1 => m.on_arm(false),
        2 | 3 => m.on_contact(true),
        4 | 5 => m.on_contact(false),
        6 => m.on_index(),
        7 => m.on_scale(op & 16 != 0, op & 32 != 0),
        _ => return Err(u32::from(op >> 2)),
    }
    Ok(())
}

proptest! {
    #[test]
    fn a_run_of_fes_pulses_equals_as_many_single_pulses(
        config in any_config(),
        ops in proptest::collection::vec(any::<u8>(), 0..300),
    ) {
        let mut batched = Measurement::new(&config);
        let mut single = batched;
        for (i, op) in ops.into_iter().enumerate() {
            match apply_op(&mut batched, op) {
                Ok(()) => {
                    let _ = apply_op(&mut single, op);
                }
                Err(n) => {
                    let raised = batched.on_fes_run(n);
                    let mut any = false;
                    for _ in 0..n {
                        any |= single.on_fes_raises();
                    }
                    prop_assert_eq!(raised, any, "op {}: run of {} raised", i, n);
                }
            }
            prop_assert_eq!(batched, single, "state after op {}", i);
        }
    }

    #[test]
    fn fes_to_decision_names_the_pulse_that_raises_register_now(
        config in any_config(),
        ops in proptest::collection::vec(any::<u8>(), 0..200), limit in 0u32..80,
    ) {
        let mut m = Measurement::new(&config);
        for (i, op) in ops.into_iter().enumerate() {
            if let Err(n) = apply_op(&mut m, op) {
                m.on_fes_run(n);
            }
            let predicted = m.fes_to_decision(limit);
            let mut probe = m;
            let first = (1..=limit).find(|_| probe.on_fes_raises());
            prop_assert_eq!(predicted, first, "after op {}", i);
        }
    }
}

proptest! {
    #[test]
    fn on_fes_raises_exactly_when_register_now_rises(
        method in 0u8..3, sticky in any::<bool>(),
        ops in proptest::collection::vec(0u8..12, 0..800),
    ) {
        let method = match method {
            0 => DecisionMethod::Counter,
            1 => DecisionMethod::Density,
            _ => DecisionMethod::SinglePulse,
        };
        let rule = if sticky { ContactRule::Sticky } else { ContactRule::Sampled };
        let mut m = measurement(method, rule);
        for (i, op) in ops.into_iter().enumerate() {
            match op {
                0 | 1 => m.on_arm(op == 0),
                2 | 3 => m.on_contact(op == 2),
                4 => m.on_index(),
                5 | 6 => m.on_scale(op == 5, op == 6),
                _ => {
                    let before = m.register_now();
                    let raised = m.on_fes_raises();
                    prop_assert_eq!(raised, !before && m.register_now(), "op {}", i);
                }
            }
        }
    }
}
