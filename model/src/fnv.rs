//! The 64-bit FNV-1a hash that identifies a configuration: vector headers, generated
//! Verilog headers and the firmware compare these hashes, so a mismatch is an error, not a
//! diff. A leaf: it hashes bytes and knows nothing of what they encode (the canonical
//! encodings are in [`crate::wire`]).

/// The FNV-1a offset basis: the digest of no bytes.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// The 64-bit FNV prime.
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// 64-bit FNV-1a over `bytes`.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    fnv1a_continue(FNV_OFFSET, bytes)
}

/// The FNV-1a digest `digest` continued over `bytes`: a digest built piece by piece from
/// [`FNV_OFFSET`] equals [`fnv1a`] of the pieces joined.
pub fn fnv1a_continue(digest: u64, bytes: &[u8]) -> u64 {
    let mut h = digest;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(FNV_PRIME);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_published_test_vectors() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn a_digest_continued_piece_by_piece_is_the_digest_of_the_whole() {
        let pieces = fnv1a_continue(fnv1a_continue(FNV_OFFSET, b"foo"), b"bar");
        assert_eq!(pieces, fnv1a(b"foobar"));
    }
}
