//! `tt_frontend.v`: the simulation top ([`crate::TOP`]): pins → synchronizer → glitch
//! filter → edge detection → kernel, every output a port (compared by the testbench), and
//! the MCU register file's combinational read mux ([`crate::MCU_REGISTERS`]).

use crate::design::{VerilogFile, TOP};
use crate::emit::{fill, pin_index, Context};
use crate::outputs::output_fields;
use crate::spi::Threshold;
use tooltouch_model::measure::frontend::pin;

/// The top: pins in, outputs and the MCU register file out.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let fields = output_fields(&ctx.config);
    let mut ports = String::new();
    let mut conns = String::new();
    for f in &fields {
        let range = if f.width == 1 {
            "      ".to_string()
        } else {
            format!("[{}:0]", f.width - 1)
        };
        ports.push_str(&format!("    output wire {range:<7} {},\n", f.name));
        conns.push_str(&format!("        .{0}({0}),\n", f.name));
    }
    let conns = conns.trim_end_matches(",\n").to_string();
    let mcu_read_mux = crate::mcu::mcu_read_mux(&ctx.config, ctx.hash, ctx.mcu_diagnostics);
    let pins: Vec<String> = pin::NAMES
        .iter()
        .rev()
        .map(|n| format!("pin_{n}"))
        .collect();
    let pin_ports: String = pin::NAMES
        .iter()
        .map(|n| format!("    input  wire         pin_{n},\n"))
        .collect();
    let body = fill(
        r#"// Top of the FPGA measurement front end. Pins -> 2-FF synchronizer -> glitch
// filter -> edge detection -> measurement kernel; every output is a register. The MCU
// reads the results through a small register file (combinational read of `mcu_addr`,
// map in tooltouch_hdl_gen::MCU_REGISTERS); `register_now` is the strobe to the CNC,
// held until the next arm. Latency from a pin to the outputs: ${LAT} clocks.
module ${TOP} (
    input  wire         clk,
    input  wire         rst,       // synchronous reset to the power-on state
${PIN_PORTS}${THRESHOLD_PORTS}    input  wire [${AB1}:0]  mcu_addr,
    output reg  [${DB1}:0] mcu_rdata,
${PORTS}    output wire         irq        // = ${IRQ_SOURCE}, for the MCU
);
    // The configuration this design was generated from (the MCU's CONFIG_HASH_HI/LO
    // words): a testbench's scoreboard reads it (dut.CONFIG_HASH) and checks it against
    // its own at time 0.
    /* verilator lint_off UNUSEDPARAM */
    localparam [63:0] CONFIG_HASH = 64'h${HASH};
    /* verilator lint_on UNUSEDPARAM */

    wire [${N1}:0] pins = {${PINS}};
    wire [${N1}:0] synced;
    wire [${N1}:0] filtered;
    wire [${N1}:0] toggles;
    wire       arm_rise, contact_rise, contact_rise_next, index_pulse, fes_rise, fes_pulse;
    wire       scale_up, scale_down, scale_error;

    tt_synchronizer u_sync (.clk(clk), .rst(rst), .pins(pins), .synced(synced));
    tt_glitch_filter u_filter (
        .clk(clk), .rst(rst), .synced(synced), .filtered(filtered),${GLITCH_CONN} .toggles(toggles)
    );
    tt_edge_detect u_edges (
        .clk(clk), .rst(rst), .toggles(toggles), .filtered(filtered),
        .arm_rise(arm_rise), .contact_rise(contact_rise),
        .contact_rise_next(contact_rise_next), .index_pulse(index_pulse),
        .fes_rise(fes_rise), .fes_pulse(fes_pulse),
        .scale_up(scale_up), .scale_down(scale_down), .scale_error(scale_error)
    );

    tt_measurement u_measure (
        .clk(clk), .rst(rst),
        .arm_level(filtered[${ARM}]), .contact_level(filtered[${CONTACT}]),
        .arm_rise(arm_rise), .contact_rise(contact_rise),
        .contact_rise_next(contact_rise_next), .index_pulse(index_pulse),
        .fes_rise(fes_rise), .fes_pulse(fes_pulse),
        .scale_up(scale_up), .scale_down(scale_down), .scale_error(scale_error),
${KERNEL_CONNS}${CONNS}
    );

    assign irq = ${IRQ_SOURCE};
${ARM_LEVEL}
${MCU_READ_MUX}endmodule
"#,
        &[
            ("TOP", TOP.to_string()),
            ("HASH", format!("{:016x}", ctx.hash)),
            ("LAT", ctx.config.latency_cycles().to_string()),
            ("PIN_PORTS", pin_ports),
            ("AB1", (crate::mcu::MCU_ADDR_BITS - 1).to_string()),
            ("DB1", (crate::mcu::MCU_DATA_BITS - 1).to_string()),
            ("PORTS", ports),
            ("N1", (pin::COUNT - 1).to_string()),
            ("PINS", pins.join(", ")),
            ("ARM", pin_index(pin::ARM)),
            ("CONTACT", pin_index(pin::CONTACT)),
            ("CONNS", conns),
            ("IRQ_SOURCE", crate::outputs::IRQ_SOURCE.to_string()),
            ("MCU_READ_MUX", mcu_read_mux),
            ("THRESHOLD_PORTS", threshold_ports(ctx)),
            (
                "GLITCH_CONN",
                if ctx.tunable && ctx.config.settings().glitch_cycles > 0 {
                    "\n        .glitch_cycles(glitch_cycles),".into()
                } else {
                    String::new()
                },
            ),
            (
                "KERNEL_CONNS",
                if ctx.tunable {
                    Threshold::ALL
                        .iter()
                        .filter(|t| **t != Threshold::GlitchCycles)
                        .map(|t| format!("        .{0}({0}),\n", t.port()))
                        .collect()
                } else {
                    String::new()
                },
            ),
            (
                "ARM_LEVEL",
                if ctx.tunable {
                    format!(
                        "    assign arm_level = filtered[{}];\n",
                        pin_index(pin::ARM)
                    )
                } else {
                    String::new()
                },
            ),
        ],
    );
    ctx.file(TOP, "top of the FPGA measurement front end", &body)
}

/// The SPI design's extra ports (empty otherwise): the run-time thresholds in
/// (`glitch_cycles` only when the filter has a counter) and the filtered arm level out,
/// which the register file's write interlock reads.
fn threshold_ports(ctx: &Context) -> String {
    if !ctx.tunable {
        return String::new();
    }
    let glitch = ctx.config.settings().glitch_cycles > 0;
    let mut ports: String = Threshold::ALL
        .iter()
        .filter(|t| glitch || **t != Threshold::GlitchCycles)
        .map(|t| {
            let range = format!("[{}:0]", t.width(&ctx.config) - 1);
            format!(
                "    input  wire {range:<7} {},  // run-time threshold\n",
                t.port()
            )
        })
        .collect();
    ports.push_str("    output wire         arm_level,  // filtered arm level (write interlock)\n");
    ports
}
