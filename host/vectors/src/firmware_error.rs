//! The firmware's error record read ([`FirmwareError`], the Python package's dict of it)
//! and explained: why an image rejected its input stream (codes of firmware/src/cosim.rs
//! `Error::code`, and the wire errors of `tooltouch_model::wire`), as the co-simulation and
//! `check` report it.

fn u64_at(p: &[u8], i: usize) -> u64 {
    p.get(i..i + 8)
        .and_then(|b| b.try_into().ok())
        .map(u64::from_le_bytes)
        .unwrap_or(0)
}

/// The fields of a firmware error record's payload (layout: `kind::FIRMWARE_ERROR`); a
/// field the payload is too short for reads as 0 (the name as empty).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FirmwareError<'a> {
    /// What the firmware rejected (firmware/src/cosim.rs `Error::code`).
    pub code: u8,
    /// The wire or chunk error under it (for codes 2 and 8).
    pub wire_error: u8,
    /// Byte offset in the event file.
    pub offset: u64,
    /// A value of the error (a length, a kind, a field's bits, ...).
    pub detail: u64,
    /// A force configuration field's name (UTF-8), for a field out of range.
    pub field: &'a [u8],
}

impl<'a> FirmwareError<'a> {
    /// Reads the payload `p`; never fails.
    pub fn decode(p: &'a [u8]) -> FirmwareError<'a> {
        FirmwareError {
            code: p.first().copied().unwrap_or(0),
            wire_error: p.get(1).copied().unwrap_or(0),
            offset: u64_at(p, 2),
            detail: u64_at(p, 10),
            field: p.get(18..).unwrap_or(&[]),
        }
    }
}

/// Explains a firmware error record (codes of firmware/src/cosim.rs `Error::code`).
pub fn describe_firmware_error(p: &[u8]) -> String {
    let FirmwareError {
        code,
        wire_error: wire_code,
        offset,
        detail,
        field,
    } = FirmwareError::decode(p);
    let what = match code {
        1 => "semihosting file I/O failed".to_string(),
        2 => {
            let w = match wire_code {
                1 => format!("truncated record, {detail} bytes needed"),
                2 => format!("bad magic {detail:#010x}"),
                3 => format!("unsupported format version {detail}"),
                4 => format!("unknown stream kind {detail}"),
                5 => format!("unknown record kind {detail:#04x}"),
                6 => format!(
                    "record kind {:#04x} with bad payload length {}",
                    detail >> 8,
                    detail & 0xff
                ),
                7 => format!("time goes backwards (record time {detail})"),
                8 => format!("configuration field out of range (value {detail})"),
                9 => "configuration record with an unknown encoding".to_string(),
                _ => format!("wire error {wire_code}"),
            };
            format!("malformed input: {w}")
        }
        3 => "header is not an event stream".to_string(),
        4 => "stream does not start with a MEASURE_CONFIG record".to_string(),
        5 => "configuration record does not match the header's hash".to_string(),
        6 => format!("unexpected record kind {detail:#04x} in an event stream"),
        7 => "input holds no stream".to_string(),
        8 => {
            let (hi, lo) = (detail >> 16, detail & 0xffff);
            let field = String::from_utf8_lossy(field).into_owned();
            let w = match wire_code {
                1 => format!(
                    "a chunk of {detail} bytes (needs a 4-byte header and 1..=44 data bytes)"
                ),
                2 => format!("a chunk announces {detail} bytes in all (allowed 1..=512)"),
                3 => format!("a chunk announces {lo} bytes in all, the first said {hi}"),
                4 => format!(
                    "a chunk at offset {lo}, expected offset {hi} (out of order or overlapping)"
                ),
                5 => format!("a chunk ends at byte {hi}, past the announced {lo} bytes"),
                6 => "a chunk after the configuration was complete".to_string(),
                7 => format!("incomplete: {hi} of {lo} bytes before the first event"),
                8 => format!("does not decode at byte {detail} of its encoding"),
                9 => format!(
                    "field `{field}` out of range (value {})",
                    tooltouch_model::units::Fx::from_bits(detail as i64)
                ),
                10 => format!("decodes to hash {detail:#018x}, not the header's force_hash"),
                _ => format!("chunk error {wire_code}"),
            };
            format!("bad force configuration chunks: {w}")
        }
        _ => format!("error code {code}"),
    };
    format!("{what} at byte {offset} of the event file")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_record_reads_its_fields_and_explains_them() {
        let mut p = vec![8, 9];
        p.extend_from_slice(&28u64.to_le_bytes());
        p.extend_from_slice(&(-5i64 << 32).to_le_bytes());
        p.extend_from_slice(b"kp");
        let e = FirmwareError::decode(&p);
        assert_eq!(
            (e.code, e.wire_error, e.offset, e.field),
            (8, 9, 28, &b"kp"[..])
        );
        assert_eq!(e.detail as i64, -5i64 << 32);
        assert_eq!(
            describe_firmware_error(&p),
            "bad force configuration chunks: field `kp` out of range (value -5) at byte 28 of the event file"
        );
        let short = FirmwareError::decode(&p[..5]);
        assert_eq!((short.code, short.offset, short.field), (8, 0, &[][..]));
    }
}
