//! The measurement status on a clean machine (issue 39): no false alarm, and the
//! decisions unchanged.
//!
//! - Over more than 1 000 clean measurements — the defaults, `examples/rig1.toml`,
//!   `examples/rig2.toml` and the fast verification lathe (docs/quickstart.md), across
//!   seeds, spindle speeds and feeds, retracting at permanent contact and at the decision —
//!   no fault at all and every decision confirmed and accepted (about 20 s in release on
//!   two cores).
//! - The decision cycles and positions of the clean runs are those of the model before the
//!   checks, bit for bit: the numbers below were recorded with `tooltouch measure` on main
//!   before the status (2490389). The status moves only the retract (the CNC waits for the
//!   confirmation), so with `retract_at = "permanent-contact"` (the default) every
//!   measurement decides where it did; with `"decision"` the tool now waits at the feed
//!   stop for the confirmation, so later measurements start at other spindle phases: the
//!   first decides where it did, and with every check off (`MeasureChecks::OFF`) the whole
//!   run, feed stops included, is main's.

use std::time::Instant;
use tooltouch_model::{MeasureChecks, MeasureConfig, MeasureSettings};
use tooltouch_plant::lathe::{LatheScenario, RetractAt};
use tooltouch_plant::measurement_cycle::{self, CycleRun};
use tooltouch_settings::Settings;

fn preset(name: &str) -> (MeasureConfig, LatheScenario) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name);
    Settings::load(&path).unwrap().resolve().unwrap()
}

fn defaults() -> (MeasureConfig, LatheScenario) {
    Settings::default().resolve().unwrap()
}

fn run(config: &MeasureConfig, s: &LatheScenario) -> CycleRun {
    measurement_cycle::run(s, config, &mut |_| {}).unwrap()
}

fn with(
    base: &LatheScenario,
    seed: u64,
    rpm: f64,
    feed: f64,
    repeats: u32,
    at: RetractAt,
) -> LatheScenario {
    let mut s = base.clone();
    s.seed = seed;
    s.rpm = rpm;
    s.feed_mm_per_rev = feed;
    s.cycle.repeats = repeats;
    s.cycle.retract_at = at;
    s
}

#[test]
fn a_thousand_clean_measurements_raise_no_fault_and_every_decision_is_confirmed() {
    let started = Instant::now();
    use RetractAt::{Decision, PermanentContact as Permanent};
    let mut runs: Vec<(&str, MeasureConfig, LatheScenario)> = Vec::new();
    let (c, d) = defaults();
    for seed in 1..=4 {
        for (rpm, feed) in [
            (600.0, 0.001),
            (800.0, 0.001),
            (1000.0, 0.001),
            (800.0, 0.002),
        ] {
            runs.push(("defaults", c, with(&d, seed, rpm, feed, 20, Permanent)));
        }
        runs.push(("defaults", c, with(&d, seed, 800.0, 0.001, 20, Decision)));
    }
    for name in ["rig1.toml", "rig2.toml"] {
        let (c, r) = preset(name);
        for seed in 1..=3 {
            for (rpm, feed) in [(600.0, 0.001), (1000.0, 0.0015), (800.0, 0.0005)] {
                runs.push((name, c, with(&r, seed, rpm, feed, 20, Permanent)));
            }
            runs.push((name, c, with(&r, seed, 800.0, 0.001, 20, Decision)));
        }
    }
    let (c, f) = super::status::fast_lathe();
    for seed in 1..=4 {
        for (rpm, feed) in [(2400.0, 0.001), (3600.0, 0.002), (4800.0, 0.001)] {
            runs.push(("fast lathe", c, with(&f, seed, rpm, feed, 10, Permanent)));
        }
        runs.push(("fast lathe", c, with(&f, seed, 4800.0, 0.001, 10, Decision)));
    }
    let measurements: u32 = runs.iter().map(|r| r.2.cycle.repeats).sum();
    assert!(measurements >= 1000, "{measurements}");

    // Two threads, each taking every other run.
    let failures: Vec<String> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..2)
            .map(|w| {
                let runs = &runs;
                scope.spawn(move || {
                    let mut failures = Vec::new();
                    for (name, config, s) in runs.iter().skip(w).step_by(2) {
                        let r = run(config, s);
                        for m in &r.measurements {
                            if m.faults != 0 || !m.confirmed || !m.accepted {
                                failures.push(format!(
                                    "{name} seed {} {} rpm feed {} {:?}: measurement {}: faults {:?}, confirmed {}",
                                    s.seed, s.rpm, s.feed_mm_per_rev, s.cycle.retract_at,
                                    m.index, m.fault_names, m.confirmed
                                ));
                            }
                        }
                        if r.summary.faulted != 0 || r.summary.decided != r.summary.measurements {
                            failures.push(format!("{name}: {:?}", r.summary));
                        }
                    }
                    failures
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    eprintln!(
        "{measurements} clean measurements in {} runs: {} not accepted, {:.1} s",
        runs.len(),
        failures.len(),
        started.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Each measurement's `(decision cycle, decision position)`.
fn decisions(r: &CycleRun) -> Vec<(u64, i64)> {
    r.measurements
        .iter()
        .map(|m| (m.decision_cycle.unwrap(), m.decision_position.unwrap()))
        .collect()
}

// Recorded on main (2490389) with `tooltouch measure`: decision_cycle, decision_position.
const DEFAULTS: [(u64, i64); 10] = [
    (51738288, -128),
    (111049812, -126),
    (175444343, -128),
    (234704597, -126),
    (294671638, -126),
    (355898445, -119),
    (423416755, -129),
    (486818855, -128),
    (546811530, -128),
    (606892097, -128),
];
const RIG1: [(u64, i64); 20] = [
    (59989021, -150),
    (141093757, -156),
    (217313239, -150),
    (295759284, -149),
    (374831550, -150),
    (455983894, -156),
    (534865730, -156),
    (611041267, -149),
    (689776618, -149),
    (770994880, -156),
    (849843757, -156),
    (929274909, -158),
    (1008065193, -158),
    (1086086433, -156),
    (1164821784, -156),
    (1247244880, -156),
    (1326079109, -156),
    (1408480232, -156),
    (1487336433, -156),
    (1563746345, -150),
];
const RIG2: [(u64, i64); 20] = [
    (47865241, -150),
    (107797859, -139),
    (170402351, -148),
    (235500007, -155),
    (298995124, -147),
    (364502937, -155),
    (428718757, -149),
    (493710945, -156),
    (550959968, -147),
    (616500007, -155),
    (679998054, -147),
    (745500007, -155),
    (808842780, -156),
    (874669929, -156),
    (931954109, -147),
    (997500007, -155),
    (1060974616, -147),
    (1126500007, -155),
    (1189971687, -147),
    (1255500007, -155),
];
/// The fast lathe, 10 measurements.
const FAST: [(u64, i64); 10] = [
    (61714, -39),
    (169538, -46),
    (261823, -39),
    (369550, -46),
    (461921, -40),
    (569721, -46),
    (661689, -39),
    (770002, -46),
    (860700, -39),
    (962446, -40),
];
/// The defaults retracting at the decision: decisions and feed stops.
const DEFAULTS_AT_DECISION: [(u64, i64, u64); 10] = [
    (51738288, -128, 51763289),
    (104337165, -128, 104362166),
    (153632820, -120, 153657821),
    (205708015, -129, 205733016),
    (254622810, -119, 254647811),
    (306947028, -129, 306972029),
    (355920417, -119, 355945418),
    (408156745, -128, 408181746),
    (457133796, -119, 457158797),
    (509329841, -128, 509354842),
];
/// The first decisions retracting at the decision: rig1, rig2, the fast lathe.
const FIRST_AT_DECISION: [(u64, i64); 3] = [(59989021, -150), (47865241, -150), (61714, -39)];

#[test]
fn clean_decisions_are_mains_bit_for_bit() {
    let (c, d) = defaults();
    let (c1, r1) = preset("rig1.toml");
    let (c2, r2) = preset("rig2.toml");
    let (cf, mut f) = super::status::fast_lathe();
    f.cycle.repeats = 10;
    assert_eq!(decisions(&run(&c, &d)), DEFAULTS);
    assert_eq!(decisions(&run(&c1, &r1)), RIG1);
    assert_eq!(decisions(&run(&c2, &r2)), RIG2);
    assert_eq!(decisions(&run(&cf, &f)), FAST);

    let at_decision = |s: &LatheScenario, repeats: u32| {
        let mut s = s.clone();
        s.cycle.retract_at = RetractAt::Decision;
        s.cycle.repeats = repeats;
        s
    };
    for ((config, s), first) in [(&c1, &r1), (&c2, &r2), (&cf, &f)]
        .into_iter()
        .zip(FIRST_AT_DECISION)
    {
        let r = run(config, &at_decision(s, 1));
        assert_eq!(decisions(&r), [first]);
        let m = &r.measurements[0];
        // The tool waited at the feed stop for the confirmation.
        assert!(m.retract_cycle > m.stop_cycle && m.confirmed_cycle.unwrap() < m.retract_cycle);
    }
    let off = MeasureSettings {
        checks: MeasureChecks::OFF,
        ..MeasureSettings::default()
    }
    .validate()
    .unwrap();
    let r = run(&off, &at_decision(&d, 10));
    let with_stops: Vec<(u64, i64, u64)> = r
        .measurements
        .iter()
        .map(|m| {
            (
                m.decision_cycle.unwrap(),
                m.decision_position.unwrap(),
                m.stop_cycle,
            )
        })
        .collect();
    assert_eq!(with_stops, DEFAULTS_AT_DECISION);
    assert!(r
        .measurements
        .iter()
        .all(|m| m.retract_cycle == m.stop_cycle));
}
