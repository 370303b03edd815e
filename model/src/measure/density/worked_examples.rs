//! Hand-worked pulse sequences of device 2 (docs/domain.md §2.4) on an 8-bit capacitor (full
//! scale 255) that fires at 192 and re-arms below 64, with the charge after every step
//! written out: the linear law by multiples of its steps, the exponential law by
//! `q += max(1, (255 − q) >> 3)` when charging and `q −= max(1, q >> 2)` when discharging,
//! evaluated by hand.

use super::DensityDetector;
use crate::measure::config::{ChargeLaw, MeasureSettings};

fn detector(law: ChargeLaw) -> DensityDetector {
    let s = MeasureSettings {
        charge_bits: 8,
        charge_law: law,
        fire_threshold: 192,
        rearm_threshold: 64,
        ..Default::default()
    };
    DensityDetector::new(&s.validate().unwrap())
}

const LINEAR: ChargeLaw = ChargeLaw::Linear {
    charge_step: 32,
    discharge_step: 16,
};

const EXPONENTIAL: ChargeLaw = ChargeLaw::Exponential {
    charge_shift: 3,
    discharge_shift: 2,
};

/// (charge, armed, fired since reset).
fn state(d: &DensityDetector) -> (u32, bool, bool) {
    (d.charge(), d.armed(), d.fired())
}

#[test]
fn exponential_charge_step_by_step() {
    let mut d = detector(EXPONENTIAL);
    // 255 − q shifted right by 3, added: 31, 59, 83, 104, 122, 138, 152, 164, 175, 185, 193.
    let expected = [31, 59, 83, 104, 122, 138, 152, 164, 175, 185];
    for (k, q) in expected.into_iter().enumerate() {
        assert!(!d.on_pulse(true), "pulse {}", k + 1);
        assert_eq!(d.charge(), q, "pulse {}", k + 1);
    }
    assert!(d.on_pulse(true), "193 >= 192 on the 11th pulse");
    assert_eq!(state(&d), (193, false, true));
    // Discharge by q >> 2: 145, 109, 82, then 62 < 64 re-arms.
    for q in [145, 109, 82] {
        d.on_pulse(false);
        assert_eq!(state(&d), (q, false, true));
    }
    d.on_pulse(false);
    assert_eq!(state(&d), (62, true, true), "re-armed; fired stays set");
}

#[test]
fn the_last_steps_are_one_lsb_and_the_ends_are_fixed_points() {
    let mut d = detector(EXPONENTIAL);
    // Near full scale (255 − q) >> 3 is 0, so the step is 1 LSB: 248 → 249 → … → 255.
    while d.charge() < 248 {
        d.on_pulse(true);
    }
    assert_eq!(d.next_charge(true), d.charge() + 1);
    while d.charge() < 255 {
        let q = d.charge();
        d.on_pulse(true);
        assert_eq!(d.charge(), q + 1);
    }
    assert_eq!(d.next_charge(true), 255, "full: no step");
    while d.charge() > 3 {
        d.on_pulse(false);
    }
    // q >> 2 is 0 below 4: 1-LSB steps to 0, which stays.
    assert_eq!(d.next_charge(false), d.charge() - 1);
    for _ in 0..3 {
        d.on_pulse(false);
    }
    assert_eq!(d.charge(), 0);
    assert_eq!(d.next_charge(false), 0);
}

#[test]
fn reset_empties_rearms_and_forgets_the_fire() {
    let mut d = detector(LINEAR);
    assert_eq!(state(&d), (0, true, false));
    for _ in 0..6 {
        d.on_pulse(true);
    }
    assert_eq!(state(&d), (192, false, true));
    d.reset();
    assert_eq!(state(&d), (0, true, false));
    // Six more 32-LSB steps fire again.
    let fires: [bool; 6] = core::array::from_fn(|_| d.on_pulse(true));
    assert_eq!(fires, [false, false, false, false, false, true]);
}

#[test]
fn the_linear_charge_saturates_at_both_ends() {
    let mut d = detector(LINEAR);
    for _ in 0..9 {
        d.on_pulse(true);
    }
    assert_eq!(d.charge(), 255, "9 × 32 = 288 clipped to 255");
    for _ in 0..15 {
        d.on_pulse(false);
    }
    assert_eq!(d.charge(), 15, "255 − 15 × 16");
    d.on_pulse(false);
    assert_eq!(d.charge(), 0, "15 − 16 clipped to 0");
}

#[test]
fn a_linear_run_moves_the_charge_by_whole_steps() {
    let mut d = detector(LINEAR);
    assert!(!d.on_pulses(true, true, 0));
    assert_eq!(state(&d), (0, true, false));
    assert!(!d.on_pulses(true, true, 1));
    assert_eq!(d.charge(), 32);
    // 32 + 4 × 32 = 160: below 192.
    assert!(!d.on_pulses(true, true, 4));
    assert_eq!(state(&d), (160, true, false));
    // 160 + 32 = 192 fires inside the run; 3 pulses end at 255.
    assert!(d.on_pulses(true, true, 3));
    assert_eq!(state(&d), (255, false, true));
    // Sticky first pulse charges (clipped), then 12 × 16 down: 63 < 64 re-arms.
    assert!(!d.on_pulses(true, false, 13));
    assert_eq!(state(&d), (63, true, true));
    // A charging run while armed from 63: 63 + 4 × 32 = 191 does not fire, 5 does.
    let mut e = d;
    assert!(!e.on_pulses(false, true, 5), "47, then 4 × 32 = 175");
    assert_eq!(e.charge(), 175);
    assert!(!d.on_pulses(true, true, 4));
    assert_eq!(d.charge(), 191);
    assert!(d.on_pulses(true, true, 1));
}

#[test]
fn a_disarmed_run_does_not_fire_and_a_discharging_run_above_rearm_stays_disarmed() {
    let mut d = detector(LINEAR);
    d.on_pulses(true, true, 6);
    assert_eq!(state(&d), (192, false, true));
    assert!(!d.on_pulses(true, true, 5), "disarmed");
    assert_eq!(d.charge(), 255);
    // 255 − 11 × 16 = 79: still above 64.
    assert!(!d.on_pulses(false, false, 11));
    assert_eq!(state(&d), (79, false, true));
    // One more pulse: 63.
    d.on_pulses(false, false, 1);
    assert_eq!(state(&d), (63, true, true));
}

#[test]
fn an_exponential_run_equals_its_pulses() {
    let mut d = detector(EXPONENTIAL);
    assert!(!d.on_pulses(true, true, 10));
    assert_eq!(state(&d), (185, true, false));
    // First pulse without contact: 185 − 46 = 139; then 153, 165.
    assert!(!d.on_pulses(false, true, 3));
    assert_eq!(state(&d), (165, true, false));
    // 176, 185, 193: fires on the third.
    assert!(d.on_pulses(true, true, 3));
    assert_eq!(state(&d), (193, false, true));
    // A long run without contact settles at 0, re-armed on the way.
    assert!(!d.on_pulses(false, false, 1000));
    assert_eq!(state(&d), (0, true, true));
}

#[test]
fn pulses_to_fire_linear() {
    let d = detector(LINEAR);
    // From 0: 6 charging pulses reach 192.
    assert_eq!(d.pulses_to_fire(true, true, 100), Some(6));
    assert_eq!(d.pulses_to_fire(true, true, 6), Some(6));
    assert_eq!(d.pulses_to_fire(true, true, 5), None);
    // A first pulse without contact keeps 0, then 6 more.
    assert_eq!(d.pulses_to_fire(false, true, 100), Some(7));
    assert_eq!(d.pulses_to_fire(true, false, 100), None);
    assert_eq!(d.pulses_to_fire(true, true, 0), None);
    // From 144, not a multiple of the step.
    let mut d = detector(LINEAR);
    d.on_pulses(true, true, 5);
    d.on_pulse(false);
    assert_eq!(d.charge(), 144);
    assert_eq!(
        d.pulses_to_fire(true, true, 100),
        Some(2),
        "144 → 176 → 208"
    );
    assert_eq!(d.pulses_to_fire(false, true, 100), Some(3), "128, 160, 192");
    d.on_pulses(true, true, 2);
    assert!(!d.armed());
    assert_eq!(d.pulses_to_fire(true, true, 100), None, "disarmed");
}

#[test]
fn pulses_to_fire_exponential() {
    let d = detector(EXPONENTIAL);
    assert_eq!(d.pulses_to_fire(true, true, 100), Some(11));
    assert_eq!(d.pulses_to_fire(true, true, 11), Some(11));
    assert_eq!(d.pulses_to_fire(true, true, 10), None);
    assert_eq!(d.pulses_to_fire(false, true, 100), Some(12));
    assert_eq!(d.pulses_to_fire(true, false, 100), None);
    assert_eq!(d.pulses_to_fire(true, true, 1), None);
    let mut d = detector(EXPONENTIAL);
    d.on_pulses(true, true, 10);
    assert_eq!(d.pulses_to_fire(true, false, 100), Some(1), "185 → 193");
}

#[test]
fn an_exponential_run_stops_stepping_once_settled() {
    // 2^32 − 1 pulses: the charge reaches full scale within a few dozen steps, after which
    // every pulse is a fixed point, so the run returns at once (stepping all of them would
    // take minutes).
    let mut d = detector(EXPONENTIAL);
    assert!(d.on_pulses(true, true, u32::MAX));
    assert_eq!(state(&d), (255, false, true));
    assert!(!d.on_pulses(false, false, u32::MAX));
    assert_eq!(state(&d), (0, true, true));
}
