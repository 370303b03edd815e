//! `tt_glitch_filter.v`: the per-pin glitch filter (model: `FrontEnd::filter`). With
//! `glitch_cycles` = 0 each pin is a single register; otherwise a level register and a
//! stability counter per pin, whose limit test is written as bit logic (or, in the SPI
//! design, compares with the run-time `glitch_cycles` input; its width is fixed by the
//! configured value, and a configured 0 leaves no counter and no input).

use crate::design::VerilogFile;
use crate::emit::{fill, ge_const, lit, Context};
use tooltouch_model::measure::frontend::pin;

/// Per pin: the filtered level and its stability counter (model: `FrontEnd::filter`).
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let glitch = u64::from(ctx.config.settings().glitch_cycles);
    let gb = u32::from(ctx.config.glitch_bits());
    let per_pin = if glitch == 0 {
        r#"        // glitch_cycles = 0: every synchronized level passes on the next clock.
        reg level_q = 1'b0;

        always @(posedge clk) begin
            if (rst)
                level_q <= 1'b0;
            else
                level_q <= synced[i];
        end

        assign toggles[i] = synced[i] ^ level_q;
"#
        .to_string()
    } else {
        fill(
            r#"        // Clocks `synced` has differed from the filtered level, 0..=${G}.
        reg         level_q  = 1'b0;
        reg [${GB1}:0] stable_q = ${GZERO};

        always @(posedge clk) begin
            if (rst) begin
                level_q  <= 1'b0;
                stable_q <= ${GZERO};
            end else if (synced[i] == level_q) begin
                stable_q <= ${GZERO};
            end else if (${AT_LIMIT}) begin
                level_q  <= ~level_q;
                stable_q <= ${GZERO};
            end else begin
                stable_q <= stable_q + ${GONE};
            end
        end

        assign toggles[i] = (synced[i] != level_q) && ${AT_LIMIT};
"#,
            &[
                ("G", glitch.to_string()),
                ("GB1", (gb - 1).to_string()),
                ("GZERO", lit(gb, 0)),
                ("GONE", lit(gb, 1)),
                (
                    "AT_LIMIT",
                    if ctx.tunable {
                        "(stable_q >= glitch_cycles)".to_string()
                    } else {
                        ge_const("stable_q", gb, glitch)
                    },
                ),
            ],
        )
    };
    let body = fill(
        r#"// Glitch filter: a new level passes once it has been seen on glitch_cycles + 1 = ${G1}
// consecutive clocks; a clock agreeing with the filtered level restarts the count.
module tt_glitch_filter (
    input  wire       clk,
    input  wire       rst,
    input  wire [${N1}:0] synced,    // synchronized levels
    output wire [${N1}:0] filtered,  // filtered levels
${LIMIT_PORT}    output wire [${N1}:0] toggles    // filtered levels that change at this clock's edge
);
    genvar i;
    generate
    for (i = 0; i < ${N}; i = i + 1) begin : pin
${PER_PIN}
        assign filtered[i] = level_q;
    end
    endgenerate
endmodule
"#,
        &[
            ("G1", (glitch + 1).to_string()),
            ("N", pin::COUNT.to_string()),
            ("N1", (pin::COUNT - 1).to_string()),
            ("PER_PIN", per_pin),
            (
                "LIMIT_PORT",
                if ctx.tunable && glitch > 0 {
                    format!(
                        "    input  wire [{}:0] glitch_cycles, // run-time glitch_cycles (SPI register)\n",
                        gb - 1
                    )
                } else {
                    String::new()
                },
            ),
        ],
    );
    ctx.file("tt_glitch_filter", "per-pin glitch filter", &body)
}
