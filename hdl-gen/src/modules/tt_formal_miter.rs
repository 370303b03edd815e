//! `tt_formal_miter.v`: the miter of the formal equivalence proof ([`crate::formal`]): the
//! optimized design ([`crate::TOP`]) and the reference ([`crate::REFERENCE_TOP`]) driven by
//! the same pins and MCU address every clock, with assertions that every output, `irq` and
//! the MCU read data are equal — and the invariants that make the equality provable by
//! induction.
//!
//! Why invariants: a k-induction step starts from *any* state in which the assertions held
//! for k clocks, reachable or not. Without more, the optimized registers that encode
//! something (the edge stage's strobes, the sticky bit as the next pulse reads it, the
//! counter's `reaches`/`exceeds` flags) are unconstrained against the reference, and the
//! step fails at every length. So the miter asserts, and the proof proves, what the
//! generator knows about its own design:
//!
//! - *register correspondence*: each optimized register equals a function of the
//!   reference's registers (e.g. the registered strobe `arm_rise_q` equals the reference's
//!   arm edge `filtered & ~previous` that the next clock acts on; `sticky_c_q` equals
//!   `sticky | contact edge`; `reaches_q` equals `count >= i_def`);
//! - *reachability of the reference*: facts of the model that hold in every reachable
//!   state (`armed` is the previous filtered arm level, the scale phase is the previous
//!   filtered phase, `count <= window_pulses`, a stability counter never above
//!   `glitch_cycles`, the decision latch valid exactly when the configured detector has
//!   decided, …);
//! - *the model's invariants* (`ok_model_*`), proven on the reference: counts never above
//!   `window_pulses`, a disarmed capacitor has fired and holds at least the re-arm charge,
//!   `register_now` once raised holds with its position until the clock that acts on the
//!   next arm rising edge, the position wraps at `scale_bits`, the charge saturates;
//! - *the latency* `3 + glitch_cycles` (`ok_latency_*`): against the pins of the last
//!   `glitch_cycles + 4` clocks kept in the miter (`hist`), the synchronizer holds the last
//!   two, the stability counters count the clocks a level has differed, the armed and
//!   contact outputs follow their pins exactly that many clocks later, and no output changes
//!   but in the clock after a filtered level did.
//!
//! The internal registers are not ports: the miter declares an undriven `probe_*` wire
//! for each, and the proof script connects it to the flattened register
//! (`connect -set probe_x opt.u_edges.arm_rise_q`), listed by [`Miter::probes`]. Every
//! assertion is a named wire `ok_*` ([`Miter::assertions`]), so a failure names what broke.

use crate::design::{Fault, VerilogFile, TOP};
use crate::emit::{fill, lit, pin_index, Context};
use crate::mcu::{MCU_ADDR_BITS, MCU_DATA_BITS};
use crate::modules::tt_frontend_ref::REFERENCE_TOP;
use crate::outputs::output_fields;
use tooltouch_model::measure::config::{ContactRule, DecisionMethod};
use tooltouch_model::measure::frontend::pin;

/// Name of the miter module (and of its file, `tt_formal_miter.v`).
pub const MITER: &str = "tt_formal_miter";

/// The miter: its Verilog, the probes the proof script must connect, and the assertions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Miter {
    /// `tt_formal_miter.v`.
    pub file: VerilogFile,
    /// `(probe wire, flattened source signal)`: `connect -set <probe> <source>` after
    /// `flatten`.
    pub probes: Vec<(String, String)>,
    /// `(ok wire, what it states)`, in the order they are asserted: the outputs first,
    /// then the correspondence, then the reference's reachability invariants.
    pub assertions: Vec<(String, String)>,
}

/// One probe: wire name, width, flattened source.
struct Probe {
    name: String,
    width: u32,
    source: String,
}

fn probe(name: &str, width: u32, source: &str) -> Probe {
    Probe {
        name: format!("probe_{name}"),
        width,
        source: source.to_string(),
    }
}

/// The miter for the design generated with `ctx`'s options (a fault included) against
/// the reference.
pub(crate) fn emit(ctx: &Context) -> Miter {
    let c = &ctx.config;
    let s = c.settings();
    let (cb, rb) = (ctx.count_bits(), u32::from(c.window_rev_bits()));
    let (rpb, ib) = (u32::from(c.rev_pulse_bits()), u32::from(c.fes_idle_bits()));
    let checks = s.checks;
    let most = u64::from(s.pulses_per_rev) + u64::from(checks.pulse_tolerance);
    let timeout = u64::from(checks.fes_timeout_cycles);
    let gb = u32::from(c.glitch_bits());
    let glitch = u64::from(s.glitch_cycles);
    let fields = output_fields(c);
    let n = pin::COUNT as u32;
    let (arm, contact, index, fes, sa, sbp) = (
        pin_index(pin::ARM),
        pin_index(pin::CONTACT),
        pin_index(pin::INDEX),
        pin_index(pin::FES),
        pin_index(pin::SCALE_A),
        pin_index(pin::SCALE_B),
    );

    // Probes of the optimized design (instance `opt`) and of the reference (`ref`).
    let mut probes = vec![
        probe("o_sync1", n, "opt.u_sync.sync1_q"),
        probe("o_sync2", n, "opt.u_sync.sync2_q"),
        probe("o_filtered", n, "opt.filtered"),
        probe("o_arm_rise", 1, "opt.u_edges.arm_rise_q"),
        probe("o_contact_rise", 1, "opt.u_edges.contact_rise_q"),
        probe("o_index_pulse", 1, "opt.u_edges.index_pulse_q"),
        probe("o_fes_rise", 1, "opt.u_edges.fes_rise_q"),
        probe("o_fes_pulse", 1, "opt.u_edges.fes_pulse_q"),
        probe("o_scale_up", 1, "opt.u_edges.scale_up_q"),
        probe("o_scale_down", 1, "opt.u_edges.scale_down_q"),
        probe("o_scale_error", 1, "opt.u_edges.scale_error_q"),
        probe("o_sticky_c", 1, "opt.u_measure.sticky_c_q"),
        probe("o_revs", rb, "opt.u_measure.u_counter.revs_q"),
        probe("o_reached", 1, "opt.u_measure.u_counter.reached_q"),
        probe("r_sync1", n, "ref.sync1_q"),
        probe("r_sync2", n, "ref.sync2_q"),
        probe("r_filtered", n, "ref.filtered_q"),
        probe("r_previous", n, "ref.previous_q"),
        probe("r_armed", 1, "ref.armed_q"),
        probe("r_contact", 1, "ref.contact_q"),
        probe("r_sticky", 1, "ref.sticky_q"),
        probe("r_phase", 2, "ref.phase_q"),
        probe("r_count", cb, "ref.count_q"),
        probe("r_revs", 8, "ref.revs_in_window_q"),
        probe("r_reached", 1, "ref.reached_q"),
        probe("r_density_fired", 1, "ref.density_fired_q"),
        probe("r_first_valid", 1, "ref.first_valid_q"),
        probe("r_first_position", ctx.scale_bits(), "ref.first_position_q"),
        probe("r_decision_valid", 1, "ref.decision_valid_q"),
        probe(
            "r_decision_position",
            ctx.scale_bits(),
            "ref.decision_position_q",
        ),
        probe("o_faults", 7, "opt.u_measure.u_checks.faults_q"),
        probe("o_rev_pulses", rpb, "opt.u_measure.u_checks.rev_q"),
        probe("o_index_seen", 1, "opt.u_measure.u_checks.seen_q"),
        probe("o_idle", ib, "opt.u_measure.u_checks.idle_q"),
        probe("o_confirm_left", 5, "opt.u_measure.u_checks.left_q"),
        probe("r_faults", 7, "ref.faults_q"),
        probe("r_rev_pulses", rpb, "ref.rev_pulses_q"),
        probe("r_index_seen", 1, "ref.index_seen_q"),
        probe("r_since", ib, "ref.since_q"),
        probe("r_confirm_left", 5, "ref.confirm_left_q"),
    ];
    // The fault variant FesBeforeIndex has no reaches/exceeds registers (its counter is
    // written unflattened), so their correspondence is stated only for the others.
    let flat_counter = ctx.fault != Fault::FesBeforeIndex;
    if flat_counter {
        probes.push(probe("o_reaches", 1, "opt.u_measure.u_counter.reaches_q"));
        probes.push(probe("o_exceeds", 1, "opt.u_measure.u_counter.exceeds_q"));
    }
    if glitch > 0 {
        for i in 0..pin::COUNT {
            probes.push(probe(
                &format!("o_stable{i}"),
                gb,
                &format!("opt.u_filter.pin[{i}].stable_q"),
            ));
            probes.push(probe(
                &format!("r_stable{i}"),
                gb,
                &format!("ref.stable{i}_q"),
            ));
        }
    }

    // Assertions: (name, expression, statement).
    let mut asserts: Vec<(String, String, String)> = Vec::new();
    let mut add = |name: &str, expr: String, what: &str| {
        asserts.push((format!("ok_{name}"), expr, what.to_string()));
    };
    for f in &fields {
        add(
            f.name,
            format!("opt_{0} == ref_{0}", f.name),
            &format!("output {} equal", f.name),
        );
    }
    add("irq", "opt_irq == ref_irq".into(), "irq equal");
    add(
        "mcu_rdata",
        "opt_mcu_rdata == ref_mcu_rdata".into(),
        "MCU read data equal at every address",
    );
    // Correspondence.
    add(
        "sync",
        "probe_o_sync1 == probe_r_sync1 && probe_o_sync2 == probe_r_sync2".into(),
        "synchronizer stages equal",
    );
    add(
        "filtered",
        "probe_o_filtered == probe_r_filtered".into(),
        "filtered levels equal",
    );
    if glitch > 0 {
        for i in 0..pin::COUNT {
            add(
                &format!("stable{i}"),
                format!("probe_o_stable{i} == probe_r_stable{i}"),
                &format!("pin {i}'s stability counter equal"),
            );
        }
    }
    add(
        "edges",
        fill(
            "probe_o_arm_rise == rise[${ARM}] && probe_o_contact_rise == rise[${CONTACT}] &&\n\
             \x20       probe_o_index_pulse == (rise[${INDEX}] && probe_r_filtered[${ARM}]) &&\n\
             \x20       probe_o_fes_rise == rise[${FES}] &&\n\
             \x20       probe_o_fes_pulse == (rise[${FES}] && probe_r_filtered[${ARM}]) &&\n\
             \x20       probe_o_scale_up == (step == 2'd1) && probe_o_scale_down == (step == 2'd3) &&\n\
             \x20       probe_o_scale_error == (step == 2'd2)",
            &[
                ("ARM", arm.clone()),
                ("CONTACT", contact.clone()),
                ("INDEX", index.clone()),
                ("FES", fes.clone()),
            ],
        ),
        "the edge stage's registered strobes equal the reference's edges (filtered against \
         previous) that the next clock acts on",
    );
    add(
        "sticky",
        format!("probe_o_sticky_c == (probe_r_sticky || rise[{contact}])"),
        "the optimized sticky bit equals the reference's sticky bit or its pending contact edge",
    );
    add(
        "counter",
        format!(
            "probe_o_revs == probe_r_revs[{}:0] && probe_o_reached == probe_r_reached",
            rb - 1
        ),
        "window revolutions and the counter's decided flag equal",
    );
    if flat_counter {
        add(
            "counter_flags",
            "probe_o_reaches == (probe_r_count >= I_DEF) && probe_o_exceeds == (probe_r_count > I_DEF)"
                .into(),
            "the counter's reaches/exceeds registers equal count >= i_def and count > i_def",
        );
    }
    // The checks: the optimized registers equal the reference's; the FES watchdog's latch
    // is also the reference's latch or its lazy verdict (both latch in every clock, so the
    // lazy verdict adds nothing; stated so that a reference observing only in clocks with
    // edges, as FrontEnd does, would still be covered).
    add(
        "checks",
        fill(
            "probe_o_rev_pulses == probe_r_rev_pulses && probe_o_index_seen == probe_r_index_seen &&\n\
             \x20       probe_o_confirm_left == probe_r_confirm_left &&\n\
             \x20       (probe_o_faults & 7'b1011111) == (probe_r_faults & 7'b1011111) &&\n\
             \x20       probe_o_idle == probe_r_since &&\n\
             \x20       probe_o_faults[5] == (probe_r_faults[5] || (probe_r_armed && ${EXPIRED}))",
            &[(
                "EXPIRED",
                if timeout == 0 {
                    "1'b0".to_string()
                } else {
                    format!("probe_r_since >= {}", lit(ib, timeout))
                },
            )],
        ),
        "the checks' registers equal (the idle count too); the design's latched FES \
         watchdog is the reference's latch or its lazy verdict",
    );
    // Reachability of the reference.
    add(
        "ref_checks",
        format!(
            "probe_r_rev_pulses <= {} && probe_r_since <= {}",
            lit(rpb, most + 1),
            lit(ib, timeout)
        ),
        "reference: the revolution's FES count at most pulses_per_rev + pulse_tolerance + 1, \
         the ticks since the last FES pulse at most fes_timeout_cycles",
    );
    add(
        "ref_levels",
        format!(
            "probe_r_armed == probe_r_previous[{arm}] && probe_r_contact == probe_r_previous[{contact}] &&\n\
             \x20       probe_r_phase == {{probe_r_previous[{sbp}], probe_r_previous[{sa}] ^ probe_r_previous[{sbp}]}}"
        ),
        "reference: armed, contact and the scale phase are those of the previous filtered levels",
    );
    if glitch > 0 {
        for i in 0..pin::COUNT {
            add(
                &format!("ref_stable{i}"),
                format!("probe_r_stable{i} <= GLITCH_CYCLES"),
                &format!("reference: pin {i}'s stability counter at most glitch_cycles"),
            );
        }
    }
    add(
        "ref_count",
        "probe_r_count <= WINDOW_PULSES && probe_r_revs < WINDOW_REVS &&\n\
         \x20       (probe_r_count <= I_DEF || probe_r_reached)"
            .into(),
        "reference: count at most window_pulses, window revolutions below window_revs, a count \
         above i_def has decided",
    );
    let decision = match s.method {
        DecisionMethod::Counter => (
            "probe_r_decision_valid == probe_r_reached",
            "reference: the decision latch is valid exactly when the counter has decided",
        ),
        DecisionMethod::Density => (
            "probe_r_decision_valid == probe_r_density_fired",
            "reference: the decision latch is valid exactly when the capacitor has fired",
        ),
        DecisionMethod::SinglePulse => (
            "probe_r_decision_valid == probe_r_first_valid &&\n\
             \x20       probe_r_decision_position == probe_r_first_position",
            "reference: the decision latch holds the first-contact latch",
        ),
    };
    add("ref_decision", decision.0.to_string(), decision.1);
    // The model's own invariants, proven on the reference (and so, by the equalities
    // above, on the design).
    add(
        "model_counts",
        "ref_count <= WINDOW_PULSES && ref_last_window_count <= WINDOW_PULSES".into(),
        "model: count and last window count never above window_pulses (saturation)",
    );
    add(
        "model_hysteresis",
        "ref_density_armed || (ref_density_fired && ref_charge >= REARM_THRESHOLD)".into(),
        "model: a disarmed capacitor has fired and holds at least the re-arm charge",
    );
    add(
        "model_decision_holds",
        "!held_register_now || held_arm_rise ||\n\
         \x20       (ref_register_now && ref_decision_position == held_decision_position)"
            .into(),
        "model: register_now, once raised, stays raised with the same decision position until \
         the clock that acts on the next arm rising edge",
    );

    // The model's invariants on the arithmetic: the position wraps at scale_bits, the
    // charge saturates in its register instead of wrapping.
    add(
        "model_position",
        "!held_valid || ref_position == held_position + held_position_step".into(),
        "model: the position moves by the scale step of the clock before, modulo 2^scale_bits",
    );
    add(
        "model_charge",
        "!held_valid ||\n\
         \x20       (held_counted_pulse ? (held_pulse_bit ? ref_charge >= held_charge_base\n\
         \x20                                             : ref_charge <= held_charge_base)\n\
         \x20                           : ref_charge == held_charge_base)"
            .into(),
        "model: the charge changes only on a counted FES pulse (from 0 after an arm rising edge), \
         up with contact and down without, saturating in its register instead of wrapping",
    );
    // Latency: pin levels `glitch_cycles + 1` clocks long pass the filter, and the outputs
    // follow one clock later, `3 + glitch_cycles` clocks after the pin was sampled.
    let pin_runs: Vec<String> = (0..pin::COUNT)
        .map(|i| {
            let stable = if glitch > 0 {
                format!("probe_r_stable{i}")
            } else {
                "0".to_string()
            };
            format!("filter_run{i}[{stable}] && !filter_run{i}[{stable} + 1]")
        })
        .collect();
    add(
        "latency_sync",
        "probe_r_sync1 == tap1 && probe_r_sync2 == tap2".into(),
        "latency: the synchronizer holds the pins of the last two clocks",
    );
    add(
        "latency_filter",
        pin_runs.join(" &&\n        "),
        "latency: each stability counter counts the clocks the synchronized level has differed \
         from the filtered one, and no level has differed for glitch_cycles + 1 clocks (it would \
         have passed)",
    );
    add(
        "latency_levels",
        "!armed_differs[GLITCH_CYCLES + 1] && !contact_differs[GLITCH_CYCLES + 1] &&\n\
         \x20       (!held_valid || (ref_armed == held_armed || armed_same[GLITCH_CYCLES + 1]) &&\n\
         \x20                       (ref_contact == held_contact || contact_same[GLITCH_CYCLES + 1]))"
            .into(),
        "latency: the armed and contact outputs show the arm and contact pin levels sampled \
         3 + glitch_cycles clocks before once held glitch_cycles + 1 clocks, and change only then",
    );
    add(
        "latency_outputs",
        "!held_valid || held_outputs == outputs_now || held_edge".into(),
        "latency: an output changes only in the clock after a filtered level changed (never \
         before 3 + glitch_cycles clocks from a pin); the FES watchdog's fault bit, which \
         rises with time, excepted",
    );

    let mut decls = String::new();
    for p in &probes {
        let range = if p.width == 1 {
            String::new()
        } else {
            format!("[{}:0] ", p.width - 1)
        };
        decls.push_str(&format!("    wire {range}{};  // = {}\n", p.name, p.source));
    }
    let mut out_decls = String::new();
    let mut opt_conns = String::new();
    let mut ref_conns = String::new();
    for f in &fields {
        let range = if f.width == 1 {
            String::new()
        } else {
            format!("[{}:0] ", f.width - 1)
        };
        out_decls.push_str(&format!(
            "    wire {range}opt_{0};\n    wire {range}ref_{0};\n",
            f.name
        ));
        opt_conns.push_str(&format!(", .{0}(opt_{0})", f.name));
        ref_conns.push_str(&format!(", .{0}(ref_{0})", f.name));
    }
    let pin_conns: String = pin::NAMES
        .iter()
        .enumerate()
        .map(|(i, name)| format!(".pin_{name}(pins[{i}]), "))
        .collect();
    let mut ok_decls = String::new();
    let mut ok_asserts = String::new();
    for (name, expr, what) in &asserts {
        ok_decls.push_str(&format!("    // {what}\n    wire {name} = {expr};\n"));
        ok_asserts.push_str(&format!("        assert ({name});\n"));
    }
    let body = fill(
        r#"// Miter of the formal equivalence proof: ${TOP} (instance opt) and ${REF} (instance
// ref) on the same pins and MCU address every clock. Every output, irq and the MCU read
// data must be equal; the register-correspondence and reachability invariants below make
// that provable by induction. The probe_* wires are connected by the proof script to
// the flattened registers they name (connect -set), after `flatten`.
module ${MITER} (
    input  wire         clk,
    input  wire         rst,
    input  wire [${N1}:0]  pins,       // bit order of tooltouch_model::measure::frontend::pin
    input  wire [${AB1}:0]  mcu_addr
);
    localparam [${CB1}:0] WINDOW_PULSES = ${WP};
    localparam [${CB1}:0] I_DEF         = ${IDEF};
    localparam [7:0]  WINDOW_REVS   = ${WR};
    localparam [${GB1}:0] GLITCH_CYCLES = ${GLITCH};
    localparam [${QB1}:0] REARM_THRESHOLD = ${REARM};

${OUT_DECLS}    wire [${DB1}:0] opt_mcu_rdata;
    wire [${DB1}:0] ref_mcu_rdata;
    wire        opt_irq;
    wire        ref_irq;

    ${TOP} opt (
        .clk(clk), .rst(rst), ${PIN_CONNS}.mcu_addr(mcu_addr),
        .mcu_rdata(opt_mcu_rdata), .irq(opt_irq)${OPT_CONNS}
    );
    ${REF} ref (
        .clk(clk), .rst(rst), ${PIN_CONNS}.mcu_addr(mcu_addr),
        .mcu_rdata(ref_mcu_rdata), .irq(ref_irq)${REF_CONNS}
    );

    // Internal registers, connected by the proof script.
${DECLS}
    // The reference's edges that the next clock acts on, and its scale step.
    wire [${N1}:0] rise = probe_r_filtered & ~probe_r_previous;
    wire [1:0] step = {probe_r_filtered[${SBP}], probe_r_filtered[${SA}] ^ probe_r_filtered[${SBP}]} -
                      {probe_r_previous[${SBP}], probe_r_previous[${SA}] ^ probe_r_previous[${SBP}]};

    // The reference's decision and arm edge one clock earlier (model_decision_holds).
    reg         held_register_now = 1'b0;
    reg         held_arm_rise     = 1'b0;
    reg [${SB1}:0] held_decision_position = ${SZERO};
    always @(posedge clk) begin
        held_register_now      <= ref_register_now && !rst;  // a reset restarts it
        held_arm_rise          <= rise[${ARM}];
        held_decision_position <= ref_decision_position;
    end

${LATENCY}
${OK_DECLS}
    always @* begin
${OK_ASSERTS}    end
endmodule
"#,
        &[
            ("TOP", TOP.to_string()),
            ("REF", REFERENCE_TOP.to_string()),
            ("MITER", MITER.to_string()),
            ("N1", (n - 1).to_string()),
            ("AB1", (MCU_ADDR_BITS - 1).to_string()),
            ("DB1", (MCU_DATA_BITS - 1).to_string()),
            ("CB1", (cb - 1).to_string()),
            ("WP", lit(cb, c.window_pulses().into())),
            ("IDEF", lit(cb, s.i_def.into())),
            ("WR", lit(8, s.window_revs.into())),
            ("GB1", (gb - 1).to_string()),
            ("GLITCH", lit(gb, glitch)),
            ("QB1", (ctx.charge_bits() - 1).to_string()),
            ("REARM", lit(ctx.charge_bits(), s.rearm_threshold.into())),
            ("SB1", (ctx.scale_bits() - 1).to_string()),
            ("SZERO", lit(ctx.scale_bits(), 0)),
            ("ARM", arm.clone()),
            ("OUT_DECLS", out_decls),
            ("PIN_CONNS", pin_conns),
            ("OPT_CONNS", opt_conns),
            ("REF_CONNS", ref_conns),
            ("DECLS", decls),
            ("SA", sa),
            ("SBP", sbp),
            ("OK_DECLS", ok_decls),
            ("LATENCY", history(ctx, &fields)),
            ("OK_ASSERTS", ok_asserts),
        ],
    );
    Miter {
        file: ctx.file(MITER, "miter of the formal equivalence proof", &body),
        probes: probes.into_iter().map(|p| (p.name, p.source)).collect(),
        assertions: asserts
            .into_iter()
            .map(|(name, _, what)| (name, what))
            .collect(),
    }
}

/// The miter's record of the past for the latency and arithmetic properties: the pins of
/// the last `glitch_cycles + 4` clocks (`hist`, tap `j` = the pins `j` clocks before, as
/// if every pin had been low before power-on and `rst`), the runs of clocks a tap has
/// differed from (or equalled) a level, and the previous clock's outputs, edges, position
/// step and charge (`held_*`, checked only when `held_valid`).
fn history(ctx: &Context, fields: &[crate::outputs::OutputField]) -> String {
    let c = &ctx.config;
    let s = c.settings();
    let n = pin::COUNT as u32;
    let glitch = u32::from(s.glitch_cycles);
    let depth = glitch + 4;
    let (arm, contact, fes) = (
        pin_index(pin::ARM),
        pin_index(pin::CONTACT),
        pin_index(pin::FES),
    );
    // A run `name[j]`: taps `first .. first + j - 1` all `op` the level `against`.
    let run = |name: &str, first: u32, bit: &str, op: &str, against: &str| {
        fill(
            "    wire [${LEN}:0] ${NAME};\n\
             \x20   assign ${NAME}[0] = 1'b1;\n\
             \x20   generate for (gj = 1; gj <= ${LEN}; gj = gj + 1) begin : g_${NAME}\n\
             \x20       assign ${NAME}[gj] = ${NAME}[gj - 1] && (hist[${N} * (gj + ${OFF}) + ${BIT}] ${OP} ${AGAINST});\n\
             \x20   end endgenerate\n",
            &[
                ("LEN", (glitch + 1).to_string()),
                ("NAME", name.to_string()),
                ("N", n.to_string()),
                ("OFF", (first - 2).to_string()),
                ("BIT", bit.to_string()),
                ("OP", op.to_string()),
                ("AGAINST", against.to_string()),
            ],
        )
    };
    let mut runs = String::new();
    for i in 0..pin::COUNT {
        runs.push_str(&run(
            &format!("filter_run{i}"),
            3,
            &i.to_string(),
            "!=",
            &format!("probe_r_filtered[{i}]"),
        ));
    }
    for (level, bit) in [("armed", &arm), ("contact", &contact)] {
        runs.push_str(&run(
            &format!("{level}_differs"),
            4,
            bit,
            "!=",
            &format!("ref_{level}"),
        ));
        runs.push_str(&run(
            &format!("{level}_same"),
            4,
            bit,
            "==",
            &format!("ref_{level}"),
        ));
    }
    let outputs_width: u32 = fields.iter().map(|f| f.width).sum();
    // The FES watchdog's bit rises with time alone: masked out of the outputs compared.
    let outputs_now: Vec<String> = fields
        .iter()
        .map(|f| {
            if f.name == "faults" {
                "(ref_faults & 7'b1011111)".to_string()
            } else {
                format!("ref_{}", f.name)
            }
        })
        .collect();
    let pulse_bit = match s.contact_rule {
        ContactRule::Sampled => format!("probe_r_filtered[{contact}]"),
        ContactRule::Sticky => format!("probe_r_sticky || rise[{contact}]"),
    };
    let (sb, qb) = (ctx.scale_bits(), ctx.charge_bits());
    fill(
        r#"    // The pins of the last ${DEPTH} clocks: tap j (bits [${N}j-1:${N}(j-1)]) = the pins j clocks
    // before; power-on and rst read as pins low for ever.
    reg [${HB1}:0] hist = ${HZERO};
    always @(posedge clk) hist <= rst ? ${HZERO} : {hist[${HB1M}:0], pins};
    wire [${N1}:0] tap1 = hist[${N1}:0];
    wire [${N1}:0] tap2 = hist[${N2M}:${N}];

    // Runs: name[j] = taps first .. first + j - 1 all differ from (or equal) a level.
    genvar gj;
${RUNS}
    // The previous clock, for the properties that relate two clocks; held_valid is low
    // after power-on and after rst.
    wire [${OW1}:0] outputs_now = {${OUTPUTS_NOW}};
    reg         held_valid         = 1'b0;
    reg [${OW1}:0] held_outputs       = ${OWZERO};
    reg         held_edge          = 1'b0;
    reg         held_armed         = 1'b0;
    reg         held_contact       = 1'b0;
    reg [${SB1}:0] held_position      = ${SZERO};
    reg [${SB1}:0] held_position_step = ${SZERO};
    reg [${QB1}:0] held_charge_base   = ${QZERO};
    reg         held_counted_pulse = 1'b0;
    reg         held_pulse_bit     = 1'b0;
    always @(posedge clk) begin
        held_valid         <= !rst;
        held_outputs       <= outputs_now;
        held_edge          <= probe_r_filtered != probe_r_previous;
        held_armed         <= ref_armed;
        held_contact       <= ref_contact;
        held_position      <= ref_position;
        held_position_step <= (step == 2'd1) ? ${SONE} : (step == 2'd3) ? ${SMINUS} : ${SZERO};
        held_charge_base   <= rise[${ARM}] ? ${QZERO} : ref_charge;   // an arm rising edge resets
        held_counted_pulse <= rise[${FES}] && probe_r_filtered[${ARM}];
        held_pulse_bit     <= ${PULSE_BIT};
    end
"#,
        &[
            ("DEPTH", depth.to_string()),
            ("N", n.to_string()),
            ("N1", (n - 1).to_string()),
            ("N2M", (2 * n - 1).to_string()),
            ("HB1", (n * depth - 1).to_string()),
            ("HB1M", (n * depth - n - 1).to_string()),
            ("HZERO", lit(n * depth, 0)),
            ("RUNS", runs),
            ("OW1", (outputs_width - 1).to_string()),
            ("OWZERO", lit(outputs_width, 0)),
            ("OUTPUTS_NOW", outputs_now.join(", ")),
            ("SB1", (sb - 1).to_string()),
            ("SZERO", lit(sb, 0)),
            ("SONE", lit(sb, 1)),
            ("SMINUS", lit(sb, crate::outputs::mask(sb))),
            ("QB1", (qb - 1).to_string()),
            ("QZERO", lit(qb, 0)),
            ("ARM", arm),
            ("FES", fes),
            ("PULSE_BIT", pulse_bit),
        ],
    )
}
