//! Hand-worked clock-by-clock traces of the cycle level: which clock reports an edge, how
//! the glitch filter counts and restarts, when the front end is settled, and the events a
//! set of edges makes, with the register values written out from the documented
//! pipeline (sync 1 at clock `k`, sync 2 at `k + 1`, the filtered level `glitch_cycles`
//! clocks later, the kernel one clock after that).

extern crate std;
use super::*;
use crate::measure::config::MeasureSettings;
use std::vec::Vec;

fn front_end(glitch: u8) -> FrontEnd {
    let s = MeasureSettings {
        pulses_per_rev: 16,
        i_def: 2,
        glitch_cycles: glitch,
        ..Default::default()
    };
    FrontEnd::new(&s.validate().unwrap())
}

fn events(edges: Edges) -> Vec<MeasureEvent> {
    let mut v = Vec::new();
    edges.for_each_event(|e| v.push(e));
    v
}

#[test]
fn pins_read_and_write_single_bits() {
    let p = Pins(pin::ARM | pin::INDEX);
    assert!(p.get(pin::ARM));
    assert!(!p.get(pin::CONTACT));
    assert!(p.get(pin::INDEX));
    assert!(!Pins(0).get(pin::SCALE_B));
    assert_eq!(p.with(pin::CONTACT, true), Pins(0b0111));
    assert_eq!(p.with(pin::ARM, false), Pins(0b0100));
    assert_eq!(p.with(pin::INDEX, true), p);
    assert_eq!(p.with(pin::FES, false), p);
}

#[test]
fn edges_make_events_in_canonical_order_and_falling_pulses_make_none() {
    let all = Edges {
        changed: pin::ALL,
        levels: pin::ALL,
    };
    assert_eq!(
        events(all),
        [
            MeasureEvent::Arm(true),
            MeasureEvent::Contact(true),
            MeasureEvent::Index,
            MeasureEvent::Fes,
            MeasureEvent::Scale { a: true, b: true },
        ]
    );
    let falling = Edges {
        changed: pin::ALL,
        levels: 0,
    };
    assert_eq!(
        events(falling),
        [
            MeasureEvent::Arm(false),
            MeasureEvent::Contact(false),
            MeasureEvent::Scale { a: false, b: false },
        ]
    );
    // Only line B changed, A is high: the scale event carries both levels.
    let b_only = Edges {
        changed: pin::SCALE_B,
        levels: pin::SCALE_A | pin::SCALE_B | pin::ARM,
    };
    assert_eq!(events(b_only), [MeasureEvent::Scale { a: true, b: true }]);
    let a_only = Edges {
        changed: pin::SCALE_A,
        levels: pin::SCALE_A | pin::INDEX | pin::FES,
    };
    assert_eq!(events(a_only), [MeasureEvent::Scale { a: true, b: false }]);
    // A high index or FES level that did not change is no pulse.
    let none = Edges {
        changed: 0,
        levels: pin::ALL,
    };
    assert!(none.is_empty());
    assert!(events(none).is_empty());
    assert!(!all.is_empty());
    let contact_only = Edges {
        changed: pin::CONTACT,
        levels: pin::ARM | pin::INDEX,
    };
    assert_eq!(events(contact_only), [MeasureEvent::Contact(false)]);
}

#[test]
fn an_arm_level_reaches_the_kernel_on_clock_three_without_a_filter() {
    let mut fe = front_end(0);
    let mut reported = Vec::new();
    for k in 0..6 {
        let e = fe.clock(Pins(pin::ARM));
        reported.push((k, e));
        if k == 2 {
            // Filtered at the end of clock 2; the kernel has not seen it yet.
            assert_eq!(fe.filtered(), Pins(pin::ARM));
            assert!(!fe.outputs().armed);
        }
    }
    let edges: Vec<_> = reported.iter().filter(|(_, e)| !e.is_empty()).collect();
    assert_eq!(
        edges,
        [&(
            3,
            Edges {
                changed: pin::ARM,
                levels: pin::ARM
            }
        )]
    );
    assert!(fe.outputs().armed);
    assert_eq!(fe.measurement().outputs(), fe.outputs());
}

#[test]
fn a_glitch_interrupted_for_one_clock_restarts_the_filter() {
    // Filter of 2: a level must differ on 3 consecutive clocks. Arm high on clocks 0–1,
    // low on 2, high on 3–4: two 2-clock pulses, neither passes.
    let mut fe = front_end(2);
    for k in 0..20 {
        let high = matches!(k, 0 | 1 | 3 | 4);
        fe.clock(Pins(0).with(pin::ARM, high));
        assert_eq!(fe.filtered(), Pins(0), "clock {k}");
    }
    // Three clocks pass (sync 2 differs on clocks 2, 3, 4: taken at the end of clock 4).
    let mut fe = front_end(2);
    for k in 0..8 {
        fe.clock(Pins(0).with(pin::ARM, k < 3));
        let expected = if (4..7).contains(&k) { pin::ARM } else { 0 };
        assert_eq!(fe.filtered(), Pins(expected), "clock {k}");
    }
}

#[test]
fn settled_only_when_every_register_agrees_with_the_pins() {
    let mut fe = front_end(0);
    assert!(fe.is_settled(Pins(0)));
    assert!(!fe.is_settled(Pins(pin::ARM)));
    // After k clocks the pin has reached sync1 (1), sync2 (2), filtered (3), previous (4).
    for k in 1..=4 {
        fe.clock(Pins(pin::ARM));
        assert_eq!(fe.is_settled(Pins(pin::ARM)), k == 4, "after {k} clocks");
    }
    // Pins above the six inputs are ignored.
    assert!(fe.is_settled(Pins(pin::ARM | 0xc0)));
    fe.clock(Pins(0xff));
    assert!(!fe.is_settled(Pins(0xff)));
    // A one-clock pulse through a filter of 2 leaves only a filter count behind.
    let mut fe = front_end(2);
    fe.clock(Pins(pin::FES));
    fe.clock(Pins(0));
    fe.clock(Pins(0));
    // sync1, sync2, filtered and previous are 0 again, the FES counter is at 1.
    assert!(!fe.is_settled(Pins(0)));
    let before = fe;
    fe.clock(Pins(0));
    assert_ne!(fe, before, "the counter restarts");
    assert!(fe.is_settled(Pins(0)));
}

#[test]
fn advance_simulates_only_until_settled() {
    let mut fe = front_end(0);
    let mut seen = Vec::new();
    assert_eq!(fe.advance(Pins(0), 100, |k, e| seen.push((k, e))), 0);
    assert_eq!(fe.advance(Pins(pin::ARM), 2, |k, e| seen.push((k, e))), 2);
    assert!(seen.is_empty());
    // Two more clocks reach the kernel (its clock 1 of this call), the third settles.
    assert_eq!(fe.advance(Pins(pin::ARM), 100, |k, e| seen.push((k, e))), 2);
    assert_eq!(
        seen,
        [(
            1,
            Edges {
                changed: pin::ARM,
                levels: pin::ARM
            }
        )]
    );
}

#[test]
fn pulses_through_the_pins_count_and_decide() {
    let mut fe = front_end(0);
    let hold = |fe: &mut FrontEnd, pins: u8, clocks: u64| {
        for _ in 0..clocks {
            fe.clock(Pins(pins));
        }
    };
    let base = pin::ARM | pin::CONTACT;
    hold(&mut fe, base, 5);
    // Three FES pulses of 2 clocks, 2 clocks apart; an index pulse of 6 clocks.
    for _ in 0..3 {
        hold(&mut fe, base | pin::FES, 2);
        hold(&mut fe, base, 2);
    }
    hold(&mut fe, base | pin::INDEX, 6);
    hold(&mut fe, base, 5);
    let o = fe.outputs();
    assert_eq!(
        (o.pulses, o.count, o.last_window_count, o.revolutions),
        (3, 0, 3, 1)
    );
    assert!(o.register_now, "3 contact pulses exceed i_def = 2");
    // A scale step forward then back.
    hold(&mut fe, base | pin::SCALE_A, 5);
    assert_eq!(fe.outputs().position, 1);
    hold(&mut fe, base, 5);
    assert_eq!(fe.outputs().position, 0);
    hold(&mut fe, base | pin::SCALE_B, 5);
    assert_eq!(fe.outputs().position, -1);
}
