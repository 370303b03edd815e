//! The cycle level and the event level agree (docs/architecture.md, "one logic, three timings"):
//! the events extracted from a cycle-level run of a closed-loop lathe scenario, replayed at
//! event level, give the same outputs — counts, charges, latched positions, decisions —
//! after the last event of every clock; and the latched positions are the scale count
//! the kernel held when the decision was taken.
//!
//! Random configurations and random lathe scenarios, at low clock rates so FES, index,
//! arm, contact and scale edges often land on the same clock. Case count: TOOLTOUCH_CASES
//! (default 24).

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use tooltouch_model::measure::config::MeasureSettings;
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::{testing, MeasureConfig, MeasureOutputs};
use tooltouch_plant::lathe::{CycleSettings, Harmonic, LatheScenario, RetractAt, SlowHarmonic};
use tooltouch_plant::measurement_cycle;
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_vectors::{
    clock_every_cycle, clock_through, events_from_stimulus, outputs_after_each_event,
};

/// Random configurations: the model's test kit, levels profile.
fn settings() -> impl Strategy<Value = MeasureSettings> {
    testing::measure_settings(&testing::MeasureProfile::LEVELS)
}

/// A small, fast lathe: 1–2 MHz clock, 8–40 clocks per FES period, a few revolutions per
/// approach, errors of every kind switched on at random.
fn scenario(config: &MeasureConfig) -> impl Strategy<Value = LatheScenario> {
    let ppr = f64::from(config.pulses_per_rev());
    let glitch = f64::from(config.settings().glitch_cycles);
    (
        (
            prop_oneof![Just(1_000_000u32), Just(2_000_000u32)],
            8.0f64..40.0,
            0.3f64..3.0,
        ),
        (
            0.5f64..4.0,
            0.0f64..1.0,
            0.0f64..0.3,
            0.0f64..1.0,
            any::<u64>(),
        ),
        (
            0u32..4,
            0.0f64..30.0,
            0.0f64..20_000.0,
            any::<bool>(),
            1u32..3,
        ),
    )
        .prop_map(
            move |(
                (clock_hz, fes_cycles, feed_um),
                (profile_um, slow_um, random_um, mismatch, seed),
                (bounce, quiet_us, spikes, at_decision, repeats),
            )| {
                let rpm = f64::from(clock_hz) * 60.0 / (ppr * fes_cycles);
                // Retract at half the fastest speed the scenario allows.
                let retract = 0.1e-3 * f64::from(clock_hz) / (4.0 * (glitch + 2.0)) / 2.0;
                LatheScenario {
                    clock_hz,
                    rpm,
                    diameter_mm: 10.0,
                    feed_mm_per_rev: feed_um * 1e-3,
                    scale_resolution_um: 0.1,
                    profile: vec![
                        Harmonic {
                            order: 2,
                            amplitude_um: profile_um,
                            phase_rad: 0.3,
                        },
                        Harmonic {
                            order: 3,
                            amplitude_um: profile_um / 2.0,
                            phase_rad: 1.0,
                        },
                    ],
                    repeating: vec![Harmonic {
                        order: 1,
                        amplitude_um: 0.5,
                        phase_rad: 0.0,
                    }],
                    repeating_mismatch: mismatch,
                    // The levels' agreement, not the path: no loads, so the
                    // clearance below clears the surface.
                    spindle_path: tooltouch_plant::lathe::SpindlePath::none(),
                    faults: Default::default(),
                    slow: vec![SlowHarmonic {
                        amplitude_um: slow_um,
                        period_revs: 2.3,
                        phase_rad: 0.0,
                        amplitude_jitter: 0.5,
                        period_scatter: 0.0,
                    }],
                    random_um,
                    electrics: tooltouch_plant::lathe::ContactElectrics {
                        bounce_pulses: bounce,
                        bounce_on_us: 20.0,
                        bounce_off_us: 15.0,
                        non_conduction_us: quiet_us,
                        spike_rate_hz: spikes,
                        spike_max_cycles: 8,
                    },
                    cycle: CycleSettings {
                        repeats,
                        clearance_um: profile_um * 2.0 + 1.0,
                        retract_mm_per_s: retract,
                        z_step_mm: 1.0,
                        nose_radius_mm: 0.4,
                        z_dwell_ms: 2.0,
                        cnc_reaction_us: 50.0,
                        retract_at: if at_decision {
                            RetractAt::Decision
                        } else {
                            RetractAt::PermanentContact
                        },
                        max_approach_revs: 40,
                        averages_per_z: 1,
                    },
                    seed,
                }
            },
        )
}

fn config_and_scenario() -> impl Strategy<Value = (MeasureConfig, LatheScenario)> {
    settings().prop_flat_map(|s| {
        let c = s.validate().expect("the strategy builds valid settings");
        scenario(&c).prop_map(move |sc| (c, sc))
    })
}

/// Cycle-level outputs after every clock at which the kernel received an event (falling
/// edges of FES and index are edges but no events).
fn cycle_outputs(stimulus: &Stimulus, config: &MeasureConfig) -> Vec<(u64, MeasureOutputs)> {
    let mut out = Vec::new();
    clock_through(stimulus, config, |k, _, fe, edges| {
        let mut events = 0;
        edges.for_each_event(|_| events += 1);
        if events > 0 {
            out.push((k, fe.outputs()));
        }
    });
    out
}

/// Scale count (relative to power-on, lines 00) from the stimulus pins sampled at clocks
/// `0..=k`.
fn scale_count_at(stimulus: &Stimulus, k: u64) -> i64 {
    let phase = |p: tooltouch_model::Pins| match (p.get(pin::SCALE_A), p.get(pin::SCALE_B)) {
        (false, false) => 0i64,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    };
    let mut count = 0i64;
    let mut last = 0i64;
    let mut clock = 0u64;
    for s in &stimulus.segments {
        if clock > k {
            break;
        }
        let p = phase(s.pins);
        match (p - last).rem_euclid(4) {
            1 => count += 1,
            3 => count -= 1,
            0 => {}
            _ => panic!("double scale change at clock {clock}"),
        }
        last = p;
        clock += u64::from(s.cycles);
    }
    count
}

fn wrap(count: i64, bits: u8) -> i32 {
    let shift = 64 - u32::from(bits);
    ((count << shift) >> shift) as i32
}

proptest! {
    #![proptest_config(ProptestConfig { cases: testing::cases(24), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn event_replay_matches_the_cycle_level((config, scenario) in config_and_scenario()) {
        let run = measurement_cycle::run(&scenario, &config, &mut |_| {}).unwrap();
        let events = events_from_stimulus(&run.stimulus, &config);
        prop_assert!(!events.is_empty());
        let replay = outputs_after_each_event(&events, &config);
        let cycle = cycle_outputs(&run.stimulus, &config);
        // After the last event of each clock, the event level equals the cycle level.
        let mut last_of_clock: Vec<(u64, MeasureOutputs)> = Vec::new();
        for (t, o) in replay {
            match last_of_clock.last_mut() {
                Some(l) if l.0 == t => l.1 = o,
                _ => last_of_clock.push((t, o)),
            }
        }
        prop_assert_eq!(last_of_clock.len(), cycle.len());
        for (a, b) in last_of_clock.iter().zip(&cycle) {
            prop_assert_eq!(a, b, "clock {}", b.0);
        }
    }

    #[test]
    fn latched_positions_are_the_scale_count_latency_earlier((config, scenario) in config_and_scenario()) {
        let run = measurement_cycle::run(&scenario, &config, &mut |_| {}).unwrap();
        let latency = u64::from(config.latency_cycles());
        let bits = config.settings().scale_bits;
        for m in &run.measurements {
            // The kernel applies edges sampled `latency` clocks earlier, FES/contact before
            // scale: it holds the count sampled up to `latency + 1` clocks earlier.
            if let (Some(k), Some(p)) = (m.decision_cycle, m.decision_position) {
                let expected = scale_count_at(&run.stimulus, k - latency - 1);
                prop_assert_eq!(wrap(p, bits), wrap(expected, bits), "decision at clock {}", k);
                prop_assert_eq!(p, expected);
            }
            if let (Some(k), Some(p)) = (m.first_contact_cycle, m.first_contact_position) {
                prop_assert_eq!(p, scale_count_at(&run.stimulus, k - latency - 1), "first contact at clock {}", k);
            }
        }
    }
}

/// Skipping settled clocks is exact: the outputs after every clock of a whole closed-loop
/// run, clocked one by one, equal those of the skipping run wherever it clocked, and never
/// change at a skipped clock.
#[test]
fn settled_skipping_is_exact() {
    let config = MeasureSettings {
        pulses_per_rev: 64,
        i_def: 32,
        glitch_cycles: 3,
        ..Default::default()
    }
    .validate()
    .unwrap();
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let scenario = scenario(&config).new_tree(&mut runner).unwrap().current();
    let run = measurement_cycle::run(&scenario, &config, &mut |_| {}).unwrap();
    let skipping = cycle_outputs(&run.stimulus, &config);
    let reset = tooltouch_model::FrontEnd::new(&config).outputs();
    let mut every = Vec::new();
    let mut previous = reset;
    clock_every_cycle(&run.stimulus, &config, |k, fe, _| {
        let o = fe.outputs();
        if o != previous {
            every.push((k, o));
            previous = o;
        }
    });
    let mut changed = Vec::new();
    let mut previous = reset;
    for &(k, o) in &skipping {
        if o != previous {
            changed.push((k, o));
            previous = o;
        }
    }
    assert!(
        every.len() > 100,
        "a real run: {} output changes",
        every.len()
    );
    let first_difference = every.iter().zip(&changed).position(|(a, b)| a != b);
    assert_eq!(first_difference, None, "clock by clock vs skipping");
    assert_eq!(every.len(), changed.len());
}

/// The random scenarios do exercise same-clock edges: index with FES (always), arm with
/// index, and scale edges in the same clock as another event.
#[test]
fn scenarios_make_same_clock_edges() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut with_scale = 0;
    let mut with_arm = 0;
    for _ in 0..8 {
        let (config, scenario) = config_and_scenario()
            .new_tree(&mut runner)
            .unwrap()
            .current();
        let run = measurement_cycle::run(&scenario, &config, &mut |_| {}).unwrap();
        let events = events_from_stimulus(&run.stimulus, &config);
        for w in events.windows(2) {
            if w[0].time == w[1].time {
                use tooltouch_model::MeasureEvent as E;
                match (w[0].event, w[1].event) {
                    (_, E::Scale { .. }) => with_scale += 1,
                    (E::Arm(_), _) => with_arm += 1,
                    _ => {}
                }
            }
        }
    }
    assert!(with_scale > 0, "scale edges sharing a clock: {with_scale}");
    assert!(with_arm > 0, "arm edges sharing a clock: {with_arm}");
}
