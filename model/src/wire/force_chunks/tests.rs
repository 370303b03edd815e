//! Tests of [`super`]: every way a chunk stream can break, and random round trips.

extern crate std;
use super::*;
use crate::force::config::ForceSettings;
use crate::force::control::adaptive::DEFAULT_ADAPTIVE;
use crate::force::control::fuzzy::DEFAULT_FUZZY;
use crate::force::control::pi::DEFAULT_PI;
use crate::force::control::ControllerSettings;
use crate::testing::force::force_settings;
use proptest::prelude::*;

/// Pushes every chunk of `records` and finishes against `hash`.
fn reassemble(records: &[Record], hash: u64) -> Result<ForceConfig, ForceChunkError> {
    let mut a = ForceConfigAssembler::new();
    for r in records {
        assert_eq!(r.kind, kind::FORCE_CONFIG_CHUNK);
        a.push(r.payload())?;
    }
    a.finish(hash)
}

#[test]
fn default_force_config_round_trips_through_its_chunks() {
    for controller in [
        ControllerSettings::Pi(DEFAULT_PI),
        ControllerSettings::Adaptive(DEFAULT_ADAPTIVE),
        ControllerSettings::Fuzzy(DEFAULT_FUZZY),
    ] {
        let c = ForceSettings {
            controller,
            ..Default::default()
        }
        .validate()
        .unwrap();
        let chunks: std::vec::Vec<Record> = force_config_chunks(&c, 0).collect();
        let (_, n) = c.canonical_bytes();
        assert_eq!(chunks.len(), n.div_ceil(FORCE_CHUNK_DATA));
        assert!(chunks.iter().all(|r| r.payload().len() <= MAX_PAYLOAD));
        assert!((kind::FORCE_FIRST..=kind::FORCE_LAST).contains(&chunks[0].kind));
        assert_eq!(reassemble(&chunks, c.hash()), Ok(c));
    }
}

#[test]
fn broken_chunk_streams_are_named_errors() {
    let c = ForceSettings {
        controller: ControllerSettings::Fuzzy(DEFAULT_FUZZY),
        ..Default::default()
    }
    .validate()
    .unwrap();
    let h = c.hash();
    let chunks: std::vec::Vec<Record> = force_config_chunks(&c, 0).collect();
    let total = c.canonical_bytes().1;
    assert!(chunks.len() >= 3);
    // Out of order: the second chunk first.
    assert_eq!(
        reassemble(&chunks[1..], h),
        Err(ForceChunkError::OutOfOrder {
            expected: 0,
            offset: FORCE_CHUNK_DATA
        })
    );
    // Overlapping: the first chunk twice.
    let dup = [chunks[0], chunks[0]];
    assert!(matches!(
        reassemble(&dup, h),
        Err(ForceChunkError::OutOfOrder { expected, offset: 0 }) if expected == FORCE_CHUNK_DATA
    ));
    // Missing the last chunk.
    assert_eq!(
        reassemble(&chunks[..chunks.len() - 1], h),
        Err(ForceChunkError::Incomplete {
            received: (chunks.len() - 1) * FORCE_CHUNK_DATA,
            total
        })
    );
    assert_eq!(
        reassemble(&[], h),
        Err(ForceChunkError::Incomplete {
            received: 0,
            total: 0
        })
    );
    // One chunk too many.
    let mut extra = chunks.clone();
    extra.push(chunks[0]);
    assert_eq!(reassemble(&extra, h), Err(ForceChunkError::AfterComplete));
    // Oversized and empty totals, short payloads.
    let mut a = ForceConfigAssembler::new();
    assert_eq!(
        a.push(force_config_chunk(0, 600, 0, &[1; 10]).payload()),
        Err(ForceChunkError::Oversized { total: 600 })
    );
    assert_eq!(
        a.push(force_config_chunk(0, 0, 0, &[1; 10]).payload()),
        Err(ForceChunkError::Oversized { total: 0 })
    );
    assert_eq!(
        a.push(&[1, 0, 0]),
        Err(ForceChunkError::BadLength { len: 3 })
    );
    assert_eq!(
        a.push(&[1, 0, 0, 0]),
        Err(ForceChunkError::BadLength { len: 4 })
    );
    // A chunk past the announced end, and a total that changes.
    let mut a = ForceConfigAssembler::new();
    assert_eq!(
        a.push(force_config_chunk(0, 10, 0, &[0; 20]).payload()),
        Err(ForceChunkError::PastEnd { end: 20, total: 10 })
    );
    let mut a = ForceConfigAssembler::new();
    a.push(chunks[0].payload()).unwrap();
    let mut p = [0u8; MAX_PAYLOAD];
    p[..chunks[1].payload().len()].copy_from_slice(chunks[1].payload());
    p[0] = p[0].wrapping_add(1);
    assert!(matches!(
        a.push(&p[..chunks[1].payload().len()]),
        Err(ForceChunkError::TotalChanged { .. })
    ));
    // The header's hash is another configuration's.
    assert_eq!(
        reassemble(&chunks, h ^ 1),
        Err(ForceChunkError::HashMismatch {
            header: h ^ 1,
            decoded: h
        })
    );
}

/// Chunks of arbitrary encoded bytes (for encodings no valid configuration makes).
fn chunks_of(bytes: &[u8]) -> std::vec::Vec<Record> {
    bytes
        .chunks(FORCE_CHUNK_DATA)
        .enumerate()
        .map(|(i, d)| force_config_chunk(0, bytes.len() as u16, (i * FORCE_CHUNK_DATA) as u16, d))
        .collect()
}

#[test]
fn bad_encodings_and_invalid_fields_are_named() {
    let c = ForceSettings::default().validate().unwrap();
    let (bytes, n) = c.canonical_bytes();
    let good = &bytes[..n];
    // Unknown format version.
    let mut b = good.to_vec();
    b[0] = 9;
    assert_eq!(
        reassemble(&chunks_of(&b), 0),
        Err(ForceChunkError::BadEncoding { at: 0 })
    );
    // Unknown controller tag.
    let tag_at = crate::wire::force_config::CONTROLLER_TAG_AT;
    assert_eq!(good[tag_at], 0, "default controller is PI");
    let mut b = good.to_vec();
    b[tag_at] = 7;
    assert_eq!(
        reassemble(&chunks_of(&b), 0),
        Err(ForceChunkError::BadEncoding { at: tag_at })
    );
    // Trailing and missing bytes.
    let mut b = good.to_vec();
    b.push(0);
    assert_eq!(
        reassemble(&chunks_of(&b), 0),
        Err(ForceChunkError::BadEncoding { at: n })
    );
    assert!(matches!(
        reassemble(&chunks_of(&good[..n - 3]), 0),
        Err(ForceChunkError::BadEncoding { .. })
    ));
    // A field out of range is named: K_p = 0 (the first fx after the tag).
    let mut b = good.to_vec();
    b[tag_at + 1..tag_at + 9].fill(0);
    match reassemble(&chunks_of(&b), 0) {
        Err(ForceChunkError::Invalid(e)) => assert_eq!(e.field, "pi.kp"),
        other => panic!("expected pi.kp to be rejected, got {other:?}"),
    }
}

proptest! {
    #[test]
    fn random_force_configs_round_trip(s in force_settings()) {
                let c = s.validate().map_err(|e| TestCaseError::fail(std::format!("{e}")))?;
        let chunks: std::vec::Vec<Record> = force_config_chunks(&c, 42).collect();
        prop_assert!(chunks.iter().all(|r| r.time == 42));
        let (bytes, n) = c.canonical_bytes();
        prop_assert_eq!(decode_force_settings(&bytes[..n]), Ok(s));
        prop_assert_eq!(reassemble(&chunks, c.hash()), Ok(c));
    }

    #[test]
    fn any_flipped_bit_in_a_chunk_stream_is_an_error(s in force_settings(), pick in any::<u32>(), bit in 0u8..8) {
        let c = s.validate().map_err(|e| TestCaseError::fail(std::format!("{e}")))?;
        let mut chunks: std::vec::Vec<Record> = force_config_chunks(&c, 0).collect();
        let sizes: std::vec::Vec<usize> = chunks.iter().map(|r| r.payload().len()).collect();
        let mut k = pick as usize % sizes.iter().sum::<usize>();
        let mut i = 0;
        while k >= sizes[i] {
            k -= sizes[i];
            i += 1;
        }
        let mut p = [0u8; MAX_PAYLOAD];
        p[..sizes[i]].copy_from_slice(chunks[i].payload());
        p[k] ^= 1 << bit;
        chunks[i] = Record::new(chunks[i].kind, 0, &p[..sizes[i]]);
        prop_assert!(reassemble(&chunks, c.hash()).is_err());
    }
}

#[test]
fn error_messages_name_what_is_wrong() {
    use std::string::ToString;
    let cases = [
        (
            ForceChunkError::BadLength { len: 3 },
            "force configuration chunk of 3 bytes: needs a 4-byte header and 1..=44 data bytes",
        ),
        (
            ForceChunkError::Oversized { total: 600 },
            "force configuration of 600 bytes: allowed 1..=512",
        ),
        (
            ForceChunkError::TotalChanged {
                first: 200,
                this: 201,
            },
            "force configuration chunk announces 201 bytes in all, the first said 200",
        ),
        (
            ForceChunkError::OutOfOrder {
                expected: 44,
                offset: 88,
            },
            "force configuration chunk at offset 88, expected offset 44 (chunks must come in \
             order without gaps or overlaps)",
        ),
        (
            ForceChunkError::PastEnd {
                end: 210,
                total: 200,
            },
            "force configuration chunk ends at byte 210, past the announced 200 bytes",
        ),
        (
            ForceChunkError::AfterComplete,
            "force configuration chunk after the configuration was complete",
        ),
        (
            ForceChunkError::Incomplete {
                received: 88,
                total: 200,
            },
            "force configuration incomplete: 88 of 200 bytes received",
        ),
        (
            ForceChunkError::BadEncoding { at: 7 },
            "force configuration does not decode at byte 7 of its encoding",
        ),
        (
            ForceChunkError::HashMismatch {
                header: 1,
                decoded: 0xabc,
            },
            "force configuration hash 0x0000000000000abc differs from the header's force_hash \
             0x0000000000000001",
        ),
    ];
    for (e, text) in cases {
        assert_eq!(e.to_string(), text);
    }
    let invalid = ForceChunkError::from(crate::validation::ForceConfigError {
        field: "pi.kp",
        value: crate::units::Fx::ZERO,
        min: crate::units::Fx::ONE,
        max: crate::units::Fx::const_from_int(2),
    });
    assert_eq!(
        invalid.to_string(),
        "force configuration field `pi.kp` = 0 is out of range: allowed 1..=2"
    );
    assert_eq!(
        ForceChunkError::from(crate::wire::force_config::ForceEncodingError { at: 9 }),
        ForceChunkError::BadEncoding { at: 9 }
    );
}

/// The announced total's bounds: 1 to 512 bytes (`FORCE_CONFIG_MAX`) are accepted, 513 is
/// not.
#[test]
fn totals_from_one_to_512_bytes_are_accepted() {
    let mut a = ForceConfigAssembler::new();
    assert_eq!(
        a.push(force_config_chunk(0, 512, 0, &[7; 44]).payload()),
        Ok(false)
    );
    let mut a = ForceConfigAssembler::new();
    assert_eq!(
        a.push(force_config_chunk(0, 1, 0, &[7]).payload()),
        Ok(true)
    );
    let mut a = ForceConfigAssembler::new();
    assert_eq!(
        a.push(force_config_chunk(0, 513, 0, &[7; 44]).payload()),
        Err(ForceChunkError::Oversized { total: 513 })
    );
}
