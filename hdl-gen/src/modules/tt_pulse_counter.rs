//! `tt_pulse_counter.v`: device 1, the pulse counter (docs/domain.md §2.3; model:
//! `PulseCounter`). The same-clock composition clear → index → pulse is flattened so every
//! comparison works on registers; the `i_def` comparisons are registers stepped by
//! equalities, and the decision is written flat over flip-flops. The
//! [`Fault::FesBeforeIndex`] variant swaps index and pulse.

use crate::design::{Fault, VerilogFile};
use crate::emit::{bool_lit, fill, lit, Context};

/// Device 1 (docs/domain.md §2.3), model: `PulseCounter`.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let c = &ctx.config;
    let s = c.settings();
    let cb = ctx.count_bits();
    let rb = u32::from(c.window_rev_bits());
    // The canonical order is index, then the FES pulse; the fault swaps them.
    let order = if ctx.fault == Fault::FesBeforeIndex {
        r#"    // FAULT: the FES pulse is applied before the index pulse.
    wire             inc        = pulse && contact_bit && (count_a < WINDOW_PULSES);
    wire [${CB1}:0]  count_f    = inc ? count_a + ${CONE} : count_a;
    wire             window_end = index && ({1'b0, revs_a} + ${RONE1} >= WINDOW_REVS);
    wire [${CB1}:0]  lwc_i      = window_end ? count_f : lwc_a;
    wire [${RB1}:0]  revs_i     = window_end ? ${RZERO} : (index ? revs_a + ${RONE} : revs_a);
    wire [${CB1}:0]  count_p    = window_end ? ${CZERO} : count_f;
"#
    } else {
        r#"    // The composition clear -> on_index -> on_pulse, flattened so that every
    // comparison and increment works on the registers alone, in parallel with the edge
    // logic (the same values as applying the three steps one after the other):
    //   count after clear and index is 0 (`from_zero`) or count_q;
    //   0 < WINDOW_PULSES always, 0 + 1 > I_DEF iff I_DEF = 0,
    //   count_q + 1 > I_DEF iff count_q >= I_DEF.
    // count_q never exceeds WINDOW_PULSES (it saturates there), so
    // count_q < WINDOW_PULSES iff count_q != WINDOW_PULSES: an equality, no carry chain.
    wire             below_full = count_q != WINDOW_PULSES;
    wire [${CB1}:0]  count_inc  = count_q + ${CONE};
    // count_q >= I_DEF and count_q > I_DEF, kept as registers stepped with the count by
    // equalities (between restarts from 0 or 1 the count only grows by 1), so no
    // comparison carry chain precedes the decision.
    reg              reaches_q  = ${REACH0};  // count_q >= I_DEF
    reg              exceeds_q  = 1'b0;  // count_q > I_DEF
    wire             last_rev   = ({1'b0, revs_q} + ${RONE1} >= WINDOW_REVS);
    wire [${RB1}:0]  revs_inc   = revs_q + ${RONE};

    // on_index: the window's last index pulse moves the count to last_window_count.
    wire             window_end = index && (clear ? ${ONE_REV} : last_rev);
    wire             from_zero  = clear || window_end;
    wire [${CB1}:0]  lwc_i      = window_end ? count_a : lwc_a;
    wire [${RB1}:0]  revs_i     = window_end ? ${RZERO} :
                                  index ? (clear ? ${RONE} : revs_inc) : revs_a;
    // on_pulse: +1 per contact pulse, saturating at window_pulses.
    wire             inc        = pulse && contact_bit && (from_zero || below_full);
    wire [${CB1}:0]  count_p    = from_zero ? {${CB_1}'d0, inc} : (inc ? count_inc : count_q);
${EXCEEDS_WIRE}
    always @(posedge clk) begin
        if (rst) begin
            reaches_q <= ${REACH_RST};
            exceeds_q <= 1'b0;
        end else if (from_zero) begin
            reaches_q <= ${FROM_ZERO_REACH};  // count_p (0 or 1) >= I_DEF
            exceeds_q <= inc && ${IDEF_ZERO};  // count_p (0 or 1) > I_DEF
        end else if (inc) begin
            reaches_q <= reaches_q || ${AT_IDEF_M1};
            exceeds_q <= exceeds_q || (count_q == I_DEF);
        end
    end
"#
    };
    // i_def >= 1: a pulse that starts the count from 0 (clear, or the window's last index)
    // cannot exceed it; otherwise the pulse decides when the count already exceeds i_def,
    // or equals it and the pulse is a contact pulse (a full count exceeds i_def, so
    // saturation changes nothing). Written flat over flip-flops: two LUT levels before the
    // latches. i_def = 0 takes the general form `pulse && !reached_a && exceeds`; with a
    // run-time i_def both forms are written and i_def = 0 selects, so that tied to a
    // constant the text reduces to the constant design's.
    let window_end = if s.window_revs == 1 {
        "index"
    } else {
        "(index && last_rev)"
    };
    let flat = format!(
        "pulse && !clear && !{window_end} && !reached_q &&\n\
         \x20                   (exceeds_q || (contact_bit && reaches_q))"
    );
    let decide = if ctx.fault == Fault::FesBeforeIndex {
        "    assign decide = pulse && !reached_a && (count_p > I_DEF);\n".to_string()
    } else if ctx.tunable {
        format!(
            "    // i_def = 0: the general form; i_def >= 1: its flat form.\n\
             \x20   assign decide = idef_zero ? (pulse && !reached_a && exceeds) :\n\
             \x20                   ({flat});\n"
        )
    } else if s.i_def == 0 {
        "    assign decide = pulse && !reached_a && exceeds;\n".to_string()
    } else {
        format!(
            "    // Flat form of `pulse && !reached_a && exceeds` for i_def >= 1.\n\
             \x20   assign decide = {flat};\n"
        )
    };
    let body = fill(
        &(r#"// Device 1, the pulse counter (docs/domain.md §2.3): contact pulses per window of
// ${WR} revolution(s) of ${PPR} FES pulses; decides on the pulse whose count exceeds i_def.
// Same-clock order: clear (arm) -> index -> pulse.
module tt_pulse_counter (
    input  wire        clk,
    input  wire        rst,
    input  wire        clear,        // arm rising edge: start of a measurement cycle
    input  wire        index,        // index pulse while armed
    input  wire        pulse,        // FES pulse while armed
    input  wire        contact_bit,  // the pulse's contact bit (sampled or sticky rule)
    output wire [${CB1}:0] count,             // contact pulses in this window
    output wire [${CB1}:0] last_window_count, // contact pulses in the previous window
${IDEF_PORT}    output wire        decide,       // this clock's pulse made the count exceed i_def
    output wire        window_closed, // this clock's index pulse closed the window
    output wire [${CB1}:0] window_count   // the closed window's count (last_window_count next)
);
    localparam [${CB1}:0] WINDOW_PULSES = ${WP};  // pulses_per_rev * window_revs
${IDEF_DECL}
    localparam [${RB}:0] WINDOW_REVS   = ${WRL};

    reg [${CB1}:0] count_q   = ${CZERO};
    reg [${CB1}:0] lwc_q     = ${CZERO};
    reg [${RB1}:0] revs_q    = ${RZERO};  // index pulses in this window, 0..window_revs-1
    reg        reached_q = 1'b0;    // the count exceeded i_def since the last clear

    // reset(): arm rising edge.
    wire [${CB1}:0]  count_a    = clear ? ${CZERO} : count_q;
    wire [${CB1}:0]  lwc_a      = clear ? ${CZERO} : lwc_q;
    wire [${RB1}:0]  revs_a     = clear ? ${RZERO} : revs_q;
    wire             reached_a  = clear ? 1'b0 : reached_q;
"#
        .to_string()
            + order
            + &decide
            + r#"

    always @(posedge clk) begin
        if (rst) begin
            count_q   <= ${CZERO};
            lwc_q     <= ${CZERO};
            revs_q    <= ${RZERO};
            reached_q <= 1'b0;
        end else begin
            count_q   <= count_p;
            lwc_q     <= lwc_i;
            revs_q    <= revs_i;
            reached_q <= reached_a | decide;
        end
    end

    assign count             = count_q;
    assign last_window_count = lwc_q;
    assign window_closed     = window_end;
    assign window_count      = lwc_i;
endmodule
"#),
        &[
            ("WR", s.window_revs.to_string()),
            ("PPR", s.pulses_per_rev.to_string()),
            ("CB1", (cb - 1).to_string()),
            ("RB", rb.to_string()),
            ("RB1", (rb - 1).to_string()),
            ("WP", lit(cb, c.window_pulses().into())),
            ("WRL", lit(rb + 1, s.window_revs.into())),
            ("CZERO", lit(cb, 0)),
            ("CONE", lit(cb, 1)),
            ("RZERO", lit(rb, 0)),
            ("RONE", lit(rb, 1)),
            ("RONE1", lit(rb + 1, 1)),
            ("CB_1", (cb - 1).to_string()),
            ("ONE_REV", bool_lit(s.window_revs == 1)),
            (
                "IDEF_ZERO",
                if ctx.tunable {
                    "idef_zero".to_string()
                } else {
                    bool_lit(s.i_def == 0)
                },
            ),
            (
                "EXCEEDS_WIRE",
                if ctx.tunable {
                    "    wire             exceeds    = from_zero ? (inc && idef_zero) :\n\
                     \x20                                 (inc ? reaches_q : exceeds_q);\n"
                        .to_string()
                } else if s.i_def == 0 {
                    "    wire             exceeds    = from_zero ? inc : (inc ? reaches_q : exceeds_q);\n"
                            .to_string()
                } else {
                    String::new()
                },
            ),
            ("REACH0", bool_lit(s.i_def == 0)),
            (
                "REACH_RST",
                if ctx.tunable {
                    "idef_zero".to_string()
                } else {
                    bool_lit(s.i_def == 0)
                },
            ),
            (
                "FROM_ZERO_REACH",
                if ctx.tunable {
                    "(idef_zero || (idef_one && inc))".to_string()
                } else {
                    match s.i_def {
                        0 => "1'b1".to_string(),
                        1 => "inc".to_string(),
                        _ => "1'b0".to_string(),
                    }
                },
            ),
            (
                "AT_IDEF_M1",
                if ctx.tunable {
                    format!("(idef_zero || (count_q == I_DEF - {}))", lit(cb, 1))
                } else if s.i_def == 0 {
                    "1'b1".to_string()
                } else {
                    format!("(count_q == {})", lit(cb, u64::from(s.i_def) - 1))
                },
            ),
            (
                "IDEF_PORT",
                if ctx.tunable {
                    format!(
                        "    input  wire [{}:0] i_def,        // run-time i_def (SPI register)\n",
                        cb - 1
                    )
                } else {
                    String::new()
                },
            ),
            (
                "IDEF_DECL",
                if ctx.tunable {
                    format!(
                        "    wire [{cb1}:0] I_DEF     = i_def;  // run-time (changed only while disarmed)\n\
                         \x20   wire        idef_zero = I_DEF == {zero};\n\
                         \x20   wire        idef_one  = I_DEF == {one};",
                        cb1 = cb - 1,
                        zero = lit(cb, 0),
                        one = lit(cb, 1)
                    )
                } else {
                    format!(
                        "    localparam [{}:0] I_DEF         = {};",
                        cb - 1,
                        lit(cb, s.i_def.into())
                    )
                },
            ),
        ],
    );
    ctx.file("tt_pulse_counter", "device 1, the pulse counter", &body)
}
