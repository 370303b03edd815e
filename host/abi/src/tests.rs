//! The ABI from Rust: every result equals the model's, and bad input is a status and a
//! message naming the culprit, never a panic.

use super::*;
use core::ptr::{null, null_mut};
use tooltouch_model::measure::config::MeasureSettings;

fn last_error() -> String {
    // SAFETY: tt_last_error returns a NUL-terminated string.
    unsafe { CStr::from_ptr(tt_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn config_of(measure: &MeasureConfig) -> *mut TtConfig {
    let (bytes, n) = measure.canonical_bytes();
    let mut config = null_mut();
    // SAFETY: valid pointers.
    let status = unsafe { tt_config_from_bytes(bytes.as_ptr(), n, &mut config) };
    assert_eq!(status, TtStatus::Ok, "{}", last_error());
    config
}

/// A small deterministic generator (xorshift64), enough to vary the pins.
fn next(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

#[test]
fn the_cycle_level_equals_the_model_on_every_clock() {
    let measure = MeasureSettings {
        glitch_cycles: 1,
        pulses_per_rev: 16,
        i_def: 4,
        ..Default::default()
    }
    .validate()
    .unwrap();
    let config = config_of(&measure);
    let mut fe = null_mut();
    // SAFETY: live handles, valid out-pointers throughout.
    unsafe {
        assert_eq!(tt_frontend_new(config, &mut fe), TtStatus::Ok);
        tt_config_free(config);
        let mut model = FrontEnd::new(&measure);
        let mut rng = 0x1234_5678_9abc_def0u64;
        let mut pins = 0u8;
        for cycle in 0..20_000 {
            if next(&mut rng).is_multiple_of(3) {
                pins ^= 1 << (next(&mut rng) % 6);
            }
            assert_eq!(tt_frontend_clock(fe, pins), TtStatus::Ok);
            model.clock(Pins(pins));
            let mut got = TtMeasureOutputs::default();
            assert_eq!(tt_frontend_outputs(fe, &mut got), TtStatus::Ok);
            assert_eq!(got, c_outputs(&model.outputs()), "cycle {cycle}");
            let mut bits = [0u64; TT_OUTPUT_COUNT as usize];
            assert_eq!(tt_frontend_registers(fe, bits.as_mut_ptr()), TtStatus::Ok);
            assert_eq!(
                bits,
                model.outputs().register_bits(&measure),
                "cycle {cycle}"
            );
        }
        let mut simulated = 0;
        assert_eq!(
            tt_frontend_advance(fe, pins, 1000, &mut simulated),
            TtStatus::Ok
        );
        let skipped = model.advance(Pins(pins), 1000, |_, _| {});
        assert_eq!(simulated, skipped);
        assert_eq!(tt_frontend_reset(fe), TtStatus::Ok);
        let mut got = TtMeasureOutputs::default();
        tt_frontend_outputs(fe, &mut got);
        assert_eq!(got, c_outputs(&FrontEnd::new(&measure).outputs()));
        tt_frontend_free(fe);
    }
}

#[test]
fn the_mcu_words_follow_the_register_map() {
    let measure = MeasureConfig::default();
    let o = MeasureOutputs {
        armed: true,
        register_now: true,
        density_fired: true,
        position: -2,
        decision_position: 5,
        first_contact_position: -1,
        count: 7,
        last_window_count: 9,
        charge: 300,
        revolutions: 3,
        pulses: 77,
        scale_errors: 4,
        confirmed: true,
        faults: 0b100_0010,
        ..Default::default()
    };
    let word = |addr, diagnostics| mcu_word(&measure, measure.hash(), &o, addr, diagnostics);
    // Flags in bits 6..0 (confirmed is bit 6), the faults word in bits 14..8.
    assert_eq!(word(0, false), 0b100_0010_0110_0101);
    assert_eq!(word(1, false), (-2i32) as u32);
    assert_eq!(word(2, false), 5);
    assert_eq!(word(3, false), u32::MAX);
    assert_eq!(
        (word(4, false), word(5, false), word(6, false)),
        (7, 9, 300)
    );
    assert_eq!((word(7, false), word(8, false)), (0, 0));
    assert_eq!((word(7, true), word(8, true)), (3, 77));
    assert_eq!(word(9, false), 4);
    let hash = measure.hash();
    assert_eq!(
        u64::from(word(11, false)) << 32 | u64::from(word(10, false)),
        hash
    );
    assert!((12..16).all(|a| word(a, true) == 0));
}

#[test]
fn the_event_level_and_the_force_kernel_equal_the_model() {
    let measure = MeasureConfig::default();
    let config = config_of(&measure);
    let force = ForceSettings::default().validate().unwrap();
    // SAFETY: live handles, valid out-pointers throughout.
    unsafe {
        let mut m = null_mut();
        assert_eq!(tt_measurement_new(config, &mut m), TtStatus::Ok);
        let mut model = Measurement::new(&measure);
        let events = [
            (
                TtMeasureEvent {
                    kind: TT_MEASURE_EVENT_ARM,
                    level: 1,
                    ..Default::default()
                },
                MeasureEvent::Arm(true),
            ),
            (
                TtMeasureEvent {
                    kind: TT_MEASURE_EVENT_CONTACT,
                    level: 1,
                    ..Default::default()
                },
                MeasureEvent::Contact(true),
            ),
            (
                TtMeasureEvent {
                    kind: TT_MEASURE_EVENT_FES,
                    ..Default::default()
                },
                MeasureEvent::Fes,
            ),
            (
                TtMeasureEvent {
                    kind: TT_MEASURE_EVENT_SCALE,
                    scale_a: 1,
                    ..Default::default()
                },
                MeasureEvent::Scale { a: true, b: false },
            ),
            (
                TtMeasureEvent {
                    kind: TT_MEASURE_EVENT_INDEX,
                    ..Default::default()
                },
                MeasureEvent::Index,
            ),
            (
                TtMeasureEvent {
                    kind: TT_MEASURE_EVENT_PRESET_PULSES,
                    pulses: u32::MAX,
                    ..Default::default()
                },
                MeasureEvent::PresetPulses(u32::MAX),
            ),
            (
                TtMeasureEvent {
                    kind: TT_MEASURE_EVENT_FES,
                    ..Default::default()
                },
                MeasureEvent::Fes,
            ),
        ];
        for (c, e) in events {
            assert_eq!(tt_measurement_apply(m, &c), TtStatus::Ok);
            model.apply(e);
            let mut got = TtMeasureOutputs::default();
            tt_measurement_outputs(m, &mut got);
            assert_eq!(got, c_outputs(&model.outputs()), "{e:?}");
        }
        tt_measurement_free(m);

        let mut f = null_mut();
        assert_eq!(tt_force_new(config, &mut f), TtStatus::Ok);
        let mut kernel = ForceKernel::new(&force);
        let adc = TtAdcCodes {
            speed: 1200,
            power: 900,
            force: 2300,
            volts: [2100, 2000, 2048],
            amps: [2060, 2040],
        };
        let mut sequence = vec![TtForceEvent {
            kind: TT_FORCE_EVENT_CONTROL,
            on: 1,
            ..Default::default()
        }];
        for _ in 0..4 {
            sequence.extend((0..50).map(|_| TtForceEvent {
                kind: TT_FORCE_EVENT_SAMPLE,
                adc,
                ..Default::default()
            }));
            sequence.push(TtForceEvent {
                kind: TT_FORCE_EVENT_TICK,
                ..Default::default()
            });
        }
        sequence.push(TtForceEvent {
            kind: TT_FORCE_EVENT_CONDITIONS,
            conditions: 200,
            ..Default::default()
        });
        for e in &sequence {
            assert_eq!(tt_force_apply(f, e), TtStatus::Ok);
            kernel.apply(force_event(e).unwrap_or_else(|_| unreachable!()));
            let mut got = TtForceOutputs::default();
            tt_force_outputs(f, &mut got);
            let o = kernel.outputs();
            assert_eq!(
                (got.override_pct, got.bad_events),
                (o.override_pct, o.bad_events)
            );
            assert_eq!(got.force_estimate, o.force_estimate.to_bits());
            assert_eq!(got.wear_allowed, o.wear_allowed.to_bits());
        }
        tt_force_free(f);
        tt_config_free(config);
    }
}

#[test]
fn bad_input_is_a_status_and_a_message() {
    // SAFETY: the pointers are NULL or valid.
    unsafe {
        let mut config = null_mut();
        assert_eq!(
            tt_config_from_bytes(null(), 0, &mut config),
            TtStatus::NullPointer
        );
        assert!(last_error().contains("bytes is NULL"));
        assert_eq!(
            tt_config_from_bytes(b"nonsense".as_ptr(), 8, &mut config),
            TtStatus::BadConfig
        );
        assert!(last_error().contains("TTFWCFG1"), "{}", last_error());
        let (mut bytes, n) = MeasureConfig::default().canonical_bytes();
        bytes[4..8].copy_from_slice(&5000u32.to_le_bytes()); // i_def above the window
        assert_eq!(
            tt_config_from_bytes(bytes.as_ptr(), n, &mut config),
            TtStatus::BadConfig
        );
        assert!(last_error().contains("i_def"), "{}", last_error());
        let mut file = b"TTFWCFG1".to_vec();
        file.extend_from_slice(&31u16.to_le_bytes());
        file.extend_from_slice(&MeasureConfig::default().canonical_bytes().0[..31]);
        assert_eq!(
            tt_config_from_bytes(file.as_ptr(), file.len(), &mut config),
            TtStatus::BadConfig
        );
        assert!(
            last_error().contains("force configuration's length"),
            "{}",
            last_error()
        );
        assert_eq!(
            tt_config_from_file(c"/nonexistent/tt.ttc".as_ptr(), &mut config),
            TtStatus::Io
        );
        assert!(
            last_error().starts_with("/nonexistent/tt.ttc: "),
            "{}",
            last_error()
        );

        let config = config_of(&MeasureConfig::default());
        let mut fe = null_mut();
        assert_eq!(tt_frontend_new(config, &mut fe), TtStatus::Ok);
        assert_eq!(tt_frontend_clock(fe, 0x40), TtStatus::BadArgument);
        assert!(last_error().contains("pins 0x40"), "{}", last_error());
        assert_eq!(tt_frontend_clock(null_mut(), 0), TtStatus::NullPointer);
        assert!(last_error().contains("front_end is NULL"));
        let mut word = 0;
        assert_eq!(
            tt_frontend_mcu_read(fe, 16, false, &mut word),
            TtStatus::BadArgument
        );
        assert!(last_error().contains("MCU address 16"));
        let mut width = 0;
        assert_eq!(
            tt_config_output_width(config, 15, &mut width),
            TtStatus::BadArgument
        );
        assert_eq!(tt_config_output_width(config, 3, &mut width), TtStatus::Ok);
        assert_eq!(width, 24);
        // The default force settings' sampling (this configuration has no force part).
        let (mut hz, mut spp) = (0, 0);
        assert_eq!(
            tt_config_force_rates(config, &mut hz, &mut spp),
            TtStatus::Ok
        );
        assert_eq!((hz, spp), (1000, 50));
        assert_eq!(
            tt_config_force_rates(config, null_mut(), &mut spp),
            TtStatus::NullPointer
        );
        assert!(last_error().contains("sample_hz is NULL"));
        let mut m = null_mut();
        tt_measurement_new(config, &mut m);
        let e = TtMeasureEvent {
            kind: TT_MEASURE_EVENT_ARM,
            level: 2,
            ..Default::default()
        };
        assert_eq!(tt_measurement_apply(m, &e), TtStatus::BadArgument);
        assert!(last_error().contains("level is 2"));
        let e = TtMeasureEvent {
            kind: 0x20,
            ..Default::default()
        };
        assert_eq!(tt_measurement_apply(m, &e), TtStatus::BadArgument);
        let mut f = null_mut();
        tt_force_new(config, &mut f);
        let e = TtForceEvent {
            kind: 0x02,
            ..Default::default()
        };
        assert_eq!(tt_force_apply(f, &e), TtStatus::BadArgument);
        assert!(last_error().contains("force event kind 0x02"));
        assert!(tt_output_name(15).is_null());
        assert_eq!(CStr::from_ptr(tt_output_name(14)), c"pulses");
        tt_force_free(f);
        tt_measurement_free(m);
        tt_frontend_free(fe);
        tt_config_free(config);
        assert_eq!(tt_abi_version(), TT_ABI_VERSION);
    }
}

#[test]
fn a_caught_panic_is_a_status() {
    assert_eq!(guard(|| panic!("test")), TtStatus::Panic);
    assert!(last_error().contains("panicked"));
}

#[test]
fn a_long_message_is_cut_not_overflowed() {
    let long = "é".repeat(ERROR_CAPACITY);
    fail(TtStatus::BadArgument, format_args!("{long}"));
    let text = last_error();
    assert!(text.len() < ERROR_CAPACITY && text.chars().all(|c| c == 'é'));
}

#[test]
fn every_output_is_named_as_in_the_models_list() {
    for (index, (name, _)) in (0u32..).zip(MeasureOutputs::LAYOUT) {
        // SAFETY: a non-NULL result is a static NUL-terminated string.
        let got = unsafe { CStr::from_ptr(tt_output_name(index)) };
        assert_eq!(got.to_str(), Ok(name), "output {index}");
    }
    assert!(tt_output_name(TT_OUTPUT_COUNT).is_null());
    assert!(tt_output_name(u32::MAX).is_null());
}
