//! tooltouch-hdl-gen: writes the Verilog-2005 of the FPGA measurement front end from the
//! model's [`MeasureConfig`], and the self-checking testbench that compares it, every
//! cycle and every output bit, with vectors written by the golden model.
//!
//! The generated design reproduces `tooltouch_model::FrontEnd::clock` exactly:
//!
//! | module | model | registers |
//! | --- | --- | --- |
//! | `tt_synchronizer` | `FrontEnd::sync1/sync2` | 2 × 6 |
//! | `tt_glitch_filter` | `FrontEnd::filter` | 6 levels + 6 × `glitch_bits` counters |
//! | `tt_edge_detect` | `filtered ^ FrontEnd::previous` | 8 strobes (rising edges, armed index/FES, scale step), registered one clock early |
//! | `tt_pulse_counter` | `PulseCounter` (SPEC 2.3) | count, last window count, revs, reached |
//! | `tt_density_detector` | `DensityDetector` (SPEC 2.4) | charge, armed, fired |
//! | `tt_quadrature_decoder` | `QuadratureDecoder` (SPEC 1) | position, errors (the phase is the filtered levels') |
//! | `tt_position_latch` | `PositionLatch` | valid, position |
//! | `tt_measurement` | `Measurement` | armed, contact, sticky, revolutions, pulses |
//! | `tt_frontend` (simulation top) | `FrontEnd` + MCU register file | none of its own |
//! | `tt_fpga` (chip top) | — | the registered MCU address and read data |
//!
//! Every register has the model's power-on value both as a Verilog initializer and as
//! the value a synchronous `rst` loads (the chip top's MCU bus registers, which hold no
//! state, only the initializer); every update is a non-blocking assignment. The
//! edges detected in one clock drive the kernel in the model's canonical order
//! arm → contact → index → FES → scale: each block receives that clock's strobes and
//! computes its next state as the *sequential composition* of the model's methods
//! (`*_a` wires: after arm, `*_i`: after index, `*_p`: after the FES pulse), so two
//! edges in the same clock act exactly as the model's consecutive calls do.
//!
//! For speed (≥ 150 MHz on an iCE40 HX8K) without changing the contract's latency, what
//! the kernel's decisions need is computed one clock early and registered: the edge
//! stage decodes the strobes from the glitch filter's next levels, the sticky contact bit
//! is kept as the next pulse will read it, the counter's `i_def` comparisons are registers
//! stepped by equalities, and the decision is written flat over flip-flops (two LUT
//! levels before the latches). Constant thresholds are written as bit logic, not as
//! comparisons (which yosys maps to carry chains).
//!
//! Every width and constant is read from the [`MeasureConfig`]; the header of every file
//! names the configuration hash ([`MeasureConfig::hash`]).
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod blocks;
mod testbench;

use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::{MeasureConfig, MeasureOutputs};

pub use testbench::{
    testbench, verilator_main, TestbenchSpec, EXPECT_HEX, STIM_HEX, STIM_WORD_BITS, TESTBENCH,
    VERILATOR_MAIN,
};

/// Name of the simulation top module (and of its file, `tt_frontend.v`): every output a
/// port, compared by the testbench.
pub const TOP: &str = "tt_frontend";
/// Name of the chip top for synthesis (file `tt_fpga.v`): pins, MCU bus and strobe only.
pub const FPGA_TOP: &str = "tt_fpga";

/// Width of the MCU read-data bus, bits.
pub const MCU_DATA_BITS: u32 = 32;
/// Width of the MCU register address, bits.
pub const MCU_ADDR_BITS: u32 = 4;

/// A fault deliberately injected into the generated Verilog, so tests can prove that the
/// co-simulation and `tooltouch check` catch a design that differs from the model. Never
/// used outside tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Fault {
    /// The correct design.
    #[default]
    None,
    /// The FES pulse is counted *before* a same-clock index pulse ends the window (the
    /// canonical order is index first), so a pulse arriving with the index is lost from
    /// the new window.
    FesBeforeIndex,
    /// The density detector's fire threshold is one LSB higher than configured.
    FireThresholdPlusOne,
}

/// Generation options.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Options {
    /// Fault to inject (tests only).
    pub fault: Fault,
    /// Make the diagnostic counters (`REVOLUTIONS`, `PULSES`) readable by the MCU. Off by
    /// default: they are outputs of the simulation top either way, but only a readable
    /// counter is synthesized into the chip (about 100 logic cells for the two).
    pub mcu_diagnostics: bool,
}

/// One generated Verilog source file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VerilogFile {
    /// File name, `<module>.v`.
    pub name: String,
    /// Verilog-2005 source text.
    pub text: String,
}

/// The generated design: one file per module, the top last.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Design {
    /// Source files, leaves first, then the simulation top ([`TOP`]) and the chip top
    /// ([`FPGA_TOP`]).
    pub files: Vec<VerilogFile>,
    /// Hash of the configuration the design was made from.
    pub config_hash: u64,
}

impl Design {
    /// File names in compile order.
    pub fn file_names(&self) -> Vec<&str> {
        self.files.iter().map(|f| f.name.as_str()).collect()
    }
}

/// Writes the Verilog of the front end for `config`.
pub fn generate(config: &MeasureConfig, options: &Options) -> Design {
    let g = blocks::Gen::new(config, options);
    let files = vec![
        g.synchronizer(),
        g.glitch_filter(),
        g.edge_detect(),
        g.pulse_counter(),
        g.density_detector(),
        g.quadrature_decoder(),
        g.position_latch(),
        g.measurement(),
        g.top(),
        g.fpga_top(),
    ];
    Design {
        files,
        config_hash: config.hash(),
    }
}

/// One output of the front end, as a port of the top module, a VCD signal and a field of
/// the expected-response hex vectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct OutputField {
    /// Name, equal to the `MeasureOutputs` field and the VCD signal.
    pub name: &'static str,
    /// Width, bits (the VCD contract's widths).
    pub width: u32,
}

/// The outputs in `MeasureOutputs` / VCD contract order, with their widths for `config`
/// ([`MeasureOutputs::widths`], the model's one list).
pub fn output_fields(config: &MeasureConfig) -> [OutputField; 15] {
    MeasureOutputs::widths(config).map(|(name, width)| OutputField { name, width })
}

/// Total width of all outputs, bits.
pub fn outputs_width(config: &MeasureConfig) -> u32 {
    output_fields(config).iter().map(|f| f.width).sum()
}

/// The raw bits of every output (two's-complement positions truncated to `scale_bits`),
/// in [`output_fields`] order.
pub fn output_values(config: &MeasureConfig, o: &MeasureOutputs) -> [u64; 15] {
    o.register_bits(config)
}

/// `width` low bits set (`width <= 64`).
pub fn mask(width: u32) -> u64 {
    if width >= 64 {
        u64::MAX
    } else {
        (1u64 << width) - 1
    }
}

/// One word of the MCU register file (read through `mcu_addr` / `mcu_rdata`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct McuRegister {
    /// Word address.
    pub addr: u32,
    /// Name.
    pub name: &'static str,
    /// Contents.
    pub what: &'static str,
    /// A diagnostic counter: reads 0 unless [`Options::mcu_diagnostics`] is set.
    pub diagnostic: bool,
}

/// The MCU register map. Unlisted addresses, and the diagnostic counters unless
/// [`Options::mcu_diagnostics`] is set, read 0. Positions are sign-extended from
/// `scale_bits` to 32 bits; counts are zero-extended.
pub const MCU_REGISTERS: [McuRegister; 12] = [
    McuRegister { addr: 0, name: "STATUS", what: "bit 0 armed, 1 contact, 2 register_now, 3 first_contact, 4 density_armed, 5 density_fired", diagnostic: false },
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

/// Verilog expressions of the MCU register words, indexed like [`MCU_REGISTERS`], over
/// signals named as [`output_fields`] with `prefix` prepended (a diagnostic word is a zero
/// constant unless `diagnostics`). The DUT's read mux and the testbench's reference use
/// this one table.
pub(crate) fn mcu_words(config: &MeasureConfig, prefix: &str, diagnostics: bool) -> [String; 12] {
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
    let hash = config.hash();
    let words = [
        format!(
            "{{26'd0, {}, {}, {}, {}, {}, {}}}",
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

/// A one-line human summary of the configuration for file headers.
pub(crate) fn describe(config: &MeasureConfig) -> String {
    let s = config.settings();
    let law = match s.charge_law {
        ChargeLaw::Linear {
            charge_step,
            discharge_step,
        } => format!("linear +{charge_step}/-{discharge_step}"),
        ChargeLaw::Exponential {
            charge_shift,
            discharge_shift,
        } => format!("exponential >>{charge_shift}/>>{discharge_shift}"),
    };
    let rule = match s.contact_rule {
        ContactRule::Sampled => "sampled",
        ContactRule::Sticky => "sticky",
    };
    let method = match s.method {
        DecisionMethod::SinglePulse => "single_pulse",
        DecisionMethod::Counter => "counter",
        DecisionMethod::Density => "density",
    };
    format!(
        "ppr {} x {} rev, i_def {}, {rule} contact, method {method}; charge {} bits {law}, \
         fire {} rearm {}; glitch {} cycles; scale {} bits",
        s.pulses_per_rev,
        s.window_revs,
        s.i_def,
        s.charge_bits,
        s.fire_threshold,
        s.rearm_threshold,
        s.glitch_cycles,
        s.scale_bits
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_file_names_the_config_hash_and_its_module() {
        let c = MeasureConfig::default();
        let d = generate(&c, &Options::default());
        let hash = format!("{:016x}", c.hash());
        assert_eq!(d.files.len(), 10);
        assert_eq!(d.files[8].name, format!("{TOP}.v"));
        assert_eq!(d.files[9].name, format!("{FPGA_TOP}.v"));
        for f in &d.files {
            assert!(f.text.contains(&hash), "{} lacks the hash", f.name);
            let module = f.name.trim_end_matches(".v");
            assert!(f.text.contains(&format!("module {module}")), "{}", f.name);
        }
    }

    #[test]
    fn output_widths_follow_the_config() {
        let c = MeasureConfig::default();
        let f = output_fields(&c);
        assert_eq!(f[3].width, 24);
        assert_eq!(f[8].width, 11);
        assert_eq!(f[10].width, 16);
        assert_eq!(outputs_width(&c), 6 + 3 * 24 + 8 + 22 + 16 + 16 + 32);
    }

    #[test]
    fn negative_positions_are_truncated_to_scale_bits() {
        let c = MeasureConfig::default();
        let o = MeasureOutputs {
            position: -1,
            ..Default::default()
        };
        assert_eq!(output_values(&c, &o)[6], 0xff_ffff);
    }

    #[test]
    fn a_fault_changes_the_text() {
        let c = MeasureConfig::default();
        let good = generate(&c, &Options::default());
        for fault in [Fault::FesBeforeIndex, Fault::FireThresholdPlusOne] {
            assert_ne!(
                good,
                generate(
                    &c,
                    &Options {
                        fault,
                        ..Options::default()
                    }
                ),
                "{fault:?}"
            );
        }
    }
}
