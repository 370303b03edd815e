//! `tt_fpga_spi.v`: the chip top of the SPI design ([`crate::spi::SPI_TOP`]), the board top of
//! both boards (`hdl-gen/boards/*.pcf`): the board clock, the six measurement inputs, the
//! SPI pins to the MCU and the register-now, interrupt and fault outputs.

use crate::design::{VerilogFile, TOP};
use crate::emit::{fill, Context};
use crate::outputs::output_fields;
use crate::spi::{extra_outputs, Threshold, SPI_MODULE, SPI_TOP};
use tooltouch_model::measure::frontend::pin;

/// The fault pin's expression: any bit of a `faults` output when the model has one,
/// otherwise any illegal scale transition counted.
fn fault_expr(ctx: &Context) -> String {
    let fields = output_fields(&ctx.config);
    if fields.iter().any(|f| f.name == "faults") {
        "|faults".to_string()
    } else {
        "scale_errors != 8'd0".to_string()
    }
}

/// The chip top with the SPI register interface.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let fields = output_fields(&ctx.config);
    let mut wires = String::new();
    let mut conns = String::new();
    for f in &fields {
        let range = if f.width == 1 {
            String::new()
        } else {
            format!("[{}:0] ", f.width - 1)
        };
        wires.push_str(&format!("    wire {range}{};\n", f.name));
        conns.push_str(&format!("        .{0}({0}),\n", f.name));
    }
    let glitch = ctx.config.settings().glitch_cycles > 0;
    let mut thresholds = String::new();
    let mut kernel_conns = String::new();
    let mut spi_conns = String::new();
    for t in Threshold::ALL {
        thresholds.push_str(&format!(
            "    wire [{}:0] {};\n",
            t.width(&ctx.config) - 1,
            t.port()
        ));
        if glitch || t != Threshold::GlitchCycles {
            kernel_conns.push_str(&format!("        .{0}({0}),\n", t.port()));
        }
        spi_conns.push_str(&format!("        .{0}({0}),\n", t.port()));
    }
    for f in extra_outputs(&ctx.config) {
        spi_conns.push_str(&format!("        .{0}({0}),\n", f.name));
    }
    let pin_ports: String = pin::NAMES
        .iter()
        .map(|n| format!("    input  wire         pin_{n},\n"))
        .collect();
    let pin_conns: String = pin::NAMES
        .iter()
        .map(|n| format!("        .pin_{n}(pin_{n}),\n"))
        .collect();
    let body = fill(
        r#"// The FPGA's top with the SPI register interface, the board top of the iCEBreaker and
// the iCE40-HX8K breakout (both clocked by their 12 MHz oscillator): the six input pins,
// the MCU's SPI bus, register-now to the CNC, the MCU's interrupt and a fault line.
// No reset pin: every register starts at its power-on value when the FPGA is
// configured, and the MCU resets the kernel through the CONTROL word.
module ${FPGA} (
    input  wire         clk,
${PIN_PORTS}    input  wire         spi_sck,
    input  wire         spi_cs_n,
    input  wire         spi_mosi,
    output wire         spi_miso,
    output wire         register_now_out,  // to the CNC: position reached, register now
    output wire         irq_out,           // to the MCU: = ${IRQ}
    output wire         fault_out          // to the MCU: ${FAULT}
);
    // Every output is read through the SPI register map.
    /* verilator lint_off UNUSEDSIGNAL */
${WIRES}    /* verilator lint_on UNUSEDSIGNAL */
${THRESHOLDS}    wire [3:0]  mcu_addr;
    wire [31:0] mcu_rdata;
    wire        irq;
    wire        arm_level;
    wire        kernel_rst;

    ${TOP} u_frontend (
        .clk(clk), .rst(kernel_rst),
${PIN_CONNS}${KERNEL_CONNS}        .arm_level(arm_level),
        .mcu_addr(mcu_addr), .mcu_rdata(mcu_rdata),
${CONNS}        .irq(irq)
    );

    ${SPI} u_spi (
        .clk(clk),
        .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi), .spi_miso(spi_miso),
        .arm_level(arm_level), .armed(armed),
        .mcu_addr(mcu_addr), .mcu_rdata(mcu_rdata),
${SPI_CONNS}        .kernel_rst(kernel_rst)
    );

    assign register_now_out = register_now;
    assign irq_out          = irq;
    assign fault_out        = ${FAULT};
endmodule
"#,
        &[
            ("FPGA", SPI_TOP.to_string()),
            ("TOP", TOP.to_string()),
            ("SPI", SPI_MODULE.to_string()),
            ("PIN_PORTS", pin_ports),
            ("PIN_CONNS", pin_conns),
            ("WIRES", wires),
            ("CONNS", conns),
            ("THRESHOLDS", thresholds),
            ("KERNEL_CONNS", kernel_conns),
            ("SPI_CONNS", spi_conns),
            ("IRQ", crate::outputs::IRQ_SOURCE.to_string()),
            ("FAULT", fault_expr(ctx)),
        ],
    );
    ctx.file(
        SPI_TOP,
        "the FPGA's top with the SPI register interface",
        &body,
    )
}
