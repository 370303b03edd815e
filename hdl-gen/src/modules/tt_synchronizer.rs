//! `tt_synchronizer.v`: the two-flip-flop synchronizer of the six asynchronous input pins
//! (model: `FrontEnd::sync1`, `sync2`). Fixed structure; only the pin count comes from
//! the model.

use crate::design::VerilogFile;
use crate::emit::{fill, lit, Context};
use tooltouch_model::measure::frontend::pin;

/// Two flip-flops per pin (model: `FrontEnd::sync1`, `sync2`).
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let body = fill(
        r#"// Two-flip-flop synchronizer for the six asynchronous input pins (bit order of
// tooltouch_model::measure::frontend::pin: arm, contact, index, fes, scale_a, scale_b).
// A level sampled at clock k is on `synced` after clock k+1.
module tt_synchronizer (
    input  wire       clk,
    input  wire       rst,     // synchronous reset to the power-on state
    input  wire [${N1}:0] pins,    // asynchronous pin levels
    output wire [${N1}:0] synced   // second stage
);
    reg [${N1}:0] sync1_q = ${ZERO};
    reg [${N1}:0] sync2_q = ${ZERO};

    always @(posedge clk) begin
        if (rst) begin
            sync1_q <= ${ZERO};
            sync2_q <= ${ZERO};
        end else begin
            sync1_q <= pins;
            sync2_q <= sync1_q;
        end
    end

    assign synced = sync2_q;
endmodule
"#,
        &[
            ("N1", (pin::COUNT - 1).to_string()),
            ("ZERO", lit(pin::COUNT as u32, 0)),
        ],
    );
    ctx.file("tt_synchronizer", "two-flip-flop input synchronizer", &body)
}
