//! The measurement status on the machine's faults (issue 39's acceptance): the README's
//! fast verification lathe (docs/quickstart.md's `fast.toml`: 1 MHz, `loads = false`), its
//! first measurement's pins as the closed-loop cycle makes them, one pin edited the way a
//! machine breaks, and the golden model run over them at cycle level (every clock) and at
//! event level (the vectors' events). Each case must end with its fault named, and the CNC
//! must never have been offered an accepted decision (`confirmed` with `faults == 0`) while
//! armed; the clean pins give no fault and an accepted decision.
//!
//! | case | the pin edited | the fault |
//! | --- | --- | --- |
//! | a chip under the tool while it is still in the air | contact held 1.2 revolutions from just after arm | `unconfirmed` — only above the defaults' confirmation level (open, see below) |
//! | every third FES pulse lost (encoder, cable) | FES | `pulses_lost` |
//! | the index pulse lost after arm | index | `index_missing` |
//! | the contact closed at arm (coolant bridge, tool touching) | contact high from before arm to the feed stop | `contact_at_arm` |
//! | no contact ever (broken wire, tool out of reach) | contact low, the CNC feeding on | `no_decision` |
//! | FES lost while the contact is permanent | FES low from just before the first contact, the contact permanent, the CNC feeding on | `fes_timeout` |
//!
//! The chip is not caught at the default confirmation (3 windows at 25 %): on this lathe the
//! real approach already reaches 30–41 % density in the windows after the chip's decision,
//! so they confirm it, and the reading (−5 counts against the clean −39: 6.8 µm on the
//! diameter) is accepted. At 50 % it is caught, but 45 % and 50 % raise `unconfirmed` on
//! 70 and 123 of the 1 040 clean measurements of `no_false_alarm`: that test is ignored
//! until the confirmation rule changes.
//!
//! "The CNC feeding on" (the last two, where the unguarded CNC would wait for a decision
//! that never comes): the approach's last revolution before the feed stop is repeated with
//! the scale held, so the armed pins last past the checks' limits (`probe_revs`, the FES
//! watchdog).

use tooltouch_model::measure::frontend::pin;
use tooltouch_model::{fault, Faults, FrontEnd, MeasureConfig, MeasureOutputs, Pins};
use tooltouch_plant::lathe::LatheScenario;
use tooltouch_plant::measurement_cycle::{self, MeasurementReport};
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_settings::Settings;

/// The `fast.toml` of docs/quickstart.md, as written there.
pub(super) fn fast_lathe() -> (MeasureConfig, LatheScenario) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/quickstart.md");
    let doc = std::fs::read_to_string(path).unwrap();
    let start = doc
        .find("```toml fast.toml\n")
        .expect("fast.toml in quickstart.md");
    let body = &doc[start..].split_once('\n').unwrap().1;
    let toml = &body[..body.find("```").unwrap()];
    Settings::parse(toml, "fast.toml")
        .unwrap()
        .resolve()
        .unwrap()
}

/// The first measurement of the fast lathe: its report and its pins, one byte per clock.
fn first_measurement() -> (MeasureConfig, u32, MeasurementReport, Vec<u8>) {
    let (config, mut scenario) = fast_lathe();
    scenario.cycle.repeats = 1;
    let run = measurement_cycle::run(&scenario, &config, &mut |_| {}).unwrap();
    let pins = run.stimulus.cycles().map(|p| p.0).collect();
    let report = run.measurements.into_iter().next().unwrap();
    (config, scenario.clock_hz, report, pins)
}

/// What the golden model made of some pins.
struct Verdict {
    /// The outputs after the last clock (cycle level).
    last: MeasureOutputs,
    /// The outputs after the last event (event level).
    last_event: MeasureOutputs,
    /// Some clock showed `confirmed` with no fault while armed: the CNC would accept.
    accepted: bool,
    /// Some clock showed "register now" while armed.
    decided: bool,
}

fn golden(config: &MeasureConfig, clock_hz: u32, pins: &[u8]) -> Verdict {
    let mut fe = FrontEnd::new(config);
    let (mut accepted, mut decided) = (false, false);
    for &p in pins {
        fe.clock(Pins(p));
        let o = fe.outputs();
        accepted |= o.armed && o.confirmed && o.faults == 0;
        decided |= o.armed && o.register_now;
    }
    let mut stimulus = Stimulus::new(clock_hz);
    for &p in pins {
        stimulus.push(Pins(p), 1);
    }
    let events = tooltouch_vectors::events_from_stimulus(&stimulus, config);
    let outputs = tooltouch_vectors::outputs_after_each_event(&events, config);
    Verdict {
        last: fe.outputs(),
        last_event: outputs.last().unwrap().1,
        accepted,
        decided,
    }
}

/// Sets (`level`) or clears the pin `bit` over clocks `from..to`.
fn force(pins: &mut [u8], bit: u8, level: bool, from: usize, to: usize) {
    let to = to.min(pins.len());
    for p in &mut pins[from..to] {
        *p = if level { *p | bit } else { *p & !bit };
    }
}

/// The pins with the CNC feeding on: the `revolution` clocks before `stop` repeated
/// `times` times there, the scale held at its level at `stop`.
fn feeding_on(pins: &[u8], stop: usize, revolution: usize, times: usize) -> Vec<u8> {
    let scale = pin::SCALE_A | pin::SCALE_B;
    let held = pins[stop - 1] & scale;
    let mut out = pins[..stop].to_vec();
    for _ in 0..times {
        out.extend(
            pins[stop - revolution..stop]
                .iter()
                .map(|p| p & !scale | held),
        );
    }
    out.extend_from_slice(&pins[stop..]);
    out
}

/// Asserts that the case `name` ends with the fault `bit` named at both levels, and that
/// no accepted decision was offered.
fn assert_faults(name: &str, v: &Verdict, bit: u8) {
    let faults = Faults(v.last.faults);
    eprintln!(
        "{name}: faults {faults}, confirmed {}, decided {}, decision_position {}",
        v.last.confirmed, v.decided, v.last.decision_position
    );
    assert!(faults.contains(bit), "{name}: faults {faults}");
    assert_eq!(v.last_event.faults, v.last.faults, "{name}: event level");
    assert!(!v.accepted, "{name}: an accepted decision was offered");
}

#[test]
fn each_machine_fault_is_named_and_never_accepted_and_the_clean_run_is() {
    // The chip, the sixth case: `a_chip_in_the_air_is_not_confirmed*` below.
    let (config, clock_hz, m, pins) = first_measurement();
    let revolution = fast_revolution();
    let arm = m.arm_cycle as usize;
    let stop = m.stop_cycle as usize;

    // The clean pins: no fault, the decision confirmed and accepted.
    let clean = golden(&config, clock_hz, &pins);
    eprintln!(
        "clean: faults {}, confirmed {}, decision_position {}",
        Faults(clean.last.faults),
        clean.last.confirmed,
        clean.last.decision_position
    );
    assert_eq!(clean.last.faults, 0);
    assert_eq!(clean.last_event.faults, 0);
    assert!(clean.last.confirmed && clean.accepted && m.accepted);
    let checks = config.settings().checks;

    // Every third FES pulse after arm lost.
    let mut lossy = pins.clone();
    let mut n = 0;
    let mut k = arm;
    while k < lossy.len() {
        if lossy[k] & pin::FES != 0 && lossy[k - 1] & pin::FES == 0 {
            n += 1;
            if n % 3 == 0 {
                let end = (k..lossy.len())
                    .find(|&j| lossy[j] & pin::FES == 0)
                    .unwrap_or(lossy.len());
                force(&mut lossy, pin::FES, false, k, end);
                k = end;
                continue;
            }
        }
        k += 1;
    }
    assert_faults(
        "every third FES pulse lost",
        &golden(&config, clock_hz, &lossy),
        fault::PULSES_LOST,
    );

    // The index lost after arm (the arm's own index pulse kept).
    let mut no_index = pins.clone();
    force(
        &mut no_index,
        pin::INDEX,
        false,
        arm + revolution / 2,
        pins.len(),
    );
    assert_faults(
        "index lost after arm",
        &golden(&config, clock_hz, &no_index),
        fault::INDEX_MISSING,
    );

    // The contact closed at arm, until the feed stops.
    let mut closed = pins.clone();
    force(&mut closed, pin::CONTACT, true, arm - 1000, stop);
    assert_faults(
        "contact closed at arm",
        &golden(&config, clock_hz, &closed),
        fault::CONTACT_AT_ARM,
    );

    // No contact ever, the CNC feeding on past probe_revs.
    let times = usize::from(checks.probe_revs) + 2;
    let mut untouched = feeding_on(&pins, stop, revolution, times);
    let len = untouched.len();
    force(&mut untouched, pin::CONTACT, false, 0, len);
    let v = golden(&config, clock_hz, &untouched);
    assert!(!v.decided);
    assert_faults("no contact ever", &v, fault::NO_DECISION);

    // FES lost as the tool touches, the contact going permanent, the CNC feeding on past
    // the watchdog.
    let touch = m.first_contact_cycle.unwrap() as usize;
    let permanent = m.permanent_contact_cycle.unwrap() as usize;
    let times = checks.fes_timeout_cycles as usize / revolution + 2;
    let mut silent = feeding_on(&pins, stop, revolution, times);
    let fed_until = stop + times * revolution;
    force(&mut silent, pin::CONTACT, true, permanent, fed_until);
    force(&mut silent, pin::FES, false, touch - 100, fed_until);
    let v = golden(&config, clock_hz, &silent);
    assert!(!v.decided);
    assert_faults("FES lost, the contact permanent", &v, fault::FES_TIMEOUT);
}

/// The chip case: contact from just after arm (the tool in the air until its first
/// contact, 0.88 revolutions later) for 1.2 revolutions. It decides early (at −5 counts,
/// the clean pins at −39).
fn chip(revolution: usize) -> (MeasureConfig, u32, Vec<u8>) {
    let (config, clock_hz, m, pins) = first_measurement();
    let mut chip = pins;
    let from = m.arm_cycle as usize + 100;
    force(
        &mut chip,
        pin::CONTACT,
        true,
        from,
        from + revolution * 6 / 5,
    );
    assert!(m.first_contact_cycle.unwrap() as usize > from, "in the air");
    (config, clock_hz, chip)
}

fn fast_revolution() -> usize {
    let (_, s) = fast_lathe();
    (f64::from(s.clock_hz) * 60.0 / s.rpm).round() as usize
}

/// At a confirmation level above the density the real approach reaches in the windows
/// after the chip's decision (its windows count 1015, 527, 417 of 1024 pulses), the chip is
/// named `unconfirmed` and never accepted.
#[test]
fn a_chip_in_the_air_is_not_confirmed_at_half_the_window() {
    let (config, clock_hz, pins) = chip(fast_revolution());
    let mut s = *config.settings();
    s.checks.confirm_percent = 50;
    let config = s.validate().unwrap();
    let v = golden(&config, clock_hz, &pins);
    assert!(v.decided, "the chip decides");
    assert_faults("chip (confirm_percent 50)", &v, fault::UNCONFIRMED);
}

/// The chip at the default confirmation (3 windows at 25 %): issue 39's acceptance, open.
#[test]
#[ignore = "open (issue 39): at the default confirm_percent 25 the chip is confirmed (windows \
            527 and 417 of 1024 after it); 45-50 % catches it but raises `unconfirmed` on 7-12 % \
            of clean rig measurements (no_false_alarm.rs): the confirmation rule needs rework"]
fn a_chip_in_the_air_is_not_confirmed_at_the_defaults() {
    let (config, clock_hz, pins) = chip(fast_revolution());
    let v = golden(&config, clock_hz, &pins);
    assert!(v.decided, "the chip decides");
    assert_faults("chip", &v, fault::UNCONFIRMED);
}
