//! The MCU's view of the front end: the register map (the model's [`MCU_REGISTERS`],
//! re-exported) and the Verilog expression of each word, shared by the design's read mux
//! (`tt_frontend`) and the testbench's reference so the two cannot disagree.

pub use tooltouch_model::measure::mcu_registers::{
    McuRegister, McuWord, MCU_ADDR_BITS, MCU_DATA_BITS, MCU_REGISTERS,
};
use tooltouch_model::measure::mcu_registers::{STATUS_FAULTS, STATUS_FAULTS_SHIFT, STATUS_FLAGS};
use tooltouch_model::{MeasureConfig, MeasureOutputs};

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
    let fields = MeasureOutputs::widths(config);
    let p = |i: usize| format!("{prefix}{}", fields[i].0);
    let width = |i: usize| fields[i].1;
    let sext = |i: usize| {
        let w = width(i);
        if w >= MCU_DATA_BITS {
            p(i)
        } else {
            format!(
                "{{{{{}{{{}[{}]}}}}, {}}}",
                MCU_DATA_BITS - w,
                p(i),
                w - 1,
                p(i)
            )
        }
    };
    let zext = |i: usize| {
        let w = width(i);
        if w >= MCU_DATA_BITS {
            p(i)
        } else {
            format!("{{{}'d0, {}}}", MCU_DATA_BITS - w, p(i))
        }
    };
    // STATUS: `{pad'd0, faults, gap'b0, flag n-1, …, flag 0}`.
    let status = || {
        let pad = MCU_DATA_BITS - STATUS_FAULTS_SHIFT - width(STATUS_FAULTS);
        let gap = STATUS_FAULTS_SHIFT - STATUS_FLAGS.len() as u32;
        let mut parts = Vec::new();
        if pad > 0 {
            parts.push(format!("{pad}'d0"));
        }
        parts.push(p(STATUS_FAULTS));
        if gap > 0 {
            parts.push(format!("{gap}'b0"));
        }
        parts.extend(STATUS_FLAGS.iter().rev().map(|&i| p(i)));
        format!("{{{}}}", parts.join(", "))
    };
    MCU_REGISTERS.map(|reg| {
        if reg.diagnostic && !diagnostics {
            return format!("{MCU_DATA_BITS}'d0");
        }
        match reg.word {
            McuWord::Status => status(),
            McuWord::SignExtended(i) => sext(i),
            McuWord::ZeroExtended(i) => zext(i),
            McuWord::HashLow => format!("32'h{:08x}", hash & 0xffff_ffff),
            McuWord::HashHigh => format!("32'h{:08x}", hash >> 32),
        }
    })
}
