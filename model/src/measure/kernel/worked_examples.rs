//! Hand-worked measurement cycles of the kernel with every output written out: the papers'
//! sequence (docs/domain.md §2) of arm, approach, first contact, contact pulses over a
//! revolution, decision, retract and re-arm, once per decision method.

use super::*;
use crate::measure::config::{ChargeLaw, MeasureSettings};

/// 16 pulses per revolution, decide above 8 contact pulses in one revolution, sampled
/// contact, a 4-bit capacitor charging and discharging by 5 LSBs that fires at 10 and
/// re-arms below 3.
fn measurement(method: DecisionMethod) -> Measurement {
    let s = MeasureSettings {
        pulses_per_rev: 16,
        i_def: 8,
        window_revs: 1,
        contact_rule: ContactRule::Sampled,
        charge_bits: 4,
        charge_law: ChargeLaw::Linear {
            charge_step: 5,
            discharge_step: 5,
        },
        fire_threshold: 10,
        rearm_threshold: 3,
        method,
        ..Default::default()
    };
    Measurement::new(&s.validate().unwrap())
}

/// The outputs at power-on: everything 0 or false but the armed capacitor.
const POWER_ON: MeasureOutputs = MeasureOutputs {
    armed: false,
    contact: false,
    register_now: false,
    decision_position: 0,
    first_contact: false,
    first_contact_position: 0,
    position: 0,
    scale_errors: 0,
    count: 0,
    last_window_count: 0,
    charge: 0,
    density_armed: true,
    density_fired: false,
    revolutions: 0,
    pulses: 0,
    confirmed: false,
    faults: 0,
};

fn forward(m: &mut Measurement, steps: usize) {
    const PHASES: [(bool, bool); 4] = [(true, false), (true, true), (false, true), (false, false)];
    // Phase k of a forward cycle after position k (mod 4): position 0 is lines 00.
    let start = m.scale().position().rem_euclid(4) as usize;
    for k in 0..steps {
        let (a, b) = PHASES[(start + k) % 4];
        m.on_scale(a, b);
    }
}

#[test]
fn a_counter_cycle_step_by_step() {
    let mut m = measurement(DecisionMethod::Counter);
    assert_eq!(m.outputs(), POWER_ON);
    // Disarmed: index and FES pulses change no count.
    m.on_index();
    m.on_fes();
    assert_eq!(m.outputs(), POWER_ON);
    m.on_arm(true);
    forward(&mut m, 3);
    m.on_contact(true);
    let mut expected = MeasureOutputs {
        armed: true,
        contact: true,
        first_contact: true,
        first_contact_position: 3,
        position: 3,
        ..POWER_ON
    };
    assert_eq!(m.outputs(), expected);
    // 5 contact pulses: count 5, charge 10 fires the capacitor (not the method in use).
    for _ in 0..5 {
        assert!(!m.on_fes_raises());
    }
    expected.count = 5;
    expected.charge = 15;
    expected.density_armed = false;
    expected.density_fired = true;
    expected.pulses = 5;
    assert_eq!(m.outputs(), expected);
    // The index closes the revolution's window: 5 moves to the last count.
    m.on_index();
    expected.count = 0;
    expected.last_window_count = 5;
    expected.revolutions = 1;
    assert_eq!(m.outputs(), expected);
    // Two pulses without contact: nothing counted, charge 15 → 10 → 5.
    m.on_contact(false);
    m.on_fes();
    m.on_fes();
    expected.contact = false;
    expected.charge = 5;
    expected.pulses = 7;
    assert_eq!(m.outputs(), expected);
    // Contact again: the 9th contact pulse of the window decides at position 3.
    m.on_contact(true);
    for k in 1..=8 {
        assert!(!m.on_fes_raises(), "pulse {k}");
    }
    assert!(m.on_fes_raises(), "9 > 8");
    expected.contact = true;
    expected.register_now = true;
    expected.decision_position = 3;
    expected.count = 9;
    expected.charge = 15;
    expected.pulses = 16;
    assert_eq!(m.outputs(), expected);
    // The slide moves on; the latched positions stay.
    forward(&mut m, 1);
    expected.position = 4;
    assert_eq!(m.outputs(), expected);
    // Disarm: results held, pulses no longer counted.
    m.on_arm(false);
    m.on_fes();
    m.on_index();
    expected.armed = false;
    assert_eq!(m.outputs(), expected);
    // Re-arm: a new cycle from nothing, but the scale keeps its position and the contact
    // line its level — closed at the arm, which the status names.
    m.on_arm(true);
    assert_eq!(
        m.outputs(),
        MeasureOutputs {
            armed: true,
            contact: true,
            position: 4,
            faults: crate::measure::checks::fault::CONTACT_AT_ARM,
            ..POWER_ON
        }
    );
}

#[test]
fn a_density_cycle_decides_when_the_capacitor_fires() {
    let mut m = measurement(DecisionMethod::Density);
    m.on_arm(true);
    forward(&mut m, 2);
    m.on_contact(true);
    assert!(!m.on_fes_raises(), "charge 5");
    assert!(m.on_fes_raises(), "charge 10 fires");
    let o = m.outputs();
    assert_eq!(
        (o.register_now, o.decision_position, o.charge, o.count),
        (true, 2, 10, 2)
    );
    assert!(!m.on_fes_raises(), "decided once");
}

#[test]
fn a_single_pulse_cycle_decides_at_the_contact_edge() {
    let mut m = measurement(DecisionMethod::SinglePulse);
    m.on_arm(true);
    forward(&mut m, 5);
    assert!(!m.register_now());
    m.on_contact(true);
    let o = m.outputs();
    assert_eq!((o.register_now, o.decision_position), (true, 5));
    // Neither detector decides for this method.
    assert_eq!(m.fes_to_decision(100), None);
    for _ in 0..20 {
        assert!(!m.on_fes_raises());
    }
    // A contact edge before arming latches nothing.
    let mut m = measurement(DecisionMethod::SinglePulse);
    m.on_contact(true);
    assert!(!m.outputs().first_contact);
    assert!(!m.register_now());
}

#[test]
fn revolutions_saturate_and_pulses_wrap() {
    let mut m = measurement(DecisionMethod::Counter);
    m.on_arm(true);
    for _ in 0..70_000 {
        m.on_index();
    }
    assert_eq!(m.outputs().revolutions, u16::MAX);
    m.preset_pulses(u32::MAX - 1);
    m.on_fes();
    assert_eq!(m.outputs().pulses, u32::MAX);
    m.on_fes();
    assert_eq!(m.outputs().pulses, 0, "2^32 wraps to 0");
    m.preset_pulses(u32::MAX - 2);
    assert!(!m.on_fes_run(5));
    assert_eq!(m.outputs().pulses, 2, "2^32 − 3 + 5");
}

#[test]
fn a_run_of_pulses_worked() {
    let mut m = measurement(DecisionMethod::Counter);
    assert!(!m.on_fes_run(0));
    m.on_arm(true);
    m.on_contact(true);
    assert!(!m.on_fes_run(0));
    assert_eq!(m.outputs().pulses, 0);
    assert!(!m.on_fes_run(8), "8 is not above 8");
    assert!(m.on_fes_run(4), "12");
    let o = m.outputs();
    assert_eq!((o.count, o.pulses, o.register_now), (12, 12, true));
    // Disarmed: a run counts nothing but consumes the sticky bit.
    let mut m = measurement(DecisionMethod::Counter);
    m.on_contact(true);
    assert!(m.sticky());
    m.on_contact(false);
    assert!(!m.on_fes_run(3));
    assert!(!m.sticky());
    assert_eq!(m.outputs().pulses, 0);
}

#[test]
fn fes_to_decision_worked() {
    let mut m = measurement(DecisionMethod::Counter);
    assert_eq!(m.fes_to_decision(100), None, "disarmed");
    m.on_arm(true);
    m.on_contact(true);
    for _ in 0..3 {
        m.on_fes();
    }
    // 3 counted: the 6th next contact pulse makes 9.
    assert_eq!(m.fes_to_decision(100), Some(6));
    assert_eq!(m.fes_to_decision(6), Some(6));
    assert_eq!(m.fes_to_decision(5), None);
    m.on_contact(false);
    assert_eq!(m.fes_to_decision(100), None, "no contact to count");
    m.on_contact(true);
    m.on_fes_run(6);
    assert!(m.register_now());
    assert_eq!(m.fes_to_decision(100), None, "decided");
    // Density: charge 0, steps of 5 to 10.
    let mut m = measurement(DecisionMethod::Density);
    m.on_arm(true);
    m.on_contact(true);
    assert_eq!(m.fes_to_decision(100), Some(2));
    assert_eq!(m.fes_to_decision(1), None);
}

#[test]
fn the_sticky_bit_lives_until_the_next_pulse() {
    let s = MeasureSettings {
        pulses_per_rev: 16,
        i_def: 8,
        contact_rule: ContactRule::Sticky,
        ..Default::default()
    };
    let mut m = Measurement::new(&s.validate().unwrap());
    assert!(!m.sticky());
    m.on_arm(true);
    m.on_contact(true);
    m.on_contact(false);
    assert!(m.sticky());
    m.on_fes();
    assert!(!m.sticky());
    assert_eq!(m.counter().count(), 1);
    assert_eq!(m.density().charge(), 64, "the default linear step");
    assert_eq!(m.scale().position(), 0);
}

#[test]
fn a_repeated_arm_level_is_no_edge() {
    // Only a rising edge of the arm line starts a cycle: arm, 3 contact pulses.
    let mut m = measurement(DecisionMethod::Counter);
    m.on_arm(true);
    m.on_contact(true);
    m.on_fes_run(3);
    // Arm high again while armed: no rising edge, the count 3 stays.
    m.on_arm(true);
    let o = m.outputs();
    assert_eq!(
        (o.armed, o.count, o.pulses, o.first_contact),
        (true, 3, 3, true)
    );
    // Disarm, and low again while disarmed: the results are held both times.
    m.on_arm(false);
    m.on_arm(false);
    let o = m.outputs();
    assert_eq!(
        (o.armed, o.count, o.pulses, o.first_contact),
        (false, 3, 3, true)
    );
}
