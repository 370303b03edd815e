//! `tt_frontend_ref.v`: the *reference* front end, written straight from the model's
//! semantics rather than for speed: one register per state field of
//! `tooltouch_model::FrontEnd` (and of the `Measurement` kernel and its blocks inside it),
//! and one `always @*` block that computes the next state by the model's own sequence of
//! statements — the edges `filtered ^ previous` of this clock, the events in canonical
//! order (arm → contact → index → FES → scale) as the methods `on_arm`, `on_contact`,
//! `on_index`, `on_fes`, `on_ab` write them (comparisons as the model writes them, `count
//! < window_pulses`, `charge >= fire_threshold`, …), then the glitch filter and the
//! synchronizers. No early decoding, no flattened decision, no bit-logic thresholds.
//!
//! It exists to be the other side of the formal equivalence proof ([`crate::formal`]):
//! the optimized `tt_frontend` must equal it on every input sequence. It has the same
//! ports as `tt_frontend`, so the co-simulation can run it against the model exactly as
//! it runs the optimized design (`tests/hdl/reference.rs`). The module name is the
//! caller's: `tt_frontend` when it stands in for the design in the testbench,
//! [`REFERENCE_TOP`] beside the design in the miter. Faults are never injected here.

use crate::design::{Options, VerilogFile};
use crate::emit::{fill, lit, pin_index, Context};
use crate::mcu::{MCU_ADDR_BITS, MCU_DATA_BITS};
use crate::outputs::output_fields;
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::MeasureConfig;

/// Module name of the reference beside the optimized design (in the formal miter).
pub const REFERENCE_TOP: &str = "tt_frontend_ref";

/// The reference front end for `config` as module `module` (file `<module>.v`); only
/// [`Options::mcu_diagnostics`] is read from `options` (no fault is ever injected).
pub fn reference(config: &MeasureConfig, options: &Options, module: &str) -> VerilogFile {
    let clean = Options {
        fault: crate::design::Fault::None,
        ..*options
    };
    let ctx = Context::new(config, &clean);
    emit(&ctx, module)
}

/// The next charge of `DensityDetector::next_charge` for a contact (`up`) or a pulse
/// without (`down`), as Verilog statements assigning `charge_n` from `charge_n`.
fn charge_law(ctx: &Context) -> (String, String) {
    let qb = ctx.charge_bits();
    match ctx.config.settings().charge_law {
        ChargeLaw::Linear {
            charge_step,
            discharge_step,
        } => (
            // q.wrapping_add(charge_step).min(full): q + step < 2^(qb+1), no wrap.
            fill(
                "wide = {1'b0, charge_n} + ${UP};\n\
                 \x20               charge_n = (wide > {1'b0, FULL}) ? FULL : wide[${QB1}:0];",
                &[
                    ("UP", lit(qb + 1, charge_step.into())),
                    ("QB1", (qb - 1).to_string()),
                ],
            ),
            // q.saturating_sub(discharge_step).
            fill(
                "wide = {1'b0, charge_n};\n\
                 \x20               charge_n = (wide >= ${DOWN}) ? charge_n - ${DOWNQ} : ${QZERO};",
                &[
                    ("DOWN", lit(qb + 1, discharge_step.into())),
                    ("DOWNQ", lit(qb, discharge_step.into())),
                    ("QZERO", lit(qb, 0)),
                ],
            ),
        ),
        ChargeLaw::Exponential {
            charge_shift,
            discharge_shift,
        } => {
            // exp_step(d, shift) = 0 if d = 0, else max(1, d >> shift).
            let step = |d: &str, shift: u8| {
                fill(
                    "distance = ${D};\n\
                     \x20               shifted = distance >> ${SH};\n\
                     \x20               if (distance == ${QZERO})\n\
                     \x20                   step = ${QZERO};\n\
                     \x20               else if (shifted == ${QZERO})\n\
                     \x20                   step = ${QONE};\n\
                     \x20               else\n\
                     \x20                   step = shifted;",
                    &[
                        ("D", d.to_string()),
                        ("SH", shift.to_string()),
                        ("QZERO", lit(qb, 0)),
                        ("QONE", lit(qb, 1)),
                    ],
                )
            };
            (
                step("FULL - charge_n", charge_shift)
                    + "\n                charge_n = charge_n + step;",
                step("charge_n", discharge_shift) + "\n                charge_n = charge_n - step;",
            )
        }
    }
}

/// The fault bits the configuration enables (model: `MeasurementChecks::new`).
fn enabled_faults(config: &MeasureConfig) -> u8 {
    use tooltouch_model::fault;
    let k = config.settings().checks;
    [
        (k.contact_at_arm, fault::CONTACT_AT_ARM),
        (k.revolutions, fault::PULSES_LOST | fault::INDEX_MISSING),
        (k.scale_errors, fault::SCALE_ERROR),
        (k.probe_revs != 0, fault::NO_DECISION),
        (k.fes_timeout_cycles != 0, fault::FES_TIMEOUT),
        (k.confirm_windows != 0, fault::UNCONFIRMED),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .fold(0, |bits, (_, bit)| bits | bit)
}

fn emit(ctx: &Context, module: &str) -> VerilogFile {
    let c = &ctx.config;
    let s = c.settings();
    let (sb, cb, qb) = (ctx.scale_bits(), ctx.count_bits(), ctx.charge_bits());
    let gb = u32::from(c.glitch_bits());
    let k = s.checks;
    let (rpb, ib) = (u32::from(c.rev_pulse_bits()), u32::from(c.fes_idle_bits()));
    let (ppr, tolerance) = (u32::from(s.pulses_per_rev), u32::from(k.pulse_tolerance));
    let fields = output_fields(c);
    let mut ports = String::new();
    for f in &fields {
        let range = if f.width == 1 {
            "      ".to_string()
        } else {
            format!("[{}:0]", f.width - 1)
        };
        ports.push_str(&format!("    output wire {range:<7} {},\n", f.name));
    }
    let pin_ports: String = pin::NAMES
        .iter()
        .map(|n| format!("    input  wire         pin_{n},\n"))
        .collect();
    let pins: Vec<String> = pin::NAMES
        .iter()
        .rev()
        .map(|n| format!("pin_{n}"))
        .collect();
    let mcu_read_mux = crate::mcu::mcu_read_mux(&ctx.config, ctx.hash, ctx.mcu_diagnostics);
    let bit = match s.contact_rule {
        ContactRule::Sampled => "contact_n",
        ContactRule::Sticky => "sticky_n",
    };
    let (method_counter, method_density, method_single) = (
        s.method == DecisionMethod::Counter,
        s.method == DecisionMethod::Density,
        s.method == DecisionMethod::SinglePulse,
    );
    let (charge_up, charge_down) = charge_law(ctx);
    let stable_regs: String = (0..pin::COUNT)
        .map(|i| format!("    reg [{}:0] stable{i}_q = {};\n", gb - 1, lit(gb, 0)))
        .collect();
    let stable_n: String = (0..pin::COUNT)
        .map(|i| format!("    reg [{}:0] stable{i}_n;\n", gb - 1))
        .collect();
    let stable_copy: String = (0..pin::COUNT)
        .map(|i| format!("        stable{i}_n = stable{i}_q;\n"))
        .collect();
    let filter_steps: String = (0..pin::COUNT)
        .map(|i| {
            fill(
                "        if (!differ[${I}])\n\
                 \x20           stable${I}_n = ${GZERO};\n\
                 \x20       else if (stable${I}_n >= GLITCH_CYCLES) begin\n\
                 \x20           filtered_n[${I}] = !filtered_n[${I}];\n\
                 \x20           stable${I}_n = ${GZERO};\n\
                 \x20       end else\n\
                 \x20           stable${I}_n = stable${I}_n + ${GONE};\n",
                &[
                    ("I", i.to_string()),
                    ("GZERO", lit(gb, 0)),
                    ("GONE", lit(gb, 1)),
                ],
            )
        })
        .collect();
    let stable_reset: String = (0..pin::COUNT)
        .map(|i| format!("            stable{i}_q <= {};\n", lit(gb, 0)))
        .collect();
    let stable_update: String = (0..pin::COUNT)
        .map(|i| format!("            stable{i}_q <= stable{i}_n;\n"))
        .collect();
    let body = fill(
        r#"// Reference front end, written from the model's semantics (FrontEnd::clock): one
// register per model state field, next state computed by the model's statements in the
// model's order. Slow but plain; the formal proof shows tt_frontend equal to it.
module ${MODULE} (
    input  wire         clk,
    input  wire         rst,       // synchronous reset to the power-on state
${PIN_PORTS}    input  wire [${AB1}:0]  mcu_addr,
    output reg  [${DB1}:0] mcu_rdata,
${PORTS}    output wire         irq        // = register_now, for the MCU
);
    localparam [${GB1}:0] GLITCH_CYCLES   = ${GLITCH};
    localparam [${CB1}:0] WINDOW_PULSES   = ${WP};
    localparam [${CB1}:0] I_DEF           = ${IDEF};
    localparam [7:0]  WINDOW_REVS     = ${WR};
    localparam [${QB1}:0] FULL            = ${FULL};
    localparam [${QB1}:0] FIRE_THRESHOLD  = ${FIRE};
    localparam [${QB1}:0] REARM_THRESHOLD = ${REARM};
    // MeasurementChecks (fault bits: tooltouch_model::fault)
    localparam [6:0]  FAULTS_ENABLED  = 7'b${ENABLED};
    localparam [6:0]  CONTACT_AT_ARM  = 7'd1;
    localparam [6:0]  PULSES_LOST     = 7'd2;
    localparam [6:0]  INDEX_MISSING   = 7'd4;
    localparam [6:0]  SCALE_ERROR     = 7'd8;
    localparam [6:0]  NO_DECISION     = 7'd16;
    localparam [6:0]  FES_TIMEOUT_BIT = 7'd32;
    localparam [6:0]  UNCONFIRMED     = 7'd64;
    localparam [${RPB1}:0] FEWEST          = ${FEWEST};
    localparam [${RPB1}:0] MOST            = ${MOST};
    localparam [15:0] PROBE_REVS      = ${PROBE};
    localparam [${IB1}:0] FES_TIMEOUT     = ${TIMEOUT};
    localparam [4:0]  CONFIRM_WINDOWS = ${WINDOWS};
    localparam [${CB1}:0] CONFIRM_COUNT   = ${CONFIRM};

    wire [${N1}:0] pins = {${PINS}};

    // FrontEnd
    reg [${N1}:0] sync1_q    = ${NZERO};
    reg [${N1}:0] sync2_q    = ${NZERO};
    reg [${N1}:0] filtered_q = ${NZERO};
    reg [${N1}:0] previous_q = ${NZERO};
${STABLE_REGS}    // Measurement
    reg        armed_q       = 1'b0;
    reg        contact_q     = 1'b0;
    reg        sticky_q      = 1'b0;
    reg [15:0] revolutions_q = 16'd0;
    reg [31:0] pulses_q      = 32'd0;
    // PulseCounter
    reg [${CB1}:0] count_q          = ${CZERO};
    reg [${CB1}:0] lwc_q            = ${CZERO};
    reg [7:0]  revs_in_window_q = 8'd0;
    reg        reached_q        = 1'b0;
    // DensityDetector
    reg [${QB1}:0] charge_q        = ${QZERO};
    reg        density_armed_q = 1'b1;
    reg        density_fired_q = 1'b0;
    // QuadratureDecoder
    reg [1:0]  phase_q        = 2'd0;
    reg [${SB1}:0] position_q     = ${SZERO};
    reg [7:0]  scale_errors_q = 8'd0;
    // PositionLatch first_contact, decision
    reg        first_valid_q    = 1'b0;
    reg [${SB1}:0] first_position_q = ${SZERO};
    reg        decision_valid_q    = 1'b0;
    reg [${SB1}:0] decision_position_q = ${SZERO};
    // MeasurementChecks; `since` is the model's `now - fes_at` (ticks since the last FES
    // pulse or the arm), kept saturating at FES_TIMEOUT: only its comparison with it is read.
    reg [6:0]  faults_q       = 7'd0;
    reg [${RPB1}:0] rev_pulses_q   = ${RZERO};
    reg        index_seen_q   = 1'b0;
    reg [${IB1}:0] since_q        = ${IZERO};
    reg [4:0]  confirm_left_q = 5'd0;
    reg        confirmed_q    = 1'b0;

    // Next state: FrontEnd::clock, statement by statement.
    reg [${N1}:0] changed, levels, differ, filtered_n;
${STABLE_N}    reg        armed_n, contact_n, sticky_n, pulse_bit;
    reg [15:0] revolutions_n;
    reg [31:0] pulses_n;
    reg [${CB1}:0] count_n, lwc_n;
    reg [7:0]  revs_in_window_n;
    reg        reached_n, counter_decides, density_decides;
    reg [${QB1}:0] charge_n;
    reg        density_armed_n, density_fired_n;
    reg [1:0]  phase_n, new_phase;
    reg [${SB1}:0] position_n;
    reg [7:0]  scale_errors_n;
    reg        first_valid_n, decision_valid_n;
    reg [${SB1}:0] first_position_n, decision_position_n;
    reg [6:0]  faults_n;
    reg [${RPB1}:0] rev_pulses_n;
    reg [${RPB}:0] rev_wide;
    reg        index_seen_n, confirmed_n, window_closed;
    reg [${IB1}:0] since_n;
    reg [4:0]  confirm_left_n;
    /* verilator lint_off UNUSEDSIGNAL */
    reg [${QB}:0] wide;       // charge arithmetic one bit wider (linear law)
    reg [${QB1}:0] distance, shifted, step;  // exponential law
    /* verilator lint_on UNUSEDSIGNAL */

    // The comparisons are the model's, so some are constant in some configurations
    // (`stable >= 0` without a glitch filter, `charge < 0` with no re-arm threshold).
    /* verilator lint_off UNSIGNED */
    /* verilator lint_off CMPCONST */
    always @* begin
        armed_n = armed_q;
        contact_n = contact_q;
        sticky_n = sticky_q;
        revolutions_n = revolutions_q;
        pulses_n = pulses_q;
        count_n = count_q;
        lwc_n = lwc_q;
        revs_in_window_n = revs_in_window_q;
        reached_n = reached_q;
        charge_n = charge_q;
        density_armed_n = density_armed_q;
        density_fired_n = density_fired_q;
        phase_n = phase_q;
        position_n = position_q;
        scale_errors_n = scale_errors_q;
        first_valid_n = first_valid_q;
        first_position_n = first_position_q;
        decision_valid_n = decision_valid_q;
        decision_position_n = decision_position_q;
        faults_n = faults_q;
        since_n = since_q;
        rev_pulses_n = rev_pulses_q;
        rev_wide = ${RWZERO};
        index_seen_n = index_seen_q;
        confirm_left_n = confirm_left_q;
        confirmed_n = confirmed_q;
        window_closed = 1'b0;
        pulse_bit = 1'b0;
        counter_decides = 1'b0;
        density_decides = 1'b0;
        wide = ${QB1ZERO};
        distance = ${QZERO};
        shifted = ${QZERO};
        step = ${QZERO};
        new_phase = 2'd0;

        // The edges of this clock: the filtered levels against the previous ones.
        changed = filtered_q ^ previous_q;
        levels = filtered_q;

        // The time moves on one tick (FrontEnd::clocks): the ticks since the last FES pulse,
        // counted while armed (only then is the model's `now - fes_at` read; the arm
        // rising edge restarts it).
        if (armed_n)
            since_n = (since_q >= FES_TIMEOUT) ? since_q : since_q + ${IONE};
        // Measurement::observe(now): MeasurementChecks::observe latches the watchdog if it
        // expired while armed. FrontEnd::clock observes in a clock with edges; observing in
        // every clock, as here, gives the same outputs (the latch is set only where the lazy
        // verdict of faults_at already shows it) and the same register as the design's.
        if (armed_n && FES_TIMEOUT != ${IZERO} && since_n >= FES_TIMEOUT)
            faults_n = faults_n | (FES_TIMEOUT_BIT & FAULTS_ENABLED);

        // Measurement::on_arm(level)
        if (changed[${ARM}]) begin
            if (levels[${ARM}] && !armed_n) begin
                // MeasurementChecks::on_arm(contact)
                faults_n = contact_n ? (CONTACT_AT_ARM & FAULTS_ENABLED) : 7'd0;
                rev_pulses_n = ${RZERO};
                index_seen_n = 1'b0;
                since_n = ${IZERO};
                confirm_left_n = 5'd0;
                confirmed_n = 1'b0;
                count_n = ${CZERO};              // PulseCounter::reset
                lwc_n = ${CZERO};
                revs_in_window_n = 8'd0;
                reached_n = 1'b0;
                charge_n = ${QZERO};             // DensityDetector::reset
                density_armed_n = 1'b1;
                density_fired_n = 1'b0;
                first_valid_n = 1'b0;            // PositionLatch::clear
                first_position_n = ${SZERO};
                decision_valid_n = 1'b0;
                decision_position_n = ${SZERO};
                revolutions_n = 16'd0;
                pulses_n = 32'd0;
            end
            armed_n = levels[${ARM}];
        end

        // Measurement::on_contact(level)
        if (changed[${CONTACT}]) begin
            contact_n = levels[${CONTACT}];
            if (levels[${CONTACT}]) begin
                sticky_n = 1'b1;
                if (armed_n) begin
                    if (!first_valid_n) begin
                        first_valid_n = 1'b1;
                        first_position_n = position_n;
                    end
                    if (${SINGLE_PULSE} && !decision_valid_n) begin
                        decision_valid_n = 1'b1;
                        decision_position_n = position_n;
                        // MeasurementChecks::on_decision
                        if (CONFIRM_WINDOWS == 5'd0)
                            confirmed_n = 1'b1;
                        else
                            confirm_left_n = CONFIRM_WINDOWS;
                    end
                end
            end
        end

        // Measurement::on_index (rising edge)
        if (changed[${INDEX}] && levels[${INDEX}]) begin
            if (armed_n) begin
                // PulseCounter::on_index
                if (revs_in_window_n != 8'd255)
                    revs_in_window_n = revs_in_window_n + 8'd1;
                if (revs_in_window_n >= WINDOW_REVS) begin
                    window_closed = 1'b1;
                    lwc_n = count_n;
                    count_n = ${CZERO};
                    revs_in_window_n = 8'd0;
                end
                if (revolutions_n != 16'hffff)
                    revolutions_n = revolutions_n + 16'd1;
                // MeasurementChecks::on_index(closed, last_window_count, decided, revolutions)
                if (index_seen_n && rev_pulses_n < FEWEST)
                    faults_n = faults_n | (PULSES_LOST & FAULTS_ENABLED);
                rev_pulses_n = ${RZERO};
                index_seen_n = 1'b1;
                if (window_closed && confirm_left_n > 5'd0) begin
                    if (lwc_n < CONFIRM_COUNT) begin
                        faults_n = faults_n | (UNCONFIRMED & FAULTS_ENABLED);
                        confirm_left_n = 5'd0;
                    end else begin
                        confirm_left_n = confirm_left_n - 5'd1;
                        confirmed_n = confirm_left_n == 5'd0;
                    end
                end
                if (!decision_valid_n && PROBE_REVS != 16'd0 && revolutions_n >= PROBE_REVS)
                    faults_n = faults_n | (NO_DECISION & FAULTS_ENABLED);
            end
        end

        // Measurement::on_fes (rising edge)
        if (changed[${FES}] && levels[${FES}]) begin
            pulse_bit = ${BIT};
            sticky_n = contact_n;
            if (armed_n) begin
                pulses_n = pulses_n + 32'd1;
                // MeasurementChecks::on_fes(1)
                since_n = ${IZERO};
                rev_wide = {1'b0, rev_pulses_n} + ${RWONE};
                if (rev_wide > {1'b0, MOST}) begin
                    rev_pulses_n = MOST + ${RONE};
                    faults_n = faults_n | (INDEX_MISSING & FAULTS_ENABLED);
                end else
                    rev_pulses_n = rev_wide[${RPB1}:0];
                // PulseCounter::on_pulse(pulse_bit)
                if (pulse_bit && count_n < WINDOW_PULSES) begin
                    count_n = count_n + ${CONE};
                    if (count_n > I_DEF && !reached_n) begin
                        reached_n = 1'b1;
                        counter_decides = ${COUNTER};
                    end
                end
                // DensityDetector::on_pulse(pulse_bit)
                if (pulse_bit) begin
                ${CHARGE_UP}
                end else begin
                ${CHARGE_DOWN}
                end
                if (density_armed_n) begin
                    if (charge_n >= FIRE_THRESHOLD) begin
                        density_armed_n = 1'b0;
                        density_fired_n = 1'b1;
                        density_decides = ${DENSITY};
                    end
                end else if (charge_n < REARM_THRESHOLD)
                    density_armed_n = 1'b1;
                // PositionLatch::capture of the decision
                if ((counter_decides || density_decides) && !decision_valid_n) begin
                    decision_valid_n = 1'b1;
                    decision_position_n = position_n;
                    // MeasurementChecks::on_decision
                    if (CONFIRM_WINDOWS == 5'd0)
                        confirmed_n = 1'b1;
                    else
                        confirm_left_n = CONFIRM_WINDOWS;
                end
            end
        end

        // Measurement::on_scale -> QuadratureDecoder::on_ab
        if (changed[${SA}] || changed[${SB_PIN}]) begin
            // phase_of(a, b): 00 -> 0, 10 -> 1, 11 -> 2, 01 -> 3
            new_phase = {levels[${SB_PIN}], levels[${SA}] ^ levels[${SB_PIN}]};
            case (new_phase - phase_n)
                2'd1: position_n = position_n + ${SONE};
                2'd3: position_n = position_n - ${SONE};
                2'd2: begin
                    if (scale_errors_n != 8'd255) scale_errors_n = scale_errors_n + 8'd1;
                    if (armed_n)  // MeasurementChecks::on_scale_error
                        faults_n = faults_n | (SCALE_ERROR & FAULTS_ENABLED);
                end
                default: ;
            endcase
            phase_n = new_phase;
        end

        // FrontEnd::filter, per pin.
        differ = sync2_q ^ filtered_q;
        filtered_n = filtered_q;
${STABLE_COPY}${FILTER_STEPS}    end
    /* verilator lint_on CMPCONST */
    /* verilator lint_on UNSIGNED */

    always @(posedge clk) begin
        if (rst) begin
            sync1_q <= ${NZERO};
            sync2_q <= ${NZERO};
            filtered_q <= ${NZERO};
            previous_q <= ${NZERO};
${STABLE_RESET}            armed_q <= 1'b0;
            contact_q <= 1'b0;
            sticky_q <= 1'b0;
            revolutions_q <= 16'd0;
            pulses_q <= 32'd0;
            count_q <= ${CZERO};
            lwc_q <= ${CZERO};
            revs_in_window_q <= 8'd0;
            reached_q <= 1'b0;
            charge_q <= ${QZERO};
            density_armed_q <= 1'b1;
            density_fired_q <= 1'b0;
            phase_q <= 2'd0;
            position_q <= ${SZERO};
            scale_errors_q <= 8'd0;
            first_valid_q <= 1'b0;
            first_position_q <= ${SZERO};
            decision_valid_q <= 1'b0;
            decision_position_q <= ${SZERO};
            faults_q <= 7'd0;
            rev_pulses_q <= ${RZERO};
            index_seen_q <= 1'b0;
            since_q <= ${IZERO};
            confirm_left_q <= 5'd0;
            confirmed_q <= 1'b0;
        end else begin
            sync1_q <= pins;
            sync2_q <= sync1_q;
            filtered_q <= filtered_n;
            previous_q <= filtered_q;
${STABLE_UPDATE}            armed_q <= armed_n;
            contact_q <= contact_n;
            sticky_q <= sticky_n;
            revolutions_q <= revolutions_n;
            pulses_q <= pulses_n;
            count_q <= count_n;
            lwc_q <= lwc_n;
            revs_in_window_q <= revs_in_window_n;
            reached_q <= reached_n;
            charge_q <= charge_n;
            density_armed_q <= density_armed_n;
            density_fired_q <= density_fired_n;
            phase_q <= phase_n;
            position_q <= position_n;
            scale_errors_q <= scale_errors_n;
            first_valid_q <= first_valid_n;
            first_position_q <= first_position_n;
            decision_valid_q <= decision_valid_n;
            decision_position_q <= decision_position_n;
            faults_q <= faults_n;
            rev_pulses_q <= rev_pulses_n;
            index_seen_q <= index_seen_n;
            since_q <= since_n;
            confirm_left_q <= confirm_left_n;
            confirmed_q <= confirmed_n;
        end
    end

    // Measurement::outputs
    assign armed                  = armed_q;
    assign contact                = contact_q;
    assign register_now           = decision_valid_q;
    assign decision_position      = decision_position_q;
    assign first_contact          = first_valid_q;
    assign first_contact_position = first_position_q;
    assign position               = position_q;
    assign scale_errors           = scale_errors_q;
    assign count                  = count_q;
    assign last_window_count      = lwc_q;
    assign charge                 = charge_q;
    assign density_armed          = density_armed_q;
    assign density_fired          = density_fired_q;
    assign revolutions            = revolutions_q;
    assign pulses                 = pulses_q;
    assign confirmed              = confirmed_q;
    // MeasurementChecks::faults_at(now, armed): the watchdog shown lazily.
    assign faults                 = faults_q |
        ((armed_q && FES_TIMEOUT != ${IZERO} && since_q >= FES_TIMEOUT) ? (FES_TIMEOUT_BIT & FAULTS_ENABLED) : 7'd0);
    assign irq                    = decision_valid_q;

${MCU_READ_MUX}endmodule
"#,
        &[
            ("MODULE", module.to_string()),
            ("PIN_PORTS", pin_ports),
            ("AB1", (MCU_ADDR_BITS - 1).to_string()),
            ("DB1", (MCU_DATA_BITS - 1).to_string()),
            ("PORTS", ports),
            ("GB1", (gb - 1).to_string()),
            ("GLITCH", lit(gb, s.glitch_cycles.into())),
            ("CB1", (cb - 1).to_string()),
            ("WP", lit(cb, c.window_pulses().into())),
            ("IDEF", lit(cb, s.i_def.into())),
            ("WR", lit(8, s.window_revs.into())),
            ("QB", qb.to_string()),
            ("QB1", (qb - 1).to_string()),
            ("FULL", lit(qb, c.full_charge().into())),
            ("FIRE", lit(qb, s.fire_threshold.into())),
            ("REARM", lit(qb, s.rearm_threshold.into())),
            ("N1", (pin::COUNT - 1).to_string()),
            ("NZERO", lit(pin::COUNT as u32, 0)),
            ("PINS", pins.join(", ")),
            ("STABLE_REGS", stable_regs),
            ("STABLE_N", stable_n),
            ("STABLE_COPY", stable_copy),
            ("FILTER_STEPS", filter_steps),
            ("STABLE_RESET", stable_reset),
            ("STABLE_UPDATE", stable_update),
            ("CZERO", lit(cb, 0)),
            ("CONE", lit(cb, 1)),
            ("QZERO", lit(qb, 0)),
            ("QB1ZERO", lit(qb + 1, 0)),
            ("SB1", (sb - 1).to_string()),
            ("SZERO", lit(sb, 0)),
            ("SONE", lit(sb, 1)),
            ("ARM", pin_index(pin::ARM)),
            ("CONTACT", pin_index(pin::CONTACT)),
            ("INDEX", pin_index(pin::INDEX)),
            ("FES", pin_index(pin::FES)),
            ("SA", pin_index(pin::SCALE_A)),
            ("SB_PIN", pin_index(pin::SCALE_B)),
            ("BIT", bit.to_string()),
            ("SINGLE_PULSE", crate::emit::bool_lit(method_single)),
            ("COUNTER", crate::emit::bool_lit(method_counter)),
            ("DENSITY", crate::emit::bool_lit(method_density)),
            ("CHARGE_UP", charge_up),
            ("CHARGE_DOWN", charge_down),
            ("MCU_READ_MUX", mcu_read_mux),
            ("ENABLED", format!("{:07b}", enabled_faults(c))),
            ("RPB", rpb.to_string()),
            ("RPB1", (rpb - 1).to_string()),
            ("IB1", (ib - 1).to_string()),
            ("FEWEST", lit(rpb, (ppr - tolerance).into())),
            ("MOST", lit(rpb, (ppr + tolerance).into())),
            ("PROBE", lit(16, k.probe_revs.into())),
            ("TIMEOUT", lit(ib, k.fes_timeout_cycles.into())),
            ("WINDOWS", lit(5, k.confirm_windows.into())),
            ("CONFIRM", lit(cb, c.confirm_count().into())),
            ("RZERO", lit(rpb, 0)),
            ("RONE", lit(rpb, 1)),
            ("RWZERO", lit(rpb + 1, 0)),
            ("RWONE", lit(rpb + 1, 1)),
            ("IZERO", lit(ib, 0)),
            ("IONE", lit(ib, 1)),
        ],
    );
    ctx.file(
        module,
        "reference front end written from the model's semantics (formal proof, co-simulation)",
        &body,
    )
}
