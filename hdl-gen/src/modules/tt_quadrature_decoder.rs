//! `tt_quadrature_decoder.v`: the x4 quadrature decoder of the linear scale
//! (docs/domain.md §1; model: `QuadratureDecoder`): a `scale_bits` position stepped by the
//! edge stage's up/down strobes through one adder, and a saturating error count.

use crate::design::VerilogFile;
use crate::emit::{fill, lit, Context};

/// x4 quadrature decoder (docs/domain.md §1), model: `QuadratureDecoder`.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let sb = ctx.scale_bits();
    let body = fill(
        r#"// x4 quadrature decoder (docs/domain.md §1): counts the steps decoded by tt_edge_detect;
// a double change counts an error (saturating at 255) and leaves the position.
// Position: ${SB} bits, two's complement, wrapping.
module tt_quadrature_decoder (
    input  wire        clk,
    input  wire        rst,
    input  wire        up,       // step +1 this clock
    input  wire        down,     // step -1 this clock
    input  wire        error,    // both lines changed this clock
    output wire [${SB1}:0] position,
    output wire [7:0]  errors
);
    reg [${SB1}:0] position_q = ${SZERO};
    reg [7:0]  errors_q   = 8'd0;

    // +1 or -1 through one adder.
    wire [${SB1}:0] delta = {{${SB_1}{down}}, 1'b1};

    always @(posedge clk) begin
        if (rst) begin
            position_q <= ${SZERO};
            errors_q   <= 8'd0;
        end else begin
            if (up || down)
                position_q <= position_q + delta;
            if (error && errors_q != 8'd255)
                errors_q <= errors_q + 8'd1;
        end
    end

    assign position = position_q;
    assign errors   = errors_q;
endmodule
"#,
        &[
            ("SB", sb.to_string()),
            ("SB1", (sb - 1).to_string()),
            ("SZERO", lit(sb, 0)),
            ("SB_1", (sb - 1).to_string()),
        ],
    );
    ctx.file(
        "tt_quadrature_decoder",
        "x4 quadrature decoder of the linear scale",
        &body,
    )
}
