//! The generator's options and its output: the top module names, the injectable faults,
//! [`Options`], and the generated files. A leaf module (re-exported at the crate root), so
//! the emitter and the per-module generators use these types without importing the root.

use tooltouch_model::measure::config::ChargeLaw;
use tooltouch_model::MeasureConfig;

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
    /// The density detector's fire threshold is one LSB lower than configured.
    FireThresholdMinusOne,
    /// The re-arm threshold is one LSB higher than configured.
    RearmThresholdPlusOne,
    /// The re-arm threshold is one LSB lower than configured.
    RearmThresholdMinusOne,
    /// The pulse counter decides above `i_def + 1`.
    IdefPlusOne,
    /// The pulse counter decides above `i_def − 1`.
    IdefMinusOne,
    /// The glitch filter waits one clock more (`glitch_cycles + 1`).
    GlitchFilterPlusOne,
    /// The glitch filter waits one clock less (`glitch_cycles − 1`).
    GlitchFilterMinusOne,
    /// The charge step is one more: `charge_step + 1` (linear law) or `charge_shift + 1`
    /// (exponential law).
    ChargeStepPlusOne,
    /// The charge step is one less (`charge_step − 1` or `charge_shift − 1`).
    ChargeStepMinusOne,
    /// The discharge step is one more (`discharge_step + 1` or `discharge_shift + 1`).
    DischargeStepPlusOne,
    /// The discharge step is one less (`discharge_step − 1` or `discharge_shift − 1`).
    DischargeStepMinusOne,
    /// The sticky bit is reloaded by FES pulses only while armed (the model reloads it on
    /// every pulse).
    StickyNotReloadedWhileDisarmed,
    /// The first-contact latch is not cleared by an arm rising edge.
    LatchNotClearedByArm,
    /// The `contact_at_arm` fault bit is never set (the check omitted).
    ContactAtArmNotRaised,
}

impl Fault {
    /// Every injected fault (not [`Fault::None`]), so a test of the checkers covers each.
    pub const ALL: [Fault; 16] = [
        Fault::FesBeforeIndex,
        Fault::FireThresholdPlusOne,
        Fault::FireThresholdMinusOne,
        Fault::RearmThresholdPlusOne,
        Fault::RearmThresholdMinusOne,
        Fault::IdefPlusOne,
        Fault::IdefMinusOne,
        Fault::GlitchFilterPlusOne,
        Fault::GlitchFilterMinusOne,
        Fault::ChargeStepPlusOne,
        Fault::ChargeStepMinusOne,
        Fault::DischargeStepPlusOne,
        Fault::DischargeStepMinusOne,
        Fault::StickyNotReloadedWhileDisarmed,
        Fault::LatchNotClearedByArm,
        Fault::ContactAtArmNotRaised,
    ];

    /// For a fault that is one parameter off by one: the settings the design is written
    /// from (its configuration hash stays the configured one), `None` when the fault is
    /// not of that kind or the changed value leaves the valid range at `config` (see
    /// [`Fault::applies_to`]).
    pub fn mutated(self, config: &MeasureConfig) -> Option<MeasureConfig> {
        let mut s = *config.settings();
        let plus = |v: u32| v.checked_add(1);
        let minus = |v: u32| v.checked_sub(1);
        let step =
            |law: &mut ChargeLaw, charge: bool, f: &dyn Fn(u32) -> Option<u32>| -> Option<()> {
                match law {
                    ChargeLaw::Linear {
                        charge_step,
                        discharge_step,
                    } => {
                        let v = if charge { charge_step } else { discharge_step };
                        *v = f(*v)?;
                    }
                    ChargeLaw::Exponential {
                        charge_shift,
                        discharge_shift,
                    } => {
                        let v = if charge {
                            charge_shift
                        } else {
                            discharge_shift
                        };
                        *v = u8::try_from(f(u32::from(*v))?).ok()?;
                    }
                }
                Some(())
            };
        match self {
            Fault::FireThresholdMinusOne => s.fire_threshold = minus(s.fire_threshold)?,
            Fault::RearmThresholdPlusOne => s.rearm_threshold = plus(s.rearm_threshold)?,
            Fault::RearmThresholdMinusOne => s.rearm_threshold = minus(s.rearm_threshold)?,
            Fault::IdefPlusOne => s.i_def = plus(s.i_def)?,
            Fault::IdefMinusOne => s.i_def = minus(s.i_def)?,
            Fault::GlitchFilterPlusOne => s.glitch_cycles = s.glitch_cycles.checked_add(1)?,
            Fault::GlitchFilterMinusOne => s.glitch_cycles = s.glitch_cycles.checked_sub(1)?,
            Fault::ChargeStepPlusOne => step(&mut s.charge_law, true, &plus)?,
            Fault::ChargeStepMinusOne => step(&mut s.charge_law, true, &minus)?,
            Fault::DischargeStepPlusOne => step(&mut s.charge_law, false, &plus)?,
            Fault::DischargeStepMinusOne => step(&mut s.charge_law, false, &minus)?,
            _ => return None,
        }
        s.validate().ok()
    }

    /// The fault's name in kebab case, as `tooltouch hdl --inject-fault` takes it
    /// (`"none"` for the correct design).
    pub fn name(self) -> &'static str {
        match self {
            Fault::None => "none",
            Fault::FesBeforeIndex => "fes-before-index",
            Fault::FireThresholdPlusOne => "fire-threshold-plus-one",
            Fault::FireThresholdMinusOne => "fire-threshold-minus-one",
            Fault::RearmThresholdPlusOne => "rearm-threshold-plus-one",
            Fault::RearmThresholdMinusOne => "rearm-threshold-minus-one",
            Fault::IdefPlusOne => "idef-plus-one",
            Fault::IdefMinusOne => "idef-minus-one",
            Fault::GlitchFilterPlusOne => "glitch-filter-plus-one",
            Fault::GlitchFilterMinusOne => "glitch-filter-minus-one",
            Fault::ChargeStepPlusOne => "charge-step-plus-one",
            Fault::ChargeStepMinusOne => "charge-step-minus-one",
            Fault::DischargeStepPlusOne => "discharge-step-plus-one",
            Fault::DischargeStepMinusOne => "discharge-step-minus-one",
            Fault::StickyNotReloadedWhileDisarmed => "sticky-not-reloaded-while-disarmed",
            Fault::LatchNotClearedByArm => "latch-not-cleared-by-arm",
            Fault::ContactAtArmNotRaised => "contact-at-arm-not-raised",
        }
    }

    /// Whether the fault can be injected at `config` (a parameter fault whose changed value
    /// is still valid, e.g. not `GlitchFilterMinusOne` at `glitch_cycles = 0`).
    pub fn applies_to(self, config: &MeasureConfig) -> bool {
        match self {
            Fault::None
            | Fault::FesBeforeIndex
            | Fault::FireThresholdPlusOne
            | Fault::StickyNotReloadedWhileDisarmed
            | Fault::LatchNotClearedByArm => true,
            Fault::ContactAtArmNotRaised => config.settings().checks.contact_at_arm,
            _ => self.mutated(config).is_some(),
        }
    }
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
