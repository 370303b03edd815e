//! The measurement outputs record ([`kind::MEASURE_OUTPUTS`], [`OUTPUTS_LEN`] bytes): every
//! [`MeasureOutputs`] field, in the order of [`MeasureOutputs::fields`] but with the flags
//! packed into the first byte.
//!
//! [`kind::MEASURE_OUTPUTS`]: crate::wire::kind::MEASURE_OUTPUTS
//!
//! ```text
//! 0      flags u8: armed, contact, register_now, first_contact, density_armed,
//!        density_fired, confirmed from bit 0
//! 1..5   decision_position i32      5..9   first_contact_position i32
//! 9..13  position i32               13     scale_errors u8
//! 14..18 count u32                  18..22 last_window_count u32
//! 22..26 charge u32                 26..28 revolutions u16
//! 28..32 pulses u32                32     faults u8 (bit per fault, see checks::fault)
//! ```

use crate::measure::outputs::MeasureOutputs;
use crate::wire::{le_u16, le_u32};
use core::ops::Range;

/// Encoded length of [`MeasureOutputs`], bytes.
pub const OUTPUTS_LEN: usize = 33;

/// Where each field is.
mod at {
    use super::Range;
    pub const FLAGS: usize = 0;
    pub const DECISION_POSITION: Range<usize> = 1..5;
    pub const FIRST_CONTACT_POSITION: Range<usize> = 5..9;
    pub const POSITION: Range<usize> = 9..13;
    pub const SCALE_ERRORS: usize = 13;
    pub const COUNT: Range<usize> = 14..18;
    pub const LAST_WINDOW_COUNT: Range<usize> = 18..22;
    pub const CHARGE: Range<usize> = 22..26;
    pub const REVOLUTIONS: Range<usize> = 26..28;
    pub const PULSES: Range<usize> = 28..32;
    pub const FAULTS: usize = 32;
}

/// Bits of the flags byte.
mod flag {
    pub const ARMED: u8 = 1 << 0;
    pub const CONTACT: u8 = 1 << 1;
    pub const REGISTER_NOW: u8 = 1 << 2;
    pub const FIRST_CONTACT: u8 = 1 << 3;
    pub const DENSITY_ARMED: u8 = 1 << 4;
    pub const DENSITY_FIRED: u8 = 1 << 5;
    pub const CONFIRMED: u8 = 1 << 6;
}

/// Encodes every measurement output (layout in the module header).
pub fn encode_outputs(o: &MeasureOutputs) -> [u8; OUTPUTS_LEN] {
    let bit = |on: bool, mask: u8| if on { mask } else { 0 };
    let mut out = [0u8; OUTPUTS_LEN];
    out[at::FLAGS] = bit(o.armed, flag::ARMED)
        | bit(o.contact, flag::CONTACT)
        | bit(o.register_now, flag::REGISTER_NOW)
        | bit(o.first_contact, flag::FIRST_CONTACT)
        | bit(o.density_armed, flag::DENSITY_ARMED)
        | bit(o.density_fired, flag::DENSITY_FIRED)
        | bit(o.confirmed, flag::CONFIRMED);
    out[at::DECISION_POSITION].copy_from_slice(&o.decision_position.to_le_bytes());
    out[at::FIRST_CONTACT_POSITION].copy_from_slice(&o.first_contact_position.to_le_bytes());
    out[at::POSITION].copy_from_slice(&o.position.to_le_bytes());
    out[at::SCALE_ERRORS] = o.scale_errors;
    out[at::COUNT].copy_from_slice(&o.count.to_le_bytes());
    out[at::LAST_WINDOW_COUNT].copy_from_slice(&o.last_window_count.to_le_bytes());
    out[at::CHARGE].copy_from_slice(&o.charge.to_le_bytes());
    out[at::REVOLUTIONS].copy_from_slice(&o.revolutions.to_le_bytes());
    out[at::PULSES].copy_from_slice(&o.pulses.to_le_bytes());
    out[at::FAULTS] = o.faults;
    out
}

/// Decodes [`encode_outputs`]' bytes; `None` if `p` is not [`OUTPUTS_LEN`] long.
pub fn decode_outputs(p: &[u8]) -> Option<MeasureOutputs> {
    if p.len() != OUTPUTS_LEN {
        return None;
    }
    let f = p[at::FLAGS];
    Some(MeasureOutputs {
        armed: f & flag::ARMED != 0,
        contact: f & flag::CONTACT != 0,
        register_now: f & flag::REGISTER_NOW != 0,
        first_contact: f & flag::FIRST_CONTACT != 0,
        density_armed: f & flag::DENSITY_ARMED != 0,
        density_fired: f & flag::DENSITY_FIRED != 0,
        decision_position: le_u32(&p[at::DECISION_POSITION]) as i32,
        first_contact_position: le_u32(&p[at::FIRST_CONTACT_POSITION]) as i32,
        position: le_u32(&p[at::POSITION]) as i32,
        scale_errors: p[at::SCALE_ERRORS],
        count: le_u32(&p[at::COUNT]),
        last_window_count: le_u32(&p[at::LAST_WINDOW_COUNT]),
        charge: le_u32(&p[at::CHARGE]),
        revolutions: le_u16(&p[at::REVOLUTIONS]),
        pulses: le_u32(&p[at::PULSES]),
        confirmed: f & flag::CONFIRMED != 0,
        faults: p[at::FAULTS],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn outputs_round_trip() {
        let o = MeasureOutputs {
            armed: true,
            register_now: true,
            decision_position: -5,
            position: 1 << 20,
            charge: 65535,
            pulses: u32::MAX,
            density_fired: true,
            confirmed: true,
            faults: 0x7f,
            ..Default::default()
        };
        assert_eq!(decode_outputs(&encode_outputs(&o)), Some(o));
    }

    #[test]
    fn the_bytes_follow_the_documented_layout() {
        let o = MeasureOutputs {
            armed: true,
            contact: false,
            register_now: true,
            decision_position: -2,
            first_contact: true,
            first_contact_position: 0x0102_0304,
            position: 0x1112_1314,
            scale_errors: 0x55,
            count: 0x2122_2324,
            last_window_count: 0x3132_3334,
            charge: 0x4142_4344,
            density_armed: false,
            density_fired: true,
            revolutions: 0x5152,
            pulses: 0x6162_6364,
            confirmed: true,
            faults: 0x45,
        };
        let bytes: [u8; OUTPUTS_LEN] = [
            0b110_1101, // armed, register_now, first_contact, density_fired, confirmed
            0xfe, 0xff, 0xff, 0xff, // -2
            0x04, 0x03, 0x02, 0x01, //
            0x14, 0x13, 0x12, 0x11, //
            0x55, //
            0x24, 0x23, 0x22, 0x21, //
            0x34, 0x33, 0x32, 0x31, //
            0x44, 0x43, 0x42, 0x41, //
            0x52, 0x51, //
            0x64, 0x63, 0x62, 0x61, //
            0x45,
        ];
        assert_eq!(encode_outputs(&o), bytes);
        assert_eq!(decode_outputs(&bytes), Some(o));
        // The other flags: contact (bit 1) and density_armed (bit 4).
        let flags = MeasureOutputs {
            contact: true,
            density_armed: true,
            ..Default::default()
        };
        assert_eq!(encode_outputs(&flags)[0], 0b1_0010);
        assert_eq!(decode_outputs(&[0u8; OUTPUTS_LEN + 1]), None);
    }

    proptest! {
        #[test]
        fn any_outputs_round_trip(
            flags in any::<[bool; 7]>(),
            faults in 0u8..0x80,
            positions in any::<[i32; 3]>(),
            counts in any::<[u32; 4]>(),
            scale_errors in any::<u8>(),
            revolutions in any::<u16>(),
        ) {
            let o = MeasureOutputs {
                armed: flags[0],
                contact: flags[1],
                register_now: flags[2],
                first_contact: flags[3],
                density_armed: flags[4],
                density_fired: flags[5],
                decision_position: positions[0],
                first_contact_position: positions[1],
                position: positions[2],
                scale_errors,
                count: counts[0],
                last_window_count: counts[1],
                charge: counts[2],
                revolutions,
                pulses: counts[3],
                confirmed: flags[6],
                faults,
            };
            let bytes = encode_outputs(&o);
            prop_assert_eq!(decode_outputs(&bytes), Some(o));
            prop_assert_eq!(decode_outputs(&bytes[..OUTPUTS_LEN - 1]), None);
        }
    }
}
