//! The Nucleo's on-target tests (firmware/tests/on_target.rs, defmt-test) under QEMU's
//! netduinoplus2: the subset that machine emulates must run and pass, every other test
//! must log its reason for being skipped (there only: on a board all of them run), and the
//! run must end with defmt-test's "all tests passed!" and exit status 0. The defmt log is
//! decoded with defmt's own decoder, as for the Nucleo image.
//!
//! Needs qemu-system-arm and the thumbv7em-none-eabihf target: without them the test
//! fails with a message naming `cargo xtask setup`.

use tooltouch_firmware_runner::on_target::{self, OnTargetRun, ALL_PASSED};

/// Every on-target test in the image's order, and why it cannot run under QEMU (`None`:
/// it runs there).
const TESTS: [(&str, Option<&str>); 7] = [
    ("the_clock_tree_comes_up_as_init_reports", None),
    (
        "systick_counts_the_core_clock_like_the_dwt_cycle_counter",
        Some("QEMU's DWT cycle counter does not count (CYCCNT reads 0)"),
    ),
    (
        "tim6_updates_at_the_sample_rate_against_systick",
        Some("TIM6 is not emulated (its registers read 0, it never counts)"),
    ),
    ("tim3_counts_at_its_rate_against_systick", None),
    (
        "the_fes_counter_counts_compares_and_wraps",
        Some(
            "GPIO is not emulated (no edge reaches PB3) and QEMU's TIM2 ignores the external \
             clock (SMCR) and never compares",
        ),
    ),
    (
        "the_adc_reads_its_internal_reference_at_the_calibrated_code",
        Some("QEMU's ADC never sets EOC and converts no input (its DR holds no sample)"),
    ),
    (
        "the_handlers_worst_case_cycles_fit_the_fes_budget",
        Some("QEMU's DWT cycle counter does not count, and GPIO is not emulated"),
    ),
];

fn run() -> OnTargetRun {
    let image = on_target::build_emulated().unwrap_or_else(|e| panic!("{e}"));
    on_target::run(&image).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_on_target_tests_pass_under_netduinoplus2_where_it_emulates_the_board() {
    let run = run();
    let log = run.log.join("\n");
    assert_eq!(
        run.status,
        Some(0),
        "QEMU's exit status (the image's semihosting exit); the log:\n{log}"
    );
    assert!(run.all_passed, "no `{ALL_PASSED}`; the log:\n{log}");
    // init: the board's setup in init's order; RCC reads 0, so the clock tree falls back.
    assert_eq!(
        run.init,
        [
            "clock setup failed (PllLock): running from the 16 MHz HSI, the measurement tasks \
             take 10.5 times longer than the 168 MHz budget of docs/firmware.md",
            "SYSCLK 16000000 Hz",
        ],
        "init's log"
    );
    let names: Vec<&str> = run.tests.iter().map(|t| t.name.as_str()).collect();
    let want: Vec<&str> = TESTS.iter().map(|(n, _)| *n).collect();
    assert_eq!(
        names, want,
        "the image's tests (update TESTS with the image)"
    );
    for (t, (_, skip)) in run.tests.iter().zip(TESTS) {
        assert_eq!(t.number.1, TESTS.len(), "{}: the announced count", t.name);
        match skip {
            Some(reason) => assert_eq!(
                t.skipped(),
                Some(reason),
                "{} must log its skip reason under QEMU: {:?}",
                t.name,
                t.lines
            ),
            None => {
                assert!(!t.lines.is_empty(), "{} logged nothing", t.name);
                assert!(
                    t.lines.iter().all(|l| !l.starts_with("skipped")),
                    "{} must run under QEMU: {:?}",
                    t.name,
                    t.lines
                );
            }
        }
    }
    let section = |name: &str| &run.tests.iter().find(|t| t.name == name).unwrap().lines;
    assert_eq!(
        section("the_clock_tree_comes_up_as_init_reports"),
        &["clock tree: SYSCLK 16000000 Hz"]
    );
    let tim3 = section("tim3_counts_at_its_rate_against_systick");
    assert!(
        tim3.len() == 1 && tim3[0].starts_with("TIM3: ") && tim3[0].contains("PSC 1599 + 1"),
        "TIM3 at the fallback's prescaler: {tim3:?}"
    );
    let ran = TESTS.iter().filter(|(_, s)| s.is_none()).count();
    eprintln!(
        "on-target tests under netduinoplus2: {ran} of {} run and pass, {} skipped with their \
         reason; QEMU {:.2} s\n  {}",
        TESTS.len(),
        TESTS.len() - ran,
        run.elapsed.as_secs_f64(),
        run.log.join("\n  ")
    );
}
