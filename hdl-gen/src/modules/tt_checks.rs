//! `tt_checks.v`: the measurement status (model: `MeasurementChecks`): the seven fault
//! conditions latched per measurement cycle and the confirmation of the decision, stepped
//! by the kernel's strobes in the canonical order arm → contact → index → FES → scale.
//! The [`Fault::ContactAtArmNotRaised`] variant never sets the `contact_at_arm` bit.

use crate::design::{Fault, VerilogFile};
use crate::emit::{bool_lit, fill, ge_const, lit, lt_const, Context};
use tooltouch_model::fault;
use tooltouch_model::measure::config::DecisionMethod;

/// The checks, model: `MeasurementChecks`.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let c = &ctx.config;
    let s = c.settings();
    let k = s.checks;
    let cb = ctx.count_bits();
    let rpb = u32::from(c.rev_pulse_bits());
    let ib = u32::from(c.fes_idle_bits());
    let ppr = u64::from(s.pulses_per_rev);
    let tolerance = u64::from(k.pulse_tolerance);
    let (fewest, most) = (ppr - tolerance, ppr + tolerance);
    let timeout = u64::from(k.fes_timeout_cycles);
    let probe = u64::from(k.probe_revs);
    let windows = u64::from(k.confirm_windows);
    let mut enabled = 0u8;
    for (on, bit) in [
        (
            k.contact_at_arm && ctx.fault != Fault::ContactAtArmNotRaised,
            fault::CONTACT_AT_ARM,
        ),
        (k.revolutions, fault::PULSES_LOST | fault::INDEX_MISSING),
        (k.scale_errors, fault::SCALE_ERROR),
        (probe != 0, fault::NO_DECISION),
        (timeout != 0, fault::FES_TIMEOUT),
        (windows != 0, fault::UNCONFIRMED),
    ] {
        if on {
            enabled |= bit;
        }
    }
    let single = s.method == DecisionMethod::SinglePulse;
    // The watchdog's latch condition idle >= T - 1 and its saturation idle >= T, as bit
    // logic (the same values as the reference's comparisons in every state, reachable or
    // not, so an equivalence checker matches the two counts register for register).
    let (fes_expiring, idle_steps) = if timeout == 0 {
        ("1'b0".to_string(), "1'b0".to_string())
    } else {
        (
            format!("armed_q && {}", ge_const("idle_q", ib, timeout - 1)),
            format!("armed_q && {}", lt_const("idle_q", ib, timeout)),
        )
    };
    let body = fill(
        r#"// The measurement status (model: MeasurementChecks): fault bits latched per measurement
// cycle (cleared by the arm rising edge, held after the arm falls) and the confirmation
// of the decision. Same-clock order as the kernel: clear (arm) -> contact -> index ->
// FES -> scale (suffix _a: after arm, _c: after contact, _i: after index, _p: after the
// FES pulse). Fault bits: 0 contact_at_arm, 1 pulses_lost, 2 index_missing,
// 3 scale_error, 4 no_decision, 5 fes_timeout, 6 unconfirmed; a disabled check's bit is
// never set (FAULTS_ENABLED). Thresholds of the configuration ([measure.checks]):
//   revolution of FES pulses within ${FEWEST}..=${MOST} (pulses_per_rev ${PPR} +/- ${TOL}),
//   probe fail after ${PROBE} revolutions (0 = off), FES watchdog ${TIMEOUT} clocks (0 = off),
//   confirmation over ${WINDOWS} window(s) of at least ${CONFIRM} contact pulses.
// FES watchdog (model: observed lazily): `idle` counts the clocks since the last FES pulse
// or the arm rising edge, saturating at FES_TIMEOUT; the fes_timeout bit is set in the
// clock where the arm was high before and idle (before the clock) >= FES_TIMEOUT - 1, i.e.
// the clock `FES_TIMEOUT` ticks after the last FES pulse, exactly when the model's lazy
// watchdog shows it.
module tt_checks (
    input  wire        clk,
    input  wire        rst,
    input  wire        clear,          // arm rising edge: a new measurement cycle
    /* verilator lint_off UNUSEDSIGNAL */  // unread without a watchdog (FES_TIMEOUT = 0)
    input  wire        armed_q,        // armed before this clock's edges
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire        contact_q,      // contact level before this clock's edges
    input  wire        decided_q,      // register_now before this clock's edges
    input  wire        decision_take,  // the decision latch captures in this clock
    input  wire        index,          // index pulse while armed
    input  wire        window_closed,  // this index pulse closed a counting window
    /* verilator lint_off UNUSEDSIGNAL */  // the thresholds read only some bits
    input  wire [${CB1}:0] window_count,   // the count of the window it closed
    input  wire [15:0] revolutions_q,  // index pulses since arm, before this clock
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire        pulse,          // FES pulse while armed
    input  wire        scale_error,    // illegal scale transition
    input  wire        armed_a,        // armed after this clock's arm edge
    output wire        confirmed,
    output wire [6:0]  faults
);
    /* verilator lint_off UNUSEDPARAM */
    localparam [6:0]  FAULTS_ENABLED  = 7'b${ENABLED};
    localparam [${RPB1}:0] FEWEST          = ${FEWEST_L};  // pulses_per_rev - pulse_tolerance
    localparam [${RPB1}:0] MOST            = ${MOST_L};  // pulses_per_rev + pulse_tolerance
    localparam [15:0] PROBE_REVS      = ${PROBE_L};
    localparam [${IB1}:0] FES_TIMEOUT     = ${TIMEOUT_L};
    localparam [4:0]  CONFIRM_WINDOWS = ${WINDOWS_L};
    localparam [${CB1}:0] CONFIRM_COUNT   = ${CONFIRM_L};
    /* verilator lint_on UNUSEDPARAM */

    reg [6:0]  faults_q    = 7'd0;
    reg [${RPB1}:0] rev_q       = ${RZERO};  // FES pulses since the last index (or arm), saturating at MOST + 1
    reg        seen_q      = 1'b0;   // an index pulse came since arm
    /* verilator lint_off UNUSEDSIGNAL */  // unread without a watchdog (FES_TIMEOUT = 0)
    reg [${IB1}:0] idle_q      = ${IZERO};  // clocks since the last FES pulse (or arm), saturating at FES_TIMEOUT
    /* verilator lint_on UNUSEDSIGNAL */
    reg [4:0]  left_q      = 5'd0;   // windows still to close before the decision is confirmed
    reg        confirmed_q = 1'b0;

    // on_arm: everything cleared; contact_at_arm from the contact level before the clock.
    wire [6:0] faults_a    = clear ? {6'd0, contact_q} : faults_q;
    wire [4:0] left_a      = clear ? 5'd0 : left_q;
    wire       confirmed_a = clear ? 1'b0 : confirmed_q;
    // The decision (on_decision): at the contact edge for the single-pulse method (before
    // the index), at the FES pulse otherwise (after it).
    wire       decides_c   = ${SINGLE} && decision_take;
    wire       decides_p   = !${SINGLE} && decision_take;
    wire [4:0] left_c      = (decides_c && CONFIRM_WINDOWS != 5'd0) ? CONFIRM_WINDOWS : left_a;
    wire       confirmed_c = confirmed_a || (decides_c && CONFIRM_WINDOWS == 5'd0);
    wire       decided_c   = (decided_q && !clear) || decides_c;

    // on_index: the revolution's pulse count, the confirmation, the probe fail.
    wire       lost        = index && !clear && seen_q && ${REV_BELOW_FEWEST};
    wire       closing     = index && window_closed && (left_c != 5'd0);
    wire       falls_back  = closing && ${BELOW_CONFIRM};
    wire [4:0] left_i      = closing ? (falls_back ? 5'd0 : left_c - 5'd1) : left_c;
    wire       confirmed_i = (closing && !falls_back) ? (left_c == 5'd1) : confirmed_c;
    // revolutions after this index pulse >= PROBE_REVS (revolutions_q + 1, or 1 after clear).
    wire       probe_due   = clear ? ${PROBE_AT_ONE} : ${REVS_DUE};
    wire       no_decision = index && !decided_c && probe_due;

    // on_fes: the count since the index saturates at MOST + 1; passing MOST is an index missing.
    wire       from_zero   = clear || index;
    wire       at_most     = ${REV_AT_MOST};  // rev_q >= MOST: the next pulse passes it
    wire       missing     = pulse && !from_zero && at_most;
    wire [${RPB1}:0] rev_p       = from_zero ? {${RPB_1}'d0, pulse} :
                             !pulse ? rev_q : at_most ? MOST + ${RONE} : rev_q + ${RONE};
    wire [4:0] left_p      = (decides_p && CONFIRM_WINDOWS != 5'd0) ? CONFIRM_WINDOWS : left_i;
    wire       confirmed_p = confirmed_i || (decides_p && CONFIRM_WINDOWS == 5'd0);

    // The FES watchdog (see the header).
    wire       expiring    = ${FES_EXPIRING};

    wire [6:0] raised = {falls_back, expiring, no_decision, scale_error && armed_a, missing,
                         lost, 1'b0};
    wire [6:0] faults_n = (faults_a | raised) & FAULTS_ENABLED;

    always @(posedge clk) begin
        if (rst) begin
            faults_q    <= 7'd0;
            rev_q       <= ${RZERO};
            seen_q      <= 1'b0;
            idle_q      <= ${IZERO};
            left_q      <= 5'd0;
            confirmed_q <= 1'b0;
        end else begin
            faults_q    <= faults_n;
            rev_q       <= rev_p;
            seen_q      <= (seen_q && !clear) || index;
            if (clear || pulse)
                idle_q  <= ${IZERO};
            else if (${IDLE_STEPS})
                idle_q  <= idle_q + ${IONE};
            left_q      <= left_p;
            confirmed_q <= confirmed_p;
        end
    end

    assign confirmed = confirmed_q;
    assign faults    = faults_q;
endmodule
"#,
        &[
            ("CB1", (cb - 1).to_string()),
            ("RPB1", (rpb - 1).to_string()),
            ("RPB_1", (rpb - 1).to_string()),
            ("IB1", (ib - 1).to_string()),
            ("ENABLED", format!("{enabled:07b}")),
            ("FEWEST", fewest.to_string()),
            ("MOST", most.to_string()),
            ("PPR", ppr.to_string()),
            ("TOL", tolerance.to_string()),
            ("PROBE", probe.to_string()),
            ("TIMEOUT", timeout.to_string()),
            ("WINDOWS", windows.to_string()),
            ("CONFIRM", c.confirm_count().to_string()),
            ("FEWEST_L", lit(rpb, fewest)),
            ("MOST_L", lit(rpb, most)),
            ("PROBE_L", lit(16, probe)),
            ("TIMEOUT_L", lit(ib, timeout)),
            ("WINDOWS_L", lit(5, windows)),
            ("CONFIRM_L", lit(cb, c.confirm_count().into())),
            ("RZERO", lit(rpb, 0)),
            ("RONE", lit(rpb, 1)),
            ("IZERO", lit(ib, 0)),
            ("IONE", lit(ib, 1)),
            ("SINGLE", bool_lit(single)),
            // rev_q < FEWEST and window_count < CONFIRM_COUNT as bit logic.
            ("REV_BELOW_FEWEST", lt_const("rev_q", rpb, fewest)),
            ("REV_AT_MOST", ge_const("rev_q", rpb, most)),
            (
                "BELOW_CONFIRM",
                lt_const("window_count", cb, c.confirm_count().into()),
            ),
            ("PROBE_AT_ONE", bool_lit(probe <= 1)),
            (
                "REVS_DUE",
                ge_const("revolutions_q", 16, probe.saturating_sub(1)),
            ),
            ("FES_EXPIRING", fes_expiring),
            ("IDLE_STEPS", idle_steps),
        ],
    );
    ctx.file(
        "tt_checks",
        "the measurement status (faults, confirmation)",
        &body,
    )
}
