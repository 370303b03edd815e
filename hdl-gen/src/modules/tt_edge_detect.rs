//! `tt_edge_detect.v`: the edges of the filtered levels and the strobes the kernel acts
//! on (arm, contact, index and FES rising edges, the scale's quadrature step), decoded
//! one clock early from the glitch filter's toggles and registered, so the kernel's
//! logic starts at flip-flops.

use crate::design::VerilogFile;
use crate::emit::{fill, pin_index, Context};
use tooltouch_model::measure::frontend::pin;

/// The edges, registered (model: `filtered ^ FrontEnd::previous`), and the strobes
/// the kernel acts on, decoded from them.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let body = fill(
        r#"// Edge detection (model: filtered ^ previous): the kernel acts on the edges of the filtered
// levels in the clock they appear. The edges are registered one clock early, from the
// filter's `toggles` (the filtered levels about to change) and decoded into the strobes
// the kernel acts on, so that the kernel's logic starts at flip-flops: the rising edges of
// arm, contact and FES, the index and FES rising edges while the arm level (after this
// clock) is high, and the scale's quadrature step (docs/domain.md §1: phases (A,B) 00 ->
// 10 -> 11 -> 01 count up; the phase before the change is the one of the filtered levels,
// as the model's decoder keeps the phase of the last levels it saw).
module tt_edge_detect (
    input  wire       clk,
    input  wire       rst,
    input  wire [${N1}:0] toggles,
    input  wire [${N1}:0] filtered,     // filtered levels, before this clock's toggles
    output wire       arm_rise,     // arm rising edge: a measurement cycle starts
    output wire       contact_rise, // contact rising edge
    output wire       contact_rise_next, // the next clock's contact_rise (its D input)
    output wire       index_pulse,  // index rising edge while armed
    output wire       fes_rise,     // FES rising edge
    output wire       fes_pulse,    // FES rising edge while armed
    output wire       scale_up,     // scale step +1
    output wire       scale_down,   // scale step -1
    output wire       scale_error   // both scale lines changed at once
);
    wire [${N1}:0] next   = filtered ^ toggles;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [${N1}:0] rising = toggles & next;  // the scale lines' are not used
    /* verilator lint_on UNUSEDSIGNAL */
    wire [1:0] phase_now  = {filtered[${SB_PIN}], filtered[${SA}] ^ filtered[${SB_PIN}]};
    wire [1:0] phase_next = {next[${SB_PIN}], next[${SA}] ^ next[${SB_PIN}]};
    wire [1:0] step       = phase_next - phase_now;

    reg       arm_rise_q     = 1'b0;
    reg       contact_rise_q = 1'b0;
    reg       index_pulse_q  = 1'b0;
    reg       fes_rise_q     = 1'b0;
    reg       fes_pulse_q    = 1'b0;
    reg       scale_up_q     = 1'b0;
    reg       scale_down_q   = 1'b0;
    reg       scale_error_q  = 1'b0;

    always @(posedge clk) begin
        if (rst) begin
            arm_rise_q     <= 1'b0;
            contact_rise_q <= 1'b0;
            index_pulse_q  <= 1'b0;
            fes_rise_q     <= 1'b0;
            fes_pulse_q    <= 1'b0;
            scale_up_q     <= 1'b0;
            scale_down_q   <= 1'b0;
            scale_error_q  <= 1'b0;
        end else begin
            arm_rise_q     <= rising[${ARM}];
            contact_rise_q <= rising[${CONTACT}];
            index_pulse_q  <= rising[${INDEX}] && next[${ARM}];
            fes_rise_q     <= rising[${FES}];
            fes_pulse_q    <= rising[${FES}] && next[${ARM}];
            scale_up_q     <= step == 2'd1;
            scale_down_q   <= step == 2'd3;
            scale_error_q  <= step == 2'd2;
        end
    end

    assign arm_rise     = arm_rise_q;
    assign contact_rise = contact_rise_q;
    assign contact_rise_next = rising[${CONTACT}];
    assign index_pulse  = index_pulse_q;
    assign fes_rise     = fes_rise_q;
    assign fes_pulse    = fes_pulse_q;
    assign scale_up     = scale_up_q;
    assign scale_down   = scale_down_q;
    assign scale_error  = scale_error_q;
endmodule
"#,
        &[
            ("N1", (pin::COUNT - 1).to_string()),
            ("ARM", pin_index(pin::ARM)),
            ("SA", pin_index(pin::SCALE_A)),
            ("SB_PIN", pin_index(pin::SCALE_B)),
            ("CONTACT", pin_index(pin::CONTACT)),
            ("INDEX", pin_index(pin::INDEX)),
            ("FES", pin_index(pin::FES)),
        ],
    );
    ctx.file("tt_edge_detect", "edge detection", &body)
}
