//! Each fault condition raised by the stream that describes it, and nothing else; the
//! checks never change another output.

extern crate std;
use super::*;
use crate::measure::config::{DecisionMethod, MeasureSettings};
use crate::measure::events::MeasureEvent;
use crate::{FrontEnd, Measurement, Pins};
use proptest::prelude::*;
use std::vec::Vec;

/// 16 pulses per revolution, a decision above 7 contact pulses, every check on with a
/// 1-pulse tolerance, a probe fail after 4 revolutions, a 100-tick FES watchdog and 2
/// confirmation windows at 50 % (8 pulses).
fn settings() -> MeasureSettings {
    MeasureSettings {
        pulses_per_rev: 16,
        i_def: 7,
        glitch_cycles: 0,
        checks: MeasureChecks {
            pulse_tolerance: 1,
            probe_revs: 4,
            fes_timeout_cycles: 100,
            confirm_windows: 2,
            confirm_percent: 50,
            ..MeasureChecks::default()
        },
        ..Default::default()
    }
}

/// A kernel driven with a clock that advances one tick per event.
struct Rig {
    m: Measurement,
    t: u64,
}

impl Rig {
    fn new(s: MeasureSettings) -> Rig {
        Rig {
            m: Measurement::new(&s.validate().unwrap()),
            t: 0,
        }
    }
    fn ev(&mut self, e: MeasureEvent) {
        self.t += 1;
        self.m.apply_at(self.t, e);
    }
    /// One revolution: an index pulse, then `pulses` FES pulses with the contact at
    /// `contact`.
    fn rev(&mut self, pulses: u32, contact: bool) {
        self.ev(MeasureEvent::Index);
        if self.m.outputs().contact != contact {
            self.ev(MeasureEvent::Contact(contact));
        }
        for _ in 0..pulses {
            self.ev(MeasureEvent::Fes);
        }
    }
    fn faults(&self) -> Faults {
        Faults(self.m.outputs_at(self.t).faults)
    }
}

#[test]
fn a_clean_approach_is_confirmed_without_fault() {
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    r.rev(16, false);
    r.rev(16, false);
    r.rev(16, true); // decides at the 8th contact pulse
    assert!(r.m.outputs().register_now);
    assert!(!r.m.outputs().confirmed);
    r.rev(16, true); // closes the deciding window (16 ≥ 8)
    assert!(!r.m.outputs().confirmed);
    r.rev(16, true); // closes the second window: confirmed
    let o = r.m.outputs();
    assert!(o.confirmed);
    assert_eq!(Faults(o.faults), Faults::NONE);
}

#[test]
fn contact_closed_at_arm_is_a_fault() {
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Contact(true));
    r.ev(MeasureEvent::Arm(true));
    assert_eq!(r.faults(), Faults(fault::CONTACT_AT_ARM));
    // A contact rising in the same clock as the arm, after it in canonical order, is not.
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    r.ev(MeasureEvent::Contact(true));
    assert_eq!(r.faults(), Faults::NONE);
    // Cleared at the next arm.
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Contact(true));
    r.ev(MeasureEvent::Arm(true));
    r.ev(MeasureEvent::Arm(false));
    r.ev(MeasureEvent::Contact(false));
    r.ev(MeasureEvent::Arm(true));
    assert_eq!(r.faults(), Faults::NONE);
}

#[test]
fn a_short_revolution_is_pulses_lost_but_the_first_partial_one_is_not() {
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    // Armed mid-revolution: 3 pulses to the first index are fine.
    for _ in 0..3 {
        r.ev(MeasureEvent::Fes);
    }
    r.rev(15, false); // 15 = 16 − 1: inside the tolerance
    r.rev(16, false);
    r.ev(MeasureEvent::Index);
    assert_eq!(r.faults(), Faults::NONE);
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    r.rev(14, false);
    r.ev(MeasureEvent::Index);
    assert_eq!(r.faults(), Faults(fault::PULSES_LOST));
}

#[test]
fn too_many_pulses_without_an_index_is_index_missing_at_the_pulse() {
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    r.rev(17, false); // 16 + 1: inside the tolerance
    assert_eq!(r.faults(), Faults::NONE);
    r.ev(MeasureEvent::Fes); // the 18th
    assert_eq!(r.faults(), Faults(fault::INDEX_MISSING));
    // Folded as one run of pulses: the same.
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    r.ev(MeasureEvent::Index);
    r.m.on_fes_run(18);
    assert_eq!(r.faults(), Faults(fault::INDEX_MISSING));
}

#[test]
fn an_illegal_scale_transition_while_armed_is_a_fault() {
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Scale { a: true, b: true }); // disarmed: counted, no fault
    r.ev(MeasureEvent::Arm(true));
    assert_eq!(r.faults(), Faults::NONE);
    r.ev(MeasureEvent::Scale { a: false, b: false });
    assert_eq!(r.faults(), Faults(fault::SCALE_ERROR));
    assert_eq!(r.m.outputs().scale_errors, 2);
}

#[test]
fn no_decision_after_probe_revs_is_a_probe_fail() {
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    for _ in 0..3 {
        r.rev(16, false);
    }
    assert_eq!(r.faults(), Faults::NONE);
    r.rev(16, false); // the 4th index pulse
    assert_eq!(r.faults(), Faults(fault::NO_DECISION));
}

#[test]
fn the_fes_watchdog_expires_exactly_at_its_timeout() {
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true)); // t = 1
    r.ev(MeasureEvent::Fes); // t = 2
    assert_eq!(Faults(r.m.outputs_at(101).faults), Faults::NONE);
    assert_eq!(
        Faults(r.m.outputs_at(102).faults),
        Faults(fault::FES_TIMEOUT)
    );
    // An FES pulse at exactly the timeout comes too late: latched, and it stays.
    r.m.apply_at(102, MeasureEvent::Fes);
    assert_eq!(
        Faults(r.m.outputs_at(103).faults),
        Faults(fault::FES_TIMEOUT)
    );
    // One tick earlier it is in time.
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    r.ev(MeasureEvent::Fes);
    r.m.apply_at(101, MeasureEvent::Fes);
    assert_eq!(Faults(r.m.outputs_at(200).faults), Faults::NONE);
    // Disarmed, the watchdog stops; the arm's fall sees it expire first.
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true)); // t = 1
    r.m.apply_at(50, MeasureEvent::Arm(false));
    assert_eq!(Faults(r.m.outputs_at(10_000).faults), Faults::NONE);
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true)); // t = 1
    r.m.apply_at(101, MeasureEvent::Arm(false));
    assert_eq!(
        Faults(r.m.outputs_at(10_000).faults),
        Faults(fault::FES_TIMEOUT)
    );
}

#[test]
fn a_decision_the_contact_falls_back_from_is_unconfirmed() {
    // A chip: 9 contact pulses decide, then the tool is in the air again.
    let mut r = Rig::new(settings());
    r.ev(MeasureEvent::Arm(true));
    r.rev(16, false);
    r.ev(MeasureEvent::Index);
    r.ev(MeasureEvent::Contact(true));
    for _ in 0..9 {
        r.ev(MeasureEvent::Fes);
    }
    r.ev(MeasureEvent::Contact(false));
    for _ in 0..7 {
        r.ev(MeasureEvent::Fes);
    }
    assert!(r.m.outputs().register_now);
    r.rev(16, false); // the deciding window closes with 9 ≥ 8: fine
    assert_eq!(r.faults(), Faults::NONE);
    r.ev(MeasureEvent::Index); // the next closes with 0
    let o = r.m.outputs();
    assert_eq!(Faults(o.faults), Faults(fault::UNCONFIRMED));
    assert!(!o.confirmed);
    assert!(o.register_now, "register now is not withheld");
}

#[test]
fn a_single_pulse_decision_is_confirmed_by_any_contact_per_window() {
    let s = MeasureSettings {
        method: DecisionMethod::SinglePulse,
        ..settings()
    };
    let mut r = Rig::new(s);
    r.ev(MeasureEvent::Arm(true));
    r.rev(16, false);
    r.ev(MeasureEvent::Index);
    r.ev(MeasureEvent::Contact(true)); // decides
    r.ev(MeasureEvent::Fes);
    r.ev(MeasureEvent::Contact(false));
    for _ in 0..15 {
        r.ev(MeasureEvent::Fes);
    }
    r.rev(1, true); // closes the deciding window (1 contact pulse)
    r.ev(MeasureEvent::Contact(false));
    for _ in 0..15 {
        r.ev(MeasureEvent::Fes);
    }
    r.ev(MeasureEvent::Index); // closes the second (1 contact pulse)
    let o = r.m.outputs();
    assert!(o.confirmed);
    assert_eq!(Faults(o.faults), Faults::NONE);
}

#[test]
fn disabled_checks_never_raise() {
    let s = MeasureSettings {
        checks: MeasureChecks::OFF,
        ..settings()
    };
    let mut r = Rig::new(s);
    r.ev(MeasureEvent::Contact(true));
    r.ev(MeasureEvent::Arm(true));
    r.ev(MeasureEvent::Scale { a: true, b: true });
    r.rev(40, true);
    r.rev(3, false);
    r.ev(MeasureEvent::Index);
    assert_eq!(Faults(r.m.outputs_at(1 << 40).faults), Faults::NONE);
    assert!(r.m.outputs().confirmed, "confirmed at the decision");
}

#[test]
fn faults_display_their_names() {
    assert_eq!(std::format!("{}", Faults::NONE), "none");
    let f = Faults(fault::PULSES_LOST | fault::NO_DECISION);
    assert_eq!(std::format!("{f}"), "pulses_lost+no_decision");
    assert_eq!(Faults::bit_named("fes_timeout"), Some(fault::FES_TIMEOUT));
    assert_eq!(Faults::bit_named("nothing"), None);
}

#[test]
fn the_cycle_level_watchdog_counts_clocks_and_survives_fast_forward() {
    let s = MeasureSettings {
        checks: MeasureChecks {
            fes_timeout_cycles: 1000,
            ..settings().checks
        },
        ..settings()
    };
    let config = s.validate().unwrap();
    let arm = Pins(crate::measure::frontend::pin::ARM);
    let mut plain = FrontEnd::new(&config);
    let mut fast = plain;
    let mut expired_at = None;
    for k in 0..2000u64 {
        plain.clock(arm);
        if expired_at.is_none() && plain.outputs().faults & fault::FES_TIMEOUT != 0 {
            expired_at = Some(k);
        }
    }
    // The arm sampled at clock 0 is applied at clock `latency` (0-based): the watchdog
    // expires 1000 clocks later.
    let arm_clock = u64::from(config.latency_cycles());
    assert_eq!(expired_at, Some(arm_clock + 1000));
    fast.advance(arm, 2000, |_, _| {});
    assert_eq!(fast, plain);
    assert_eq!(fast.outputs(), plain.outputs());
}

/// A random event stream over the 16-pulse configuration.
fn events() -> impl Strategy<Value = Vec<(u64, MeasureEvent)>> {
    let event = prop_oneof![
        any::<bool>().prop_map(MeasureEvent::Arm),
        any::<bool>().prop_map(MeasureEvent::Contact),
        Just(MeasureEvent::Index),
        Just(MeasureEvent::Fes),
        Just(MeasureEvent::Fes),
        Just(MeasureEvent::Fes),
        (any::<bool>(), any::<bool>()).prop_map(|(a, b)| MeasureEvent::Scale { a, b }),
    ];
    proptest::collection::vec((0u64..60, event), 0..400)
}

proptest! {
    /// The checks add outputs and change none: every other output equals the kernel's
    /// with every check off, event by event.
    #[test]
    fn the_checks_change_no_other_output(stream in events(), checks in crate::testing::measure_checks()) {
        let on = MeasureSettings { checks: MeasureChecks { pulse_tolerance: checks.pulse_tolerance.min(4), ..checks }, ..settings() };
        let off = MeasureSettings { checks: MeasureChecks::OFF, ..settings() };
        let mut a = Measurement::new(&on.validate().unwrap());
        let mut b = Measurement::new(&off.validate().unwrap());
        let mut t = 0;
        for (dt, e) in stream {
            t += dt;
            a.apply_at(t, e);
            b.apply_at(t, e);
            let (mut oa, ob) = (a.outputs(), b.outputs());
            prop_assert_eq!(ob.faults, 0);
            oa.faults = 0;
            oa.confirmed = ob.confirmed;
            prop_assert_eq!(oa, ob);
        }
    }

    /// A run of `n` FES pulses folded at once leaves the checks as `n` single pulses do.
    #[test]
    fn a_folded_run_equals_single_pulses(prefix in events(), n in 0u32..80, contact in any::<bool>()) {
        let config = settings().validate().unwrap();
        let mut a = Measurement::new(&config);
        let mut t = 0;
        for (dt, e) in prefix {
            t += dt;
            a.apply_at(t, e);
        }
        a.apply_at(t, MeasureEvent::Contact(contact));
        let mut b = a;
        a.on_fes_run(n);
        for _ in 0..n {
            b.on_fes();
        }
        prop_assert_eq!(a.outputs(), b.outputs());
        prop_assert_eq!(a.checks(), b.checks());
    }
}

proptest! {
    /// The predictions the firmware and the host schedule themselves by: the watchdog's
    /// deadline is the first time the outputs show `fes_timeout`, and `index_missing`
    /// rises on exactly the predicted pulse.
    #[test]
    fn the_deadline_and_the_pulses_to_index_missing_are_exact(prefix in events()) {
        let config = settings().validate().unwrap();
        let mut m = Measurement::new(&config);
        let mut t = 0;
        for (dt, e) in prefix {
            t += dt;
            m.apply_at(t, e);
        }
        let shown = |m: &Measurement, at: u64| m.outputs_at(at).faults & fault::FES_TIMEOUT != 0;
        match m.fes_deadline() {
            Some(d) if !shown(&m, t) => {
                prop_assert!(d > t);
                prop_assert!(!shown(&m, d - 1));
                prop_assert!(shown(&m, d));
            }
            Some(_) => {}
            None => prop_assert!(!shown(&m, t + 1_000_000) || shown(&m, t)),
        }
        if let Some(k) = m.fes_to_index_missing() {
            let mut a = m;
            for i in 1..=k {
                prop_assert_eq!(a.outputs().faults & fault::INDEX_MISSING, 0);
                a.on_fes();
                let raised = a.outputs().faults & fault::INDEX_MISSING != 0;
                prop_assert_eq!(raised, i == k, "pulse {} of {}", i, k);
            }
        } else {
            let mut a = m;
            let before = a.outputs().faults & fault::INDEX_MISSING;
            for _ in 0..40 {
                a.on_fes();
            }
            prop_assert_eq!(a.outputs().faults & fault::INDEX_MISSING, before);
        }
    }
}
