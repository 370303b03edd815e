//! Hand-worked pulse sequences of device 1 (docs/domain.md §2.3) with every output written
//! out: the counter of a 16-pulse revolution decides on the pulse that takes the contact
//! count above `i_def`, a window of `window_revs` index pulses closes the count, and a
//! reset starts a new measurement cycle from nothing.

use super::PulseCounter;
use crate::measure::config::MeasureSettings;

/// A counter of 16 pulses per revolution.
fn counter(i_def: u32, window_revs: u8) -> PulseCounter {
    let s = MeasureSettings {
        pulses_per_rev: 16,
        i_def,
        window_revs,
        ..Default::default()
    };
    PulseCounter::new(&s.validate().unwrap())
}

/// (count, last window's count, index pulses in the window, reached).
fn state(c: &PulseCounter) -> (u32, u32, u8, bool) {
    (
        c.count(),
        c.last_window_count(),
        c.revs_in_window(),
        c.reached(),
    )
}

#[test]
fn reset_forgets_counts_window_progress_and_decision() {
    let mut c = counter(4, 3);
    for _ in 0..6 {
        c.on_pulse(true);
    }
    c.on_index();
    assert_eq!(
        state(&c),
        (6, 0, 1, true),
        "5th pulse decided, 6 counted, 1 of 3 revs"
    );
    c.reset();
    assert_eq!(state(&c), (0, 0, 0, false));
    // A new cycle: the fifth contact pulse decides again, and the window needs three
    // fresh index pulses.
    for k in 1..=4 {
        assert!(!c.on_pulse(true), "pulse {k}");
    }
    assert!(c.on_pulse(true), "5 > 4");
    c.on_index();
    c.on_index();
    assert_eq!(state(&c), (5, 0, 2, true));
    c.on_index();
    assert_eq!(state(&c), (0, 5, 0, true));
}

#[test]
fn a_reset_after_a_closed_window_clears_the_last_count() {
    let mut c = counter(10, 1);
    for _ in 0..7 {
        c.on_pulse(true);
    }
    c.on_index();
    assert_eq!(state(&c), (0, 7, 0, false));
    c.reset();
    assert_eq!(state(&c), (0, 0, 0, false));
}

#[test]
fn the_count_saturates_at_the_window_and_the_window_closes_on_its_last_index() {
    // 2 revolutions of 16 pulses: at most 32 counted however many pulses arrive.
    let mut c = counter(31, 2);
    for _ in 0..40 {
        c.on_pulse(true);
    }
    assert_eq!(state(&c), (32, 0, 0, true));
    c.on_index();
    assert_eq!(state(&c), (32, 0, 1, true));
    c.on_index();
    assert_eq!(state(&c), (0, 32, 0, true));
}

#[test]
fn pulses_without_contact_never_count() {
    let mut c = counter(0, 1);
    for _ in 0..20 {
        assert!(!c.on_pulse(false));
    }
    assert_eq!(state(&c), (0, 0, 0, false));
    assert!(
        c.on_pulse(true),
        "i_def = 0: the first contact pulse decides"
    );
}

#[test]
fn a_run_counts_its_contact_pulses_and_decides_when_it_ends_above_i_def() {
    let mut c = counter(8, 1);
    assert!(!c.on_pulses(true, true, 0), "an empty run");
    assert_eq!(state(&c), (0, 0, 0, false));
    // The sticky first pulse alone carries contact: 1 counted of 5.
    assert!(!c.on_pulses(true, false, 5));
    assert_eq!(c.count(), 1);
    // 7 more contact pulses: 8, not above 8.
    assert!(!c.on_pulses(false, true, 8));
    assert_eq!(c.count(), 8);
    // The next contact pulse of a run decides; the run saturates at 16.
    assert!(c.on_pulses(true, true, 30));
    assert_eq!(state(&c), (16, 0, 0, true));
    // Decided already: a run never decides twice.
    assert!(!c.on_pulses(true, true, 3));
    assert_eq!(c.count(), 16);
}

#[test]
fn a_run_decides_on_its_last_needed_pulse() {
    // 3 counted: 6 more contact pulses exceed 8.
    let mut c = counter(8, 1);
    c.on_pulses(true, true, 3);
    assert!(!c.on_pulses(false, true, 6), "5 contact pulses: 8");
    let mut d = counter(8, 1);
    d.on_pulses(true, true, 3);
    assert!(d.on_pulses(false, true, 7), "6 contact pulses: 9");
    assert_eq!(d.count(), 9);
}

#[test]
fn pulses_to_decision_counts_the_pulses_still_needed() {
    let c = counter(8, 1);
    // 9 contact pulses needed from 0.
    assert_eq!(c.pulses_to_decision(true, true), Some(9));
    assert_eq!(c.pulses_to_decision(false, true), Some(10));
    assert_eq!(c.pulses_to_decision(true, false), None);
    assert_eq!(c.pulses_to_decision(false, false), None);
    let mut c = counter(8, 1);
    c.on_pulses(true, true, 8);
    // At 8: the next contact pulse decides.
    assert_eq!(c.pulses_to_decision(true, false), Some(1));
    assert_eq!(c.pulses_to_decision(true, true), Some(1));
    assert_eq!(c.pulses_to_decision(false, true), Some(2));
    assert_eq!(c.pulses_to_decision(false, false), None);
    c.on_pulse(true);
    assert_eq!(c.pulses_to_decision(true, true), None, "decided");
    let c = counter(0, 1);
    assert_eq!(c.pulses_to_decision(true, false), Some(1));
    assert_eq!(c.pulses_to_decision(false, true), Some(2));
}

#[test]
fn pulses_to_decision_agrees_with_pulse_by_pulse_counting() {
    // Reference: step a copy pulse by pulse (first, then `rest` forever) until it decides.
    for i_def in [0u32, 1, 5, 15] {
        for start in 0..=i_def {
            for (first, rest) in [(true, true), (true, false), (false, true), (false, false)] {
                let mut c = counter(i_def, 1);
                for _ in 0..start {
                    c.on_pulse(true);
                }
                let mut probe = c;
                let stepped =
                    (1..=40u32).find(|&k| probe.on_pulse(if k == 1 { first } else { rest }));
                assert_eq!(
                    c.pulses_to_decision(first, rest),
                    stepped,
                    "i_def {i_def}, count {start}, first {first}, rest {rest}"
                );
            }
        }
    }
}
