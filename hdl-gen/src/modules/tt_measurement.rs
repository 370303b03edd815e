//! `tt_measurement.v`: the measurement kernel (model: `Measurement`): arm, contact, the
//! sticky contact bit, the counters since arm, and the instances of both detectors, the
//! quadrature decoder, the two position latches and the checks (`tt_checks`). The contact
//! rule picks the pulse's contact bit and the decision method picks which detector drives
//! the decision latch.

use crate::design::{Fault, VerilogFile};
use crate::emit::{fill, pin_index, Context};
use crate::spi::Threshold;
use tooltouch_model::measure::config::{ContactRule, DecisionMethod};
use tooltouch_model::measure::frontend::pin;

/// The kernel, model: `Measurement` (arm, contact, sticky bit, counters, decision).
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let s = ctx.config.settings();
    let bit = match s.contact_rule {
        ContactRule::Sampled => "contact_c   /* sampled rule: contact level at the pulse */",
        ContactRule::Sticky => "sticky_c    /* sticky rule: contact since the previous pulse */",
    };
    let decision = match s.method {
        DecisionMethod::SinglePulse => "first_take /* single_pulse: the first contact edge */",
        DecisionMethod::Counter => "counter_decide /* counter: device 1 */",
        DecisionMethod::Density => {
            "density_fire && (clear || !density_fired) /* density: device 2 */"
        }
    };
    let body = fill(
        r#"// The measurement kernel: the edges detected in one clock act in the canonical order
// arm -> contact -> index -> FES -> scale, each on the state left by the previous ones
// (suffix _a: after arm, _c: after contact, _i: after index, _p: after the FES pulse).
// The latches see the scale position as it was at the start of the clock.
// The arm and contact states after this clock's edges are the filtered levels themselves
// (a level changes exactly when its edge is reported), so they are read from `levels`.
module tt_measurement (
    input  wire        clk,
    input  wire        rst,
    input  wire        arm_level,     // filtered arm level
    input  wire        contact_level, // filtered contact level
    input  wire        arm_rise,      // strobes decoded by tt_edge_detect
    input  wire        contact_rise,
    input  wire        contact_rise_next, // contact_rise of the next clock (its D input)
    input  wire        index_pulse,
    input  wire        fes_rise,
    input  wire        fes_pulse,
    input  wire        scale_up,
    input  wire        scale_down,
    input  wire        scale_error,
${THRESHOLD_PORTS}    output wire        armed,
    output wire        contact,
    output wire        register_now,
    output wire [${SB1}:0] decision_position,
    output wire        first_contact,
    output wire [${SB1}:0] first_contact_position,
    output wire [${SB1}:0] position,
    output wire [7:0]  scale_errors,
    output wire [${CB1}:0] count,
    output wire [${CB1}:0] last_window_count,
    output wire [${QB1}:0] charge,
    output wire        density_armed,
    output wire        density_fired,
    output wire [15:0] revolutions,
    output wire [31:0] pulses,
    output wire        confirmed,
    output wire [6:0]  faults
);
    reg        armed_q       = 1'b0;
    reg        contact_q     = 1'b0;
    // The sticky bit as the next FES pulse would read it: contact since the previous
    // pulse, including this clock's contact rising edge (model: sticky | contact_rise),
    // registered one clock early from the edge stage's next contact strobe so that the
    // counter and the capacitor start from a flip-flop.
    reg        sticky_c_q    = 1'b0;
    reg [15:0] revolutions_q = 16'd0;  // index pulses since arm, saturating
    reg [31:0] pulses_q      = 32'd0;  // FES pulses since arm, wrapping

    // on_arm: a rising edge clears the cycle's state.
    wire clear   = arm_rise;
    wire armed_a = arm_level;

    // on_contact: a rising edge sets the sticky bit and, while armed, latches the
    // first-contact position if none is held after the clear.
    wire contact_c     = contact_level;
    wire sticky_c      = sticky_c_q;
    wire first_take    = contact_rise && armed_a && (clear || !first_contact);

    // on_index (while armed).
    wire        index         = index_pulse;
    // (clear, then +1 saturating at 65535: written as reset / enable below.)
    wire        revolutions_steps = index && (revolutions_q != 16'hffff);

    // on_fes: the pulse's contact bit, then the sticky bit reloads with the contact level.
    wire        pulse       = fes_pulse;
    wire        contact_bit = ${BIT};
    wire        sticky_p    = ${STICKY_RELOAD} ? contact_c : sticky_c;
    // pulses_q + 1 in two 16-bit halves (the upper steps when the lower wraps), so no
    // carry chain is longer than 16 bits.
    wire [15:0] pulses_lo_inc = pulses_q[15:0] + 16'd1;
    wire [15:0] pulses_hi_inc = pulses_q[31:16] + 16'd1;
    wire [31:0] pulses_inc  = {(&pulses_q[15:0]) ? pulses_hi_inc : pulses_q[31:16],
                               pulses_lo_inc};

    // The detectors; only the configured method's decision drives the decision latch,
    // which takes the position when it holds none after the clear.
    /* verilator lint_off UNUSEDSIGNAL */
    wire counter_decide;  // at most once per cycle (the counter remembers it decided)
    wire density_fire;
    /* verilator lint_on UNUSEDSIGNAL */
    wire decision_take = ${DECISION};
    wire window_closed;                 // this clock's index pulse closed a counting window
    wire [${CB1}:0] window_count;        // the count of the window it closed

    tt_pulse_counter u_counter (
        .clk(clk), .rst(rst), .clear(clear), .index(index), .pulse(pulse),
        .contact_bit(contact_bit), .count(count), .last_window_count(last_window_count),
${COUNTER_THRESHOLDS}        .decide(counter_decide), .window_closed(window_closed), .window_count(window_count)
    );

    tt_density_detector u_density (
        .clk(clk), .rst(rst), .clear(clear), .pulse(pulse), .contact_bit(contact_bit),
${DENSITY_THRESHOLDS}        .charge(charge), .armed(density_armed), .fired(density_fired), .fire(density_fire)
    );

    tt_quadrature_decoder u_scale (
        .clk(clk), .rst(rst), .up(scale_up), .down(scale_down), .error(scale_error),
        .position(position), .errors(scale_errors)
    );

    tt_position_latch u_first_contact (
        .clk(clk), .rst(rst), .clear(${FIRST_CLEAR}), .take(first_take), .position_in(position),
        .valid(first_contact), .position(first_contact_position)
    );

    tt_position_latch u_decision (
        .clk(clk), .rst(rst), .clear(clear), .take(decision_take),
        .position_in(position), .valid(register_now), .position(decision_position)
    );

    // The measurement status: faults latched per cycle and the decision's confirmation.
    tt_checks u_checks (
        .clk(clk), .rst(rst), .clear(clear), .armed_q(armed_q), .contact_q(contact_q),
        .decided_q(register_now), .decision_take(decision_take), .index(index),
        .window_closed(window_closed), .window_count(window_count),
        .revolutions_q(revolutions_q), .pulse(pulse), .scale_error(scale_error),
        .armed_a(armed_a), .confirmed(confirmed), .faults(faults)
    );

    always @(posedge clk) begin
        if (rst) begin
            armed_q       <= 1'b0;
            contact_q     <= 1'b0;
            sticky_c_q    <= 1'b0;
        end else begin
            armed_q       <= armed_a;
            contact_q     <= contact_c;
            sticky_c_q    <= sticky_p | contact_rise_next;
        end
    end

    // Counters since arm: clear, then count (clear and an edge in one clock give 1).
    always @(posedge clk) begin
        if (rst)
            revolutions_q <= 16'd0;
        else if (clear)
            revolutions_q <= {15'd0, index};
        else if (revolutions_steps)
            revolutions_q <= revolutions_q + 16'd1;
    end

    always @(posedge clk) begin
        if (rst)
            pulses_q <= 32'd0;
        else if (clear)
            pulses_q <= {31'd0, pulse};
        else if (pulse)
            pulses_q <= pulses_inc;
    end

    assign armed       = armed_q;
    assign contact     = contact_q;
    assign revolutions = revolutions_q;
    assign pulses      = pulses_q;
endmodule
"#,
        &[
            ("N1", (pin::COUNT - 1).to_string()),
            ("SB1", (ctx.scale_bits() - 1).to_string()),
            ("CB1", (ctx.count_bits() - 1).to_string()),
            ("QB1", (ctx.charge_bits() - 1).to_string()),
            ("ARM", pin_index(pin::ARM)),
            ("CONTACT", pin_index(pin::CONTACT)),
            ("INDEX", pin_index(pin::INDEX)),
            ("FES", pin_index(pin::FES)),
            ("SA", pin_index(pin::SCALE_A)),
            ("SB_PIN", pin_index(pin::SCALE_B)),
            ("BIT", bit.to_string()),
            ("THRESHOLD_PORTS", kernel_threshold_ports(ctx)),
            (
                "COUNTER_THRESHOLDS",
                if ctx.tunable {
                    "        .i_def(i_def),\n".into()
                } else {
                    String::new()
                },
            ),
            (
                "DENSITY_THRESHOLDS",
                if ctx.tunable {
                    "        .fire_threshold(fire_threshold), .rearm_threshold(rearm_threshold),\n\
                     \x20       .charge_step(charge_step), .discharge_step(discharge_step),\n"
                        .into()
                } else {
                    String::new()
                },
            ),
            ("DECISION", decision.to_string()),
            (
                "STICKY_RELOAD",
                if ctx.fault == Fault::StickyNotReloadedWhileDisarmed {
                    "(fes_rise && armed_a) /* FAULT: only while armed */".into()
                } else {
                    "fes_rise".into()
                },
            ),
            (
                "FIRST_CLEAR",
                if ctx.fault == Fault::LatchNotClearedByArm {
                    "1'b0 /* FAULT: arm does not clear it */".into()
                } else {
                    "clear".into()
                },
            ),
        ],
    );
    ctx.file("tt_measurement", "the measurement kernel", &body)
}

/// The kernel's run-time threshold inputs (the SPI design only; empty otherwise): every
/// [`Threshold`] but the glitch filter's, which precedes the kernel.
pub(crate) fn kernel_threshold_ports(ctx: &Context) -> String {
    if !ctx.tunable {
        return String::new();
    }
    Threshold::ALL
        .iter()
        .filter(|t| **t != Threshold::GlitchCycles)
        .map(|t| {
            format!(
                "    input  wire [{}:0] {},\n",
                t.width(&ctx.config) - 1,
                t.port()
            )
        })
        .collect()
}
