//! `tt_position_latch.v`: the capture-once position register (model: `PositionLatch`),
//! instantiated twice by `tt_measurement` (first contact, decision).

use crate::design::VerilogFile;
use crate::emit::{fill, lit, Context};

/// Capture-once position register, model: `PositionLatch`.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let sb = ctx.scale_bits();
    let body = fill(
        r#"// Position latch: captures the scale position once, holds it until the next clear.
module tt_position_latch (
    input  wire        clk,
    input  wire        rst,
    input  wire        clear,      // arm rising edge: empty (reads 0)
    input  wire        take,       // capture `position_in` (only when none is held after
                                   // the clear; the caller checks that)
    input  wire [${SB1}:0] position_in,
    output wire        valid,
    output wire [${SB1}:0] position
);
    reg        valid_q    = 1'b0;
    reg [${SB1}:0] position_q = ${SZERO};

    always @(posedge clk) begin
        if (rst) begin
            valid_q    <= 1'b0;
            position_q <= ${SZERO};
        end else begin
            valid_q <= (valid_q && !clear) || take;
            if (take)
                position_q <= position_in;
            else if (clear)
                position_q <= ${SZERO};
        end
    end

    assign valid    = valid_q;
    assign position = position_q;
endmodule
"#,
        &[("SB1", (sb - 1).to_string()), ("SZERO", lit(sb, 0))],
    );
    ctx.file("tt_position_latch", "capture-once position latch", &body)
}
