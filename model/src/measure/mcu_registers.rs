//! The front end's MCU register map: the words an MCU reads through `mcu_addr` /
//! `mcu_rdata` (and, on the SPI chip top, through its frames). This table is the one owner
//! of the map: the generated Verilog's read mux and testbench reference (tooltouch-hdl-gen),
//! the C ABI's cycle-level front end, the formal proof's counterexample replay, `check`'s
//! mismatch report and the Python package's `FrontEnd.run(…, mcu_addr=…)` all derive their
//! words from [`McuRegister::word`].
//!
//! Each word is built from the outputs' register bits ([`MeasureOutputs::register_bits`]):
//! a position is sign-extended from its width (`scale_bits`) to 32 bits, a count
//! zero-extended, the `STATUS` word packs the flags of [`STATUS_FLAGS`] from bit 0 and the
//! faults word from bit [`STATUS_FAULTS_SHIFT`]. Unlisted addresses read 0, and so do the
//! diagnostic counters of a design generated without them.

use crate::measure::config::MeasureConfig;
use crate::measure::outputs::MeasureOutputs;

/// Width of the MCU read-data bus, bits.
pub const MCU_DATA_BITS: u32 = 32;
/// Width of the MCU register address, bits.
pub const MCU_ADDR_BITS: u32 = 4;

/// What one MCU word holds. Outputs are named by their index in [`MeasureOutputs::LAYOUT`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum McuWord {
    /// The flags of [`STATUS_FLAGS`] in bits 0.., the faults word from bit
    /// [`STATUS_FAULTS_SHIFT`], 0 elsewhere.
    Status,
    /// An output sign-extended from its register width to 32 bits.
    SignExtended(usize),
    /// An output zero-extended (its low 32 bits when wider).
    ZeroExtended(usize),
    /// The configuration hash, bits 31..0.
    HashLow,
    /// The configuration hash, bits 63..32.
    HashHigh,
}

/// One word of the MCU register file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct McuRegister {
    /// Word address.
    pub addr: u32,
    /// Name.
    pub name: &'static str,
    /// Contents, as the docs show them.
    pub what: &'static str,
    /// The word's source.
    pub word: McuWord,
    /// A diagnostic counter: reads 0 unless the design was generated with the diagnostic
    /// counters (hdl-gen's `mcu_diagnostics` option).
    pub diagnostic: bool,
}

/// The index of output `name` in [`MeasureOutputs::LAYOUT`]; a name that is no output
/// fails to compile where the table uses it.
const fn output(name: &str) -> usize {
    let mut i = 0;
    while i < MeasureOutputs::FIELD_COUNT {
        let field = MeasureOutputs::LAYOUT[i].0.as_bytes();
        let wanted = name.as_bytes();
        if field.len() == wanted.len() {
            let mut k = 0;
            while k < field.len() && field[k] == wanted[k] {
                k += 1;
            }
            if k == field.len() {
                return i;
            }
        }
        i += 1;
    }
    panic!("no such output")
}

/// The outputs in the `STATUS` word's bits 0.., as [`MeasureOutputs::LAYOUT`] indices.
pub const STATUS_FLAGS: [usize; 7] = [
    output("armed"),
    output("contact"),
    output("register_now"),
    output("first_contact"),
    output("density_armed"),
    output("density_fired"),
    output("confirmed"),
];
/// The faults word's output index ([`MeasureOutputs::LAYOUT`]).
pub const STATUS_FAULTS: usize = output("faults");
/// The faults word's lowest bit in the `STATUS` word (bit 8 + n = fault bit n).
pub const STATUS_FAULTS_SHIFT: u32 = 8;

const fn register(
    addr: u32,
    name: &'static str,
    what: &'static str,
    word: McuWord,
    diagnostic: bool,
) -> McuRegister {
    McuRegister {
        addr,
        name,
        what,
        word,
        diagnostic,
    }
}

/// The MCU register map, by address.
pub const MCU_REGISTERS: [McuRegister; 12] = {
    use McuWord::*;
    [
        register(0, "STATUS", "bit 0 armed, 1 contact, 2 register_now, 3 first_contact, 4 density_armed, 5 density_fired, 6 confirmed; bits 14..8 faults (bit 8 + n = fault bit n)", Status, false),
        register(1, "POSITION", "live scale position, counts, sign-extended", SignExtended(output("position")), false),
        register(2, "DECISION_POSITION", "position latched at the decision, counts, sign-extended", SignExtended(output("decision_position")), false),
        register(3, "FIRST_CONTACT_POSITION", "position latched at the first contact, counts, sign-extended", SignExtended(output("first_contact_position")), false),
        register(4, "COUNT", "contact pulses in the current window", ZeroExtended(output("count")), false),
        register(5, "LAST_WINDOW_COUNT", "contact pulses in the previous window", ZeroExtended(output("last_window_count")), false),
        register(6, "CHARGE", "capacitor charge, LSBs", ZeroExtended(output("charge")), false),
        register(7, "REVOLUTIONS", "index pulses since arm", ZeroExtended(output("revolutions")), true),
        register(8, "PULSES", "FES pulses since arm", ZeroExtended(output("pulses")), true),
        register(9, "SCALE_ERRORS", "illegal scale transitions", ZeroExtended(output("scale_errors")), false),
        register(10, "CONFIG_HASH_LO", "configuration hash, bits 31..0", HashLow, false),
        register(11, "CONFIG_HASH_HI", "configuration hash, bits 63..32", HashHigh, false),
    ]
};

/// `bits` sign-extended from `width` bits to 32 (its low 32 bits when `width >= 32`).
fn sign_extend(bits: u64, width: u32) -> u32 {
    if width == 0 || width >= MCU_DATA_BITS {
        bits as u32
    } else {
        let shift = MCU_DATA_BITS - width;
        (((bits as u32) << shift) as i32 >> shift) as u32
    }
}

impl McuRegister {
    /// The register at `addr`, if the map has one.
    pub fn at(addr: u32) -> Option<&'static McuRegister> {
        MCU_REGISTERS.iter().find(|r| r.addr == addr)
    }

    /// This word from the outputs: `output(i)` gives output `i`'s register bits and width
    /// ([`MeasureOutputs::LAYOUT`] index), `None` when it is unknown (an X in a dump), which
    /// makes the word unknown. `hash` is the configuration hash. A diagnostic counter is
    /// given as it would read with the counters generated.
    pub fn word(&self, hash: u64, output: impl Fn(usize) -> Option<(u64, u32)>) -> Option<u32> {
        Some(match self.word {
            McuWord::Status => {
                let mut status = 0u32;
                for (bit, &i) in STATUS_FLAGS.iter().enumerate() {
                    status |= ((output(i)?.0 & 1) as u32) << bit;
                }
                let (faults, width) = output(STATUS_FAULTS)?;
                let faults =
                    faults & ((1u64 << width.min(MCU_DATA_BITS - STATUS_FAULTS_SHIFT)) - 1);
                status | (faults as u32) << STATUS_FAULTS_SHIFT
            }
            McuWord::SignExtended(i) => {
                let (bits, width) = output(i)?;
                sign_extend(bits, width)
            }
            McuWord::ZeroExtended(i) => output(i)?.0 as u32,
            McuWord::HashLow => hash as u32,
            McuWord::HashHigh => (hash >> 32) as u32,
        })
    }
}

/// The word at `addr` of a front end with `config` and configuration hash `hash` whose
/// outputs' register bits are `bits` ([`MeasureOutputs::register_bits`]); 0 at an
/// unlisted address and, unless `diagnostics`, at a diagnostic counter.
pub fn mcu_word(
    config: &MeasureConfig,
    hash: u64,
    bits: &[u64; MeasureOutputs::FIELD_COUNT],
    addr: u32,
    diagnostics: bool,
) -> u32 {
    match McuRegister::at(addr) {
        Some(r) if diagnostics || !r.diagnostic => {
            let widths = MeasureOutputs::widths(config);
            r.word(hash, |i| Some((bits[i], widths[i].1))).unwrap_or(0)
        }
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::config::MeasureSettings;

    /// Outputs with a distinct value in every field, and the words they give, written from
    /// the map's documentation (not from the table).
    #[test]
    fn each_word_holds_what_its_documentation_says() {
        let config = MeasureSettings {
            scale_bits: 24,
            ..MeasureSettings::default()
        }
        .validate()
        .unwrap();
        let o = MeasureOutputs {
            armed: true,
            contact: false,
            register_now: true,
            decision_position: -5,
            first_contact: false,
            first_contact_position: 0x7f_ffff,
            position: -1,
            scale_errors: 9,
            count: 300,
            last_window_count: 301,
            charge: 1234,
            density_armed: true,
            density_fired: false,
            revolutions: 0xbeef,
            pulses: 0xdead_beef,
            confirmed: true,
            faults: 0b101_0011,
        };
        let bits = o.register_bits(&config);
        let hash = 0x0123_4567_89ab_cdef;
        let word = |addr, diagnostics| mcu_word(&config, hash, &bits, addr, diagnostics);
        assert_eq!(
            word(0, false),
            0b101_0011 << 8 | 1 << 6 | 1 << 4 | 1 << 2 | 1
        );
        assert_eq!(word(1, false), u32::MAX, "position −1 sign-extended");
        assert_eq!(word(2, false), (-5i32) as u32);
        assert_eq!(
            word(3, false),
            0x7f_ffff,
            "the largest positive 24-bit position"
        );
        assert_eq!(word(4, false), 300);
        assert_eq!(word(5, false), 301);
        assert_eq!(word(6, false), 1234);
        assert_eq!((word(7, false), word(7, true)), (0, 0xbeef));
        assert_eq!((word(8, false), word(8, true)), (0, 0xdead_beef));
        assert_eq!(word(9, false), 9);
        assert_eq!(word(10, false), 0x89ab_cdef);
        assert_eq!(word(11, false), 0x0123_4567);
        for addr in 12..16 {
            assert_eq!(word(addr, true), 0, "address {addr} is unmapped");
        }
    }

    #[test]
    fn the_map_is_dense_from_zero_and_names_are_unique() {
        for (i, r) in MCU_REGISTERS.iter().enumerate() {
            assert_eq!(r.addr, i as u32);
            assert_eq!(McuRegister::at(r.addr), Some(r));
            assert!(MCU_REGISTERS[..i].iter().all(|s| s.name != r.name));
        }
        assert!(MCU_REGISTERS.len() <= 1 << MCU_ADDR_BITS);
        assert!(
            STATUS_FLAGS.len() as u32 <= STATUS_FAULTS_SHIFT,
            "the flags end below the faults"
        );
    }

    #[test]
    fn an_unknown_output_makes_its_word_unknown_and_no_other() {
        let unknown_charge = |i: usize| (i != output("charge")).then_some((1, 8));
        assert_eq!(MCU_REGISTERS[6].word(0, unknown_charge), None);
        assert_eq!(MCU_REGISTERS[4].word(0, unknown_charge), Some(1));
        assert_eq!(MCU_REGISTERS[10].word(7, |_| None), Some(7));
    }
}
