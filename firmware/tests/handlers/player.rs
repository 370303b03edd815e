//! Host tests of the lathe player's schedule (`tooltouch_firmware::player`): the steps
//! replayed on simulated pins must reproduce every event of the stream, in order, within
//! half a timer tick of its time, with every pulse a separate high and low.

use tooltouch_firmware::model::wire::measure_event::decode_event;
use tooltouch_firmware::model::wire::{kind, Header, Record, Records, StreamKind, WireError};
use tooltouch_firmware::model::MeasureEvent;
use tooltouch_firmware::player::{
    PinMap, PlayerError, Schedule, Step, StepKind, Summary, MAX_PULSE_TICKS, NUCLEO_PINS,
    NUCLEO_TIMER_HZ,
};

/// The demo stream the player image embeds by default.
const DEMO: &[u8] = include_bytes!("../../tooltouch-events.bin");

/// An event stream of `records` (kind, time, payload) at `tick_hz`, ended by `END` at the
/// last time.
fn stream(tick_hz: u32, records: &[(u8, u64, &[u8])]) -> Vec<u8> {
    let mut out = Header {
        stream: StreamKind::Events,
        tick_hz,
        measure_hash: 1,
        force_hash: 0,
    }
    .encode()
    .to_vec();
    let end = records.last().map_or(0, |r| r.1);
    for &(k, t, p) in records.iter().chain([(kind::END, end, &[][..])].iter()) {
        let mut buf = [0u8; 64];
        let n = Record::new(k, t, p).encode(&mut buf).unwrap();
        out.extend_from_slice(&buf[..n]);
    }
    out
}

/// The stream's measurement events with their times, read with the model's decoder.
fn events(bytes: &[u8]) -> (Header, Vec<(u64, MeasureEvent)>) {
    let (header, records) = Records::new(bytes).unwrap();
    let mut out = Vec::new();
    for record in records {
        let record = record.unwrap();
        if let Ok(Some(e)) = decode_event(&record, 0) {
            out.push((record.time, e));
        }
    }
    (header, out)
}

fn schedule(bytes: &[u8]) -> (Summary, Vec<Step>) {
    let (_, summary, steps) = Schedule::new(bytes, NUCLEO_TIMER_HZ, NUCLEO_PINS).unwrap();
    (summary, steps.collect())
}

/// Simulated output port: applies a BSRR word as the hardware does (set wins).
fn apply(odr: u32, bsrr: u32) -> u32 {
    (odr & !(bsrr >> 16)) | (bsrr & 0xffff)
}

/// Checks `steps` against the stream `bytes`: order, time within half a tick, the pins'
/// levels after each event, pulses high and low for at least a tick.
fn check(bytes: &[u8], summary: &Summary, steps: &[Step]) {
    let (header, expected) = events(bytes);
    let pins: PinMap = NUCLEO_PINS;
    let bit = |p: u8| 1u32 << p;
    // Steps in time order, and only the player's pins.
    assert!(
        steps.windows(2).all(|w| w[0].at <= w[1].at),
        "steps out of order"
    );
    assert!(steps
        .iter()
        .all(|s| s.bsrr & !(pins.all_low() | pins.mask()) == 0));
    // The events, in the stream's order.
    let played: Vec<&Step> = steps
        .iter()
        .filter(|s| matches!(s.what, StepKind::Event(_)))
        .collect();
    assert_eq!(played.len(), expected.len());
    assert_eq!(summary.events as usize, expected.len());
    let tick_s = 1.0 / f64::from(NUCLEO_TIMER_HZ);
    for (step, (t, e)) in played.iter().zip(&expected) {
        assert_eq!(step.what, StepKind::Event(*e));
        let want = *t as f64 / f64::from(header.tick_hz);
        let got = step.at as f64 * tick_s;
        assert!(
            (got - want).abs() <= tick_s / 2.0 + 1e-15,
            "{e:?} at {want} s played at {got} s"
        );
    }
    // Replay on the port: after each event its pins hold its levels; pulses alternate.
    let mut odr = 0u32;
    let (mut fes_rises, mut fes_falls, mut index_rises, mut index_falls) = (0, 0, 0, 0);
    let mut fes_rose_at = None::<u64>;
    let mut fes_fell_at = None::<u64>;
    for s in steps {
        let before = odr;
        odr = apply(odr, s.bsrr);
        match s.what {
            StepKind::Event(MeasureEvent::Arm(l)) => assert_eq!(odr & bit(pins.arm) != 0, l),
            StepKind::Event(MeasureEvent::Contact(l)) => {
                assert_eq!(odr & bit(pins.contact) != 0, l)
            }
            StepKind::Event(MeasureEvent::Scale { a, b }) => {
                assert_eq!(odr & bit(pins.scale_a) != 0, a);
                assert_eq!(odr & bit(pins.scale_b) != 0, b);
            }
            StepKind::Event(MeasureEvent::Fes) => {
                assert_eq!(before & bit(pins.fes), 0, "FES rises from low");
                assert_ne!(odr & bit(pins.fes), 0);
                if let Some(f) = fes_fell_at {
                    assert!(s.at > f, "FES low for at least a tick");
                }
                fes_rose_at = Some(s.at);
                fes_rises += 1;
            }
            StepKind::FesFall => {
                assert_ne!(before & bit(pins.fes), 0, "FES falls from high");
                assert_eq!(odr & bit(pins.fes), 0);
                assert_eq!(s.at - fes_rose_at.unwrap(), summary.fes_width);
                fes_fell_at = Some(s.at);
                fes_falls += 1;
            }
            StepKind::Event(MeasureEvent::Index) => {
                assert_eq!(before & bit(pins.index), 0, "index rises from low");
                index_rises += 1;
            }
            StepKind::IndexFall => {
                assert_ne!(before & bit(pins.index), 0, "index falls from high");
                index_falls += 1;
            }
            StepKind::Event(MeasureEvent::PresetPulses(_)) => panic!("no pin"),
        }
        // A step changes only its own pins.
        let own = match s.what {
            StepKind::Event(MeasureEvent::Arm(_)) => bit(pins.arm),
            StepKind::Event(MeasureEvent::Contact(_)) => bit(pins.contact),
            StepKind::Event(MeasureEvent::Scale { .. }) => bit(pins.scale_a) | bit(pins.scale_b),
            StepKind::Event(MeasureEvent::Fes) | StepKind::FesFall => bit(pins.fes),
            _ => bit(pins.index),
        };
        assert_eq!((odr ^ before) & !own, 0);
    }
    let count = |k: MeasureEvent| expected.iter().filter(|(_, e)| *e == k).count();
    assert_eq!(fes_rises, count(MeasureEvent::Fes));
    assert_eq!(fes_falls, fes_rises, "every FES pulse falls");
    assert_eq!(summary.fes_pulses as usize, fes_rises);
    assert_eq!(index_rises, count(MeasureEvent::Index));
    assert_eq!(index_falls, index_rises);
    assert_eq!(summary.index_pulses as usize, index_rises);
    assert_eq!(odr & (bit(pins.fes) | bit(pins.index)), 0, "pulses end low");
    assert_eq!(steps.last().map_or(0, |s| s.at), summary.end);
}

#[test]
fn demo_stream_plays_every_event_in_order_within_half_a_tick() {
    let (summary, steps) = schedule(DEMO);
    check(DEMO, &summary, &steps);
    // The demo stream (1 MHz ticks, 4800 rpm): 8538 FES pulses at least 12 µs apart, 9
    // index pulses at least 12.5 ms apart, so 6 µs and 1 ms (the cap) wide at 84 MHz.
    assert_eq!(summary.fes_pulses, 8538);
    assert_eq!(summary.index_pulses, 9);
    assert_eq!(summary.fes_width, 504);
    assert_eq!(summary.index_width, MAX_PULSE_TICKS);
    assert_eq!(steps.len(), summary.events as usize + 8538 + 9);
    assert_eq!(summary.force_skipped, 0);
}

#[test]
fn fifty_mhz_stream_rounds_to_the_nearest_tick() {
    // 50 MHz stream ticks = 1.68 timer ticks: 1 -> 2 (1.68), 3 -> 5 (5.04), 4 -> 7 (6.72).
    let bytes = stream(
        50_000_000,
        &[
            (kind::MEASURE_CONFIG, 0, &[0; 4]),
            (kind::ARM, 1, &[1]),
            (kind::FES, 3, &[]),
            (kind::FES, 4, &[]),
            (kind::CONTACT, 4, &[1]),
            (kind::SCALE, 4, &[2]),
        ],
    );
    let (summary, steps) = schedule(&bytes);
    check(&bytes, &summary, &steps);
    let times: Vec<(u64, StepKind)> = steps.iter().map(|s| (s.at, s.what)).collect();
    // FES 2 ticks apart: 1 tick wide; the first pulse falls before the second rises.
    assert_eq!(summary.fes_width, 1);
    assert_eq!(
        times,
        [
            (2, StepKind::Event(MeasureEvent::Arm(true))),
            (5, StepKind::Event(MeasureEvent::Fes)),
            (6, StepKind::FesFall),
            (7, StepKind::Event(MeasureEvent::Fes)),
            (7, StepKind::Event(MeasureEvent::Contact(true))),
            (
                7,
                StepKind::Event(MeasureEvent::Scale { a: false, b: true })
            ),
            (8, StepKind::FesFall),
        ]
    );
    assert_eq!(steps[0].bsrr, 1 << NUCLEO_PINS.arm);
    assert_eq!(
        steps[5].bsrr,
        1 << (NUCLEO_PINS.scale_a + 16) | 1 << NUCLEO_PINS.scale_b
    );
}

#[test]
fn force_records_are_skipped_and_counted() {
    let bytes = stream(
        1_000_000,
        &[
            (kind::ARM, 10, &[1]),
            (kind::TICK, 11, &[]),
            (kind::CONTROL, 12, &[1]),
            (kind::FES, 13, &[]),
        ],
    );
    let (summary, steps) = schedule(&bytes);
    check(&bytes, &summary, &steps);
    assert_eq!(summary.force_skipped, 2);
    assert_eq!(summary.events, 2);
}

#[test]
fn unplayable_streams_are_refused_before_any_step() {
    let err = |bytes: &[u8]| Schedule::new(bytes, NUCLEO_TIMER_HZ, NUCLEO_PINS).err();
    // The test event has no pin.
    let preset = stream(
        1_000_000,
        &[(kind::ARM, 1, &[1]), (kind::PRESET_PULSES, 2, &[0; 4])],
    );
    assert_eq!(
        err(&preset),
        Some(PlayerError::Unplayable {
            kind: kind::PRESET_PULSES,
            offset: 28 + 11
        })
    );
    // Two FES pulses in one timer tick.
    let close = stream(168_000_000, &[(kind::FES, 1, &[]), (kind::FES, 2, &[])]);
    assert_eq!(err(&close), Some(PlayerError::PulsesTooClose(1)));
    // Not an event stream; bad magic; a bad level; no END; a second stream.
    let mut outputs = stream(1_000_000, &[(kind::ARM, 1, &[1])]);
    outputs[6] = 2;
    assert_eq!(err(&outputs), Some(PlayerError::NotEvents));
    assert!(matches!(
        err(&outputs[1..]),
        Some(PlayerError::Wire(WireError::BadMagic(_)))
    ));
    let level = stream(1_000_000, &[(kind::ARM, 1, &[2])]);
    assert!(matches!(
        err(&level),
        Some(PlayerError::Wire(WireError::BadLength { .. }))
    ));
    let whole = stream(1_000_000, &[(kind::ARM, 1, &[1])]);
    assert_eq!(
        err(&whole[..whole.len() - 10]),
        Some(PlayerError::MissingEnd)
    );
    let two = [whole.clone(), whole.clone()].concat();
    assert_eq!(err(&two), Some(PlayerError::TrailingBytes(whole.len())));
    // Time going backwards; a time too large for the timer; a zero rate.
    let back = stream(1_000_000, &[(kind::ARM, 5, &[1]), (kind::ARM, 4, &[0])]);
    assert!(matches!(
        err(&back),
        Some(PlayerError::Wire(WireError::NonMonotonicTime { .. }))
    ));
    let late = stream(1, &[(kind::ARM, u64::MAX / 2, &[1])]);
    assert_eq!(err(&late), Some(PlayerError::TimeOverflow(u64::MAX / 2)));
    assert_eq!(err(&stream(0, &[])), Some(PlayerError::ZeroRate));
    assert_eq!(
        Schedule::new(&whole, 0, NUCLEO_PINS).err(),
        Some(PlayerError::ZeroRate)
    );
}

#[test]
fn pin_map_words() {
    assert_eq!(NUCLEO_PINS.mask(), 0b11_0000_1111);
    assert_eq!(NUCLEO_PINS.all_low(), 0b11_0000_1111 << 16);
}

proptest::proptest! {
    #![proptest_config(crate::proptest_config())]

    /// Random streams at rates below, at and above the timer's: either the schedule passes
    /// every check above, or two pulses of one kind really are less than 2 ticks apart.
    #[test]
    fn random_streams_play_or_are_refused_for_close_pulses(
        rate in proptest::sample::select(vec![1_000_000u32, 50_000_000, 84_000_000, 200_000_000]),
        raw in proptest::collection::vec((0u64..400, 0u8..5, proptest::bool::ANY, proptest::bool::ANY), 1..200),
    ) {
        let mut t = 0;
        let payloads: Vec<(u8, u64, Vec<u8>)> = raw
            .iter()
            .map(|&(dt, k, x, y)| {
                t += dt;
                match k {
                    0 => (kind::ARM, t, vec![u8::from(x)]),
                    1 => (kind::CONTACT, t, vec![u8::from(x)]),
                    2 => (kind::INDEX, t, vec![]),
                    3 => (kind::FES, t, vec![]),
                    _ => (kind::SCALE, t, vec![u8::from(x) | u8::from(y) << 1]),
                }
            })
            .collect();
        let records: Vec<(u8, u64, &[u8])> =
            payloads.iter().map(|(k, t, p)| (*k, *t, &p[..])).collect();
        let bytes = stream(rate, &records);
        match Schedule::new(&bytes, NUCLEO_TIMER_HZ, NUCLEO_PINS) {
            Ok((_, summary, steps)) => {
                let steps: Vec<Step> = steps.collect();
                check(&bytes, &summary, &steps);
            }
            Err(PlayerError::PulsesTooClose(at)) => {
                // Some pulse kind has two rises less than 2 ticks apart, the later at `at`.
                let ticks = |t: u64| (t * u64::from(NUCLEO_TIMER_HZ) + u64::from(rate) / 2) / u64::from(rate);
                let close = [kind::INDEX, kind::FES].iter().any(|&k| {
                    let rises: Vec<u64> =
                        records.iter().filter(|r| r.0 == k).map(|r| ticks(r.1)).collect();
                    rises.windows(2).any(|w| w[1] - w[0] < 2 && w[1] == at)
                });
                proptest::prop_assert!(close, "refused at {at} without close pulses");
            }
            Err(e) => proptest::prop_assert!(false, "{e:?}"),
        }
    }
}
