// tooltouch_bench: a stimulus-only bench for tt_frontend under tooltouch_scoreboard (the
// DPI-C one, host/rtl-sim/sv, under Verilator; the VPI one, tooltouch_scoreboard.v here, under
// Icarus): Verilog-2005, no expected vectors, the scoreboard computes them as it goes.
//
// Reads the run-length pins of stim.hex (`tooltouch hdl --vectors` or `tooltouch vectors`
// writes it; +stim=FILE for another) word by word: word 0 counts the segments, each
// segment is {pins[37:32], clocks[31:0]} with pins {scale_b, scale_a, fes, index, contact,
// arm}. Pins change on the falling edge before the rising edge that samples them; mcu_addr
// steps through 0..15 (k mod 16 at rising edge k), so every MCU word is compared. Prints
// `tooltouch_bench <clocks> clocks` and finishes after the last falling edge; the
// scoreboard prints its verdict. Widths: the parameters, as the DUT's ports.
`timescale 1ns / 1ns
`default_nettype none

module tooltouch_bench;
    parameter integer SCALE_BITS      = 24;
    parameter integer COUNT_BITS      = 11;
    parameter integer CHARGE_BITS     = 16;
    parameter         MCU_DIAGNOSTICS = 0;
    parameter integer PERIOD          = 20;  // ns

    reg         clk = 1'b0;
    reg         rst = 1'b0;
    reg  [5:0]  pins = 6'd0;
    reg  [3:0]  mcu_addr = 4'd0;
    wire [31:0] mcu_rdata;
    wire        irq;
    // BEGIN GENERATED wires: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
    wire                   armed;
    wire                   contact;
    wire                   register_now;
    wire [SCALE_BITS-1:0]  decision_position;
    wire                   first_contact;
    wire [SCALE_BITS-1:0]  first_contact_position;
    wire [SCALE_BITS-1:0]  position;
    wire [7:0]             scale_errors;
    wire [COUNT_BITS-1:0]  count;
    wire [COUNT_BITS-1:0]  last_window_count;
    wire [CHARGE_BITS-1:0] charge;
    wire                   density_armed;
    wire                   density_fired;
    wire [15:0]            revolutions;
    wire [31:0]            pulses;
    wire                   confirmed;
    wire [6:0]             faults;
    // END GENERATED wires

    tt_frontend dut (
        .clk(clk), .rst(rst),
        .pin_arm(pins[0]), .pin_contact(pins[1]), .pin_index(pins[2]), .pin_fes(pins[3]),
        .pin_scale_a(pins[4]), .pin_scale_b(pins[5]),
        .mcu_addr(mcu_addr), .mcu_rdata(mcu_rdata),
        // BEGIN GENERATED connections: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
        .armed(armed), .contact(contact), .register_now(register_now),
        .decision_position(decision_position), .first_contact(first_contact),
        .first_contact_position(first_contact_position), .position(position),
        .scale_errors(scale_errors), .count(count), .last_window_count(last_window_count),
        .charge(charge), .density_armed(density_armed), .density_fired(density_fired),
        .revolutions(revolutions), .pulses(pulses), .confirmed(confirmed), .faults(faults),
        // END GENERATED connections
        .irq(irq)
    );

    tooltouch_scoreboard #(
        .SCALE_BITS(SCALE_BITS), .COUNT_BITS(COUNT_BITS), .CHARGE_BITS(CHARGE_BITS),
        .MCU_DIAGNOSTICS(MCU_DIAGNOSTICS)
    ) sb (
        .clk(clk), .rst(rst),
        .pin_arm(pins[0]), .pin_contact(pins[1]), .pin_index(pins[2]), .pin_fes(pins[3]),
        .pin_scale_a(pins[4]), .pin_scale_b(pins[5]),
        .mcu_addr(mcu_addr), .mcu_rdata(mcu_rdata),
        // BEGIN GENERATED connections: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
        .armed(armed), .contact(contact), .register_now(register_now),
        .decision_position(decision_position), .first_contact(first_contact),
        .first_contact_position(first_contact_position), .position(position),
        .scale_errors(scale_errors), .count(count), .last_window_count(last_window_count),
        .charge(charge), .density_armed(density_armed), .density_fired(density_fired),
        .revolutions(revolutions), .pulses(pulses), .confirmed(confirmed), .faults(faults),
        // END GENERATED connections
        .irq(irq),
        .dut_config_hash(dut.CONFIG_HASH)
    );

    always #(PERIOD / 2) clk = ~clk;

    integer      fd;
    integer      r;
    integer      segments;
    integer      segment;
    integer      k = 0;       // rising edges
    reg [31:0]   left;
    reg [39:0]   word;
    reg [8*512-1:0] stim_path;   // up to 512 characters

    initial begin
        if (!$value$plusargs("stim=%s", stim_path)) stim_path = "stim.hex";
        fd = $fopen(stim_path, "r");
        if (fd == 0) begin
            $display("tooltouch_bench ERROR %0s: cannot open it (tooltouch hdl --vectors or tooltouch vectors writes stim.hex)", stim_path);
            $fatal(1, "no stimulus");
        end
        r = $fscanf(fd, "%h", word);
        if (r != 1) begin
            $display("tooltouch_bench ERROR %0s: no header word", stim_path);
            $fatal(1, "bad stimulus");
        end
        segments = word[31:0];
        for (segment = 1; segment <= segments; segment = segment + 1) begin
            r = $fscanf(fd, "%h", word);
            if (r != 1) begin
                $display("tooltouch_bench ERROR %0s word %0d: missing or not a hex word (the header says %0d segments)",
                         stim_path, segment, segments);
                $fatal(1, "bad stimulus");
            end
            pins = word[37:32];
            left = word[31:0];
            while (left != 32'd0) begin
                @(posedge clk);
                mcu_addr = k[3:0];
                k = k + 1;
                left = left - 32'd1;
                @(negedge clk);
            end
        end
        $fclose(fd);
        #1;
        $display("tooltouch_bench %0d clocks", k);
        $finish;
    end
endmodule

`default_nettype wire
