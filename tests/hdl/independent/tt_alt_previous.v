// A second independent tt_frontend, written from docs/CONTRACT.md for the formal tests
// (not part of the product), structured unlike the first: glitch filters counting up, the
// edges taken against a register of the previous filtered levels, no phase, armed or
// contact registers (all three are read from the previous levels), the window's
// revolutions counted down. Every configuration
// value is a parameter (set by the test's wrapper); FAULT != 0 injects one single-point
// fault (tests/hdl/formal_dut.rs lists them).
`default_nettype none
module tt_alt_previous #(
    parameter integer GLITCH = 4,        // glitch_cycles
    parameter integer SB = 24,           // scale_bits
    parameter integer CB = 11,           // count bits
    parameter integer QB = 16,           // charge_bits
    parameter integer WINDOW_PULSES = 1024,
    parameter integer I_DEF = 512,
    parameter integer WINDOW_REVS = 1,
    parameter integer FIRE = 32768,
    parameter integer REARM = 8192,
    parameter integer LAW = 0,           // 0 linear (UP/DOWN steps), 1 exponential (UP/DOWN shifts)
    parameter integer UP = 64,
    parameter integer DOWN = 64,
    parameter integer STICKY = 1,        // 1 sticky rule, 0 sampled
    parameter integer METHOD = 1,        // 0 single pulse, 1 counter, 2 density
    parameter integer DIAG = 0,          // MCU diagnostic counters readable
    parameter integer CAA = 1,           // checks.contact_at_arm
    parameter integer REV_CHECK = 1,     // checks.revolutions
    parameter integer PPR = 1024,        // pulses_per_rev
    parameter integer TOL = 2,           // checks.pulse_tolerance
    parameter integer SCALE_CHECK = 1,   // checks.scale_errors
    parameter integer PROBE = 100,       // checks.probe_revs
    parameter integer FES_T = 65536,     // checks.fes_timeout_cycles
    parameter integer CW = 3,            // checks.confirm_windows
    parameter integer CC = 256,          // confirmation level, contact pulses a window
    parameter [63:0] HASH = 64'd0,
    parameter integer FAULT = 0
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          pin_arm, pin_contact, pin_index, pin_fes, pin_scale_a, pin_scale_b,
    input  wire [3:0]    mcu_addr,
    output reg  [31:0]   mcu_rdata,
    output reg           armed,
    output reg           contact,
    output reg           register_now,
    output reg  [SB-1:0] decision_position,
    output reg           first_contact,
    output reg  [SB-1:0] first_contact_position,
    output reg  [SB-1:0] position,
    output reg  [7:0]    scale_errors,
    output reg  [CB-1:0] count,
    output reg  [CB-1:0] last_window_count,
    output reg  [QB-1:0] charge,
    output reg           density_armed,
    output reg           density_fired,
    output reg  [15:0]   revolutions,
    output reg  [31:0]   pulses,
    output reg           confirmed,
    output wire [6:0]    faults,
    output wire          irq
);
    // Fault-shifted constants (FAULT 0: as configured).
    localparam integer G  = GLITCH + (FAULT == 7 ? 1 : 0) - (FAULT == 8 ? 1 : 0);
    localparam integer ID = I_DEF + (FAULT == 1 ? 1 : 0) - (FAULT == 2 ? 1 : 0);
    localparam integer FI = FIRE + (FAULT == 3 ? 1 : 0) - (FAULT == 4 ? 1 : 0);
    localparam integer RE = REARM + (FAULT == 5 ? 1 : 0) - (FAULT == 6 ? 1 : 0);
    localparam integer U  = UP + (FAULT == 9 ? 1 : 0);
    localparam integer D  = DOWN - (FAULT == 10 ? 1 : 0);
    localparam [QB:0] FULL = (1 << QB) - 1;

    wire [5:0] pins = {pin_scale_b, pin_scale_a, pin_fes, pin_index, pin_contact, pin_arm};
    reg [5:0] s1 = 6'd0, s2 = 6'd0, lv = 6'd0, prev = 6'd0;
    wire [5:0] chg = lv ^ prev;
    localparam [8:0] G9 = G;
    reg [53:0] seen = 54'd0;           // clocks each synchronized level has differed
    reg [5:0] lv_n;
    reg       sticky = 1'b0;
    reg       reached = 1'b0;
    localparam [7:0] WR8 = WINDOW_REVS;
    reg [7:0] revs_left = WR8;          // index pulses to the end of the window
    // The status: faults latched since arm (the watchdog's bit only in a clock with edges,
    // shown lazily in between, as the model observes the time), FES pulses since the index
    // counted up to PPR + TOL + 1, windows to confirm counted down.
    reg [6:0]  flt = 7'd0;
    reg [16:0] revp = 17'd0;
    reg        idx_seen = 1'b0;
    reg [32:0] idle = 33'd0;            // ticks since the last FES pulse or arm, while armed
    reg [4:0]  to_confirm = 5'd0;
    localparam [6:0] EN = {CW != 0, FES_T != 0, PROBE != 0, SCALE_CHECK != 0, REV_CHECK != 0,
                           REV_CHECK != 0, CAA != 0};
    localparam [32:0] FT = FES_T;
    integer i;
    initial begin
        confirmed = 1'b0;
        register_now = 1'b0; decision_position = 0;
        first_contact = 1'b0; first_contact_position = 0; position = 0; scale_errors = 8'd0;
        count = 0; last_window_count = 0; charge = 0; density_armed = 1'b1;
        density_fired = 1'b0; revolutions = 16'd0; pulses = 32'd0;
    end

    // Glitch filters: a level passes once it has differed G + 1 clocks in a row.
    always @* begin
        for (i = 0; i < 6; i = i + 1)
            lv_n[i] = (s2[i] != lv[i] && seen[9*i +: 9] >= G9) ? s2[i] : lv[i];
    end
    always @* begin
        armed = prev[0];
        contact = prev[1];
    end

    // The kernel, in the canonical order, on the registered strobes.
    reg          a_armed, a_contact, a_stk, a_reached, a_reg, a_first, a_dens_armed, a_fired;
    reg [SB-1:0] a_dpos, a_fpos, a_pos;
    reg [CB-1:0] a_count, a_lwc;
    reg [QB-1:0] a_charge;
    reg [QB:0]   t;
    reg [QB-1:0] dist, st;
    reg [7:0]    a_revs_left, a_err;
    reg [15:0]   a_revolutions;
    reg [31:0]   a_pulses;
    reg [1:0]    old_phase, new_phase;
    reg          bit_now, decide;
    reg [6:0]    a_flt;
    reg [16:0]   a_revp;
    reg          a_idx_seen, a_confirmed, closed;
    reg [32:0]   a_idle;
    reg [4:0]    a_to_confirm;
    always @* begin
        a_flt = flt; a_revp = revp; a_idx_seen = idx_seen; a_confirmed = confirmed;
        a_to_confirm = to_confirm; closed = 1'b0;
        // one tick of the watchdog
        a_idle = (armed && idle < FT) ? idle + 33'd1 : idle;
        if (chg != 6'd0 && armed && FES_T != 0 && a_idle >= FT) a_flt[5] = 1'b1;
        {a_armed, a_contact, a_stk, a_reached} = {armed, contact, sticky, reached};
        {a_reg, a_first, a_dens_armed, a_fired} = {register_now, first_contact, density_armed, density_fired};
        a_dpos = decision_position; a_fpos = first_contact_position; a_pos = position;
        a_count = count; a_lwc = last_window_count; a_charge = charge;
        a_revs_left = revs_left; a_err = scale_errors; a_revolutions = revolutions; a_pulses = pulses;
        old_phase = {prev[5], prev[4] ^ prev[5]}; new_phase = {lv[5], lv[4] ^ lv[5]}; bit_now = 1'b0; decide = 1'b0; t = 0; dist = 0; st = 0;
        // arm
        if (chg[0]) begin
            if (lv[0] && !a_armed) begin
                a_flt = {6'd0, a_contact && FAULT != 15};  // fault 15: contact at arm not raised
                a_revp = 0; a_idx_seen = 1'b0; a_idle = 0; a_to_confirm = 0; a_confirmed = 1'b0;
                a_count = 0; a_lwc = 0; a_revs_left = WR8; a_reached = 1'b0;
                a_charge = 0; a_dens_armed = 1'b1; a_fired = 1'b0;
                if (FAULT != 12) begin a_first = 1'b0; a_fpos = 0; end
                a_reg = 1'b0; a_dpos = 0; a_revolutions = 0; a_pulses = 0;
            end
            a_armed = lv[0];
        end
        // contact
        if (chg[1]) begin
            a_contact = lv[1];
            if (lv[1]) begin
                a_stk = 1'b1;
                if (a_armed && !a_first) begin a_first = 1'b1; a_fpos = a_pos; end
                if (a_armed && METHOD == 0 && !a_reg) begin
                    a_reg = 1'b1; a_dpos = a_pos;
                    if (CW == 0) a_confirmed = 1'b1; else a_to_confirm = CW;
                end
            end
        end
        // index
        if (chg[2] && lv[2] && a_armed) begin
            if (a_revs_left <= 8'd1) begin a_lwc = a_count; a_count = 0; a_revs_left = WR8; closed = 1'b1; end
            else a_revs_left = a_revs_left - 8'd1;
            if (a_revolutions != 16'hffff) a_revolutions = a_revolutions + 16'd1;
            if (a_idx_seen && a_revp + TOL < PPR) a_flt[1] = 1'b1;
            a_revp = 0; a_idx_seen = 1'b1;
            if (closed && a_to_confirm != 0) begin
                if (a_lwc < CC) begin a_flt[6] = 1'b1; a_to_confirm = 0; end
                else begin a_to_confirm = a_to_confirm - 5'd1; a_confirmed = a_to_confirm == 0; end
            end
            if (!a_reg && PROBE != 0 && a_revolutions >= PROBE) a_flt[4] = 1'b1;
        end
        // FES
        if (chg[3] && lv[3]) begin
            bit_now = STICKY ? a_stk : a_contact;
            if (FAULT != 11 || a_armed) a_stk = a_contact;
            if (a_armed) begin
                a_pulses = a_pulses + 32'd1;
                a_idle = 0;
                if (a_revp > PPR + TOL) a_flt[2] = 1'b1;
                else begin
                    a_revp = a_revp + 17'd1;
                    if (a_revp > PPR + TOL) a_flt[2] = 1'b1;
                end
                if (bit_now && a_count < WINDOW_PULSES) begin
                    // decides on the pulse that takes the count past i_def
                    if (a_count >= ID && !a_reached) begin
                        a_reached = 1'b1;
                        if (METHOD == 1) decide = 1'b1;
                    end
                    a_count = a_count + 1'b1;
                end
                if (LAW == 0) begin
                    if (bit_now) begin
                        t = {1'b0, a_charge} + U;
                        a_charge = (t > FULL) ? FULL[QB-1:0] : t[QB-1:0];
                    end else
                        a_charge = ({1'b0, a_charge} >= D) ? a_charge - D : 0;
                end else begin
                    dist = bit_now ? FULL[QB-1:0] - a_charge : a_charge;
                    st = dist >> (bit_now ? U : D);
                    if (dist != 0 && st == 0) st = 1;
                    a_charge = bit_now ? a_charge + st : a_charge - st;
                end
                if (a_dens_armed) begin
                    if (a_charge >= FI) begin
                        a_dens_armed = 1'b0; a_fired = 1'b1;
                        if (METHOD == 2) decide = 1'b1;
                    end
                end else if (a_charge < RE)
                    a_dens_armed = 1'b1;
                if (decide && !a_reg) begin
                    a_reg = 1'b1; a_dpos = a_pos;
                    if (CW == 0) a_confirmed = 1'b1; else a_to_confirm = CW;
                end
            end
        end
        // scale
        if (chg[4] || chg[5]) begin
            if (new_phase == old_phase + 2'd1) a_pos = a_pos + 1'b1;
            else if (new_phase == old_phase - 2'd1) a_pos = a_pos - 1'b1;
            else if (new_phase != old_phase) begin
                if (a_err != 8'd255) a_err = a_err + 8'd1;
                if (a_armed) a_flt[3] = 1'b1;
            end
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            s1 <= 0; s2 <= 0; lv <= 0; prev <= 0; sticky <= 0; reached <= 0;
            revs_left <= WR8;
            seen <= 54'd0;
            register_now <= 0; decision_position <= 0;
            first_contact <= 0; first_contact_position <= 0; scale_errors <= 0;
            if (FAULT != 13) position <= 0;  // fault 13: rst leaves the position
            count <= 0; last_window_count <= 0; charge <= 0; density_armed <= 1'b1;
            density_fired <= 0; revolutions <= 0; pulses <= 0;
            flt <= 0; revp <= 0; idx_seen <= 0; idle <= 0; to_confirm <= 0; confirmed <= 0;
        end else begin
            s1 <= pins; s2 <= s1;
            lv <= lv_n; prev <= lv;
            for (i = 0; i < 6; i = i + 1)
                seen[9*i +: 9] <= (s2[i] == lv[i] || seen[9*i +: 9] >= G9) ? 9'd0 : seen[9*i +: 9] + 9'd1;
            {sticky, reached} <= {a_stk, a_reached};
            {register_now, first_contact, density_armed, density_fired} <= {a_reg, a_first, a_dens_armed, a_fired};
            decision_position <= a_dpos; first_contact_position <= a_fpos; position <= a_pos;
            count <= a_count; last_window_count <= a_lwc; charge <= a_charge;
            revs_left <= a_revs_left; scale_errors <= a_err; revolutions <= a_revolutions; pulses <= a_pulses;
            flt <= a_flt & EN; revp <= a_revp; idx_seen <= a_idx_seen; idle <= a_idle;
            to_confirm <= a_to_confirm; confirmed <= a_confirmed;
        end
    end

    assign faults = flt | ((armed && FES_T != 0 && idle >= FT) ? 7'd32 : 7'd0);
    assign irq = register_now;
    wire [63:0] pos_x = {{(64-SB){position[SB-1]}}, position};
    wire [63:0] dpos_x = {{(64-SB){decision_position[SB-1]}}, decision_position};
    wire [63:0] fpos_x = {{(64-SB){first_contact_position[SB-1]}}, first_contact_position};
    always @* begin
        case (mcu_addr)
            4'd0: mcu_rdata = {17'd0, faults, 1'b0, confirmed, density_fired, density_armed, first_contact, register_now, contact, armed};
            4'd1: mcu_rdata = pos_x[31:0];
            4'd2: mcu_rdata = dpos_x[31:0];
            4'd3: mcu_rdata = (FAULT == 14) ? pos_x[31:0] : fpos_x[31:0];  // fault 14: wrong word
            4'd4: mcu_rdata = {{(32-CB){1'b0}}, count};
            4'd5: mcu_rdata = {{(32-CB){1'b0}}, last_window_count};
            4'd6: mcu_rdata = {{(32-QB){1'b0}}, charge};
            4'd7: mcu_rdata = DIAG ? {16'd0, revolutions} : 32'd0;
            4'd8: mcu_rdata = DIAG ? pulses : 32'd0;
            4'd9: mcu_rdata = {24'd0, scale_errors};
            4'd10: mcu_rdata = HASH[31:0];
            4'd11: mcu_rdata = HASH[63:32];
            default: mcu_rdata = 32'd0;
        endcase
    end
endmodule
`default_nettype wire
