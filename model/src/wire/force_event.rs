//! Force event records (kinds [`kind::SAMPLE`]..=[`kind::TOOL_CHANGED`], inside the force
//! range `0x20..=0x3f`): one record per [`ForceEvent`], and the canonical order of events
//! that carry the same time.
//!
//! | event | kind | payload |
//! |---|---|---|
//! | `Sample(codes)` | `SAMPLE` | the codes in [`AdcChannel::ALL`] order (speed, power, force, v_u, v_v, v_w, i_u, i_v): u16 LE each |
//! | `Tick`, `ToolChanged` | `TICK`, `TOOL_CHANGED` | none |
//! | `Identify(on)`, `Control(on)` | `IDENTIFY`, `CONTROL` | level, 1 byte: 0 or 1 |
//! | `Conditions(index)` | `CONDITIONS` | index, 1 byte |

use crate::force::events::ForceEvent;
use crate::force::sampling::{AdcChannel, AdcCodes};
use crate::wire::{kind, le_u16, Record, WireError};

/// ADC channels in a [`kind::SAMPLE`] payload, one u16 each.
const SAMPLE_WORDS: usize = AdcChannel::COUNT;
/// Length of a [`kind::SAMPLE`] payload, bytes.
const SAMPLE_LEN: usize = 2 * SAMPLE_WORDS;

impl ForceEvent {
    /// Order of events with the same time: samples first (they belong to the period a
    /// tick closes), then the tick, then CNC commands (which act from the next period).
    pub const CANONICAL_ORDER: [u8; 6] = [
        kind::SAMPLE,
        kind::TICK,
        kind::IDENTIFY,
        kind::CONTROL,
        kind::CONDITIONS,
        kind::TOOL_CHANGED,
    ];

    /// The event's wire kind.
    pub fn kind(&self) -> u8 {
        match self {
            ForceEvent::Sample(_) => kind::SAMPLE,
            ForceEvent::Tick => kind::TICK,
            ForceEvent::Identify(_) => kind::IDENTIFY,
            ForceEvent::Control(_) => kind::CONTROL,
            ForceEvent::Conditions(_) => kind::CONDITIONS,
            ForceEvent::ToolChanged => kind::TOOL_CHANGED,
        }
    }
}

/// Encodes a force event as a record at `time`.
pub fn encode_force_event(time: u64, event: &ForceEvent) -> Record {
    match event {
        ForceEvent::Sample(c) => {
            let mut p = [0u8; SAMPLE_LEN];
            for (chunk, w) in p.chunks_exact_mut(2).zip(c.to_array()) {
                chunk.copy_from_slice(&w.to_le_bytes());
            }
            Record::new(kind::SAMPLE, time, &p)
        }
        ForceEvent::Tick => Record::new(kind::TICK, time, &[]),
        ForceEvent::Identify(on) => Record::new(kind::IDENTIFY, time, &[u8::from(*on)]),
        ForceEvent::Control(on) => Record::new(kind::CONTROL, time, &[u8::from(*on)]),
        ForceEvent::Conditions(i) => Record::new(kind::CONDITIONS, time, &[*i]),
        ForceEvent::ToolChanged => Record::new(kind::TOOL_CHANGED, time, &[]),
    }
}

/// Decodes a force-event record (found at byte `offset`); `Ok(None)` for another kind.
pub fn decode_force_event(record: &Record, offset: usize) -> Result<Option<ForceEvent>, WireError> {
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
        kind::SAMPLE => {
            if p.len() != SAMPLE_LEN {
                return Err(bad);
            }
            let mut w = [0u16; SAMPLE_WORDS];
            for (d, chunk) in w.iter_mut().zip(p.chunks_exact(2)) {
                *d = le_u16(chunk);
            }
            ForceEvent::Sample(AdcCodes::from_array(w))
        }
        kind::TICK if p.is_empty() => ForceEvent::Tick,
        kind::IDENTIFY => ForceEvent::Identify(level()?),
        kind::CONTROL => ForceEvent::Control(level()?),
        kind::CONDITIONS => match p {
            [i] => ForceEvent::Conditions(*i),
            _ => return Err(bad),
        },
        kind::TOOL_CHANGED if p.is_empty() => ForceEvent::ToolChanged,
        kind::TICK | kind::TOOL_CHANGED => return Err(bad),
        _ => return Ok(None),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn events_round_trip() {
        let events = [
            ForceEvent::Sample(AdcCodes {
                speed: 1,
                power: 2,
                force: 3,
                volts: [4, 5, 6],
                amps: [7, 4095],
            }),
            ForceEvent::Tick,
            ForceEvent::Identify(true),
            ForceEvent::Control(false),
            ForceEvent::Conditions(3),
            ForceEvent::ToolChanged,
        ];
        for e in events {
            let r = encode_force_event(9, &e);
            assert!((0x20..=0x3f).contains(&r.kind));
            assert_eq!(decode_force_event(&r, 0).unwrap(), Some(e));
        }
        let bad = Record::new(kind::CONTROL, 0, &[2]);
        assert!(decode_force_event(&bad, 5).is_err());
    }

    #[test]
    fn payloads_are_the_documented_bytes() {
        let sample = ForceEvent::Sample(AdcCodes {
            speed: 0x0102,
            power: 0x0304,
            force: 0x0506,
            volts: [0x0708, 0x090a, 0x0b0c],
            amps: [0x0d0e, 0x0f10],
        });
        let r = encode_force_event(3, &sample);
        assert_eq!((r.kind, r.time), (0x20, 3));
        assert_eq!(
            r.payload(),
            &[2, 1, 4, 3, 6, 5, 8, 7, 0x0a, 9, 0x0c, 0x0b, 0x0e, 0x0d, 0x10, 0x0f]
        );
        let cases: [(ForceEvent, u8, &[u8]); 6] = [
            (ForceEvent::Tick, 0x21, &[]),
            (ForceEvent::Identify(true), 0x22, &[1]),
            (ForceEvent::Identify(false), 0x22, &[0]),
            (ForceEvent::Control(true), 0x23, &[1]),
            (ForceEvent::Conditions(200), 0x24, &[200]),
            (ForceEvent::ToolChanged, 0x25, &[]),
        ];
        for (event, k, payload) in cases {
            let r = encode_force_event(0, &event);
            assert_eq!((r.kind, r.payload()), (k, payload), "{event:?}");
            assert_eq!(event.kind(), k);
            assert_eq!(decode_force_event(&r, 0), Ok(Some(event)));
        }
        assert_eq!(sample.kind(), 0x20);
    }

    #[test]
    fn malformed_payloads_are_errors_and_other_kinds_are_none() {
        let bad = |k: u8, payload: &[u8]| {
            decode_force_event(&Record::new(k, 0, payload), 21)
                == Err(WireError::BadLength {
                    kind: k,
                    len: payload.len() as u8,
                    offset: 21,
                })
        };
        assert!(bad(kind::SAMPLE, &[0; 15]));
        assert!(bad(kind::SAMPLE, &[0; 17]));
        assert!(bad(kind::TICK, &[0]));
        assert!(bad(kind::TOOL_CHANGED, &[1]));
        assert!(bad(kind::IDENTIFY, &[2]));
        assert!(bad(kind::IDENTIFY, &[]));
        assert!(bad(kind::CONTROL, &[0, 0]));
        assert!(bad(kind::CONDITIONS, &[]));
        assert!(bad(kind::CONDITIONS, &[1, 2]));
        for k in [
            kind::ARM,
            kind::FORCE_CONFIG_CHUNK,
            kind::FORCE_OUTPUTS,
            kind::END,
        ] {
            assert_eq!(decode_force_event(&Record::new(k, 0, &[]), 0), Ok(None));
        }
    }

    fn any_event() -> impl Strategy<Value = ForceEvent> {
        prop_oneof![
            (any::<[u16; 3]>(), any::<[u16; 3]>(), any::<[u16; 2]>()).prop_map(
                |([speed, power, force], volts, amps)| ForceEvent::Sample(AdcCodes {
                    speed,
                    power,
                    force,
                    volts,
                    amps,
                })
            ),
            Just(ForceEvent::Tick),
            any::<bool>().prop_map(ForceEvent::Identify),
            any::<bool>().prop_map(ForceEvent::Control),
            any::<u8>().prop_map(ForceEvent::Conditions),
            Just(ForceEvent::ToolChanged),
        ]
    }

    proptest! {
        #[test]
        fn any_event_round_trips(event in any_event(), time in any::<u64>()) {
            let r = encode_force_event(time, &event);
            prop_assert_eq!(r.kind, event.kind());
            prop_assert!((kind::FORCE_FIRST..=kind::FORCE_LAST).contains(&r.kind));
            prop_assert_eq!(r.time, time);
            prop_assert_eq!(decode_force_event(&r, 0), Ok(Some(event)));
        }
    }

    #[test]
    fn canonical_order_lists_every_event_kind_once() {
        let mut order = ForceEvent::CANONICAL_ORDER;
        order.sort();
        assert_eq!(order, ForceEvent::CANONICAL_ORDER, "in kind order");
        assert_eq!(
            order,
            [
                kind::SAMPLE,
                kind::TICK,
                kind::IDENTIFY,
                kind::CONTROL,
                kind::CONDITIONS,
                kind::TOOL_CHANGED
            ]
        );
    }
}
