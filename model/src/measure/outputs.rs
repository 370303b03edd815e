//! Every output of the measurement front end, and its register widths: the one list the
//! model, the VCD files, the Verilog ports and the wire encoding
//! ([`crate::wire::measure_outputs`]) follow, so an output's name and width are written
//! once.

use crate::measure::config::MeasureConfig;

/// Every output of the measurement front end, as compared bit for bit between the model,
/// the firmware and the Verilog.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct MeasureOutputs {
    /// A measurement cycle is running (the CNC's arm input is high).
    pub armed: bool,
    /// Filtered contact level.
    pub contact: bool,
    /// "Position reached, register now" to the CNC; held until the next arm.
    pub register_now: bool,
    /// Scale position latched at the decision, counts (`scale_bits`, 0 until decided).
    pub decision_position: i32,
    /// A contact edge has been seen since arm.
    pub first_contact: bool,
    /// Scale position latched at the first contact edge, counts (0 until then).
    pub first_contact_position: i32,
    /// Live scale position, counts, `scale_bits` two's complement.
    pub position: i32,
    /// Illegal scale transitions since power-on, saturating at 255.
    pub scale_errors: u8,
    /// Contact pulses in the current window (`count_bits`).
    pub count: u32,
    /// Contact pulses in the previous window (`count_bits`).
    pub last_window_count: u32,
    /// Capacitor charge, LSBs (`charge_bits`).
    pub charge: u32,
    /// The density detector is armed (hysteresis state).
    pub density_armed: bool,
    /// The density detector has fired since arm.
    pub density_fired: bool,
    /// Index pulses since arm, saturating at 65535.
    pub revolutions: u16,
    /// FES pulses since arm, wrapping at 2^32.
    pub pulses: u32,
}

impl MeasureOutputs {
    /// Number of output signals.
    pub const FIELD_COUNT: usize = 15;

    /// Every output as `(name, value)`, names as the fields (and as the VCD signals and
    /// Verilog ports), in declaration order; flags are 0/1, positions sign-extended.
    pub fn fields(&self) -> [(&'static str, i64); Self::FIELD_COUNT] {
        [
            ("armed", self.armed.into()),
            ("contact", self.contact.into()),
            ("register_now", self.register_now.into()),
            ("decision_position", self.decision_position.into()),
            ("first_contact", self.first_contact.into()),
            ("first_contact_position", self.first_contact_position.into()),
            ("position", self.position.into()),
            ("scale_errors", self.scale_errors.into()),
            ("count", self.count.into()),
            ("last_window_count", self.last_window_count.into()),
            ("charge", self.charge.into()),
            ("density_armed", self.density_armed.into()),
            ("density_fired", self.density_fired.into()),
            ("revolutions", self.revolutions.into()),
            ("pulses", self.pulses.into()),
        ]
    }

    /// Every output's name and register width in bits for `config`, in [`Self::fields`]
    /// order: the widths of the VCD signals and the Verilog ports, derived here only.
    pub fn widths(config: &MeasureConfig) -> [(&'static str, u32); Self::FIELD_COUNT] {
        let s = config.settings();
        let scale = u32::from(s.scale_bits);
        let count = u32::from(config.count_bits());
        let charge = u32::from(s.charge_bits);
        let flag = 1;
        [
            ("armed", flag),
            ("contact", flag),
            ("register_now", flag),
            ("decision_position", scale),
            ("first_contact", flag),
            ("first_contact_position", scale),
            ("position", scale),
            ("scale_errors", 8),
            ("count", count),
            ("last_window_count", count),
            ("charge", charge),
            ("density_armed", flag),
            ("density_fired", flag),
            ("revolutions", 16),
            ("pulses", 32),
        ]
    }

    /// Every output as the unsigned bits of its register for `config`, in [`Self::fields`]
    /// order (two's-complement positions truncated to `scale_bits`).
    pub fn register_bits(&self, config: &MeasureConfig) -> [u64; Self::FIELD_COUNT] {
        let widths = Self::widths(config);
        let mut out = [0u64; Self::FIELD_COUNT];
        for ((bits, (_, value)), (_, width)) in out.iter_mut().zip(self.fields()).zip(widths) {
            let mask = if width >= 64 {
                u64::MAX
            } else {
                (1u64 << width) - 1
            };
            *bits = (value as u64) & mask;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A set of outputs with a distinct value in every field, listed by hand in the
    /// documented order (the order of the struct, the VCD signals and the Verilog ports).
    #[test]
    fn fields_name_every_output_in_declaration_order() {
        let outputs = MeasureOutputs {
            armed: true,
            contact: false,
            register_now: true,
            decision_position: -5,
            first_contact: true,
            first_contact_position: 7,
            position: -1,
            scale_errors: 255,
            count: 9,
            last_window_count: 10,
            charge: 65535,
            density_armed: false,
            density_fired: true,
            revolutions: 65535,
            pulses: u32::MAX,
        };
        assert_eq!(
            outputs.fields(),
            [
                ("armed", 1),
                ("contact", 0),
                ("register_now", 1),
                ("decision_position", -5),
                ("first_contact", 1),
                ("first_contact_position", 7),
                ("position", -1),
                ("scale_errors", 255),
                ("count", 9),
                ("last_window_count", 10),
                ("charge", 65535),
                ("density_armed", 0),
                ("density_fired", 1),
                ("revolutions", 65535),
                ("pulses", 4_294_967_295),
            ]
        );
    }
}
