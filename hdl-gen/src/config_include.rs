//! `tt_config.vh`: the configuration as Verilog `localparam`s, for a hand-written
//! `tt_frontend` to `` `include `` inside its module (docs/CONTRACT.md, "How a design gets
//! its configuration"). The generated design writes its constants inline and does not use
//! it.

use crate::design::VerilogFile;
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::MeasureConfig;

/// File name of the include.
pub const CONFIG_INCLUDE: &str = "tt_config.vh";

/// The include for `config`: every setting, the derived widths and `CONFIG_HASH`, one
/// `localparam` each (`NAME = value;  // what`), with enumerations as small integers
/// named in the comment.
pub fn config_include(config: &MeasureConfig) -> VerilogFile {
    let s = config.settings();
    let k = s.checks;
    let (law, up, down) = match s.charge_law {
        ChargeLaw::Linear {
            charge_step,
            discharge_step,
        } => (0, charge_step, discharge_step),
        ChargeLaw::Exponential {
            charge_shift,
            discharge_shift,
        } => (1, u32::from(charge_shift), u32::from(discharge_shift)),
    };
    let rule = match s.contact_rule {
        ContactRule::Sampled => 0,
        ContactRule::Sticky => 1,
    };
    let method = match s.method {
        DecisionMethod::SinglePulse => 0,
        DecisionMethod::Counter => 1,
        DecisionMethod::Density => 2,
    };
    let params: [(&str, String, &str); 29] = [
        (
            "PULSES_PER_REV",
            s.pulses_per_rev.to_string(),
            "FES pulses per revolution",
        ),
        (
            "WINDOW_REVS",
            s.window_revs.to_string(),
            "revolutions per counting window",
        ),
        (
            "WINDOW_PULSES",
            config.window_pulses().to_string(),
            "PULSES_PER_REV * WINDOW_REVS: the count saturates here",
        ),
        (
            "I_DEF",
            s.i_def.to_string(),
            "decide when the window's count exceeds this",
        ),
        ("CONTACT_RULE", rule.to_string(), "0 sampled, 1 sticky"),
        (
            "METHOD",
            method.to_string(),
            "decision method: 0 single pulse, 1 counter, 2 density",
        ),
        ("CHARGE_LAW", law.to_string(), "0 linear, 1 exponential"),
        (
            "CHARGE_STEP",
            up.to_string(),
            "linear: LSBs per contact pulse; exponential: charge_shift",
        ),
        (
            "DISCHARGE_STEP",
            down.to_string(),
            "linear: LSBs per pulse without contact; exponential: discharge_shift",
        ),
        (
            "FULL_CHARGE",
            config.full_charge().to_string(),
            "2**CHARGE_BITS - 1",
        ),
        (
            "FIRE_THRESHOLD",
            s.fire_threshold.to_string(),
            "fire when armed and charge >= this",
        ),
        (
            "REARM_THRESHOLD",
            s.rearm_threshold.to_string(),
            "re-arm when fired and charge < this",
        ),
        (
            "GLITCH_CYCLES",
            s.glitch_cycles.to_string(),
            "a level passes once seen on GLITCH_CYCLES + 1 clocks",
        ),
        (
            "LATENCY_CYCLES",
            config.latency_cycles().to_string(),
            "3 + GLITCH_CYCLES: pin to outputs",
        ),
        (
            "SCALE_BITS",
            s.scale_bits.to_string(),
            "width of the positions",
        ),
        (
            "COUNT_BITS",
            config.count_bits().to_string(),
            "ceil(log2(WINDOW_PULSES + 1)): width of count, last_window_count",
        ),
        ("CHARGE_BITS", s.charge_bits.to_string(), "width of charge"),
        (
            "MCU_ADDR_BITS",
            crate::MCU_ADDR_BITS.to_string(),
            "width of mcu_addr",
        ),
        (
            "MCU_DATA_BITS",
            crate::MCU_DATA_BITS.to_string(),
            "width of mcu_rdata",
        ),
        (
            "CHECK_CONTACT_AT_ARM",
            u8::from(k.contact_at_arm).to_string(),
            "1: fault 0 when the contact is closed as the arm rises",
        ),
        (
            "CHECK_REVOLUTIONS",
            u8::from(k.revolutions).to_string(),
            "1: faults 1, 2 on a revolution outside PULSES_PER_REV +/- PULSE_TOLERANCE",
        ),
        (
            "PULSE_TOLERANCE",
            k.pulse_tolerance.to_string(),
            "FES pulses a revolution may differ from PULSES_PER_REV",
        ),
        (
            "CHECK_SCALE_ERRORS",
            u8::from(k.scale_errors).to_string(),
            "1: fault 3 on an illegal scale transition while armed",
        ),
        (
            "PROBE_REVS",
            k.probe_revs.to_string(),
            "fault 4 after this many index pulses without a decision (0 off)",
        ),
        (
            "FES_TIMEOUT_CYCLES",
            k.fes_timeout_cycles.to_string(),
            "fault 5 after this many clocks without an FES pulse while armed (0 off)",
        ),
        (
            "CONFIRM_WINDOWS",
            k.confirm_windows.to_string(),
            "windows after the decision that must confirm it (0: at the decision)",
        ),
        (
            "CONFIRM_COUNT",
            config.confirm_count().to_string(),
            "contact pulses a confirming window counts at least (else fault 6)",
        ),
        (
            "REV_PULSE_BITS",
            config.rev_pulse_bits().to_string(),
            "bits of the FES count of a revolution (0 ..= ppr + tolerance + 1)",
        ),
        (
            "FES_IDLE_BITS",
            config.fes_idle_bits().to_string(),
            "bits of the FES watchdog's count (0 ..= FES_TIMEOUT_CYCLES)",
        ),
    ];
    let mut text = format!(
        "// {CONFIG_INCLUDE}: the configuration of tt_frontend, generated by tooltouch-hdl-gen\n\
         // from MeasureConfig hash {:016x} ({}).\n\
         // `include it inside your tt_frontend module; regenerate with `tooltouch hdl`.\n",
        config.hash(),
        crate::emit::describe(config)
    );
    for (name, value, what) in params {
        text.push_str(&format!(
            "localparam integer {name:<16} = {value};  // {what}\n"
        ));
    }
    text.push_str(&format!(
        "localparam [63:0]  CONFIG_HASH      = 64'h{:016x};  // MCU words 10 (bits 31..0) and 11 (63..32)\n",
        config.hash()
    ));
    VerilogFile {
        name: CONFIG_INCLUDE.into(),
        text,
    }
}
