//! The SPI register interface of the chip top `tt_fpga_spi` (`tooltouch_hdl_gen::generate_spi`): the
//! run-time thresholds ([`Threshold`]), the register map ([`spi_registers`], derived from
//! the MCU map [`crate::mcu::MCU_REGISTERS`] and the model's outputs), the frame format and
//! status bits, the settings CRC ([`settings_crc`]), and the model's value of every word
//! ([`spi_word_values`]) that the SPI testbench compares with.
//!
//! Frame (docs/CONTRACT.md, "SPI register interface"): SPI mode 0, MSB first, CS low for
//! exactly [`SPI_FRAME_BITS`] = 40 bits: a command byte (bit 7 = 1 for a write, bits
//! 6..0 the address) and a 32-bit data word. While the command byte is shifted in, MISO
//! shifts out the low byte of [`SPI_STATUS_ADDR`]; then the addressed word (a read) or
//! zeros (a write). A write takes effect when CS rises after exactly 40 bits.

use crate::mcu::{mcu_words, MCU_DATA_BITS, MCU_REGISTERS};
use crate::outputs::output_fields;
use tooltouch_model::measure::config::{bits_for, ChargeLaw};
use tooltouch_model::{MeasureConfig, MeasureOutputs, MeasureSettings};

/// Name of the SPI chip top (file `tt_fpga_spi.v`), the board top of both boards.
pub const SPI_TOP: &str = "tt_fpga_spi";
/// Name of the SPI register interface module (file `tt_spi.v`).
pub const SPI_MODULE: &str = "tt_spi";
/// Bits of one SPI frame: the command byte and a 32-bit data word.
pub const SPI_FRAME_BITS: u32 = 8 + MCU_DATA_BITS;
/// Width of the SPI register address (bits 6..0 of the command byte).
pub const SPI_ADDR_BITS: u32 = 7;
/// Command byte bit 7: the frame is a write.
pub const SPI_WRITE: u8 = 0x80;
/// First address of the output words that the MCU map does not show (new model outputs
/// land here, one word each, in [`MeasureOutputs::LAYOUT`] order).
pub const SPI_EXTRA_BASE: u8 = 0x10;
/// First address of the run-time thresholds, in [`Threshold::ALL`] order.
pub const SPI_THRESHOLD_BASE: u8 = 0x20;
/// Address of the status word (read; a write clears the error bits set in its data).
pub const SPI_STATUS_ADDR: u8 = 0x30;
/// Address of the settings CRC ([`settings_crc`] of the thresholds in force).
pub const SPI_SETTINGS_CRC_ADDR: u8 = 0x31;
/// Address of the control word (write only, reads 0): bit 0 resets the kernel to its
/// power-on state, bit 1 restores every threshold to the configured value.
pub const SPI_CONTROL_ADDR: u8 = 0x32;
/// Minimum FPGA clocks per SCK phase (high or low): a shorter phase seen in a frame sets
/// [`status::SCK_FAST`] and the frame's write is dropped. SCK ≤ f_clk / 4.
pub const SPI_MIN_PHASE_CLOCKS: u32 = 2;

/// Bits of the status word ([`SPI_STATUS_ADDR`]). Bits 0–4 are sticky error flags (set by
/// a refused or broken frame, cleared by writing 1s to them); bits 15..8 count the
/// accepted threshold writes (wrapping).
pub mod status {
    /// A write to a read-only or unmapped address (nothing written).
    pub const READ_ONLY: u32 = 1 << 0;
    /// A threshold write out of its range (nothing written).
    pub const RANGE: u32 = 1 << 1;
    /// A threshold write while the cycle is armed (nothing written).
    pub const ARMED: u32 = 1 << 2;
    /// A frame that ended with a bit count other than 40 (nothing written).
    pub const TORN: u32 = 1 << 3;
    /// A frame in which an SCK phase lasted fewer than two FPGA clocks (nothing written).
    pub const SCK_FAST: u32 = 1 << 4;
    /// All error flags.
    pub const ERRORS: u32 = READ_ONLY | RANGE | ARMED | TORN | SCK_FAST;
    /// Shift of the accepted-writes counter (8 bits).
    pub const WRITES_SHIFT: u32 = 8;
}

/// A threshold that is a register of the SPI interface rather than a constant of the
/// logic. Its width is fixed at synthesis; it resets to the configured value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Threshold {
    /// `i_def`: decision when the window's count exceeds it.
    IDef,
    /// `fire_threshold`, LSBs of charge.
    FireThreshold,
    /// `rearm_threshold`, LSBs of charge.
    RearmThreshold,
    /// `glitch_cycles`, clocks.
    GlitchCycles,
    /// `charge_step` (linear law, LSBs) or `charge_shift` (exponential law).
    ChargeStep,
    /// `discharge_step` (linear law, LSBs) or `discharge_shift` (exponential law).
    DischargeStep,
}

impl Threshold {
    /// Every threshold, in address order from [`SPI_THRESHOLD_BASE`].
    pub const ALL: [Threshold; 6] = [
        Threshold::IDef,
        Threshold::FireThreshold,
        Threshold::RearmThreshold,
        Threshold::GlitchCycles,
        Threshold::ChargeStep,
        Threshold::DischargeStep,
    ];

    /// The register's name in the map.
    pub fn name(self) -> &'static str {
        match self {
            Threshold::IDef => "I_DEF",
            Threshold::FireThreshold => "FIRE_THRESHOLD",
            Threshold::RearmThreshold => "REARM_THRESHOLD",
            Threshold::GlitchCycles => "GLITCH_CYCLES",
            Threshold::ChargeStep => "CHARGE_STEP",
            Threshold::DischargeStep => "DISCHARGE_STEP",
        }
    }

    /// The kernel input port it drives (and the register file's output).
    pub fn port(self) -> &'static str {
        match self {
            Threshold::IDef => "i_def",
            Threshold::FireThreshold => "fire_threshold",
            Threshold::RearmThreshold => "rearm_threshold",
            Threshold::GlitchCycles => "glitch_cycles",
            Threshold::ChargeStep => "charge_step",
            Threshold::DischargeStep => "discharge_step",
        }
    }

    /// Its SPI address.
    pub fn addr(self) -> u8 {
        let index = Threshold::ALL.iter().position(|t| *t == self).unwrap_or(0);
        SPI_THRESHOLD_BASE + index as u8
    }

    /// Width of the register, bits (fixed at synthesis).
    pub fn width(self, config: &MeasureConfig) -> u32 {
        let s = config.settings();
        match self {
            Threshold::IDef => config.count_bits().into(),
            Threshold::FireThreshold | Threshold::RearmThreshold => s.charge_bits.into(),
            Threshold::GlitchCycles => config.glitch_bits().into(),
            Threshold::ChargeStep | Threshold::DischargeStep => match s.charge_law {
                ChargeLaw::Linear { .. } => s.charge_bits.into(),
                ChargeLaw::Exponential { .. } => bits_for(s.charge_bits.into()).into(),
            },
        }
    }

    /// The value in `settings` (the register's reset value for the configured settings).
    pub fn value(self, settings: &MeasureSettings) -> u32 {
        let (charge, discharge) = match settings.charge_law {
            ChargeLaw::Linear {
                charge_step,
                discharge_step,
            } => (charge_step, discharge_step),
            ChargeLaw::Exponential {
                charge_shift,
                discharge_shift,
            } => (charge_shift.into(), discharge_shift.into()),
        };
        match self {
            Threshold::IDef => settings.i_def,
            Threshold::FireThreshold => settings.fire_threshold,
            Threshold::RearmThreshold => settings.rearm_threshold,
            Threshold::GlitchCycles => settings.glitch_cycles.into(),
            Threshold::ChargeStep => charge,
            Threshold::DischargeStep => discharge,
        }
    }

    /// `settings` with this threshold set to `value`, `None` when `value` does not fit
    /// the field's type. Not validated: see [`Threshold::accepts`].
    pub fn with(self, settings: &MeasureSettings, value: u32) -> Option<MeasureSettings> {
        let mut s = *settings;
        let small = u8::try_from(value).ok();
        match (self, &mut s.charge_law) {
            (Threshold::IDef, _) => s.i_def = value,
            (Threshold::FireThreshold, _) => s.fire_threshold = value,
            (Threshold::RearmThreshold, _) => s.rearm_threshold = value,
            (Threshold::GlitchCycles, _) => s.glitch_cycles = small?,
            (Threshold::ChargeStep, ChargeLaw::Linear { charge_step, .. }) => *charge_step = value,
            (Threshold::DischargeStep, ChargeLaw::Linear { discharge_step, .. }) => {
                *discharge_step = value
            }
            (Threshold::ChargeStep, ChargeLaw::Exponential { charge_shift, .. }) => {
                *charge_shift = small?
            }
            (
                Threshold::DischargeStep,
                ChargeLaw::Exponential {
                    discharge_shift, ..
                },
            ) => *discharge_shift = small?,
        }
        Some(s)
    }

    /// The largest value the synthesized register takes: the model's range cut to the
    /// width (`glitch_cycles` to `2^glitch_bits − 1`, and 0 when configured 0: that
    /// filter has no counter).
    pub fn max(self, config: &MeasureConfig) -> u32 {
        let s = config.settings();
        match self {
            Threshold::IDef => config.window_pulses() - 1,
            Threshold::FireThreshold | Threshold::RearmThreshold => config.full_charge(),
            Threshold::GlitchCycles if s.glitch_cycles == 0 => 0,
            Threshold::GlitchCycles => (1u32 << config.glitch_bits()) - 1,
            Threshold::ChargeStep | Threshold::DischargeStep => match s.charge_law {
                ChargeLaw::Linear { .. } => config.full_charge(),
                ChargeLaw::Exponential { .. } => s.charge_bits.into(),
            },
        }
    }

    /// The smallest value the register takes: 1 for `fire_threshold` and the linear
    /// law's steps, 0 otherwise.
    pub fn min(self, config: &MeasureConfig) -> u32 {
        let linear = matches!(config.settings().charge_law, ChargeLaw::Linear { .. });
        match self {
            Threshold::FireThreshold => 1,
            Threshold::ChargeStep | Threshold::DischargeStep if linear => 1,
            _ => 0,
        }
    }

    /// Whether the FPGA accepts `value` for this threshold when the thresholds in force
    /// are those of `current` (whose widths are `config`'s): the value is at most
    /// [`Threshold::max`] and the settings with it validate (so `rearm < fire` holds
    /// against the other register's value in force).
    pub fn accepts(self, config: &MeasureConfig, current: &MeasureSettings, value: u32) -> bool {
        value <= self.max(config)
            && self
                .with(current, value)
                .is_some_and(|s| s.validate().is_ok())
    }
}

/// Who may write an SPI register.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Access {
    /// Read only: a write sets [`status::READ_ONLY`].
    ReadOnly,
    /// Read and write (a run-time threshold, range-checked, only while disarmed).
    ReadWrite,
    /// Read; a write clears the bits set in its data (the status word).
    WriteOneToClear,
    /// Write only, reads 0 (the control word).
    WriteOnly,
}

/// One word of the SPI register map.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct SpiRegister {
    /// Address (bits 6..0 of the command byte).
    pub addr: u8,
    /// Name.
    pub name: String,
    /// Access.
    pub access: Access,
    /// Contents.
    pub what: String,
}

/// The output fields no MCU word shows (every field a word names with the diagnostic
/// counters readable counts as shown), in [`MeasureOutputs::LAYOUT`] order: each gets a
/// word from [`SPI_EXTRA_BASE`], so a new model output is readable over SPI unchanged.
pub fn extra_outputs(config: &MeasureConfig) -> Vec<crate::outputs::OutputField> {
    unshown(&mcu_words(config, 0, "", true), &output_fields(config))
}

/// The fields of `fields` that no word of `words` names (at most 32 bits wide).
fn unshown(
    words: &[String],
    fields: &[crate::outputs::OutputField],
) -> Vec<crate::outputs::OutputField> {
    fields
        .iter()
        .filter(|f| f.width <= MCU_DATA_BITS)
        .filter(|f| !words.iter().any(|w| names_signal(w, f.name)))
        .copied()
        .collect()
}

/// Whether the Verilog expression `expr` names the signal `name` (as a whole identifier).
fn names_signal(expr: &str, name: &str) -> bool {
    expr.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .any(|token| token == name)
}

/// The SPI register map for `config`: the MCU words at their MCU addresses, the extra
/// output words, the thresholds, the status, settings CRC and control words.
pub fn spi_registers(config: &MeasureConfig) -> Vec<SpiRegister> {
    let mut map: Vec<SpiRegister> = MCU_REGISTERS
        .iter()
        .map(|r| SpiRegister {
            addr: r.addr as u8,
            name: r.name.to_string(),
            access: Access::ReadOnly,
            what: if r.diagnostic {
                format!("{} (0 unless `--mcu-diagnostics`)", r.what)
            } else {
                r.what.to_string()
            },
        })
        .collect();
    for (i, f) in extra_outputs(config).iter().enumerate() {
        map.push(SpiRegister {
            addr: SPI_EXTRA_BASE + i as u8,
            name: f.name.to_ascii_uppercase(),
            access: Access::ReadOnly,
            what: format!("output `{}` ({} bits), zero-extended", f.name, f.width),
        });
    }
    for t in Threshold::ALL {
        map.push(SpiRegister {
            addr: t.addr(),
            name: t.name().to_string(),
            access: Access::ReadWrite,
            what: format!(
                "run-time `{}`, {} bits, {}..={}{} (resets to the configured {})",
                t.port(),
                t.width(config),
                t.min(config),
                t.max(config),
                match t {
                    Threshold::FireThreshold => ", above REARM_THRESHOLD",
                    Threshold::RearmThreshold => ", below FIRE_THRESHOLD",
                    _ => "",
                },
                t.value(config.settings())
            ),
        });
    }
    map.push(SpiRegister {
        addr: SPI_STATUS_ADDR,
        name: "SPI_STATUS".into(),
        access: Access::WriteOneToClear,
        what: "bit 0 read-only, 1 range, 2 armed, 3 torn, 4 SCK fast (sticky, write 1 to clear); 15..8 accepted threshold writes".into(),
    });
    map.push(SpiRegister {
        addr: SPI_SETTINGS_CRC_ADDR,
        name: "SETTINGS_CRC".into(),
        access: Access::ReadOnly,
        what: "CRC-32/MPEG-2 (the STM32 CRC unit's) of the six threshold words in address order"
            .into(),
    });
    map.push(SpiRegister {
        addr: SPI_CONTROL_ADDR,
        name: "CONTROL".into(),
        access: Access::WriteOnly,
        what: "bit 0 resets the kernel, bit 1 restores the configured thresholds".into(),
    });
    map
}

/// The register map as a Markdown table (address, name, access, contents), as
/// docs/CONTRACT.md shows it for the default configuration (a test keeps them equal).
pub fn spi_map_markdown(config: &MeasureConfig) -> String {
    let mut t = String::from("| address | name | access | contents |\n| --- | --- | --- | --- |\n");
    for r in spi_registers(config) {
        let access = match r.access {
            Access::ReadOnly => "read",
            Access::ReadWrite => "read/write",
            Access::WriteOneToClear => "read, write 1 to clear",
            Access::WriteOnly => "write",
        };
        t.push_str(&format!(
            "| 0x{:02x} | `{}` | {access} | {} |\n",
            r.addr, r.name, r.what
        ));
    }
    t
}

/// One step of CRC-32/MPEG-2 (polynomial 0x04C11DB7, MSB first, no reflection) over a
/// 32-bit word, as the STM32F4's CRC unit computes it for one write of `CRC_DR`.
pub fn crc32_mpeg2_word(crc: u32, word: u32) -> u32 {
    let mut c = crc ^ word;
    for _ in 0..32 {
        c = if c & 0x8000_0000 != 0 {
            (c << 1) ^ 0x04C1_1DB7
        } else {
            c << 1
        };
    }
    c
}

/// The settings CRC the FPGA shows at [`SPI_SETTINGS_CRC_ADDR`]: CRC-32/MPEG-2 from
/// 0xFFFF_FFFF over the threshold words in [`Threshold::ALL`] order, what the STM32 CRC
/// unit gives after `CRC_CR.RESET` and one `CRC_DR` write per word.
pub fn settings_crc(words: &[u32; 6]) -> u32 {
    words
        .iter()
        .fold(0xFFFF_FFFF, |crc, w| crc32_mpeg2_word(crc, *w))
}

/// The threshold words of `settings`, in [`Threshold::ALL`] order.
pub fn threshold_words(settings: &MeasureSettings) -> [u32; 6] {
    Threshold::ALL.map(|t| t.value(settings))
}

/// The model's value of every readable SPI word after a clock whose outputs are
/// `outputs`, the thresholds in force `thresholds` and the status word `status`:
/// `(address, value)` in map order (the control word reads 0). The MCU words are written
/// here from the model's fields, independently of the Verilog's read mux.
pub fn spi_word_values(
    config: &MeasureConfig,
    outputs: &MeasureOutputs,
    diagnostics: bool,
    thresholds: &MeasureSettings,
    status: u32,
) -> Vec<(u8, u32)> {
    let bits = outputs.register_bits(config);
    let field = |name: &str| -> u64 {
        output_fields(config)
            .iter()
            .position(|f| f.name == name)
            .map(|i| bits[i])
            .unwrap_or(0)
    };
    let sb = u32::from(config.settings().scale_bits);
    let sext = |v: u64| -> u32 { (((v as u32) << (32 - sb)) as i32 >> (32 - sb)) as u32 };
    let hash = config.hash();
    let flag = |name: &str, bit: u32| (field(name) as u32 & 1) << bit;
    let mcu: [u32; 12] = [
        flag("armed", 0)
            | flag("contact", 1)
            | flag("register_now", 2)
            | flag("first_contact", 3)
            | flag("density_armed", 4)
            | flag("density_fired", 5)
            // The measurement status (issue 39's outputs, 0 while the model has none).
            | flag("confirmed", 6)
            | (field("faults") as u32 & 0x7f) << 8,
        sext(field("position")),
        sext(field("decision_position")),
        sext(field("first_contact_position")),
        field("count") as u32,
        field("last_window_count") as u32,
        field("charge") as u32,
        if diagnostics {
            field("revolutions") as u32
        } else {
            0
        },
        if diagnostics {
            field("pulses") as u32
        } else {
            0
        },
        field("scale_errors") as u32,
        hash as u32,
        (hash >> 32) as u32,
    ];
    let mut values: Vec<(u8, u32)> = MCU_REGISTERS
        .iter()
        .zip(mcu)
        .map(|(r, v)| (r.addr as u8, v))
        .collect();
    for (i, f) in extra_outputs(config).iter().enumerate() {
        values.push((SPI_EXTRA_BASE + i as u8, field(f.name) as u32));
    }
    let words = threshold_words(thresholds);
    for (t, w) in Threshold::ALL.iter().zip(words) {
        values.push((t.addr(), w));
    }
    values.push((SPI_STATUS_ADDR, status));
    values.push((SPI_SETTINGS_CRC_ADDR, settings_crc(&words)));
    values.push((SPI_CONTROL_ADDR, 0));
    values
}

/// Name of [`tied_frontend`]'s module.
pub const TIED_TOP: &str = "tt_frontend_tied";
/// Name of [`wrapped_frontend`]'s module.
pub const WRAPPED_TOP: &str = "tt_frontend_wrapped";

/// A module with the ports of `tooltouch_hdl_gen::generate`'s `tt_frontend` that instantiates the SPI
/// design's `tt_frontend` (`tooltouch_hdl_gen::generate_spi`) as `u` with every threshold tied to its reset
/// value: what an equivalence check proves equal to [`wrapped_frontend`] (the SPI design
/// with no write is the configured front end).
pub fn tied_frontend(config: &MeasureConfig) -> crate::design::VerilogFile {
    frontend_wrapper(config, true)
}

/// The same wrapper around the constant design's `tt_frontend` (`tooltouch_hdl_gen::generate`), so
/// that both sides of the equivalence name their registers alike (`u.…`).
pub fn wrapped_frontend(config: &MeasureConfig) -> crate::design::VerilogFile {
    frontend_wrapper(config, false)
}

fn frontend_wrapper(config: &MeasureConfig, tied: bool) -> crate::design::VerilogFile {
    let name = if tied { TIED_TOP } else { WRAPPED_TOP };
    let s = config.settings();
    let fields = output_fields(config);
    let mut ports = String::new();
    let mut conns = String::new();
    for f in &fields {
        let range = if f.width == 1 {
            String::new()
        } else {
            format!("[{}:0] ", f.width - 1)
        };
        ports.push_str(&format!("    output wire {range}{},\n", f.name));
        conns.push_str(&format!("        .{0}({0}),\n", f.name));
    }
    let pins = tooltouch_model::measure::frontend::pin::NAMES;
    let pin_ports: String = pins
        .iter()
        .map(|n| format!("    input  wire pin_{n},\n"))
        .collect();
    let pin_conns: String = pins
        .iter()
        .map(|n| format!(".pin_{n}(pin_{n}), "))
        .collect();
    let ties: String = Threshold::ALL
        .iter()
        .filter(|_| tied)
        .filter(|t| s.glitch_cycles > 0 || **t != Threshold::GlitchCycles)
        .map(|t| {
            format!(
                "        .{}({}),\n",
                t.port(),
                crate::emit::lit(t.width(config), t.value(s).into())
            )
        })
        .collect();
    let text = format!(
        "// {name}: {what}, with the constant tt_frontend's ports\n\
         // (configuration hash {hash:016x}).\n\
         `default_nettype none\n\
         module {name} (\n    input  wire clk,\n    input  wire rst,\n{pin_ports}\
         \x20   input  wire [3:0] mcu_addr,\n    output wire [31:0] mcu_rdata,\n{ports}\
         \x20   output wire irq\n);\n\
         {arm}\
         \x20   {top} u (\n        .clk(clk), .rst(rst), {pin_conns}\n{ties}\
         \x20       {arm_conn}.mcu_addr(mcu_addr), .mcu_rdata(mcu_rdata),\n{conns}\
         \x20       .irq(irq)\n    );\nendmodule\n`default_nettype wire\n",
        hash = config.hash(),
        top = crate::design::TOP,
        what = if tied {
            "the SPI design's tt_frontend with its thresholds tied to the reset values"
        } else {
            "the constant design's tt_frontend"
        },
        arm = if tied {
            "    /* verilator lint_off UNUSEDSIGNAL */\n    wire arm_level;\n    /* verilator lint_on UNUSEDSIGNAL */\n"
        } else {
            ""
        },
        arm_conn = if tied { ".arm_level(arm_level), " } else { "" },
    );
    crate::design::VerilogFile {
        name: format!("{name}.v"),
        text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_crc_is_the_stm32_units() {
        // The STM32 CRC unit's documented check: one word 0x12345678 from reset gives
        // 0xDF8A8A2B (RM0090 / AN4187's example value for CRC-32/MPEG-2 over a word).
        assert_eq!(crc32_mpeg2_word(0xFFFF_FFFF, 0x1234_5678), 0xDF8A_8A2B);
    }

    #[test]
    fn the_map_has_unique_addresses_and_shows_every_output() {
        let c = MeasureConfig::default();
        let map = spi_registers(&c);
        let mut addrs: Vec<u8> = map.iter().map(|r| r.addr).collect();
        addrs.sort_unstable();
        addrs.dedup();
        assert_eq!(addrs.len(), map.len());
        assert!(addrs.iter().all(|a| u32::from(*a) < 1 << SPI_ADDR_BITS));
        // Today every output is in an MCU word.
        let words = mcu_words(&c, 0, "", true);
        for f in output_fields(&c) {
            let shown = words.iter().any(|w| names_signal(w, f.name))
                || extra_outputs(&c).iter().any(|e| e.name == f.name);
            assert!(shown, "{}", f.name);
        }
    }

    #[test]
    fn a_new_output_gets_a_word_of_its_own() {
        let c = MeasureConfig::default();
        let words = mcu_words(&c, 0, "", true);
        let mut fields = output_fields(&c).to_vec();
        fields.push(crate::outputs::OutputField {
            name: "future_flag",
            width: 1,
        });
        fields.push(crate::outputs::OutputField {
            name: "future_word",
            width: 7,
        });
        let extra: Vec<&str> = unshown(&words, &fields).iter().map(|f| f.name).collect();
        assert_eq!(extra, ["future_flag", "future_word"]);
        // `count` in `last_window_count` is not a match for `count`'s word and vice versa.
        assert!(names_signal(
            "{21'd0, last_window_count}",
            "last_window_count"
        ));
        assert!(!names_signal("{21'd0, last_window_count}", "count"));
    }

    #[test]
    fn reset_values_are_accepted_and_ranges_follow_the_model() {
        let c = MeasureConfig::default();
        let s = c.settings();
        for t in Threshold::ALL {
            assert!(t.accepts(&c, s, t.value(s)), "{t:?}");
            assert!(!t.accepts(&c, s, t.max(&c) + 1), "{t:?}");
            assert!(t.value(s) < 1 << t.width(&c), "{t:?}");
        }
        assert!(!Threshold::FireThreshold.accepts(&c, s, s.rearm_threshold));
        assert!(!Threshold::RearmThreshold.accepts(&c, s, s.fire_threshold));
        assert!(!Threshold::IDef.accepts(&c, s, c.window_pulses()));
        assert!(!Threshold::ChargeStep.accepts(&c, s, 0));
        assert_eq!(Threshold::GlitchCycles.max(&c), 7);
    }
}
