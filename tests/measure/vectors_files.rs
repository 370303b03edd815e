//! Vector files: the golden VCD reads back as the model's values on every clock, `check`
//! finds a flipped bit and names cycle, signal and both values, and corrupt binary files
//! give errors that say what is wrong.

use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_model::wire::{self, Header, StreamKind};
use tooltouch_model::{MeasureConfig, MeasureOutputs, MeasureSettings};
use tooltouch_plant::lathe::{CycleSettings, LatheScenario};
use tooltouch_plant::measurement_cycle;
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_vectors::check::{compare_binary, compare_vcd, Verdict};
use tooltouch_vectors::vcd::{output_values, period_ns, write_golden, Dump};
use tooltouch_vectors::{
    binary, clock_every_cycle, events_from_stimulus, outputs_after_each_event,
};

fn small() -> (MeasureConfig, Stimulus) {
    let config = MeasureSettings {
        pulses_per_rev: 64,
        i_def: 32,
        glitch_cycles: 2,
        ..Default::default()
    }
    .validate()
    .unwrap();
    let scenario = LatheScenario {
        clock_hz: 1_000_000,
        rpm: 1_000_000.0 * 60.0 / (64.0 * 20.0),
        feed_mm_per_rev: 0.001,
        // No loads: at 46 875 rpm the default spindle path lifts the surface above the
        // clearance, and the contact is closed at arm (the status's `contact_at_arm`).
        spindle_path: tooltouch_plant::lathe::SpindlePath::none(),
        cycle: CycleSettings {
            repeats: 1,
            retract_mm_per_s: 1.0,
            z_dwell_ms: 1.0,
            cnc_reaction_us: 100.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let run = measurement_cycle::run(&scenario, &config, &mut |_| {}).unwrap();
    assert_eq!(run.summary.decided, 1);
    (config, run.stimulus)
}

fn golden_text(config: &MeasureConfig, stimulus: &Stimulus) -> String {
    let mut buf = Vec::new();
    write_golden(&mut buf, stimulus, config, None).unwrap();
    String::from_utf8(buf).unwrap()
}

#[test]
fn golden_vcd_reads_back_as_the_model_on_every_clock() {
    let (config, stimulus) = small();
    let text = golden_text(&config, &stimulus);
    let dump = Dump::parse(&text, "golden.vcd").unwrap();
    assert_eq!(dump.golden_stamp(), Some((config.hash(), 1_000_000)));
    let p_fs = period_ns(1_000_000) * 1_000_000;
    let outs: Vec<_> = tooltouch_vectors::vcd::output_signals(&config)
        .iter()
        .map(|(name, _)| dump.find_in_scope("outputs", name).unwrap().id.clone())
        .collect();
    let ins: Vec<_> = pin::NAMES
        .iter()
        .map(|name| dump.find_in_scope("inputs", name).unwrap().id.clone())
        .collect();
    let pins: Vec<_> = stimulus.cycles().collect();
    let mut checked = 0u64;
    clock_every_cycle(&stimulus, &config, |k, fe, _| {
        let t = k * p_fs + p_fs / 2;
        let expected = output_values(&fe.outputs(), &config);
        for (i, id) in outs.iter().enumerate() {
            let v = dump.value_at(id, t).unwrap();
            assert!(!v.unknown);
            assert_eq!(v.to_u64(), Some(expected[i]), "clock {k} output {i}");
        }
        for (i, id) in ins.iter().enumerate() {
            let level = pins[k as usize].get(1 << i);
            assert_eq!(
                dump.value_at(id, t).unwrap().to_u64(),
                Some(u64::from(level)),
                "clock {k} pin {i}"
            );
        }
        checked += 1;
    });
    assert_eq!(checked, stimulus.total_cycles());
}

#[test]
fn a_golden_vcd_starting_settled_checks_against_itself() {
    // All pins low for a while: clock 0 changes nothing, yet every signal needs a value
    // from time 0 on.
    let (config, tail) = small();
    let mut stimulus = Stimulus::new(tail.clock_hz);
    stimulus.push(Pins(0), 50);
    for s in &tail.segments {
        stimulus.push(s.pins, s.cycles.into());
    }
    let text = golden_text(&config, &stimulus);
    assert!(text.contains("#0\n$dumpvars\n"), "values at time 0");
    let e = Dump::parse(&text, "e.vcd").unwrap();
    match compare_vcd(&e, "e.vcd", &e, "e.vcd").unwrap() {
        Verdict::Match(line) => assert!(line.starts_with("OK"), "{line}"),
        v => panic!("{v:?}"),
    }
}

#[test]
fn check_accepts_a_dut_dump_with_other_scopes_and_timescale() {
    let (config, stimulus) = small();
    let text = golden_text(&config, &stimulus);
    let e = Dump::parse(&text, "e.vcd").unwrap();
    // The same values as a testbench would dump them: ps, another hierarchy, no comment.
    let dut: String = text
        .lines()
        .filter(|l| !l.starts_with("$comment"))
        .map(|l| {
            if let Some(t) = l.strip_prefix('#') {
                format!("#{}", t.parse::<u64>().unwrap() * 1000)
            } else {
                l.replace("$timescale 1ns", "$timescale 1ps")
                    .replace("module tooltouch", "module tb")
                    .replace("module outputs", "module dut")
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let d = Dump::parse(&dut, "d.vcd").unwrap();
    match compare_vcd(&e, "e.vcd", &d, "d.vcd").unwrap() {
        Verdict::Match(line) => assert!(line.starts_with("OK"), "{line}"),
        v => panic!("{v:?}"),
    }
}

#[test]
fn check_names_the_first_flipped_bit() {
    let (config, stimulus) = small();
    let text = golden_text(&config, &stimulus);
    let e = Dump::parse(&text, "e.vcd").unwrap();
    let count_id = e.find_in_scope("outputs", "count").unwrap().id.clone();
    // Flip bit 0 of the 5th change of `count`.
    let mut seen = 0;
    let mut time = 0u64;
    let mut flipped_at = None;
    let dut: Vec<String> = text
        .lines()
        .map(|l| {
            if let Some(t) = l.strip_prefix('#') {
                time = t.parse().unwrap();
            }
            let parts: Vec<&str> = l.split(' ').collect();
            if parts.len() == 2 && parts[1] == count_id && parts[0].starts_with('b') {
                seen += 1;
                if seen == 5 {
                    let v = u64::from_str_radix(&parts[0][1..], 2).unwrap() ^ 1;
                    flipped_at = Some((time, v ^ 1, v));
                    return format!("b{v:b} {count_id}");
                }
            }
            l.to_string()
        })
        .collect();
    let (t, expected, got) = flipped_at.unwrap();
    let d = Dump::parse(&dut.join("\n"), "d.vcd").unwrap();
    let v = compare_vcd(&e, "e.vcd", &d, "d.vcd").unwrap();
    let want = format!(
        "cycle {} (time {t} ns): signal count expected 0x{expected:x} got 0x{got:x}",
        t / 1000
    );
    assert_eq!(v, Verdict::Mismatch(want));
}

#[test]
fn check_names_a_missing_dut_signal() {
    let (config, stimulus) = small();
    let text = golden_text(&config, &stimulus);
    let e = Dump::parse(&text, "e.vcd").unwrap();
    let d = Dump::parse(&text.replace(" charge ", " chrg "), "d.vcd").unwrap();
    let err = compare_vcd(&e, "e.vcd", &d, "d.vcd")
        .unwrap_err()
        .to_string();
    assert!(err.contains("d.vcd") && err.contains("`charge`"), "{err}");
}

/// An Outputs stream of measurement outputs made under `config`.
fn encode_outputs(outputs: &[(u64, MeasureOutputs)], config: &MeasureConfig) -> Vec<u8> {
    let header = Header {
        stream: StreamKind::Outputs,
        tick_hz: 1_000_000,
        measure_hash: config.hash(),
        force_hash: 0,
    };
    binary::encode_output_stream(
        header,
        outputs
            .iter()
            .map(|&(t, o)| (t, binary::Output::Measure(o))),
    )
}

fn streams() -> (MeasureConfig, Vec<u8>, Vec<u8>) {
    let (config, stimulus) = small();
    let events = events_from_stimulus(&stimulus, &config);
    let outputs = outputs_after_each_event(&events, &config);
    (
        config,
        binary::encode_event_stream(&binary::InputStream::of_measure_events(
            &config, 1_000_000, &events,
        )),
        encode_outputs(&outputs, &config),
    )
}

#[test]
fn binary_streams_round_trip() {
    let (config, stimulus) = small();
    let events = events_from_stimulus(&stimulus, &config);
    let (_, ev, _) = streams();
    let back = binary::decode_event_stream(&ev, "events.ttv").unwrap();
    back.expect_measure_hash("events.ttv", config.hash())
        .unwrap();
    assert_eq!(back.measure_events(), events);
    assert_eq!(back.measure, Some(config));
    assert_eq!(back.header.tick_hz, 1_000_000);
}

#[test]
fn corrupt_binary_files_give_clear_errors() {
    let (config, ev, _) = streams();
    let err = |bytes: &[u8], hash: Option<u64>| {
        binary::decode_event_stream(bytes, "events.ttv")
            .and_then(|s| match hash {
                Some(h) => s.expect_measure_hash("events.ttv", h),
                None => Ok(()),
            })
            .unwrap_err()
            .to_string()
    };
    // Truncated in a record, and cut at a record boundary (no END).
    let e = err(&ev[..ev.len() - 15], None);
    assert!(e.contains("events.ttv") && e.contains("truncated"), "{e}");
    let e = err(&ev[..wire::HEADER_LEN + 41], None);
    assert!(e.contains("END") || e.contains("truncated"), "{e}");
    let e = err(&ev[..10], None);
    assert!(e.contains("truncated at byte 0"), "{e}");
    // Wrong magic, wrong version.
    let mut bad = ev.clone();
    bad[0] = b'X';
    assert!(err(&bad, None).contains("wrong magic"));
    let mut bad = ev.clone();
    bad[4] = 9;
    let e = err(&bad, None);
    assert!(e.contains("unsupported format version 9"), "{e}");
    // Configuration: another configuration's hash expected, and a header that lies.
    let e = err(&ev, Some(config.hash() ^ 1));
    assert!(
        e.contains("configuration hash") && e.contains("does not match"),
        "{e}"
    );
    let mut bad = ev.clone();
    bad[12] ^= 0xff;
    let e = err(&bad, None);
    assert!(e.contains("configuration hash"), "{e}");
    // Time going backwards: set the second event's time below the first's.
    let mut bad = ev.clone();
    let first_event =
        wire::HEADER_LEN + wire::RECORD_HEADER_LEN + wire::measure_config::CANONICAL_CONFIG_LEN;
    let second = first_event + wire::RECORD_HEADER_LEN + usize::from(ev[first_event + 1]);
    bad[second + 2..second + 10].copy_from_slice(&0u64.to_le_bytes());
    let e = err(&bad, None);
    assert!(e.contains("time goes backwards"), "{e}");
    // An Outputs stream where Events are expected.
    let h = Header {
        stream: StreamKind::Outputs,
        tick_hz: 1,
        measure_hash: config.hash(),
        force_hash: 0,
    };
    let e = err(&h.encode(), None);
    assert!(
        e.contains("Outputs") && e.contains("expected Events"),
        "{e}"
    );
}

#[test]
fn binary_check_names_record_field_and_values() {
    let (config, _, out) = streams();
    assert!(matches!(
        compare_binary(&out, "e.ttv", &out, "d.ttv").unwrap(),
        Verdict::Match(_)
    ));
    let records = binary::decode_output_stream(&out, "e.ttv").unwrap().measure;
    let i = records.len() / 2;
    let mut changed = records.clone();
    changed[i].1.charge ^= 4;
    let dut = encode_outputs(&changed, &config);
    let v = compare_binary(&out, "e.ttv", &dut, "d.ttv").unwrap();
    let want = format!(
        "record {i} (time {}): field charge expected 0x{:x} got 0x{:x}",
        records[i].0,
        records[i].1.charge,
        records[i].1.charge ^ 4
    );
    assert_eq!(v, Verdict::Mismatch(want));
    let short = encode_outputs(&records[..i], &config);
    let v = compare_binary(&out, "e.ttv", &short, "d.ttv").unwrap();
    assert!(
        matches!(v, Verdict::Mismatch(ref s) if s.contains(&format!("record {i}"))),
        "{v:?}"
    );
    let other = MeasureSettings {
        i_def: 33,
        pulses_per_rev: 64,
        glitch_cycles: 2,
        ..Default::default()
    }
    .validate()
    .unwrap();
    let dut = encode_outputs(&records, &other);
    let e = compare_binary(&out, "e.ttv", &dut, "d.ttv")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("d.ttv") && e.contains("configuration hash"),
        "{e}"
    );
}
