//! The framing written out byte by byte from the layout in the module header: a header
//! and records encoded and compared with hand-written bytes, those bytes decoded, and every
//! error with the exact offset and message it names.

extern crate std;
use super::*;
use std::string::ToString;

/// Header of an events stream at 50 MHz with hashes 0x0102…08 and 0x1112…18, as the
/// layout spells it: "TTVX", version 2, stream 1, tick_hz, two hashes, all little-endian.
const HEADER_BYTES: [u8; HEADER_LEN] = [
    b'T', b'T', b'V', b'X', // magic
    0x02, 0x00, // version 2
    0x01, 0x00, // stream: events
    0x80, 0xf0, 0xfa, 0x02, // 50_000_000 = 0x02faf080
    0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01, // measure hash
    0x18, 0x17, 0x16, 0x15, 0x14, 0x13, 0x12, 0x11, // force hash
];

const HEADER: Header = Header {
    stream: StreamKind::Events,
    tick_hz: 50_000_000,
    measure_hash: 0x0102_0304_0506_0708,
    force_hash: 0x1112_1314_1516_1718,
};

#[test]
fn the_header_is_the_documented_28_bytes() {
    assert_eq!(HEADER.encode(), HEADER_BYTES);
    assert_eq!(Header::decode(&HEADER_BYTES), Ok(HEADER));
    let outputs = Header {
        stream: StreamKind::Outputs,
        ..HEADER
    };
    assert_eq!(outputs.encode()[6..8], [0x02, 0x00]);
    assert_eq!(Header::decode(&outputs.encode()), Ok(outputs));
}

#[test]
fn a_bad_header_names_its_fault() {
    assert_eq!(
        Header::decode(&HEADER_BYTES[..27]),
        Err(WireError::Truncated {
            offset: 0,
            needed: 28
        })
    );
    let mut b = HEADER_BYTES;
    b[3] = b'Y';
    assert_eq!(Header::decode(&b), Err(WireError::BadMagic(*b"TTVY")));
    let mut b = HEADER_BYTES;
    b[4] = 1;
    assert_eq!(Header::decode(&b), Err(WireError::BadVersion(1)));
    let mut b = HEADER_BYTES;
    b[5] = 1;
    assert_eq!(Header::decode(&b), Err(WireError::BadVersion(0x0102)));
    for (lo, hi, stream) in [(0u8, 0u8, 0u16), (3, 0, 3), (1, 1, 0x0101)] {
        let mut b = HEADER_BYTES;
        b[6] = lo;
        b[7] = hi;
        assert_eq!(Header::decode(&b), Err(WireError::BadStream(stream)));
    }
}

#[test]
fn a_record_is_kind_length_time_payload() {
    let r = Record::new(kind::SCALE, 0x0102_0304_0506_0708, &[0xaa, 0xbb]);
    assert_eq!(r.encoded_len(), 12);
    assert_eq!(r.payload(), &[0xaa, 0xbb]);
    let mut out = [0u8; 16];
    assert_eq!(r.encode(&mut out), Some(12));
    assert_eq!(
        out[..12],
        [0x06, 0x02, 0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01, 0xaa, 0xbb]
    );
    assert_eq!(out[12..], [0; 4], "nothing written past the record");
    assert_eq!(r.encode(&mut out[..11]), None, "one byte short");
    assert_eq!(Record::decode(&out, 40), Ok((r, 12)));
    // An empty payload: 10 bytes.
    let end = Record::new(kind::END, 7, &[]);
    assert_eq!(end.encoded_len(), 10);
    assert_eq!(end.payload(), &[] as &[u8]);
    // A payload longer than 48 bytes is cut to 48.
    let long = Record::new(kind::SAMPLE, 0, &[9; 60]);
    assert_eq!((long.payload().len(), long.encoded_len()), (48, 58));
}

#[test]
fn a_bad_record_names_its_offset() {
    assert_eq!(
        Record::decode(&[0x05, 0, 1, 2, 3, 4, 5, 6, 7], 100),
        Err(WireError::Truncated {
            offset: 100,
            needed: 10
        })
    );
    let mut b = [0u8; 70];
    b[0] = kind::SAMPLE;
    b[1] = 49;
    assert_eq!(
        Record::decode(&b, 3),
        Err(WireError::BadLength {
            kind: 0x20,
            len: 49,
            offset: 3
        })
    );
    b[1] = 48;
    assert_eq!(Record::decode(&b, 3).map(|(_, n)| n), Ok(58));
    assert_eq!(
        Record::decode(&b[..57], 3),
        Err(WireError::Truncated {
            offset: 3,
            needed: 58
        })
    );
}

/// The header, then FES at 10, INDEX at 10 (equal times are in order), END at 12, then a
/// record after the end.
fn stream() -> ([u8; 128], usize) {
    let mut b = [0u8; 128];
    b[..HEADER_LEN].copy_from_slice(&HEADER_BYTES);
    let mut at = HEADER_LEN;
    for (k, t) in [
        (kind::FES, 10),
        (kind::INDEX, 10),
        (kind::END, 12),
        (kind::FES, 13),
    ] {
        at += Record::new(k, t, &[]).encode(&mut b[at..]).unwrap();
    }
    (b, at)
}

#[test]
fn records_stop_at_the_end_record() {
    let (b, len) = stream();
    assert_eq!(len, 28 + 4 * 10);
    let (h, records) = Records::new(&b[..len]).unwrap();
    assert_eq!(h, HEADER);
    let got: std::vec::Vec<_> = records.map(|r| r.map(|r| (r.kind, r.time))).collect();
    assert_eq!(
        got,
        [
            Ok((kind::FES, 10)),
            Ok((kind::INDEX, 10)),
            Ok((kind::END, 12))
        ]
    );
    // Without an END record the records run to the end of the bytes.
    let (_, records) = Records::new(&b[..48]).unwrap();
    assert_eq!(records.count(), 2);
    let (_, mut records) = Records::new(&b[..28]).unwrap();
    assert!(records.next().is_none());
}

#[test]
fn an_error_ends_the_records_and_names_the_byte() {
    let (mut b, len) = stream();
    // The second record goes back to time 9.
    b[38 + 2] = 9;
    let (_, mut records) = Records::new(&b[..len]).unwrap();
    assert!(records.next().unwrap().is_ok());
    assert_eq!(
        records.next(),
        Some(Err(WireError::NonMonotonicTime {
            offset: 38,
            previous: 10,
            time: 9
        }))
    );
    assert_eq!(records.next(), None, "stops after an error");
    // A truncated second record.
    let (b, _) = stream();
    let (_, mut records) = Records::new(&b[..45]).unwrap();
    records.next();
    assert_eq!(
        records.next(),
        Some(Err(WireError::Truncated {
            offset: 38,
            needed: 10
        }))
    );
    assert_eq!(records.next(), None);
}

#[test]
fn error_messages_name_what_is_wrong() {
    let cases = [
        (
            WireError::Truncated {
                offset: 5,
                needed: 10,
            },
            "truncated at byte 5: 10 more bytes needed",
        ),
        (
            WireError::BadMagic(*b"ABCD"),
            "wrong magic [41, 42, 43, 44], expected \"TTVX\"",
        ),
        (
            WireError::BadVersion(3),
            "unsupported format version 3, expected 2",
        ),
        (
            WireError::BadStream(9),
            "unknown stream kind 9, expected 1 or 2",
        ),
        (
            WireError::UnknownKind {
                kind: 0x1e,
                offset: 40,
            },
            "unknown record kind 0x1e at byte 40",
        ),
        (
            WireError::BadLength {
                kind: 0x20,
                len: 3,
                offset: 28,
            },
            "record kind 0x20 at byte 28 has a bad payload length 3",
        ),
        (
            WireError::NonMonotonicTime {
                offset: 38,
                previous: 10,
                time: 9,
            },
            "time goes backwards at byte 38: 9 after 10",
        ),
        (
            WireError::BadConfigEncoding,
            "configuration record has an unknown encoding",
        ),
    ];
    for (e, text) in cases {
        assert_eq!(e.to_string(), text);
    }
    let config = crate::validation::ConfigError {
        field: "i_def",
        value: 9,
        min: 0,
        max: 8,
    };
    assert_eq!(
        WireError::from(config).to_string(),
        "bad configuration record: configuration field `i_def` = 9 is out of range: allowed 0..=8"
    );
}

#[test]
fn little_endian_helpers_read_the_low_bytes_first() {
    assert_eq!(le_u16(&[0x34, 0x12]), 0x1234);
    assert_eq!(le_u32(&[0x78, 0x56, 0x34, 0x12]), 0x1234_5678);
    assert_eq!(le_u64(&[1, 0, 0, 0, 0, 0, 0, 0x80]), 0x8000_0000_0000_0001);
    assert_eq!(le_u32(&[0xff]), 0xff, "short input is zero-padded");
    assert_eq!(le_array::<3>(&[1, 2, 3, 4]), [1, 2, 3]);
}
