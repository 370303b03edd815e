//! Each fault does to the pins what its description says, the same whatever the span it
//! is asked for in, and the default does nothing.

use super::*;
use crate::lathe::{LatheScenario, Motion};
use tooltouch_model::MeasureConfig;

/// A lathe at 6000 rpm and 1 MHz (10 clocks per FES period at 1024 ppr) with `faults`.
fn lathe(faults: LatheFaults) -> crate::lathe::Lathe {
    let mut scenario = LatheScenario {
        clock_hz: 1_000_000,
        rpm: 6000.0,
        faults,
        ..Default::default()
    };
    scenario.cycle.retract_mm_per_s = 1.0;
    scenario.electrics.spike_rate_hz = 0.0;
    crate::lathe::Lathe::new(&scenario, &MeasureConfig::default()).unwrap()
}

/// The pins of clocks `[a, b)` with the arm high and the slide far from the part.
fn pins(l: &crate::lathe::Lathe, a: u64, b: u64) -> Vec<Segment> {
    l.chunk(a, b, &Motion::hold(l.home_um() + 1000.0), true, false)
        .segments
}

/// Rising edges of `bit` in `segments` starting at clock `k_a`, with their clocks.
fn rises(segments: &[Segment], k_a: u64, bit: u8) -> Vec<u64> {
    let mut out = Vec::new();
    let mut k = k_a;
    let mut previous: Option<bool> = None;
    for s in segments {
        let level = s.pins.get(bit);
        if level && previous == Some(false) {
            out.push(k);
        }
        previous = Some(level);
        k += u64::from(s.cycles);
    }
    out
}

fn high_clocks(segments: &[Segment], bit: u8) -> u64 {
    segments
        .iter()
        .filter(|s| s.pins.get(bit))
        .map(|s| u64::from(s.cycles))
        .sum()
}

#[test]
fn no_fault_changes_no_pin() {
    let clean = lathe(LatheFaults::default());
    let segments = pins(&clean, 0, 100_000);
    let ctx = Context {
        spindle: clean.spindle(),
        clock_hz: 1_000_000,
        seed: 1,
        arm_rise: Some(0),
    };
    assert_eq!(
        inject(&LatheFaults::default(), &segments, 0, &ctx),
        segments
    );
}

#[test]
fn lost_fes_pulses_are_missing_at_their_rate_and_doubled_ones_added() {
    let clean = pins(&lathe(LatheFaults::default()), 0, 1_000_000);
    let n_clean = rises(&clean, 0, pin::FES).len() as f64;
    let lost = pins(
        &lathe(LatheFaults {
            fes_lost: 1.0 / 3.0,
            ..Default::default()
        }),
        0,
        1_000_000,
    );
    let n_lost = rises(&lost, 0, pin::FES).len() as f64;
    // 102 400 pulses: a third lost within 1 %.
    assert!(
        (n_lost / n_clean - 2.0 / 3.0).abs() < 0.01,
        "{n_lost} of {n_clean}"
    );
    let doubled = pins(
        &lathe(LatheFaults {
            fes_doubled: 0.1,
            ..Default::default()
        }),
        0,
        1_000_000,
    );
    let n_doubled = rises(&doubled, 0, pin::FES).len() as f64;
    assert!(
        (n_doubled / n_clean - 1.1).abs() < 0.01,
        "{n_doubled} of {n_clean}"
    );
}

#[test]
fn a_lost_index_leaves_the_fes_pulses_and_a_doubled_one_comes_half_a_turn_later() {
    let l = lathe(LatheFaults {
        index_lost: 1.0,
        ..Default::default()
    });
    let p = pins(&l, 0, 100_000);
    assert!(rises(&p, 0, pin::INDEX).is_empty());
    assert_eq!(
        rises(&p, 0, pin::FES),
        rises(
            &pins(&lathe(LatheFaults::default()), 0, 100_000),
            0,
            pin::FES
        )
    );
    let l = lathe(LatheFaults {
        index_doubled: 1.0,
        ..Default::default()
    });
    let r = rises(&pins(&l, 1, 30_000), 1, pin::INDEX);
    // 10 000 clocks per revolution: index at 10 000 and 20 000, doubles at 5 000, 15 000, 25 000.
    assert_eq!(r, [5000, 10_000, 15_000, 20_000, 25_000]);
}

#[test]
fn chips_close_the_contact_for_their_length() {
    let l = lathe(LatheFaults {
        chips: Chips {
            rate_hz: 20.0,
            length_revs: 1.2,
        },
        ..Default::default()
    });
    let p = pins(&l, 0, 10_000_000); // 10 s, 1000 revolutions
    let bursts = rises(&p, 0, pin::CONTACT).len();
    // 20 per second, in slots of 1.2 revolutions (12 ms): p = 1 − e^(−0.24) per slot, 833
    // slots, about 178 bursts (some merge).
    assert!((120..=200).contains(&bursts), "{bursts} bursts");
    let high = high_clocks(&p, pin::CONTACT);
    assert!(
        high >= bursts as u64 * 12_000,
        "each burst 1.2 revolutions long"
    );
}

#[test]
fn a_coolant_bridge_closes_the_contact_from_the_arm() {
    let l = lathe(LatheFaults {
        coolant_bridge: CoolantBridge {
            probability: 1.0,
            length_ms: 5.0,
        },
        ..Default::default()
    });
    let p = pins(&l, 0, 20_000);
    assert!(p[0].pins.get(pin::CONTACT), "closed at the arm");
    assert!(
        !p[0].pins.get(pin::ARM),
        "the arm rises a clock after the bridge"
    );
    assert_eq!(p[0].cycles, 1);
    assert_eq!(high_clocks(&p, pin::CONTACT), 5000);
}

#[test]
fn scale_emi_flips_both_lines_at_once() {
    let l = lathe(LatheFaults {
        emi: Emi {
            scale_hz: 1000.0,
            length_cycles: 8,
            ..Default::default()
        },
        ..Default::default()
    });
    let p = pins(&l, 0, 1_000_000);
    let (a, b) = (rises(&p, 0, pin::SCALE_A), rises(&p, 0, pin::SCALE_B));
    assert!(a.len() > 500, "{} spikes", a.len());
    assert_eq!(
        a, b,
        "both lines together: an illegal quadrature transition"
    );
}

#[test]
fn a_broken_wire_holds_its_line_low_from_the_break() {
    let l = lathe(LatheFaults {
        broken_wire: BrokenWire::Fes,
        broken_after_s: 0.05,
        ..Default::default()
    });
    let p = pins(&l, 0, 100_000);
    assert!(rises(&p, 0, pin::FES).iter().all(|&k| k < 50_000));
    assert!(!rises(&p, 0, pin::FES).is_empty());
}

#[test]
fn a_span_gets_the_same_faults_however_it_is_cut() {
    let f = LatheFaults {
        chips: Chips {
            rate_hz: 50.0,
            length_revs: 0.5,
        },
        fes_lost: 0.2,
        fes_doubled: 0.1,
        index_lost: 0.3,
        emi: Emi {
            contact_hz: 5000.0,
            fes_hz: 3000.0,
            length_cycles: 6,
            ..Default::default()
        },
        ..Default::default()
    };
    let l = lathe(f);
    let whole = pins(&l, 0, 300_000);
    let mut cut = Stimulus::new(1_000_000);
    for (a, b) in [(0, 12_345), (12_345, 150_000), (150_000, 300_000)] {
        for s in pins(&l, a, b) {
            cut.push(s.pins, s.cycles.into());
        }
    }
    assert_eq!(cut.segments, whole);
}

#[test]
fn rates_out_of_range_are_named() {
    let e = LatheFaults {
        fes_lost: 1.5,
        ..Default::default()
    }
    .validate()
    .unwrap_err();
    assert_eq!(e.field, "faults.fes_lost");
    let e = LatheFaults {
        chips: Chips {
            rate_hz: f64::NAN,
            length_revs: 1.0,
        },
        ..Default::default()
    }
    .validate()
    .unwrap_err();
    assert_eq!(e.field, "faults.chips.rate_hz");
}

/// A fast verification lathe (1 MHz, no path loads), 3 measurements, with `faults`; at
/// 4800 rpm, 12.2 clocks per FES period, so that each FES pulse is high for at least 6
/// clocks and passes the default 4-clock glitch filter (at 6000 rpm some are 4 clocks high
/// and the filter drops them: the revolution check sees it).
fn fast_lathe(faults: LatheFaults) -> LatheScenario {
    let mut s = LatheScenario {
        clock_hz: 1_000_000,
        rpm: 4800.0,
        faults,
        spindle_path: crate::lathe::SpindlePath::none(),
        ..Default::default()
    };
    s.cycle.repeats = 3;
    s.cycle.clearance_um = 3.0;
    s.cycle.z_dwell_ms = 0.2;
    s.cycle.retract_mm_per_s = 2.0;
    s
}

/// The model's `faults` word at each fall of the arm over a whole closed-loop run.
fn faults_per_measurement(scenario: &LatheScenario) -> Vec<tooltouch_model::Faults> {
    let config = MeasureConfig::default();
    let run = crate::measurement_cycle::run(scenario, &config, &mut |_| {}).unwrap();
    let mut fe = tooltouch_model::FrontEnd::new(&config);
    let mut words = Vec::new();
    for seg in &run.stimulus.segments {
        for _ in 0..seg.cycles {
            let e = fe.clock(seg.pins);
            if e.changed & pin::ARM != 0 && e.levels & pin::ARM == 0 {
                words.push(tooltouch_model::Faults(fe.outputs().faults));
            }
        }
    }
    words
}

#[test]
fn faulted_measurement_cycles_are_flagged_by_the_model_and_clean_ones_are_not() {
    use tooltouch_model::fault;
    let clean = faults_per_measurement(&fast_lathe(LatheFaults::default()));
    assert_eq!(clean.len(), 3);
    assert!(clean.iter().all(|f| f.is_empty()), "clean: {clean:?}");
    // At 6000 rpm the glitch filter itself loses FES pulses, and the status says so.
    let too_fast = LatheScenario {
        rpm: 6000.0,
        ..fast_lathe(LatheFaults::default())
    };
    let words = faults_per_measurement(&too_fast);
    assert!(
        words.iter().all(|f| f.contains(fault::PULSES_LOST)),
        "{words:?}"
    );
    for (faults, expected) in [
        (
            LatheFaults {
                fes_lost: 1.0 / 3.0,
                ..Default::default()
            },
            fault::PULSES_LOST,
        ),
        (
            LatheFaults {
                index_lost: 1.0,
                ..Default::default()
            },
            fault::INDEX_MISSING,
        ),
        (
            LatheFaults {
                coolant_bridge: CoolantBridge {
                    probability: 1.0,
                    length_ms: 20.0,
                },
                ..Default::default()
            },
            fault::CONTACT_AT_ARM,
        ),
        (
            LatheFaults {
                emi: Emi {
                    scale_hz: 200.0,
                    length_cycles: 20,
                    ..Default::default()
                },
                ..Default::default()
            },
            fault::SCALE_ERROR,
        ),
        (
            LatheFaults {
                broken_wire: BrokenWire::Contact,
                ..Default::default()
            },
            fault::NO_DECISION,
        ),
        (
            LatheFaults {
                broken_wire: BrokenWire::Fes,
                ..Default::default()
            },
            fault::FES_TIMEOUT,
        ),
    ] {
        let words = faults_per_measurement(&fast_lathe(faults));
        assert!(!words.is_empty());
        assert!(
            words.iter().all(|f| f.contains(expected)),
            "{:?}: {words:?}",
            tooltouch_model::Faults(expected)
        );
    }
}
