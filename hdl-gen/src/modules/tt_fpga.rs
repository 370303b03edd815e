//! `tt_fpga.v`: the chip top for synthesis ([`crate::FPGA_TOP`]): only the pins, the MCU
//! bus, the register-now strobe and the fault line leave the FPGA; the reset pin is synchronized and the
//! bus address and read data are registered (without reset: they hold no state).

use crate::design::{VerilogFile, TOP};
use crate::emit::{fill, lit, Context};
use crate::outputs::output_fields;
use tooltouch_model::measure::frontend::pin;

/// The chip top for synthesis: only the pins, the MCU bus, the strobe and the fault line
/// leave the FPGA; the read data is registered (valid the clock after `mcu_addr`).
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
    let pin_ports: String = pin::NAMES
        .iter()
        .map(|n| format!("    input  wire         pin_{n},\n"))
        .collect();
    let pin_conns: String = pin::NAMES
        .iter()
        .map(|n| format!("        .pin_{n}(pin_{n}),\n"))
        .collect();
    let body = fill(
        r#"// The FPGA's top for synthesis: the six input pins, the MCU's register bus, the
// register-now strobe to the CNC and MCU, and the fault line (any fault bit latched). Address and read data are registered: the
// word addressed at clock k is on mcu_rdata after clock k+1.
module ${FPGA} (
    input  wire         clk,
    input  wire         rst,
${PIN_PORTS}    input  wire [${AB1}:0]  mcu_addr,
    output reg  [${DB1}:0] mcu_rdata,
    output wire         register_now_out,  // to the CNC: position reached, register now
    output wire         fault_out          // to the CNC's alarm input (and an MCU interrupt
                                           // input): a fault latched in this measurement
);
    // Every output is read through the register file; the ports are kept for simulation.
    /* verilator lint_off UNUSEDSIGNAL */
${WIRES}    /* verilator lint_on UNUSEDSIGNAL */
    wire [${DB1}:0] rdata;
    wire        irq;
    reg  [${AB1}:0]  addr_q = ${AZERO};
    reg         rst_meta = 1'b0;  // the reset pin, synchronized (2 flip-flops)
    reg         rst_q    = 1'b0;

    always @(posedge clk) begin
        rst_meta <= rst;
        rst_q    <= rst_meta;
    end

    initial mcu_rdata = ${DZERO};

    ${TOP} u_frontend (
        .clk(clk), .rst(rst_q),
${PIN_CONNS}        .mcu_addr(addr_q), .mcu_rdata(rdata),
${CONNS}        .irq(irq)
    );

    // The bus registers hold no state (the data is the addressed word of the previous
    // clock, with or without reset), so the reset does not reach them: a reset term would
    // become a synchronous reset merged with the read mux's zero words, which nextpnr
    // routes through a global buffer on the critical path.
    always @(posedge clk) begin
        addr_q    <= mcu_addr;
        mcu_rdata <= rdata;
    end

    assign register_now_out = irq;
    assign fault_out        = |faults;
endmodule
"#,
        &[
            ("FPGA", crate::design::FPGA_TOP.to_string()),
            ("TOP", TOP.to_string()),
            ("PIN_PORTS", pin_ports),
            ("PIN_CONNS", pin_conns),
            ("AB1", (crate::mcu::MCU_ADDR_BITS - 1).to_string()),
            ("DB1", (crate::mcu::MCU_DATA_BITS - 1).to_string()),
            ("WIRES", wires),
            ("CONNS", conns),
            ("DZERO", lit(crate::mcu::MCU_DATA_BITS, 0)),
            ("AZERO", lit(crate::mcu::MCU_ADDR_BITS, 0)),
        ],
    );
    ctx.file(
        crate::design::FPGA_TOP,
        "the FPGA's top for synthesis",
        &body,
    )
}
