//! `tt_density_detector.v`: device 2, the contact-density detector (docs/domain.md §2.4;
//! model: `DensityDetector`). Each charge law writes its next charge and its threshold
//! tests (as constant comparisons of the current charge where the law allows, so no
//! comparator carry chain precedes the decision); the threshold block and the state
//! update are shared. The [`Fault::FireThresholdPlusOne`] variant raises the fire
//! threshold by one LSB.

use crate::design::{Fault, VerilogFile};
use crate::emit::{bool_lit, fill, ge_const, lit, lt_const, Context};
use tooltouch_model::measure::config::ChargeLaw;

/// The density detector's threshold tests of the new charge and the values after a
/// same-clock clear, shared by both charge laws (holes filled by each law).
const DENSITY_THRESHOLDS: &str = r#"    wire        up_fires     = ${UP_FIRES};
    wire        down_fires   = ${DOWN_FIRES};
    wire        up_rearms    = ${UP_REARMS};
    wire        down_rearms  = ${DOWN_REARMS};
    // From an empty capacitor (the same clock's clear).
    localparam [${QB1}:0] UP_FROM_EMPTY = ${UP0};
    localparam        UP0_FIRES     = ${UP0_FIRES};
    localparam        UP0_REARMS    = ${UP0_REARMS};
    localparam        DOWN0_REARMS  = ${DOWN0_REARMS};
"#;

/// Device 2 (docs/domain.md §2.4), model: `DensityDetector`.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let s = ctx.config.settings();
    let qb = ctx.charge_bits();
    let full = u64::from(ctx.config.full_charge());
    let mut fire = u64::from(s.fire_threshold);
    if ctx.fault == Fault::FireThresholdPlusOne {
        fire = (fire + 1).min(full);
    }
    let law = if ctx.tunable {
        tunable_law(ctx)
    } else {
        constant_law(ctx, fire)
    };
    let body = fill(
        &(DETECTOR_HEAD.to_string() + &law + DETECTOR_TAIL),
        &[
            ("QB", qb.to_string()),
            ("QB1", (qb - 1).to_string()),
            ("FULL", lit(qb, full)),
            ("FIRE", fire.to_string()),
            ("REARM", s.rearm_threshold.to_string()),
            ("QZERO", lit(qb, 0)),
            ("QONE", lit(qb, 1)),
            (
                "THRESHOLD_PORTS",
                if ctx.tunable {
                    let sw = step_bits(ctx) - 1;
                    format!(
                        "    input  wire [{q1}:0] fire_threshold,  // run-time thresholds and steps (SPI registers)\n\
                         \x20   input  wire [{q1}:0] rearm_threshold,\n\
                         \x20   input  wire [{sw}:0] charge_step,     // {what}\n\
                         \x20   input  wire [{sw}:0] discharge_step,\n",
                        q1 = qb - 1,
                        what = match s.charge_law {
                            ChargeLaw::Linear { .. } => "linear law: LSBs per pulse",
                            ChargeLaw::Exponential { .. } => "exponential law: the shifts",
                        }
                    )
                } else {
                    String::new()
                },
            ),
        ],
    );
    ctx.file(
        "tt_density_detector",
        "device 2, the contact-density detector",
        &body,
    )
}

/// Width of the run-time charge and discharge steps, bits: `charge_bits` for the linear
/// law's steps (`1..=full`), enough for `0..=charge_bits` for the exponential law's shifts.
pub(crate) fn step_bits(ctx: &Context) -> u32 {
    match ctx.config.settings().charge_law {
        ChargeLaw::Linear { .. } => ctx.charge_bits(),
        ChargeLaw::Exponential { .. } => u32::from(tooltouch_model::measure::config::bits_for(
            ctx.charge_bits().into(),
        )),
    }
}

/// The SPI design's charge law: steps and thresholds are input ports, compared at run
/// time (the same values as the constant forms of [`constant_law`]).
fn tunable_law(ctx: &Context) -> String {
    let qb = ctx.charge_bits();
    let tests = r#"    wire        up_fires     = up_q >= fire_threshold;
    wire        down_fires   = down_q >= fire_threshold;
    wire        up_rearms    = up_q < rearm_threshold;
    wire        down_rearms  = down_q < rearm_threshold;
    wire        UP0_FIRES    = UP_FROM_EMPTY >= fire_threshold;
    wire        UP0_REARMS   = UP_FROM_EMPTY < rearm_threshold;
    wire        DOWN0_REARMS = rearm_threshold != ${QZERO};
"#;
    let law = match ctx.config.settings().charge_law {
        ChargeLaw::Linear { .. } => r#"    // Linear law, run-time steps: +charge_step per contact pulse (saturating at full
    // scale: the carry out of q + step), -discharge_step per pulse without (saturating
    // at 0). A step is at most full scale, so from an empty capacitor the charge is the
    // step itself.
    wire [${QB}:0] sum_c        = {1'b0, charge_q} + {1'b0, charge_step};
    wire [${QB1}:0] diff         = charge_q - discharge_step;
    wire        up_sat       = sum_c[${QB}];
    wire        down_sat     = charge_q < discharge_step;
    wire [${QB1}:0] up_q         = up_sat ? FULL : sum_c[${QB1}:0];
    wire [${QB1}:0] down_q       = down_sat ? ${QZERO} : diff;
    wire [${QB1}:0] UP_FROM_EMPTY = charge_step;
"#
        .to_string(),
        ChargeLaw::Exponential { .. } => r#"    // Exponential law, run-time shifts: +max(1, (full - q) >> charge_step) per contact
    // pulse, -max(1, q >> discharge_step) per pulse without; a zero distance steps by 0.
    wire [${QB1}:0] room         = FULL - charge_q;
    wire [${QB1}:0] room_shift   = room >> charge_step;
    wire [${QB1}:0] q_shift      = charge_q >> discharge_step;
    wire [${QB1}:0] full_shift   = FULL >> charge_step;
    wire [${QB1}:0] step_up      = (room == ${QZERO}) ? ${QZERO} :
                               (room_shift == ${QZERO}) ? ${QONE} : room_shift;
    wire [${QB1}:0] step_down    = (charge_q == ${QZERO}) ? ${QZERO} :
                               (q_shift == ${QZERO}) ? ${QONE} : q_shift;
    wire [${QB1}:0] up_q         = charge_q + step_up;
    wire [${QB1}:0] down_q       = charge_q - step_down;
    wire [${QB1}:0] UP_FROM_EMPTY = (full_shift == ${QZERO}) ? ${QONE} : full_shift;
"#
        .to_string(),
    };
    fill(
        &(law + tests),
        &[
            ("QB", qb.to_string()),
            ("QB1", (qb - 1).to_string()),
            ("QZERO", lit(qb, 0)),
            ("QONE", lit(qb, 1)),
        ],
    )
}

/// The configured charge law written with constant steps and thresholds.
fn constant_law(ctx: &Context, fire: u64) -> String {
    let s = ctx.config.settings();
    let qb = ctx.charge_bits();
    let full = u64::from(ctx.config.full_charge());
    let rearm = u64::from(s.rearm_threshold);
    // `charge_q >= c` and `charge_q < c` for a constant c, folded when constant
    // (so no comparison is trivially true or false).
    let ge = |c: u64| ge_const("charge_q", qb, c);
    let lt = |c: u64| lt_const("charge_q", qb, c);
    match s.charge_law {
        ChargeLaw::Linear {
            charge_step,
            discharge_step,
        } => {
            let (up, down) = (u64::from(charge_step), u64::from(discharge_step));
            fill(
                &(r#"    // Linear law: +${UP} per contact pulse (saturating at full scale),
    // -${DOWN} per pulse without (saturating at 0). The threshold tests of the new charge
    // are rewritten as constant comparisons of charge_q (fire <= full, so
    // min(q + up, full) >= fire iff q >= fire - up; q - down >= fire iff q >= fire + down;
    // min(q + up, full) < rearm iff q < rearm - up; sat(q - down) < rearm iff
    // q < rearm + down, rearm > 0).
    // Saturation is decided by constant comparisons of charge_q (q + up > full iff
    // q >= full - up + 1; q - down < 0 iff q < down), in parallel with the adders,
    // rather than by their carry out.
    wire [${QB1}:0] sum          = charge_q + ${UPL};
    wire [${QB1}:0] diff         = charge_q - ${DOWNL};
    wire        up_sat       = ${UP_SAT};
    wire        down_sat     = ${DOWN_SAT};
    wire [${QB1}:0] up_q         = up_sat ? FULL : sum;
    wire [${QB1}:0] down_q       = down_sat ? ${QZERO} : diff;
"#
                .to_string()
                    + DENSITY_THRESHOLDS),
                &[
                    ("UP", up.to_string()),
                    ("DOWN", down.to_string()),
                    ("UPL", lit(qb, up & full)),
                    ("DOWNL", lit(qb, down & full)),
                    ("UP_SAT", ge((full + 1).saturating_sub(up))),
                    ("DOWN_SAT", lt(down)),
                    ("UP_FIRES", ge(fire.saturating_sub(up))),
                    ("DOWN_FIRES", ge(fire + down)),
                    (
                        "UP_REARMS",
                        if up >= rearm {
                            "1'b0".into()
                        } else {
                            lt(rearm - up)
                        },
                    ),
                    (
                        "DOWN_REARMS",
                        if rearm == 0 {
                            "1'b0".into()
                        } else {
                            lt(rearm + down)
                        },
                    ),
                    ("UP0", lit(qb, up.min(full))),
                    ("UP0_FIRES", bool_lit(up.min(full) >= fire)),
                    ("UP0_REARMS", bool_lit(up.min(full) < rearm)),
                    ("DOWN0_REARMS", bool_lit(0 < rearm)),
                ],
            )
        }
        ChargeLaw::Exponential {
            charge_shift,
            discharge_shift,
        } => {
            let shifted = |x: &str, sh: u8| -> String {
                let sh = u32::from(sh);
                if sh == 0 {
                    x.to_string()
                } else if sh >= qb {
                    lit(qb, 0)
                } else {
                    format!("({x} >> {sh})")
                }
            };
            let exp_step = |d: u64, sh: u8| -> u64 {
                if d == 0 {
                    0
                } else {
                    (d >> sh.min(63)).max(1)
                }
            };
            let up0 = exp_step(full, charge_shift);
            let cmp = |x: &str, op: &str, c: u64| -> String {
                if op == ">=" {
                    ge_const(x, qb, c)
                } else {
                    lt_const(x, qb, c)
                }
            };
            fill(
                &(r#"    // Exponential law: +max(1, (full - q) >> ${CS}) per contact pulse,
    // -max(1, q >> ${DS}) per pulse without; a zero distance steps by 0.
    wire [${QB1}:0] room         = FULL - charge_q;
    wire [${QB1}:0] room_shift   = ${ROOM_SHIFT};
    wire [${QB1}:0] q_shift      = ${Q_SHIFT};
    wire [${QB1}:0] step_up      = (room == ${QZERO}) ? ${QZERO} :
                               (room_shift == ${QZERO}) ? ${QONE} : room_shift;
    wire [${QB1}:0] step_down    = (charge_q == ${QZERO}) ? ${QZERO} :
                               (q_shift == ${QZERO}) ? ${QONE} : q_shift;
    wire [${QB1}:0] up_q         = charge_q + step_up;
    wire [${QB1}:0] down_q       = charge_q - step_down;
"#
                .to_string()
                    + DENSITY_THRESHOLDS),
                &[
                    ("CS", charge_shift.to_string()),
                    ("DS", discharge_shift.to_string()),
                    ("ROOM_SHIFT", shifted("room", charge_shift)),
                    ("Q_SHIFT", shifted("charge_q", discharge_shift)),
                    ("UP_FIRES", cmp("up_q", ">=", fire)),
                    ("DOWN_FIRES", cmp("down_q", ">=", fire)),
                    ("UP_REARMS", cmp("up_q", "<", rearm)),
                    ("DOWN_REARMS", cmp("down_q", "<", rearm)),
                    ("UP0", lit(qb, up0)),
                    ("UP0_FIRES", bool_lit(up0 >= fire)),
                    ("UP0_REARMS", bool_lit(up0 < rearm)),
                    ("DOWN0_REARMS", bool_lit(0 < rearm)),
                ],
            )
        }
    }
}

/// The detector's module head: ports, state registers.
const DETECTOR_HEAD: &str = r#"// Device 2, the contact-density detector (docs/domain.md §2.4): a digital capacitor of
// ${QB} bits (UQ0.${QB} of full scale) updated once per FES pulse; fires when armed and the
// charge reaches ${FIRE}, re-arms below ${REARM}. Same-clock order: clear (arm) -> pulse.
// The next charge and both threshold tests are computed from charge_q alone and from an
// empty capacitor, then selected by the clock's clear / pulse / contact bit.
module tt_density_detector (
    input  wire        clk,
    input  wire        rst,
    input  wire        clear,        // arm rising edge: empty and re-arm
    input  wire        pulse,        // FES pulse while armed
    input  wire        contact_bit,  // the pulse's contact bit
${THRESHOLD_PORTS}    output wire [${QB1}:0] charge,       // LSBs of full scale
    output wire        armed,        // hysteresis state: ready to fire
    output wire        fired,        // fired since the last clear
    output wire        fire          // this clock's pulse fired
);
    localparam [${QB1}:0] FULL = ${FULL};  // 2^charge_bits - 1

    reg [${QB1}:0] charge_q = ${QZERO};
    reg        armed_q  = 1'b1;   // power-on state: empty and armed (DensityDetector::new)
    reg        fired_q  = 1'b0;

"#;

/// The detector's shared tail: clear, pulse update, fire and re-arm.
const DETECTOR_TAIL: &str = r#"
    // reset() on clear, then on_pulse(): new charge, then fire (if armed) or re-arm.
    wire        armed_a  = clear | armed_q;
    wire [${QB1}:0] charge_p = pulse ? (contact_bit ? (clear ? UP_FROM_EMPTY : up_q)
                                                : (clear ? ${QZERO} : down_q))
                                 : (clear ? ${QZERO} : charge_q);
    wire        fires    = contact_bit ? (clear ? UP0_FIRES : up_fires)
                                       : (clear ? 1'b0 : down_fires);
    wire        rearms   = contact_bit ? (clear ? UP0_REARMS : up_rearms)
                                       : (clear ? DOWN0_REARMS : down_rearms);
    assign fire        = pulse && armed_a && fires;
    wire        rearm  = pulse && !armed_a && rearms;

    always @(posedge clk) begin
        if (rst) begin
            charge_q <= ${QZERO};
            armed_q  <= 1'b1;
            fired_q  <= 1'b0;
        end else begin
            charge_q <= charge_p;
            armed_q  <= fire ? 1'b0 : (rearm ? 1'b1 : armed_a);
            fired_q  <= (fired_q && !clear) || fire;
        end
    end

    assign charge = charge_q;
    assign armed  = armed_q;
    assign fired  = fired_q;
endmodule
"#;
