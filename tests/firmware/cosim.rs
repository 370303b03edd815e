//! The RTIC firmware under QEMU agrees with the event-level golden model on every output
//! of every event: proptest-generated scenarios (random configuration, spindle speed,
//! workpiece form, contact growth, faults; and on the force path a random force
//! configuration — PI, adaptive or fuzzy — sent in the stream's chunk records, with the
//! ADC stream of the spindle-drive plant closed around the golden kernel) batched into one
//! QEMU boot per test.
//!
//! Needs qemu-system-arm and the thumbv7m-none-eabi target: without them the tests fail
//! with a message naming `cargo xtask setup`.

use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, TestRunner};
use std::path::PathBuf;
use std::sync::OnceLock;
use tooltouch_firmware_runner::{
    self as cosim, trace::EVENT_KIND_NAMES, Case, CosimError, Fault, Observe,
};
use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::wire::force_chunks::{
    force_config_chunk, force_config_chunks, FORCE_CHUNK_DATA,
};
use tooltouch_model::wire::{self, kind, Record, Records, MAX_PAYLOAD, RECORD_HEADER_LEN};
use tooltouch_model::MeasureEvent;

/// Builds the QEMU firmware once per test binary.
fn image() -> PathBuf {
    static IMAGE: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    IMAGE
        .get_or_init(|| cosim::qemu::build_firmware().map_err(|e| e.to_string()))
        .clone()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Cases per batch: 32, or TOOLTOUCH_CASES.
pub(crate) fn case_count() -> usize {
    tooltouch_model::testing::cases(32) as usize
}

/// proptest draws the seeds; each seed fixes a whole scenario (reproduce a failure from
/// the seed printed in the case name).
pub(crate) fn proptest_seeds(n: usize, name: &str) -> Vec<u64> {
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        proptest::test_runner::TestRng::from_seed(
            proptest::test_runner::RngAlgorithm::ChaCha,
            &seed_bytes(name),
        ),
    );
    (0..n)
        .map(|_| {
            proptest::num::u64::ANY
                .new_tree(&mut runner)
                .map(|t| t.current())
                .unwrap_or(0)
        })
        .collect()
}

/// A fixed per-test seed (so CI runs are repeatable), or TOOLTOUCH_SEED to explore.
fn seed_bytes(name: &str) -> [u8; 32] {
    let extra: u64 = std::env::var("TOOLTOUCH_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let mut out = [0u8; 32];
    for (i, b) in name.bytes().chain(extra.to_le_bytes()).enumerate() {
        out[i % 32] ^= b;
    }
    out
}

fn run(cases: &[Case]) -> cosim::Report {
    match cosim::run_batch(&image(), cases) {
        Ok(report) => report,
        Err(e) => panic!("{e}"),
    }
}

/// Runs `cases` with outputs records after every event but FES pulses: the firmware
/// folds runs of pulses as on a board; every output of every other event is compared.
fn run_folding(cases: &[Case]) -> cosim::Report {
    match cosim::run_batch_observing(&image(), cases, Observe::SkipFes) {
        Ok(report) => report,
        Err(e) => panic!("folding FES runs: {e}"),
    }
}

/// FES pulses in `cases`.
fn fes_pulses(cases: &[Case]) -> u64 {
    cases
        .iter()
        .flat_map(|c| &c.events)
        .filter(|e| e.event == MeasureEvent::Fes)
        .count() as u64
}

/// The FES path's cost per pulse when runs are folded: the compare interrupts, and the
/// whole measurement load (every measurement task, the folds they do included) spread
/// over the pulses, in instructions and interrupts (QEMU counts no cycles for the
/// exception entry and exit: docs/firmware.md converts these to Cortex-M4 cycles).
fn print_fes_cost(cases: &[Case], r: &cosim::Report) {
    let pulses = fes_pulses(cases).max(1) as f64;
    let interrupts =
        |k: usize| -> u64 { r.profiles.iter().map(|p| u64::from(p.per_kind[k].0)).sum() };
    let compares = interrupts(3);
    let per_compare = r.instructions_per_event(3).unwrap_or(0.0);
    let (mut all_interrupts, mut all_instructions) = (0u64, 0f64);
    for k in 0..5 {
        all_interrupts += interrupts(k);
        all_instructions += r.instructions_per_event(k).unwrap_or(0.0) * interrupts(k) as f64;
    }
    eprintln!(
        "  FES: {pulses} pulses, {compares} compare interrupts (one per {:.1} pulses), \
         {per_compare:.1} instructions each = {:.2} instructions per pulse",
        pulses / compares.max(1) as f64,
        per_compare * compares as f64 / pulses
    );
    let costliest = r
        .profiles
        .iter()
        .filter_map(|p| p.instructions_per_event(3))
        .fold(0.0, f64::max);
    eprintln!("  costliest case: {costliest:.1} instructions per compare interrupt");
    eprintln!(
        "  all measurement tasks: {:.4} interrupts and {:.2} instructions per FES pulse",
        all_interrupts as f64 / pulses,
        all_instructions / pulses
    );
}

pub(crate) fn print_report(what: &str, r: &cosim::Report) {
    eprintln!(
        "{what}: {} cases, {} events in {:.2} s of QEMU = {:.0} events/s; stack {} bytes",
        r.cases,
        r.events,
        r.qemu_time.as_secs_f64(),
        r.events_per_second(),
        r.stack_bytes()
    );
    if let Some(p) = r.profiles.first() {
        eprintln!(
            "  SysTick calibration: {} instructions in {} ticks ({:.2} instructions per tick)",
            p.calibration_instructions,
            p.calibration_ticks,
            p.instructions_per_tick()
        );
    }
    for (k, name) in EVENT_KIND_NAMES.iter().enumerate() {
        if let Some(i) = r.instructions_per_event(k) {
            eprintln!(
                "  {name:14} {i:7.1} instructions per interrupt (pend to return, QEMU -icount)"
            );
        }
    }
}

#[test]
fn firmware_matches_the_golden_model_on_random_scenarios() {
    let faults = [
        Fault::None,
        Fault::None,
        Fault::MissingIndex,
        Fault::SpindleStopped,
        Fault::EncoderGlitches,
        Fault::ContactChatter,
        Fault::AdcSaturation,
    ];
    let cases: Vec<Case> = proptest_seeds(case_count(), "random scenarios")
        .into_iter()
        .enumerate()
        .map(|(i, seed)| cosim::generate(seed, faults[i % faults.len()]))
        .collect();
    // The scenarios must exercise what they claim to: decisions, contact, counting.
    let decided = cases
        .iter()
        .filter(|c| cosim::golden(c).iter().any(|o| o.register_now))
        .count();
    assert!(
        decided * 2 >= cases.len(),
        "only {decided} of {} cases reach a decision",
        cases.len()
    );
    // …and the force path: control on, the override moved away from the manual value.
    let controlled = cases
        .iter()
        .filter(|c| {
            cosim::golden_force(c)
                .iter()
                .any(|(_, o)| o.control_enabled && o.override_pct != 100)
        })
        .count();
    assert!(
        controlled * 2 >= cases.len(),
        "only {controlled} of {} cases control the force",
        cases.len()
    );
    // …under random force configurations: every controller kind, and no two cases alike.
    let mut kinds = std::collections::BTreeMap::new();
    for c in &cases {
        let f = c
            .force
            .as_ref()
            .expect("every random case has a force path");
        *kinds
            .entry(f.settings().controller.name())
            .or_insert(0usize) += 1;
    }
    eprintln!("force controllers per case: {kinds:?}");
    assert_eq!(
        kinds.len(),
        3,
        "the cases use every controller kind (pi, adaptive, fuzzy): {kinds:?}"
    );
    let hashes: std::collections::BTreeSet<u64> = cases
        .iter()
        .filter_map(|c| c.force.as_ref().map(|f| f.hash()))
        .collect();
    assert_eq!(
        hashes.len(),
        cases.len(),
        "each case draws its own force configuration"
    );
    let report = run(&cases);
    assert_eq!(report.cases, cases.len());
    print_report("random scenarios", &report);
    let folded = run_folding(&cases);
    print_report("random scenarios, FES runs folded", &folded);
    print_fes_cost(&cases, &folded);
    // The gate is stated for the default batch (TOOLTOUCH_CASES explores others).
    if case_count() == 32 {
        crate::gates::check_stack(
            "qemu",
            "the 32 random scenarios",
            report.stack_bytes().max(folded.stack_bytes()),
        );
    }
    // Folding must really batch: far fewer compare interrupts than pulses.
    let compares: u64 = folded
        .profiles
        .iter()
        .map(|p| u64::from(p.per_kind[3].0))
        .sum();
    assert!(
        compares * 8 < fes_pulses(&cases),
        "{compares} compare interrupts for {} FES pulses",
        fes_pulses(&cases)
    );
}

#[test]
fn firmware_and_model_agree_on_every_fault_case() {
    let seeds = proptest_seeds(Fault::ALL.len(), "fault cases");
    let cases: Vec<Case> = Fault::ALL
        .iter()
        .zip(seeds)
        .map(|(&fault, seed)| cosim::generate(seed, fault))
        .collect();
    for case in &cases {
        let outputs = cosim::golden(case);
        let last = outputs.last().copied().unwrap_or_default();
        if case.name.contains("SpindleStopped") {
            // The spindle stops before the contact is dense enough: the CNC aborts.
            assert!(!last.armed, "{}: the CNC aborts", case.name);
        }
        if case.name.contains("AdcSaturation") {
            let clipped = case.force_events.iter().any(|(_, e)| {
                matches!(e, ForceEvent::Sample(c) if c.force == 4095 || c.amps.contains(&0) || c.volts.contains(&4095))
            });
            assert!(clipped, "{}: the ADC clips", case.name);
        }
        if case.name.contains("CounterWrap") {
            let outputs = cosim::golden(case);
            let wrapped = outputs
                .windows(2)
                .any(|w| w[0].pulses == u32::MAX && w[1].pulses == 0);
            assert!(
                wrapped,
                "{}: the pulse count wraps from 2^32 - 1 to 0",
                case.name
            );
        }
        if case.name.contains("BrokenFesLine") {
            assert_eq!(last.revolutions, u16::MAX, "{}: saturates", case.name);
            assert_eq!(last.pulses, 0, "{}: no FES pulse", case.name);
        }
    }
    let report = run(&cases);
    print_report("fault cases", &report);
    let folded = run_folding(&cases);
    print_report("fault cases, FES runs folded", &folded);
}

#[test]
fn a_configuration_that_does_not_match_its_hash_is_rejected_by_the_firmware() {
    let case = cosim::generate(7, Fault::None);
    let mut input = Vec::new();
    cosim::encode_case(&case, &mut input);
    // Corrupt the header's hash (bytes 12..20).
    input[12] ^= 0xff;
    match cosim::qemu::run_image(&image(), &input) {
        Err(CosimError::Firmware(why)) => {
            assert!(why.contains("hash"), "{why}");
        }
        other => panic!("expected the firmware to reject the stream, got {other:?}"),
    }
}

#[test]
fn a_truncated_stream_is_rejected_with_its_offset() {
    let case = cosim::generate(8, Fault::None);
    let mut input = Vec::new();
    cosim::encode_case(&case, &mut input);
    input.truncate(input.len() - 5);
    match cosim::qemu::run_image(&image(), &input) {
        Err(CosimError::Firmware(why)) => {
            assert!(
                why.contains("truncated") && why.contains("at byte"),
                "{why}"
            );
        }
        other => panic!("expected the firmware to reject the stream, got {other:?}"),
    }
}

/// The lathe simulator's closed-loop measurement cycles (spindle, surface with form errors
/// and spindle wander, contact electrics, the CNC retracting on "register now"), as the
/// cycle-level front end extracts their events: the firmware agrees on every event.
#[test]
fn firmware_matches_the_golden_model_on_lathe_simulator_streams() {
    let cases = lathe_cases();
    for case in &cases {
        assert!(
            cosim::golden(case).iter().any(|o| o.register_now),
            "{}: the cycle decides",
            case.name
        );
    }
    let report = run(&cases);
    print_report("lathe simulator streams", &report);
    // The lathe's streams are the realistic FES load (1024 ppr, contact growing over
    // revolutions): the per-pulse cost of the folded path is measured here.
    let folded = run_folding(&cases);
    print_report("lathe simulator streams, FES runs folded", &folded);
    print_fes_cost(&cases, &folded);
}

/// Four closed-loop measurement cycles of the lathe simulator (default configuration),
/// their events as the cycle-level front end extracts them.
pub(crate) fn lathe_cases() -> Vec<Case> {
    use tooltouch_plant::lathe::LatheScenario;
    let config = tooltouch_model::MeasureConfig::default();
    proptest_seeds(4, "lathe streams")
        .into_iter()
        .map(|seed| {
            let scenario = LatheScenario {
                seed,
                ..Default::default()
            };
            let stimulus =
                tooltouch_plant::measurement_cycle::closed_loop_stimulus(&scenario, &config)
                    .unwrap_or_else(|e| panic!("lathe scenario (seed {seed:#x}): {e}"));
            Case {
                name: format!("lathe simulator, seed {seed:#018x}"),
                config,
                tick_hz: stimulus.clock_hz,
                events: tooltouch_vectors::events_from_stimulus(&stimulus, &config),
                force: None,
                force_events: Vec::new(),
            }
        })
        .collect()
}

/// Rebuilds `case`'s event file with `chunks` in place of its force configuration records
/// and `force_hash` in its header.
fn with_force_chunks(case: &Case, chunks: &[Record], force_hash: u64) -> Vec<u8> {
    let mut input = Vec::new();
    cosim::encode_case(case, &mut input);
    let (mut header, records) = Records::new(&input).expect("a valid stream");
    header.force_hash = force_hash;
    let mut out = header.encode().to_vec();
    let mut buf = [0u8; RECORD_HEADER_LEN + MAX_PAYLOAD];
    let mut put = |r: &Record, out: &mut Vec<u8>| {
        let n = r.encode(&mut buf).expect("fits");
        out.extend_from_slice(&buf[..n]);
    };
    for r in records {
        let r = r.expect("a valid record");
        match r.kind {
            kind::FORCE_CONFIG_CHUNK => {}
            wire::kind::MEASURE_CONFIG => {
                put(&r, &mut out);
                for c in chunks {
                    put(c, &mut out);
                }
            }
            _ => put(&r, &mut out),
        }
    }
    out
}

fn expect_rejected(input: &[u8], what: &str, needles: &[&str]) {
    match cosim::qemu::run_image(&image(), input) {
        Err(CosimError::Firmware(why)) => {
            for n in needles {
                assert!(why.contains(n), "{what}: expected `{n}` in: {why}");
            }
            eprintln!("{what}: {why}");
        }
        other => panic!("{what}: expected the firmware to reject the stream, got {other:?}"),
    }
}

/// A broken force configuration (out-of-order, missing or overlapping chunks, a field out
/// of range, another configuration's hash) is an error record in the trace naming what is
/// wrong — not a panic, not a silently wrong configuration.
#[test]
fn broken_force_configuration_chunks_are_rejected_by_the_firmware() {
    let case = cosim::generate(9, Fault::None);
    let force = case.force.expect("the case has a force path");
    let hash = force.hash();
    let chunks: Vec<Record> = force_config_chunks(&force, 0).collect();
    assert!(chunks.len() >= 3, "{} chunks", chunks.len());
    let mut swapped = chunks.clone();
    swapped.swap(0, 1);
    expect_rejected(
        &with_force_chunks(&case, &swapped, hash),
        "swapped chunks",
        &["force configuration", "offset 44, expected offset 0"],
    );
    let mut overlapping = chunks.clone();
    overlapping.insert(1, chunks[0]);
    expect_rejected(
        &with_force_chunks(&case, &overlapping, hash),
        "a repeated chunk",
        &["offset 0, expected offset 44"],
    );
    expect_rejected(
        &with_force_chunks(&case, &chunks[..chunks.len() - 1], hash),
        "a missing last chunk",
        &["incomplete"],
    );
    expect_rejected(
        &with_force_chunks(&case, &chunks, hash ^ 0x5a),
        "another configuration's hash",
        &["force_hash"],
    );
    // PI with K_p = 0: the firmware names the field.
    let pi = ForceSettings::default().validate().unwrap();
    let (mut bytes, n) = pi.canonical_bytes();
    let kp_at = 2 + 4 + 1 + 5 * 8 + 12 * 8 + 3 + 8 + 1;
    assert_eq!(bytes[kp_at - 1], 0, "the default controller is PI");
    bytes[kp_at..kp_at + 8].fill(0);
    let bad: Vec<Record> = bytes[..n]
        .chunks(FORCE_CHUNK_DATA)
        .enumerate()
        .map(|(i, d)| force_config_chunk(0, n as u16, (i * FORCE_CHUNK_DATA) as u16, d))
        .collect();
    expect_rejected(
        &with_force_chunks(&case, &bad, hash),
        "K_p = 0",
        &["field `pi.kp` out of range"],
    );
}

/// One measurement configuration whose checks are all on and tight (16 pulses per
/// revolution ± 1, a probe fail after 3 revolutions, an FES watchdog of 1 000 ticks, two
/// confirming windows at 50 %), and one stream of measurement cycles, each reaching one
/// status condition: the contact closed at arm, a revolution of too few pulses, no index,
/// an illegal scale transition, no decision, the FES line silent, an unconfirmed decision,
/// and a clean, confirmed one. The fault cases of `tooltouch-stimuli` reach the
/// conditions from the lathe's side; this stream names each one on its own.
pub(crate) fn every_status_case() -> Case {
    use tooltouch_model::measure::config::{ContactRule, DecisionMethod};
    use tooltouch_model::{MeasureChecks, MeasureSettings, TimedEvent};
    let config = MeasureSettings {
        pulses_per_rev: 16,
        i_def: 8,
        window_revs: 1,
        method: DecisionMethod::Counter,
        contact_rule: ContactRule::Sampled,
        checks: MeasureChecks {
            contact_at_arm: true,
            revolutions: true,
            pulse_tolerance: 1,
            scale_errors: true,
            probe_revs: 3,
            fes_timeout_cycles: 1_000,
            confirm_windows: 2,
            confirm_percent: 50,
        },
        ..Default::default()
    }
    .validate()
    .unwrap_or_else(|e| panic!("{e}"));
    let mut events = Vec::new();
    let mut t = 0u64;
    let mut at = |dt: u64, event: MeasureEvent, events: &mut Vec<TimedEvent>| {
        t += dt;
        events.push(TimedEvent { time: t, event });
    };
    let fes = |n: usize,
               events: &mut Vec<TimedEvent>,
               at: &mut dyn FnMut(u64, MeasureEvent, &mut Vec<TimedEvent>)| {
        for _ in 0..n {
            at(10, MeasureEvent::Fes, events);
        }
    };
    use MeasureEvent::{Arm, Contact, Index};
    // contact_at_arm
    at(100, Contact(true), &mut events);
    at(10, Arm(true), &mut events);
    fes(5, &mut events, &mut at);
    at(10, Arm(false), &mut events);
    at(10, Contact(false), &mut events);
    // pulses_lost: a revolution of 10 pulses
    at(100, Arm(true), &mut events);
    at(10, Index, &mut events);
    fes(10, &mut events, &mut at);
    at(10, Index, &mut events);
    fes(4, &mut events, &mut at);
    at(10, Arm(false), &mut events);
    // index_missing: 20 pulses without an index
    at(100, Arm(true), &mut events);
    fes(20, &mut events, &mut at);
    at(10, Arm(false), &mut events);
    // scale_error: A and B change together
    at(100, Arm(true), &mut events);
    fes(3, &mut events, &mut at);
    at(10, MeasureEvent::Scale { a: true, b: true }, &mut events);
    fes(3, &mut events, &mut at);
    at(10, Arm(false), &mut events);
    at(10, MeasureEvent::Scale { a: false, b: false }, &mut events);
    // no_decision: three revolutions without contact
    at(100, Arm(true), &mut events);
    for _ in 0..3 {
        at(10, Index, &mut events);
        fes(16, &mut events, &mut at);
    }
    at(10, Arm(false), &mut events);
    // fes_timeout: the FES line falls silent for 5 000 ticks, then comes back
    at(100, Arm(true), &mut events);
    fes(4, &mut events, &mut at);
    at(5_000, Index, &mut events);
    fes(4, &mut events, &mut at);
    at(10, Arm(false), &mut events);
    // unconfirmed: decided in a dense window, the next window without contact
    at(100, Arm(true), &mut events);
    at(10, Index, &mut events);
    at(5, Contact(true), &mut events);
    fes(16, &mut events, &mut at);
    at(10, Index, &mut events);
    at(5, Contact(false), &mut events);
    fes(16, &mut events, &mut at);
    at(10, Index, &mut events);
    at(10, Arm(false), &mut events);
    // clean: decided and confirmed over two windows, no fault
    at(100, Arm(true), &mut events);
    at(10, Index, &mut events);
    at(5, Contact(true), &mut events);
    for _ in 0..3 {
        fes(16, &mut events, &mut at);
        at(10, Index, &mut events);
    }
    at(10, Contact(false), &mut events);
    at(10, Arm(false), &mut events);
    Case {
        name: "every status condition, one cycle each".into(),
        config,
        tick_hz: 1_000_000,
        events,
        force: None,
        force_events: Vec::new(),
    }
}

/// The faults each cycle of [`every_status_case`] must show at its arm's fall, in order,
/// and whether the decision was confirmed.
pub(crate) fn assert_every_status_condition(case: &Case) {
    use tooltouch_model::fault;
    let outputs = cosim::golden(case);
    let ends: Vec<(u8, bool)> = case
        .events
        .iter()
        .zip(&outputs)
        .filter(|(e, _)| e.event == MeasureEvent::Arm(false))
        .map(|(_, o)| (o.faults, o.confirmed))
        .collect();
    assert_eq!(
        ends,
        [
            (fault::CONTACT_AT_ARM, false),
            (fault::PULSES_LOST, false),
            (fault::INDEX_MISSING, false),
            (fault::SCALE_ERROR, false),
            (fault::NO_DECISION, false),
            (fault::FES_TIMEOUT, false),
            (fault::UNCONFIRMED, false),
            (0, true),
        ],
        "the cycles' status at their end (faults, confirmed)"
    );
}

/// Every status condition, in one stream: the firmware agrees with the model on every
/// output of every event (`faults` and `confirmed` with the fault line, the FES watchdog
/// raised by the clock's alarm inside the silent gap), with every event observed and with
/// FES runs folded (the model then replayed at the firmware's fold times).
#[test]
fn firmware_and_model_agree_on_every_status_condition() {
    let case = every_status_case();
    assert_every_status_condition(&case);
    let cases = [case];
    let report = run(&cases);
    print_report("every status condition", &report);
    let folded = run_folding(&cases);
    print_report("every status condition, FES runs folded", &folded);
}
