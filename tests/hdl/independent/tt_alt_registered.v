// An independent tt_frontend, written from docs/CONTRACT.md for the formal tests (not
// part of the product): registered edge strobes, glitch filters counting down, a one-hot
// scale phase, the counter's decision compared before the increment. Every configuration
// value is a parameter (set by the test's wrapper); FAULT != 0 injects one single-point
// fault (tests/hdl/formal_dut.rs lists them).
`default_nettype none
module tt_alt_registered #(
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
    output reg  [6:0]    faults,
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
    reg [5:0] s1 = 6'd0, s2 = 6'd0, lv = 6'd0, chg = 6'd0;
    localparam [8:0] G9 = G;
    reg [53:0] left = {6{G9}};
    reg [5:0] lv_n;
    reg [3:0] ph = 4'b0001;              // one-hot phase: 00, 10, 11, 01 (A B)
    reg       sticky = 1'b0;
    reg       reached = 1'b0;
    reg [7:0] revs = 8'd0;
    // The status: every fault a flag of its own; the watchdog latched in every clock from
    // a tick count saturating at FES_T (no lazy term); FES pulses since the index counted
    // up to PPR + TOL + 1; the windows confirmed so far counted up to CW.
    reg        f_caa = 1'b0, f_lost = 1'b0, f_missing = 1'b0, f_scale = 1'b0;
    reg        f_probe = 1'b0, f_fes = 1'b0, f_unconf = 1'b0;
    reg [16:0] revp = 17'd0;
    reg        idx_seen = 1'b0;
    reg [32:0] idle = 33'd0;
    reg        pending = 1'b0;           // a decision waits for its confirmation
    reg [4:0]  windows_ok = 5'd0;        // windows confirmed so far
    localparam [32:0] FT = FES_T;
    integer i;
    initial begin
        confirmed = 1'b0; faults = 7'd0;
        armed = 1'b0; contact = 1'b0; register_now = 1'b0; decision_position = 0;
        first_contact = 1'b0; first_contact_position = 0; position = 0; scale_errors = 8'd0;
        count = 0; last_window_count = 0; charge = 0; density_armed = 1'b1;
        density_fired = 1'b0; revolutions = 16'd0; pulses = 32'd0;
    end

    // Glitch filters: `left` clocks of disagreement to go before the level passes.
    always @* begin
        for (i = 0; i < 6; i = i + 1)
            lv_n[i] = (s2[i] != lv[i] && left[9*i +: 9] == 9'd0) ? s2[i] : lv[i];
    end

    // The kernel, in the canonical order, on the registered strobes.
    reg          a_armed, a_contact, a_stk, a_reached, a_reg, a_first, a_dens_armed, a_fired;
    reg [SB-1:0] a_dpos, a_fpos, a_pos;
    reg [CB-1:0] a_count, a_lwc;
    reg [QB-1:0] a_charge;
    reg [QB:0]   t;
    reg [QB-1:0] dist, st;
    reg [7:0]    a_revs, a_err;
    reg [15:0]   a_revolutions;
    reg [31:0]   a_pulses;
    reg [3:0]    a_ph, new_ph;
    reg          bit_now, decide;
    reg          b_caa, b_lost, b_missing, b_scale, b_probe, b_fes, b_unconf;
    reg [16:0]   b_revp;
    reg          b_idx_seen, b_pending, b_confirmed, closed, b_decided;
    reg [32:0]   b_idle;
    reg [4:0]    b_windows_ok;
    always @* begin
        {b_caa, b_lost, b_missing, b_scale} = {f_caa, f_lost, f_missing, f_scale};
        {b_probe, b_fes, b_unconf} = {f_probe, f_fes, f_unconf};
        b_revp = revp; b_idx_seen = idx_seen; b_pending = pending; b_confirmed = confirmed;
        b_windows_ok = windows_ok; closed = 1'b0; b_decided = 1'b0;
        // the watchdog: latched in the clock the ticks since the last FES pulse reach FES_T
        if (FES_T != 0 && armed && idle + 33'd1 >= FT) b_fes = 1'b1;
        b_idle = (idle >= FT || !armed) ? idle : idle + 33'd1;
        {a_armed, a_contact, a_stk, a_reached} = {armed, contact, sticky, reached};
        {a_reg, a_first, a_dens_armed, a_fired} = {register_now, first_contact, density_armed, density_fired};
        a_dpos = decision_position; a_fpos = first_contact_position; a_pos = position;
        a_count = count; a_lwc = last_window_count; a_charge = charge;
        a_revs = revs; a_err = scale_errors; a_revolutions = revolutions; a_pulses = pulses;
        a_ph = ph; new_ph = ph; bit_now = 1'b0; decide = 1'b0; t = 0; dist = 0; st = 0;
        // arm
        if (chg[0]) begin
            if (lv[0] && !a_armed) begin
                b_caa = CAA != 0 && a_contact && FAULT != 15;  // fault 15: contact at arm not raised
                {b_lost, b_missing, b_scale, b_probe, b_fes, b_unconf} = 6'd0;
                b_revp = 0; b_idx_seen = 1'b0; b_idle = 0; b_pending = 1'b0; b_windows_ok = 0;
                b_confirmed = 1'b0;
                a_count = 0; a_lwc = 0; a_revs = 0; a_reached = 1'b0;
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
                    if (CW == 0) b_confirmed = 1'b1; else begin b_pending = 1'b1; b_windows_ok = 0; end
                end
            end
        end
        // index
        if (chg[2] && lv[2] && a_armed) begin
            if (a_revs != 8'd255) a_revs = a_revs + 8'd1;
            if (a_revs >= WINDOW_REVS) begin a_lwc = a_count; a_count = 0; a_revs = 0; closed = 1'b1; end
            if (a_revolutions != 16'hffff) a_revolutions = a_revolutions + 16'd1;
            if (REV_CHECK != 0 && b_idx_seen && b_revp < PPR - TOL) b_lost = 1'b1;
            b_revp = 0; b_idx_seen = 1'b1;
            if (closed && b_pending) begin
                if (a_lwc < CC) begin b_unconf = 1'b1; b_pending = 1'b0; end
                else begin
                    b_windows_ok = b_windows_ok + 5'd1;
                    if (b_windows_ok == CW) begin b_pending = 1'b0; b_confirmed = 1'b1; end
                end
            end
            if (PROBE != 0 && !a_reg && a_revolutions >= PROBE) b_probe = 1'b1;
        end
        // FES
        if (chg[3] && lv[3]) begin
            bit_now = STICKY ? a_stk : a_contact;
            if (FAULT != 11 || a_armed) a_stk = a_contact;
            if (a_armed) begin
                a_pulses = a_pulses + 32'd1;
                b_idle = 0;
                if (b_revp >= PPR + TOL) begin
                    if (REV_CHECK != 0) b_missing = 1'b1;
                    b_revp = PPR + TOL + 1;
                end else
                    b_revp = b_revp + 17'd1;
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
                    if (CW == 0) b_confirmed = 1'b1; else begin b_pending = 1'b1; b_windows_ok = 0; end
                end
            end
        end
        // scale
        if (chg[4] || chg[5]) begin
            case ({lv[4], lv[5]})
                2'b00: new_ph = 4'b0001;
                2'b10: new_ph = 4'b0010;
                2'b11: new_ph = 4'b0100;
                default: new_ph = 4'b1000;
            endcase
            if (new_ph == {a_ph[2:0], a_ph[3]}) a_pos = a_pos + 1'b1;
            else if (new_ph == {a_ph[0], a_ph[3:1]}) a_pos = a_pos - 1'b1;
            else if (new_ph != a_ph) begin
                if (a_err != 8'd255) a_err = a_err + 8'd1;
                if (SCALE_CHECK != 0 && a_armed) b_scale = 1'b1;
            end
            a_ph = new_ph;
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            s1 <= 0; s2 <= 0; lv <= 0; chg <= 0; ph <= 4'b0001; sticky <= 0; reached <= 0;
            revs <= 0;
            left <= {6{G9}};
            armed <= 0; contact <= 0; register_now <= 0; decision_position <= 0;
            first_contact <= 0; first_contact_position <= 0; scale_errors <= 0;
            if (FAULT != 13) position <= 0;  // fault 13: rst leaves the position
            count <= 0; last_window_count <= 0; charge <= 0; density_armed <= 1'b1;
            density_fired <= 0; revolutions <= 0; pulses <= 0;
            {f_caa, f_lost, f_missing, f_scale, f_probe, f_fes, f_unconf} <= 7'd0;
            revp <= 0; idx_seen <= 0; idle <= 0; pending <= 0; windows_ok <= 0; confirmed <= 0;
            faults <= 0;
        end else begin
            s1 <= pins; s2 <= s1;
            lv <= lv_n; chg <= lv_n ^ lv;
            for (i = 0; i < 6; i = i + 1)
                left[9*i +: 9] <= (s2[i] == lv[i] || left[9*i +: 9] == 9'd0) ? G9 : left[9*i +: 9] - 9'd1;
            {armed, contact, sticky, reached} <= {a_armed, a_contact, a_stk, a_reached};
            {register_now, first_contact, density_armed, density_fired} <= {a_reg, a_first, a_dens_armed, a_fired};
            decision_position <= a_dpos; first_contact_position <= a_fpos; position <= a_pos;
            count <= a_count; last_window_count <= a_lwc; charge <= a_charge;
            revs <= a_revs; scale_errors <= a_err; revolutions <= a_revolutions; pulses <= a_pulses;
            ph <= a_ph;
            {f_caa, f_lost, f_missing, f_scale, f_probe, f_fes, f_unconf} <=
                {b_caa, b_lost, b_missing, b_scale, b_probe, b_fes, b_unconf};
            faults <= {b_unconf, b_fes, b_probe, b_scale, b_missing, b_lost, b_caa};
            revp <= b_revp; idx_seen <= b_idx_seen; idle <= b_idle; pending <= b_pending;
            windows_ok <= b_windows_ok; confirmed <= b_confirmed;
        end
    end

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
