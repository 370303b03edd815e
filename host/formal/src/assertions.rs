//! The contract as assertions: a SystemVerilog checker module (`tt_frontend_props`) and a
//! `bind` of it into `tt_frontend`, generated from the configuration, for the user's own
//! simulator or formal tool ([`bind_file`], written by `tooltouch formal` as
//! [`PROPS_FILE`]).
//!
//! The checker watches only the ports: it keeps the pins of the last `glitch_cycles + 4`
//! clocks (power-on reads as pins low, as the synchronizer's power-on value does) and the
//! outputs of the clock before, and asserts, at every clock after the first:
//!
//! - **latency `3 + glitch_cycles`**: `armed` (`contact`) changes only to the level its pin
//!   held on each of the `glitch_cycles + 1` samples ending 3 clocks before;
//! - **latches**: `register_now` with `decision_position`, and `first_contact` with
//!   `first_contact_position`, once raised, stay raised and unchanged until a clock at which
//!   `armed` rises;
//! - **wraps**: `position` moves by at most one count a clock, modulo `2^scale_bits`;
//!   `pulses` by at most one, modulo `2^32`, or restarts (0 or 1) as `armed` rises;
//! - **saturation**: `count` and `last_window_count` never above `window_pulses`;
//!   `scale_errors` never decreases (it saturates at 255 instead of wrapping);
//!   `revolutions` moves by at most one and never wraps from 65535; the charge changes only
//!   at a counted FES pulse (when `pulses` moves) or as `armed` rises;
//! - **status**: the `faults` bits and `confirmed`, once raised, stay raised until a clock
//!   at which `armed` rises, and change only while armed (or in the clock the arm falls);
//!   `confirmed` only with `register_now` and never with the `unconfirmed` fault.
//!
//! Immediate assertions in a clocked block, so Icarus (`-g2012`), Verilator (`--assert`),
//! commercial simulators and yosys (`read_verilog -sv -formal`) all read them.

use std::fmt::Write as _;
use tooltouch_hdl_gen::{output_fields, TOP};
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::MeasureConfig;

/// File name of the assertion bind file.
pub const PROPS_FILE: &str = "tt_frontend_props.sv";
/// Module name of the checker.
pub const PROPS_MODULE: &str = "tt_frontend_props";

/// The checker module and its `bind` into `tt_frontend`, for `config`.
pub fn bind_file(config: &MeasureConfig) -> String {
    let s = config.settings();
    let g = u32::from(s.glitch_cycles);
    let depth = g + 4;
    let sb = u32::from(s.scale_bits);
    let window = u32::from(s.pulses_per_rev) * u32::from(s.window_revs);
    let fields = output_fields(config);
    let mut v = String::new();
    let _ = writeln!(
        v,
        "// tt_frontend_props: the timing contract of tooltouch (docs/CONTRACT.md,\n\
         // docs/formal.md) as assertions, generated for configuration hash {:016x}.\n\
         // Bind it to your design (the `bind` at the end) in a simulator or formal tool;\n\
         // every assertion holds on the generated design for every input sequence.",
        config.hash()
    );
    let _ = writeln!(
        v,
        "module {PROPS_MODULE} (\n    input wire clk,\n    input wire rst,"
    );
    for n in pin::NAMES {
        let _ = writeln!(v, "    input wire pin_{n},");
    }
    let ports: Vec<String> = fields
        .iter()
        .map(|f| format!("    input wire [{}:0] {}", f.width - 1, f.name))
        .collect();
    let _ = writeln!(v, "{}\n);", ports.join(",\n"));
    let _ = writeln!(
        v,
        "    localparam integer GLITCH = {g};\n\
         \x20   localparam integer DEPTH = {depth};  // pins kept: GLITCH + 4 clocks\n\
         \x20   localparam [31:0] WINDOW_PULSES = 32'd{window};\n\
         \x20   // hist[6*i +: 6]: the pins sampled i + 1 clocks before (arm bit 0 … scale_b bit 5).\n\
         \x20   reg [6*DEPTH-1:0] hist = {{(6*DEPTH){{1'b0}}}};\n\
         \x20   reg started = 1'b0;"
    );
    for f in &fields {
        let _ = writeln!(
            v,
            "    reg [{}:0] past_{} = {}'d0;",
            f.width - 1,
            f.name,
            f.width
        );
    }
    let pins: Vec<String> = pin::NAMES
        .iter()
        .rev()
        .map(|n| format!("pin_{n}"))
        .collect();
    let _ = writeln!(
        v,
        "    wire [5:0] pins = {{{}}};\n\
         \x20   wire arm_rose = armed && !past_armed;\n\
         \x20   // A level held on every sample from 3 to 3 + GLITCH clocks before this one.\n\
         \x20   function held(input integer bit_index, input reg level);\n\
         \x20       integer i;\n\
         \x20       begin\n\
         \x20           held = 1'b1;\n\
         \x20           for (i = 3; i <= 3 + GLITCH; i = i + 1)\n\
         \x20               if (hist[6*i + bit_index] != level) held = 1'b0;\n\
         \x20       end\n\
         \x20   endfunction",
        pins.join(", ")
    );
    let one_step = |name: &str, width: u32| {
        format!(
            "({name} == past_{name} || {name} == past_{name} + {width}'d1 || {name} == past_{name} - {width}'d1)"
        )
    };
    let _ = writeln!(
        v,
        "    always @(posedge clk) begin\n\
         \x20       if (started && !rst) begin\n\
         \x20           // latency 3 + GLITCH\n\
         \x20           if (armed != past_armed) assert (held(0, armed));\n\
         \x20           if (contact != past_contact) assert (held(1, contact));\n\
         \x20           // latches hold until the arm rising edge\n\
         \x20           if (past_register_now && !arm_rose)\n\
         \x20               assert (register_now && decision_position == past_decision_position);\n\
         \x20           if (past_first_contact && !arm_rose)\n\
         \x20               assert (first_contact && first_contact_position == past_first_contact_position);\n\
         \x20           // wraps\n\
         \x20           assert {pos};\n\
         \x20           assert (pulses == past_pulses || pulses == past_pulses + 32'd1 || (arm_rose && pulses <= 32'd1));\n\
         \x20           // saturation\n\
         \x20           assert ({{{{(32-{cw}){{1'b0}}}}, count}} <= WINDOW_PULSES);\n\
         \x20           assert ({{{{(32-{cw}){{1'b0}}}}, last_window_count}} <= WINDOW_PULSES);\n\
         \x20           assert (scale_errors >= past_scale_errors);\n\
         \x20           assert (revolutions == past_revolutions || revolutions == past_revolutions + 16'd1 || (arm_rose && revolutions <= 16'd1));\n\
         \x20           if (!arm_rose && pulses == past_pulses) assert (charge == past_charge);\n\
         \x20           // the status: latched until the arm rising edge, raised only while armed\n\
         \x20           if (!arm_rose) assert ((faults & past_faults) == past_faults && (confirmed || !past_confirmed));\n\
         \x20           if (!armed && !past_armed) assert (faults == past_faults && confirmed == past_confirmed);\n\
         \x20           assert (!confirmed || (register_now && !faults[6]));\n\
         \x20       end\n\
         \x20       started <= !rst;\n\
         \x20       hist <= rst ? {{(6*DEPTH){{1'b0}}}} : {{hist[6*DEPTH-7:0], pins}};",
        pos = one_step("position", sb),
        cw = config.count_bits(),
    );
    for f in &fields {
        let _ = writeln!(v, "        past_{0} <= {0};", f.name);
    }
    let _ = writeln!(v, "    end\nendmodule\n");
    let mut conns = vec![".clk(clk)".to_string(), ".rst(rst)".to_string()];
    conns.extend(pin::NAMES.iter().map(|n| format!(".pin_{n}(pin_{n})")));
    conns.extend(fields.iter().map(|f| format!(".{0}({0})", f.name)));
    let _ = writeln!(
        v,
        "bind {TOP} {PROPS_MODULE} u_props (\n    {}\n);",
        conns.join(",\n    ")
    );
    v
}

/// The checker's instance in a wrapper around `top` (for tools without `bind`, such as
/// yosys 0.23, which ignores it): module `tt_frontend_checked`, the design's ports.
pub fn checked_wrapper(config: &MeasureConfig, top: &str) -> String {
    let ports = super::miter::contract_ports(config);
    let decl: Vec<String> = ports
        .iter()
        .map(|p| {
            format!(
                "    {} wire [{}:0] {}",
                match p.direction {
                    super::miter::Direction::Input => "input",
                    super::miter::Direction::Output => "output",
                },
                p.width - 1,
                p.name
            )
        })
        .collect();
    let all: Vec<String> = ports.iter().map(|p| format!(".{0}({0})", p.name)).collect();
    let props: Vec<String> = ports
        .iter()
        .filter(|p| !matches!(p.name.as_str(), "mcu_addr" | "mcu_rdata" | "irq"))
        .map(|p| format!(".{0}({0})", p.name))
        .collect();
    format!(
        "module tt_frontend_checked (\n{}\n);\n    {top} u_dut ({});\n    {PROPS_MODULE} u_props ({});\nendmodule\n",
        decl.join(",\n"),
        all.join(", "),
        props.join(", ")
    )
}

/// Proves every assertion of [`bind_file`] on the design `files` (top `top`) with ABC
/// (`dprove`, then `scorr; pdr`, each at most `seconds`), in `dir`: the checker is instantiated beside the
/// design ([`checked_wrapper`]), yosys turns the assertions into one miter output
/// (`miter -assert`), written as AIGER.
pub fn prove_assertions(
    config: &MeasureConfig,
    props: &str,
    files: &[std::path::PathBuf],
    top: &str,
    dir: &std::path::Path,
    seconds: u64,
) -> Result<super::engines::Attempt, super::error::FormalError> {
    std::fs::create_dir_all(dir).map_err(super::error::io(dir))?;
    let props_path = dir.join(PROPS_FILE);
    std::fs::write(&props_path, props).map_err(super::error::io(&props_path))?;
    let wrapper_path = dir.join("tt_frontend_checked.v");
    std::fs::write(&wrapper_path, checked_wrapper(config, top))
        .map_err(super::error::io(&wrapper_path))?;
    let reads: String = files
        .iter()
        .map(|f| format!("read_verilog -sv \"{}\"\n", f.display()))
        .collect();
    let script = format!(
        "{reads}read_verilog -sv -formal {PROPS_FILE}\n\
         read_verilog tt_frontend_checked.v\n\
         hierarchy -check -top tt_frontend_checked\n\
         proc\n\
         flatten\n\
         setundef -zero -undriven\n\
         select -assert-min 1 t:$assert\n\
         miter -assert -flatten tt_frontend_checked props_miter\n\
         hierarchy -top props_miter\n\
         opt_clean\n\
         async2sync\n\
         dffunmap\n\
         techmap\n\
         opt -fast\n\
         dfflegalize -cell $_DFF_P_ 01\n\
         abc -g AND\n\
         opt_clean\n\
         write_aiger -zinit props.aig\n"
    );
    super::miter::run_yosys(dir, &script, "props")?;
    // `dprove` closes these properties in a second where `scorr; pdr` did not in 300 s
    // (docs/formal.md); PDR second, for what it does not.
    let mut last = None;
    for engine in [
        super::engines::Engine::Dprove,
        super::engines::Engine::ScorrPdr,
    ] {
        let a = super::engines::run_engine(engine, dir, "props.aig", seconds)?;
        if !matches!(a.result, super::engines::EngineResult::Undecided { .. }) {
            return Ok(a);
        }
        last = Some(a);
    }
    Ok(last.expect("two engines tried"))
}
