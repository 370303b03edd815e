//! The entry functions of the fuzz targets: one per decoder or parser that reads what a
//! user or a device hands tooltouch. Each takes arbitrary bytes and must return without
//! a panic, a hang or unbounded memory, whatever the bytes; errors are the expected
//! outcome for most inputs and are dropped.
//!
//! The functions live in this library, not in the target binaries, so that two drivers
//! share them: the libFuzzer binaries of `fuzz_targets/` (built by `cargo xtask fuzz` with
//! coverage instrumentation, feature `libfuzzer`), and the plain test
//! `tests/regressions.rs`, which replays the committed seed corpus and every input that
//! once failed (`fuzz/corpus/<target>/`, `fuzz/regressions/<target>/`) on the stable
//! toolchain with no special flag.

use std::io::Read;
use tooltouch_model::wire::force_chunks::ForceConfigAssembler;
use tooltouch_model::MeasureConfig;
use tooltouch_vectors::{binary, check, stimulus_file, vcd};

/// A target's entry function: any bytes in, nothing out, never a panic.
pub type Entry = fn(&[u8]);

/// Every target, by name: the binary of `fuzz_targets/`, the folders of its corpus and
/// regressions, and its entry function.
pub const TARGETS: &[(&str, Entry)] = &[
    ("ttv_outputs", ttv_outputs),
    ("ttv_events", ttv_events),
    ("force_chunks", force_chunks),
    ("vcd", vcd),
    ("stimulus", stimulus),
    ("settings", settings),
    ("tune_spec", tune_spec),
    ("tune_merge", tune_merge),
    ("abi", abi),
];

/// A reader that hands out at most `step` bytes per `read` call, so the streaming
/// readers meet records split across reads as they do at a buffer's edge.
struct Trickle<'a> {
    bytes: &'a [u8],
    step: usize,
}

impl Read for Trickle<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.step).min(self.bytes.len());
        buf[..n].copy_from_slice(&self.bytes[..n]);
        self.bytes = &self.bytes[n..];
        Ok(n)
    }
}

/// Outputs streams (`expected_outputs.ttv`, a firmware trace): the whole-file decoder,
/// the record-by-record reader fed in odd-sized pieces (it must give the same result),
/// and `check`'s streaming comparison of the stream with itself.
pub fn ttv_outputs(data: &[u8]) {
    let whole = binary::decode_output_stream(data, "fuzz.ttv");
    let streamed = (|| {
        let step = usize::from(data.first().copied().unwrap_or(1) % 7) + 1;
        let mut r = binary::OutputReader::new(Trickle { bytes: data, step }, "fuzz.ttv")?;
        let mut n = 0usize;
        while r.next_output()?.is_some() {
            n += 1;
        }
        Ok::<_, binary::BinaryError>(n)
    })();
    match (&whole, &streamed) {
        (Ok(s), Ok(n)) => assert_eq!(s.measure.len() + s.force.len(), *n),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
        _ => panic!("whole-file and streamed decoding disagree: {whole:?} vs {streamed:?}"),
    }
    if whole.is_ok() {
        let v = check::compare_binary(data, "e.ttv", data, "d.ttv");
        assert!(
            matches!(v, Ok(check::Verdict::Match(_))) || v.is_err(),
            "a stream must match itself: {v:?}"
        );
    }
}

/// Input streams (`events.ttv`, force event files): measurement events, force events and
/// the force configuration chunks, through the decoder of input streams, whole and fed in
/// odd-sized pieces (both must give the same result).
pub fn ttv_events(data: &[u8]) {
    let whole = binary::decode_event_stream(data, "fuzz.ttv");
    let step = usize::from(data.first().copied().unwrap_or(1) % 7) + 1;
    let streamed = binary::read_event_stream(Trickle { bytes: data, step }, "fuzz.ttv");
    match (&whole, &streamed) {
        (Ok(a), Ok(b)) => assert_eq!(a, b),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
        _ => panic!("whole-file and streamed decoding disagree: {whole:?} vs {streamed:?}"),
    }
    if let Ok(stream) = whole {
        // What decodes re-encodes to a stream that decodes to the same thing.
        let again = binary::encode_event_stream(&stream);
        let back = binary::decode_event_stream(&again, "again.ttv");
        assert_eq!(
            back.ok().as_ref(),
            Some(&stream),
            "re-encoded stream differs"
        );
    }
}

/// Force configuration chunks on their own: the first 8 bytes are the header's
/// `force_hash`, then each chunk is a length byte and that many payload bytes; and the
/// same bytes as one canonical force configuration.
pub fn force_chunks(data: &[u8]) {
    let (hash, mut rest) = match data.split_first_chunk::<8>() {
        Some((h, rest)) => (u64::from_le_bytes(*h), rest),
        None => (0, data),
    };
    let mut a = ForceConfigAssembler::new();
    while let Some((&len, tail)) = rest.split_first() {
        let n = usize::from(len).min(tail.len());
        let _ = a.push(&tail[..n]);
        rest = &tail[n..];
    }
    let _ = a.finish(hash);
    if let Ok(settings) = tooltouch_model::wire::force_config::decode_force_settings(data) {
        let _ = settings.validate();
    }
}

/// VCD: the streaming reader over every item, and when the bytes are a golden file,
/// `check`'s comparison of the file with itself.
pub fn vcd(data: &[u8]) {
    let Ok(mut r) = vcd::VcdReader::new(data, "fuzz.vcd") else {
        return;
    };
    let mut items = 0u64;
    while let Ok(Some(_)) = r.next_item() {
        items += 1;
    }
    let _ = items;
    let (Ok(mut e), Ok(mut d)) = (
        vcd::VcdReader::new(data, "e.vcd"),
        vcd::VcdReader::new(data, "d.vcd"),
    ) else {
        return;
    };
    let (ed, dd) = (e.declarations().clone(), d.declarations().clone());
    let _ = check::compare_vcd_sides(
        &mut check::VcdSide {
            name: "e.vcd",
            declarations: &ed,
            changes: &mut e,
        },
        &mut check::VcdSide {
            name: "d.vcd",
            declarations: &dd,
            changes: &mut d,
        },
        &Vec::new,
    );
}

/// A user's stimulus for `tooltouch vectors` and `hdl --vectors`: the dispatcher over
/// VCD pins, input event streams and run-length pins (`stim.hex`, the testbench's
/// `$readmemh` words), and one word of an `expect.hex` explained.
pub fn stimulus(data: &[u8]) {
    let _ = stimulus_file::read_from(data, "fuzz.stim", None);
    if let Ok(word) = std::str::from_utf8(data) {
        let _ = tooltouch_vectors::hex::describe_word(&MeasureConfig::default(), word.trim());
    }
}

/// A settings file (`[measure]` and `[lathe]`), parsed and validated.
pub fn settings(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(s) = tooltouch_settings::Settings::parse(text, "fuzz.toml") {
        let _ = s.resolve();
    }
}

/// A tune sweep spec (`--spec` TOML), parsed and counted (its points listed, not run).
pub fn tune_spec(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(spec) = tooltouch_tune::SweepSpec::from_toml(text) {
        let _ = tooltouch_tune::points_in(&spec, None);
    }
}

/// A shard's `results.json`, read and merged with itself and alone.
pub fn tune_merge(data: &[u8]) {
    let Ok(r) = serde_json::from_slice::<tooltouch_tune::Results>(data) else {
        return;
    };
    let _ = tooltouch_tune::merge(std::slice::from_ref(&r));
    let _ = tooltouch_tune::merge(&[r.clone(), r]);
}

/// The C ABI (`tooltouch-abi`): a configuration from the first `n` bytes (`n` the first two
/// bytes, little-endian; a `tooltouch cosim config` file or canonical bytes), then — when
/// it decodes — the cycle level, the event level and the force kernel driven by the rest,
/// out-of-range pins, MCU addresses and event kinds included. The ABI catches panics at
/// its boundary, so a caught one (`TtStatus::Panic`) fails here.
pub fn abi(data: &[u8]) {
    use core::ptr::null_mut;
    use tooltouch_abi::*;
    fn no_panic(status: TtStatus) {
        assert_ne!(status, TtStatus::Panic, "the C ABI caught a panic");
    }
    let (n, rest) = match data.split_first_chunk::<2>() {
        Some((n, rest)) => (usize::from(u16::from_le_bytes(*n)).min(rest.len()), rest),
        None => return,
    };
    let (config_bytes, drive) = rest.split_at(n);
    let mut config = null_mut();
    // SAFETY: every pointer is valid for the call; handles are freed once.
    unsafe {
        let status = tt_config_from_bytes(config_bytes.as_ptr(), config_bytes.len(), &mut config);
        no_panic(status);
        if status != TtStatus::Ok {
            return;
        }
        let (mut fe, mut m, mut f) = (null_mut(), null_mut(), null_mut());
        no_panic(tt_frontend_new(config, &mut fe));
        no_panic(tt_measurement_new(config, &mut m));
        no_panic(tt_force_new(config, &mut f));
        let mut registers = [0u64; TT_OUTPUT_COUNT as usize];
        let mut time = 0u64;
        for chunk in drive.chunks(4) {
            let [a, b, c, d] = [0, 1, 2, 3].map(|i| chunk.get(i).copied().unwrap_or(0));
            no_panic(tt_frontend_clock(fe, a));
            let mut simulated = 0;
            no_panic(tt_frontend_advance(
                fe,
                a & 0x3f,
                u64::from(b),
                &mut simulated,
            ));
            let mut word = 0;
            no_panic(tt_frontend_mcu_read(
                fe,
                u32::from(c),
                d & 1 != 0,
                &mut word,
            ));
            no_panic(tt_frontend_registers(fe, registers.as_mut_ptr()));
            let event = TtMeasureEvent {
                kind: b,
                level: c,
                scale_a: d & 1,
                scale_b: d >> 1 & 1,
                pulses: u32::from_le_bytes([a, b, c, d]),
                // Mostly forwards, now and then backwards (refused, never a panic).
                time: if d == 0xff {
                    time / 2
                } else {
                    time + u64::from(a)
                },
            };
            if tt_measurement_apply(m, &event) == TtStatus::Ok {
                time = event.time;
            }
            let observed = tt_measurement_observe(m, time + u64::from(c));
            no_panic(observed);
            if observed == TtStatus::Ok {
                time += u64::from(c);
            }
            let mut outputs = TtMeasureOutputs::default();
            no_panic(tt_measurement_outputs_at(
                m,
                time + u64::from(d),
                &mut outputs,
            ));
            let force = TtForceEvent {
                kind: c,
                on: d,
                conditions: a,
                adc: TtAdcCodes {
                    speed: u16::from_le_bytes([a, b]),
                    power: u16::from_le_bytes([c, d]),
                    force: u16::from(d) << 4,
                    volts: [u16::from(a) << 4; 3],
                    amps: [u16::from(b) << 4; 2],
                },
            };
            no_panic(tt_force_apply(f, &force));
        }
        let mut outputs = TtForceOutputs::default();
        no_panic(tt_force_outputs(f, &mut outputs));
        tt_force_free(f);
        tt_measurement_free(m);
        tt_frontend_free(fe);
        tt_config_free(config);
    }
}
