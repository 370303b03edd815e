//! The Nucleo-F446RE image executed: its `emulated` build booted on QEMU's `netduinoplus2`
//! (STM32F405, Cortex-M4F, the Nucleo's interrupt numbers and priorities), driven over
//! semihosting like the lm3s6965 image — the driver pends EXTI0, EXTI1, EXTI2, EXTI9_5,
//! TIM2 (on its count's compare match), TIM7, EXTI15_10, TIM6_DAC and TIM3 — and checked
//! event for event against the golden model, in both observation modes; `tooltouch
//! check` checks the demo stream's trace; the defmt log (boot, clock fallback,
//! configuration hashes, every decision) is decoded with defmt's own decoder and compared
//! line for line with what the golden model says it must be.
//!
//! Needs qemu-system-arm and the thumbv7em-none-eabihf target: without them the tests fail
//! with a message naming `cargo xtask setup`.

use crate::common::{s, text, tooltouch};
use crate::cosim::{case_count, lathe_cases, print_report, proptest_seeds};
use std::path::PathBuf;
use std::sync::OnceLock;
use tooltouch_firmware_runner::nucleo::{self, NucleoRun};
use tooltouch_firmware_runner::{self as cosim, Case, Fault, Observe};
use tooltouch_model::measure::calibration::{applied_offset, CalibrationRecord};
use tooltouch_settings::firmware_config::FirmwareConfig;

/// Builds the emulated Nucleo image once per test binary.
fn image() -> PathBuf {
    static IMAGE: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    IMAGE
        .get_or_init(|| nucleo::build_emulated().map_err(|e| e.to_string()))
        .clone()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The boot log every run starts with: the clock setup's bounded wait for the PLL runs
/// out (QEMU emulates no RCC), the board says so and runs on the HSI with the settings
/// derived for it; then the configuration baked in (the defaults) and, when one is baked,
/// the calibration with its hash and offset (the names `tooltouch cosim config` prints).
fn boot_log(calibration: Option<&CalibrationRecord>) -> Vec<String> {
    let config = FirmwareConfig::default();
    let mut log = vec![
        "clock setup failed (PllLock): running from the 16 MHz HSI, the measurement tasks \
         take 10.5 times longer than the 168 MHz budget of docs/firmware.md"
            .to_string(),
        "tooltouch firmware on Nucleo-F446RE, SYSCLK 16000000 Hz, feed-override PWM 15625 Hz: \
         waiting for the CNC's arm line (PA0)"
            .to_string(),
        format!(
            "configuration measure_hash={:016x} force_hash={:016x}",
            config.measure.hash(),
            config.force.hash()
        ),
    ];
    if let Some(c) = calibration {
        log.push(format!(
            "calibration calibration_hash={:016x} offset={} counts",
            c.hash(),
            c.offset_counts
        ));
    }
    log
}

/// The log a run of `cases` with `observe` must leave on an image built with
/// `calibration`: the boot, then per case every change of "register now" after an event,
/// and every other change of the status (faults, confirmed), as the board's idle logs it
/// (outputs of the golden model after that event, and after each alarm of the FES
/// watchdog, as the firmware folds the events: [`cosim::firmware_steps`], the position corrected by the offset the image applies to
/// the case's configuration; no ADC sample dropped), then the driver's end.
pub(crate) fn expected_log(
    cases: &[Case],
    observe: Observe,
    calibration: Option<&CalibrationRecord>,
) -> Vec<String> {
    use tooltouch_firmware_runner::bench::{decision_line, status_line};
    let mut log = boot_log(calibration);
    for case in cases {
        let (mut on, mut status) = (false, (0, false));
        let offset = applied_offset(calibration, &case.config);
        let bits = case.config.settings().scale_bits;
        for o in cosim::firmware_steps(case, observe) {
            let now = (o.faults, o.confirmed);
            if o.register_now != on {
                on = o.register_now;
                log.push(format!(
                    "{}; 0 ADC samples dropped",
                    decision_line(&o, offset, bits)
                ));
            } else if now != status {
                log.push(status_line(&o));
            }
            status = now;
        }
    }
    log.push("co-simulation ended, QEMU exit status 0".to_string());
    log
}

/// Runs `cases` on the emulated Nucleo with `observe`, checks every output and the log.
fn run(what: &str, cases: &[Case], observe: Observe) -> NucleoRun {
    run_on(&image(), None, what, cases, observe)
}

/// Runs `cases` on the emulated Nucleo `image` built with `calibration`, with `observe`;
/// checks every output, every reported decision and the log.
pub(crate) fn run_on(
    image: &std::path::Path,
    calibration: Option<&CalibrationRecord>,
    what: &str,
    cases: &[Case],
    observe: Observe,
) -> NucleoRun {
    let run = nucleo::run_calibrated_batch(image, cases, observe, calibration)
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    let want = expected_log(cases, observe, calibration);
    for (i, (w, g)) in want.iter().zip(&run.log).enumerate() {
        assert_eq!(w, g, "{what}: defmt line {i}");
    }
    assert_eq!(
        want.len(),
        run.log.len(),
        "{what}: defmt lines (expected, decoded); the decoded log: {:#?}",
        run.log
    );
    print_report(what, &run.report);
    eprintln!(
        "  defmt: {} lines decoded, {} decisions",
        run.log.len(),
        run.log
            .iter()
            .filter(|l| l.starts_with("register now"))
            .count()
    );
    run
}

/// Both observation modes: every event observed (each pulse through the snapshot's fold,
/// the compare on the exact deciding pulse), and FES pulses unobserved (runs folded by
/// TIM2's compare and the other edges' tasks, as on the board).
fn run_both(what: &str, cases: &[Case]) -> (NucleoRun, NucleoRun) {
    (
        run(what, cases, Observe::EveryEvent),
        run(&format!("{what}, FES runs folded"), cases, Observe::SkipFes),
    )
}

#[test]
fn the_nucleo_image_matches_the_golden_model_on_random_scenarios() {
    let faults = [
        Fault::None,
        Fault::None,
        Fault::MissingIndex,
        Fault::SpindleStopped,
        Fault::EncoderGlitches,
        Fault::ContactChatter,
        Fault::AdcSaturation,
    ];
    let cases: Vec<Case> = proptest_seeds(case_count(), "nucleo random scenarios")
        .into_iter()
        .enumerate()
        .map(|(i, seed)| nucleo::for_nucleo(&cosim::generate(seed, faults[i % faults.len()])))
        .collect();
    // The cases exercise what they claim: decisions, and force control with commands.
    let decided = cases
        .iter()
        .filter(|c| cosim::golden(c).iter().any(|o| o.register_now))
        .count();
    assert!(decided * 2 >= cases.len(), "only {decided} cases decide");
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
        "only {controlled} cases control"
    );
    let (every, folded) = run_both("Nucleo, random scenarios", &cases);
    let deepest = every.report.stack_bytes().max(folded.report.stack_bytes());
    // The gate is stated for the default batch (TOOLTOUCH_CASES explores others).
    if case_count() == 32 {
        crate::gates::check_stack("nucleo-emulated", "the 32 random scenarios", deepest);
    }
}

#[test]
fn the_nucleo_image_matches_the_golden_model_on_fault_and_lathe_streams() {
    // Every fault but the pulse-count wrap, whose preset test event has no task on the
    // Nucleo (it would be reported as a lost event).
    let faults: Vec<Fault> = Fault::ALL
        .into_iter()
        .filter(|f| *f != Fault::CounterWrap)
        .collect();
    let mut cases: Vec<Case> = faults
        .iter()
        .zip(proptest_seeds(faults.len(), "nucleo fault cases"))
        .map(|(&fault, seed)| nucleo::for_nucleo(&cosim::generate(seed, fault)))
        .collect();
    cases.extend(lathe_cases());
    run_both("Nucleo, fault cases and lathe simulator streams", &cases);
}

/// Every status condition in one stream ([`crate::cosim::every_status_case`]), in the
/// Nucleo's interrupt order, the FES watchdog raised by TIM5's alarm: every output, the
/// fault line (PA7) and the log's status lines as the model's.
#[test]
fn the_nucleo_image_matches_the_golden_model_on_every_status_condition() {
    let case = crate::cosim::every_status_case();
    crate::cosim::assert_every_status_condition(&case);
    let (every, _) = run_both("Nucleo, every status condition", &[case]);
    assert!(
        every
            .log
            .iter()
            .any(|l| l.starts_with("status: faults fes_timeout")),
        "the watchdog's line: {:#?}",
        every.log
    );
}

#[test]
fn a_stream_with_an_event_the_nucleo_has_no_input_for_is_reported_lost() {
    // The pulse-count wrap case presets the count (a test event with no task on the
    // Nucleo): the trace's status counts each preset lost, and the check fails.
    let case = nucleo::for_nucleo(&cosim::generate(11, Fault::CounterWrap));
    let presets = case
        .events
        .iter()
        .filter(|e| matches!(e.event, tooltouch_model::MeasureEvent::PresetPulses(_)))
        .count();
    assert!(presets > 0, "{}", case.name);
    let input = cosim::encode_batch(std::slice::from_ref(&case), Observe::EveryEvent);
    let run = cosim::qemu::run_machine(&nucleo::MACHINE_ARGS, &image(), &input)
        .unwrap_or_else(|e| panic!("{e}"));
    let streams = cosim::trace::parse(&run.trace).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(streams.len(), 1);
    assert_eq!(
        streams[0].profile.lost as usize, presets,
        "every preset is counted lost"
    );
    match cosim::check_batch(&[case], Observe::EveryEvent, &run.trace, run.elapsed) {
        Err(cosim::CosimError::Mismatch(m)) => eprintln!("as expected: {m}"),
        other => panic!("expected the check to fail, got {other:?}"),
    }
}

/// The demo stream (firmware/tooltouch-events.bin, a `tooltouch measure` run of
/// firmware/demo-lathe.toml) on the emulated Nucleo, its trace checked by `tooltouch check`
/// against that run's expected outputs, as docs/firmware.md shows.
#[test]
fn tooltouch_check_accepts_the_nucleo_trace_of_the_demo_stream() {
    let w = tempfile::tempdir().unwrap();
    let p = |name: &str| w.path().join(name);
    std::fs::write(p("demo-lathe.toml"), crate::common::FAST_LATHE).unwrap();
    let o = tooltouch(&[
        "measure",
        "--config",
        s(&p("demo-lathe.toml")),
        "--vcd",
        "none",
        "--no-progress",
        "--out",
        s(&p("m")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let events = std::fs::read(p("m").join("events.ttv")).unwrap();
    let run = cosim::qemu::run_machine(&nucleo::MACHINE_ARGS, &image(), &events)
        .unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(p("nucleo.ttv"), &run.trace).unwrap();
    let o = tooltouch(&[
        "check",
        "--expected",
        s(&p("m").join("expected_outputs.ttv")),
        "--dut",
        s(&p("nucleo.ttv")),
    ]);
    let out = text(&o);
    assert!(o.status.success(), "{out}");
    assert!(out.contains("none lost or overflowed"), "{out}");
    eprintln!("{}", out.trim());
    let elf = std::fs::read(image()).unwrap();
    let log = nucleo::decode_defmt(&elf, &run.defmt).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(log[..3], boot_log(None)[..], "the boot log");
    assert!(
        log.iter().any(|l| l.starts_with("register now: position")),
        "the demo measurement decides: {log:#?}"
    );
    // The bench's host command expects from a board what the image logs here.
    let want = cosim::bench::expected_lines(&events, None).unwrap_or_else(|e| panic!("{e}"));
    let got = cosim::bench::decision_lines(&log);
    assert_eq!(cosim::bench::first_difference(&want, &got), None);
    assert_eq!(want, got);
}
