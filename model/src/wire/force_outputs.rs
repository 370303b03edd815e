//! The force outputs record ([`kind::FORCE_OUTPUTS`], [`FORCE_OUTPUTS_LEN`] bytes): every
//! [`ForceOutputs`] field, the flags packed into one byte.
//!
//! ```text
//! 0      override_pct u8
//! 1      flags u8: saturated, fast_estimate, control_enabled, identifying, identified,
//!        wear_over, wear_alarm, wear_blind from bit 0
//! 2      bad_events u8
//! 3..43  force_estimate, force_measured, wear_power, wear_allowed, coulomb: the raw
//!        I32F32 bits, i64 LE each
//! ```

use crate::force::kernel::ForceOutputs;
use crate::units::Fx;
use crate::wire::{kind, le_array, Record};

/// Encoded length of [`ForceOutputs`], bytes.
pub const FORCE_OUTPUTS_LEN: usize = 43;

/// Where each field is.
mod at {
    pub const OVERRIDE_PCT: usize = 0;
    pub const FLAGS: usize = 1;
    pub const BAD_EVENTS: usize = 2;
    /// The fixed-point values, 8 bytes each, from here to the end.
    pub const VALUES: usize = 3;
}

/// Bits of the flags byte.
mod flag {
    pub const SATURATED: u8 = 1 << 0;
    pub const FAST_ESTIMATE: u8 = 1 << 1;
    pub const CONTROL_ENABLED: u8 = 1 << 2;
    pub const IDENTIFYING: u8 = 1 << 3;
    pub const IDENTIFIED: u8 = 1 << 4;
    pub const WEAR_OVER: u8 = 1 << 5;
    pub const WEAR_ALARM: u8 = 1 << 6;
    pub const WEAR_BLIND: u8 = 1 << 7;
}

/// Bytes of one fixed-point value (the i64 of its I32F32 bits).
const FX_LEN: usize = 8;

/// Encodes every force output (layout in the module header).
pub fn encode_force_outputs(o: &ForceOutputs) -> [u8; FORCE_OUTPUTS_LEN] {
    let bit = |on: bool, mask: u8| if on { mask } else { 0 };
    let mut out = [0u8; FORCE_OUTPUTS_LEN];
    out[at::OVERRIDE_PCT] = o.override_pct;
    out[at::FLAGS] = bit(o.saturated, flag::SATURATED)
        | bit(o.fast_estimate, flag::FAST_ESTIMATE)
        | bit(o.control_enabled, flag::CONTROL_ENABLED)
        | bit(o.identifying, flag::IDENTIFYING)
        | bit(o.identified, flag::IDENTIFIED)
        | bit(o.wear_over, flag::WEAR_OVER)
        | bit(o.wear_alarm, flag::WEAR_ALARM)
        | bit(o.wear_blind, flag::WEAR_BLIND);
    out[at::BAD_EVENTS] = o.bad_events;
    let values = [
        o.force_estimate,
        o.force_measured,
        o.wear_power,
        o.wear_allowed,
        o.coulomb,
    ];
    for (chunk, v) in out[at::VALUES..].chunks_exact_mut(FX_LEN).zip(values) {
        chunk.copy_from_slice(&v.to_bits().to_le_bytes());
    }
    out
}

/// Decodes [`encode_force_outputs`]' bytes; `None` if `p` is not [`FORCE_OUTPUTS_LEN`]
/// long (every flag bit is an output).
pub fn decode_force_outputs(p: &[u8]) -> Option<ForceOutputs> {
    if p.len() != FORCE_OUTPUTS_LEN {
        return None;
    }
    let mut v = [Fx::ZERO; 5];
    for (d, chunk) in v.iter_mut().zip(p[at::VALUES..].chunks_exact(FX_LEN)) {
        *d = Fx::from_bits(i64::from_le_bytes(le_array(chunk)));
    }
    let f = p[at::FLAGS];
    Some(ForceOutputs {
        override_pct: p[at::OVERRIDE_PCT],
        saturated: f & flag::SATURATED != 0,
        fast_estimate: f & flag::FAST_ESTIMATE != 0,
        control_enabled: f & flag::CONTROL_ENABLED != 0,
        identifying: f & flag::IDENTIFYING != 0,
        identified: f & flag::IDENTIFIED != 0,
        wear_over: f & flag::WEAR_OVER != 0,
        wear_alarm: f & flag::WEAR_ALARM != 0,
        wear_blind: f & flag::WEAR_BLIND != 0,
        bad_events: p[at::BAD_EVENTS],
        force_estimate: v[0],
        force_measured: v[1],
        wear_power: v[2],
        wear_allowed: v[3],
        coulomb: v[4],
    })
}

/// The [`ForceOutputs`] record at `time`.
pub fn outputs_record(time: u64, o: &ForceOutputs) -> Record {
    Record::new(kind::FORCE_OUTPUTS, time, &encode_force_outputs(o))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn outputs_round_trip() {
        let o = ForceOutputs {
            override_pct: 83,
            saturated: true,
            wear_alarm: true,
            bad_events: 2,
            force_estimate: Fx::lit("-12.5"),
            coulomb: Fx::DELTA,
            ..ForceOutputs::default()
        };
        assert_eq!(decode_force_outputs(&encode_force_outputs(&o)), Some(o));
    }

    #[test]
    fn the_bytes_follow_the_documented_layout() {
        let o = ForceOutputs {
            override_pct: 0x83,
            saturated: false,
            fast_estimate: true,
            control_enabled: true,
            identifying: false,
            identified: true,
            wear_over: false,
            wear_alarm: true,
            wear_blind: false,
            bad_events: 0x07,
            force_estimate: Fx::lit("1.5"),
            force_measured: Fx::from_bits(-1),
            wear_power: Fx::from_bits(0x0102_0304_0506_0708),
            wear_allowed: Fx::ZERO,
            coulomb: Fx::DELTA,
        };
        let mut bytes = [0u8; FORCE_OUTPUTS_LEN];
        bytes[..3].copy_from_slice(&[0x83, 0b101_0110, 0x07]);
        // 1.5 = 0x1_8000_0000 in I32F32.
        bytes[3..11].copy_from_slice(&[0, 0, 0, 0x80, 1, 0, 0, 0]);
        bytes[11..19].copy_from_slice(&[0xff; 8]);
        bytes[19..27].copy_from_slice(&[8, 7, 6, 5, 4, 3, 2, 1]);
        bytes[35] = 1;
        assert_eq!(encode_force_outputs(&o), bytes);
        assert_eq!(decode_force_outputs(&bytes), Some(o));
        // The other flags: saturated (bit 0), identifying (3), wear_over (5).
        let other = ForceOutputs {
            saturated: true,
            identifying: true,
            wear_over: true,
            ..ForceOutputs::default()
        };
        assert_eq!(encode_force_outputs(&other)[1], 0b10_1001);
        // Bit 7 is wear_blind; wrong lengths are no record.
        let mut b = bytes;
        b[1] |= 0x80;
        assert_eq!(
            decode_force_outputs(&b),
            Some(ForceOutputs {
                wear_blind: true,
                ..o
            })
        );
        assert_eq!(decode_force_outputs(&bytes[..42]), None);
        let mut long = [0u8; 44];
        long[..43].copy_from_slice(&bytes);
        assert_eq!(decode_force_outputs(&long), None);
    }

    proptest! {
        #[test]
        fn any_outputs_round_trip(bytes in any::<[u8; 3]>(), flags in any::<u8>(), values in any::<[i64; 5]>(), time in any::<u64>()) {
            let [override_pct, bad_events, _] = bytes;
            let [force_estimate, force_measured, wear_power, wear_allowed, coulomb] = values.map(Fx::from_bits);
            let o = ForceOutputs {
                override_pct,
                saturated: flags & 1 != 0,
                fast_estimate: flags & 2 != 0,
                control_enabled: flags & 4 != 0,
                identifying: flags & 8 != 0,
                identified: flags & 16 != 0,
                wear_over: flags & 32 != 0,
                wear_alarm: flags & 64 != 0,
                wear_blind: flags & 128 != 0,
                bad_events,
                force_estimate,
                force_measured,
                wear_power,
                wear_allowed,
                coulomb,
            };
            let encoded = encode_force_outputs(&o);
            prop_assert_eq!(encoded[1], flags);
            prop_assert_eq!(decode_force_outputs(&encoded), Some(o));
            let r = outputs_record(time, &o);
            prop_assert_eq!((r.kind, r.time), (kind::FORCE_OUTPUTS, time));
            prop_assert_eq!(decode_force_outputs(r.payload()), Some(o));
        }
    }
}
