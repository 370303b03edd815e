//! The MCU's view of the front end: the register map ([`MCU_REGISTERS`]) and the Verilog
//! expression of each word, shared by the design's read mux (`tt_frontend`) and the
//! testbench's reference so the two cannot disagree.

use tooltouch_model::MeasureConfig;

/// Width of the MCU read-data bus, bits.
pub const MCU_DATA_BITS: u32 = 32;
/// Width of the MCU register address, bits.
pub const MCU_ADDR_BITS: u32 = 4;

/// One word of the MCU register file (read through `mcu_addr` / `mcu_rdata`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct McuRegister {
    /// Word address.
    pub addr: u32,
    /// Name.
    pub name: &'static str,
    /// Contents.
    pub what: &'static str,
    /// A diagnostic counter: reads 0 unless [`crate::Options::mcu_diagnostics`] is set.
    pub diagnostic: bool,
}

/// The MCU register map. Unlisted addresses, and the diagnostic counters unless
/// [`crate::Options::mcu_diagnostics`] is set, read 0. Positions are sign-extended from
/// `scale_bits` to 32 bits; counts are zero-extended.
pub const MCU_REGISTERS: [McuRegister; 12] = [
    McuRegister { addr: 0, name: "STATUS", what: "bit 0 armed, 1 contact, 2 register_now, 3 first_contact, 4 density_armed, 5 density_fired, 6 confirmed; bits 14..8 faults (bit 8 + n = fault bit n)", diagnostic: false },
    McuRegister { addr: 1, name: "POSITION", what: "live scale position, counts, sign-extended", diagnostic: false },
    McuRegister { addr: 2, name: "DECISION_POSITION", what: "position latched at the decision, counts, sign-extended", diagnostic: false },
    McuRegister { addr: 3, name: "FIRST_CONTACT_POSITION", what: "position latched at the first contact, counts, sign-extended", diagnostic: false },
    McuRegister { addr: 4, name: "COUNT", what: "contact pulses in the current window", diagnostic: false },
    McuRegister { addr: 5, name: "LAST_WINDOW_COUNT", what: "contact pulses in the previous window", diagnostic: false },
    McuRegister { addr: 6, name: "CHARGE", what: "capacitor charge, LSBs", diagnostic: false },
    McuRegister { addr: 7, name: "REVOLUTIONS", what: "index pulses since arm", diagnostic: true },
    McuRegister { addr: 8, name: "PULSES", what: "FES pulses since arm", diagnostic: true },
    McuRegister { addr: 9, name: "SCALE_ERRORS", what: "illegal scale transitions", diagnostic: false },
    McuRegister { addr: 10, name: "CONFIG_HASH_LO", what: "configuration hash, bits 31..0", diagnostic: false },
    McuRegister { addr: 11, name: "CONFIG_HASH_HI", what: "configuration hash, bits 63..32", diagnostic: false },
];

/// The MCU read mux: an `always @*` block with one `case (mcu_addr)` arm per register of
/// [`MCU_REGISTERS`] (`<addr>: mcu_rdata = <word>;  // <name>`) over the output signals
/// themselves, 0 at any other address. The design and the reference share it.
pub(crate) fn mcu_read_mux(config: &MeasureConfig, hash: u64, diagnostics: bool) -> String {
    let words = mcu_words(config, hash, "", diagnostics);
    let arms: String = MCU_REGISTERS
        .iter()
        .zip(words.iter())
        .map(|(reg, word)| {
            format!(
                "            {}: mcu_rdata = {word};  // {}\n",
                crate::emit::lit(MCU_ADDR_BITS, reg.addr.into()),
                reg.name
            )
        })
        .collect();
    format!(
        "    always @* begin\n        case (mcu_addr)\n{arms}            default: mcu_rdata = {};\n        endcase\n    end\n",
        crate::emit::lit(MCU_DATA_BITS, 0)
    )
}

/// Verilog expressions of the MCU register words, indexed like [`MCU_REGISTERS`], over
/// signals named as [`crate::output_fields`] with `prefix` prepended (a diagnostic word is a zero
/// constant unless `diagnostics`). The DUT's read mux and the testbench's reference use
/// this one table.
pub(crate) fn mcu_words(
    config: &MeasureConfig,
    hash: u64,
    prefix: &str,
    diagnostics: bool,
) -> [String; 12] {
    let s = config.settings();
    let sb = u32::from(s.scale_bits);
    let p = |n: &str| format!("{prefix}{n}");
    let sext = |n: &str| {
        if sb >= MCU_DATA_BITS {
            p(n)
        } else {
            format!(
                "{{{{{}{{{}[{}]}}}}, {}}}",
                MCU_DATA_BITS - sb,
                p(n),
                sb - 1,
                p(n)
            )
        }
    };
    let zext = |n: &str, w: u32| {
        if w >= MCU_DATA_BITS {
            p(n)
        } else {
            format!("{{{}'d0, {}}}", MCU_DATA_BITS - w, p(n))
        }
    };
    let cb = u32::from(config.count_bits());
    let words = [
        format!(
            "{{17'd0, {}, 1'b0, {}, {}, {}, {}, {}, {}, {}}}",
            p("faults"),
            p("confirmed"),
            p("density_fired"),
            p("density_armed"),
            p("first_contact"),
            p("register_now"),
            p("contact"),
            p("armed")
        ),
        sext("position"),
        sext("decision_position"),
        sext("first_contact_position"),
        zext("count", cb),
        zext("last_window_count", cb),
        zext("charge", u32::from(s.charge_bits)),
        zext("revolutions", 16),
        p("pulses"),
        zext("scale_errors", 8),
        format!("32'h{:08x}", hash & 0xffff_ffff),
        format!("32'h{:08x}", hash >> 32),
    ];
    let mut index = 0;
    words.map(|word| {
        let diagnostic = MCU_REGISTERS[index].diagnostic;
        index += 1;
        if diagnostic && !diagnostics {
            format!("{MCU_DATA_BITS}'d0")
        } else {
            word
        }
    })
}
