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

/// `config` with every check off: the kernel before the status.
fn without_checks(config: &MeasureConfig) -> MeasureConfig {
    MeasureSettings {
        checks: MeasureChecks::OFF,
        ..*config.settings()
    }
    .validate()
    .unwrap()
}

/// The status changes no clean decision: the decision clocks and positions of the
/// defaults, rig1, rig2 and the fast lathe (retracting at permanent contact) equal, bit for
/// bit, those of the same runs with every check off (the kernel before the status); with
/// the retract at the decision, the first decision of each and every decision with the
/// checks off (where the CNC then retracts at the decision's reaction as before).
#[test]
fn clean_decisions_are_those_without_the_checks_bit_for_bit() {
    let (c, d) = defaults();
    let (c1, r1) = preset("rig1.toml");
    let (c2, r2) = preset("rig2.toml");
    let (cf, mut f) = super::status::fast_lathe();
    f.cycle.repeats = 10;
    for (config, s) in [(&c, &d), (&c1, &r1), (&c2, &r2), (&cf, &f)] {
        let with = decisions(&run(config, s));
        assert_eq!(with.len(), s.cycle.repeats as usize);
        assert_eq!(with, decisions(&run(&without_checks(config), s)));
    }
    let at_decision = |s: &LatheScenario, repeats: u32| {
        let mut s = s.clone();
        s.cycle.retract_at = RetractAt::Decision;
        s.cycle.repeats = repeats;
        s
    };
    for (config, s) in [(&c1, &r1), (&c2, &r2), (&cf, &f)] {
        let r = run(config, &at_decision(s, 1));
        let off = run(&without_checks(config), &at_decision(s, 1));
        assert_eq!(decisions(&r), decisions(&off));
        let m = &r.measurements[0];
        // The tool waited at the feed stop for the confirmation.
        assert!(m.retract_cycle > m.stop_cycle && m.confirmed_cycle.unwrap() < m.retract_cycle);
    }
    let r = run(&without_checks(&c), &at_decision(&d, 10));
    let reaction = (d.cycle.cnc_reaction_us * 50.0) as u64;
    assert!(r
        .measurements
        .iter()
        .all(|m| m.retract_cycle == m.stop_cycle
            && m.stop_cycle == m.decision_cycle.unwrap() + reaction + 1));
}
