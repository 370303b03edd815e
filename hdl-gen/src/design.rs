//! The generator's options and its output: the top module names, the injectable faults,
//! [`Options`], and the generated files. A leaf module (re-exported at the crate root), so
//! the emitter and the per-module generators use these types without importing the root.

/// Name of the simulation top module (and of its file, `tt_frontend.v`): every output a
/// port, compared by the testbench.
pub const TOP: &str = "tt_frontend";
/// Name of the chip top for synthesis (file `tt_fpga.v`): pins, MCU bus and strobe only.
pub const FPGA_TOP: &str = "tt_fpga";

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

impl Fault {
    /// Every injected fault (not [`Fault::None`]), so a test of the checkers covers each.
    pub const ALL: [Fault; 2] = [Fault::FesBeforeIndex, Fault::FireThresholdPlusOne];
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
