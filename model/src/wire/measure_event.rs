//! Measurement event records (kinds [`kind::ARM`]..=[`kind::PRESET_PULSES`]): one record
//! per [`MeasureEvent`], its level or scale lines in the payload.
//!
//! | event | kind | payload |
//! |---|---|---|
//! | `Arm(level)`, `Contact(level)` | `ARM`, `CONTACT` | level, 1 byte: 0 or 1 |
//! | `Index`, `Fes` | `INDEX`, `FES` | none |
//! | `Scale { a, b }` | `SCALE` | 1 byte: bit 0 = A, bit 1 = B |
//! | `PresetPulses(n)` | `PRESET_PULSES` | n, u32 LE |

use crate::measure::events::MeasureEvent;
use crate::wire::{kind, le_u32, Record, WireError};

/// Bit of line A in a [`kind::SCALE`] payload.
const SCALE_A: u8 = 1;
/// Bit of line B in a [`kind::SCALE`] payload.
const SCALE_B: u8 = 2;

/// Encodes a measurement event as a record at `time`.
pub fn encode_event(time: u64, event: MeasureEvent) -> Record {
    match event {
        MeasureEvent::Arm(level) => Record::new(kind::ARM, time, &[level as u8]),
        MeasureEvent::Contact(level) => Record::new(kind::CONTACT, time, &[level as u8]),
        MeasureEvent::Index => Record::new(kind::INDEX, time, &[]),
        MeasureEvent::Fes => Record::new(kind::FES, time, &[]),
        MeasureEvent::Scale { a, b } => {
            let lines = if a { SCALE_A } else { 0 } | if b { SCALE_B } else { 0 };
            Record::new(kind::SCALE, time, &[lines])
        }
        MeasureEvent::PresetPulses(n) => Record::new(kind::PRESET_PULSES, time, &n.to_le_bytes()),
    }
}

/// Decodes a measurement-event record (found at byte `offset`); `Ok(None)` for a record of
/// another kind.
pub fn decode_event(record: &Record, offset: usize) -> Result<Option<MeasureEvent>, WireError> {
    let p = record.payload();
    let bad = WireError::BadLength {
        kind: record.kind,
        len: u8::try_from(p.len()).unwrap_or(u8::MAX),
        offset,
    };
    let level = || match p {
        [b] if *b <= 1 => Ok(*b == 1),
        _ => Err(bad),
    };
    Ok(Some(match record.kind {
        kind::ARM => MeasureEvent::Arm(level()?),
        kind::CONTACT => MeasureEvent::Contact(level()?),
        kind::INDEX if p.is_empty() => MeasureEvent::Index,
        kind::FES if p.is_empty() => MeasureEvent::Fes,
        kind::SCALE => match p {
            [b] if *b <= SCALE_A | SCALE_B => MeasureEvent::Scale {
                a: b & SCALE_A != 0,
                b: b & SCALE_B != 0,
            },
            _ => return Err(bad),
        },
        kind::PRESET_PULSES => match p {
            [_, _, _, _] => MeasureEvent::PresetPulses(le_u32(p)),
            _ => return Err(bad),
        },
        kind::INDEX | kind::FES => return Err(bad),
        _ => return Ok(None),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn any_event() -> impl Strategy<Value = MeasureEvent> {
        prop_oneof![
            any::<bool>().prop_map(MeasureEvent::Arm),
            any::<bool>().prop_map(MeasureEvent::Contact),
            Just(MeasureEvent::Index),
            Just(MeasureEvent::Fes),
            (any::<bool>(), any::<bool>()).prop_map(|(a, b)| MeasureEvent::Scale { a, b }),
            any::<u32>().prop_map(MeasureEvent::PresetPulses),
        ]
    }

    proptest! {
        #[test]
        fn every_event_round_trips(event in any_event(), time in any::<u64>()) {
            let r = encode_event(time, event);
            prop_assert!(r.kind < kind::FORCE_FIRST);
            prop_assert_eq!(r.time, time);
            prop_assert_eq!(decode_event(&r, 0), Ok(Some(event)));
        }

        #[test]
        fn a_wrong_payload_length_is_an_error(event in any_event(), extra in 1u8..4) {
            let r = encode_event(0, event);
            let mut p = [0u8; 8];
            p[..r.payload().len()].copy_from_slice(r.payload());
            let long = Record::new(r.kind, 0, &p[..r.payload().len() + usize::from(extra)]);
            let is_bad_length = matches!(decode_event(&long, 7), Err(WireError::BadLength { offset: 7, .. }));
            prop_assert!(is_bad_length);
        }
    }

    #[test]
    fn payloads_are_the_documented_bytes() {
        let cases: [(MeasureEvent, u8, &[u8]); 8] = [
            (MeasureEvent::Arm(true), 0x02, &[1]),
            (MeasureEvent::Arm(false), 0x02, &[0]),
            (MeasureEvent::Contact(true), 0x03, &[1]),
            (MeasureEvent::Index, 0x04, &[]),
            (MeasureEvent::Fes, 0x05, &[]),
            (MeasureEvent::Scale { a: true, b: false }, 0x06, &[1]),
            (MeasureEvent::Scale { a: false, b: true }, 0x06, &[2]),
            (MeasureEvent::PresetPulses(0x0403_0201), 0x07, &[1, 2, 3, 4]),
        ];
        for (event, k, payload) in cases {
            let r = encode_event(9, event);
            assert_eq!((r.kind, r.time, r.payload()), (k, 9, payload), "{event:?}");
            assert_eq!(
                decode_event(&Record::new(k, 0, payload), 0),
                Ok(Some(event))
            );
        }
    }

    #[test]
    fn out_of_range_bytes_are_errors() {
        let bad = |k: u8, payload: &[u8]| {
            decode_event(&Record::new(k, 0, payload), 11)
                == Err(WireError::BadLength {
                    kind: k,
                    len: payload.len() as u8,
                    offset: 11,
                })
        };
        assert!(bad(kind::ARM, &[2]), "a level is 0 or 1");
        assert!(bad(kind::CONTACT, &[0xff]));
        assert!(bad(kind::ARM, &[]));
        assert!(bad(kind::SCALE, &[4]), "only bits 0 and 1");
        assert!(bad(kind::SCALE, &[3, 0]));
        assert!(bad(kind::INDEX, &[0]));
        assert!(bad(kind::FES, &[1]));
        assert!(bad(kind::PRESET_PULSES, &[1, 2, 3]));
        assert_eq!(
            decode_event(&Record::new(kind::SCALE, 0, &[3]), 0),
            Ok(Some(MeasureEvent::Scale { a: true, b: true }))
        );
    }

    #[test]
    fn other_kinds_are_not_measurement_events() {
        for k in [
            kind::MEASURE_CONFIG,
            kind::TICK,
            kind::MEASURE_OUTPUTS,
            kind::END,
        ] {
            assert_eq!(decode_event(&Record::new(k, 0, &[]), 0), Ok(None));
        }
    }
}
