// tooltouch_scoreboard: the golden model beside your tt_frontend, every clock (DPI-C).
//
// Instantiate it next to the DUT with the same signals (the generated tt_frontend's
// ports) and the DUT's CONFIG_HASH; run with +tooltouch_config=FILE, the configuration
// file `tooltouch cosim config --config settings.toml --out FILE` writes:
//
//   tooltouch_scoreboard #(.SCALE_BITS(24), .COUNT_BITS(11), .CHARGE_BITS(16)) sb (
//       .clk(clk), .rst(rst), .pin_arm(pin_arm), ... , .mcu_addr(mcu_addr),
//       .mcu_rdata(mcu_rdata), .armed(armed), ... , .irq(irq),
//       .dut_config_hash(dut.CONFIG_HASH));
//
// At time 0 it refuses a configuration whose hash is not the DUT's, and widths that are
// not the configuration's ($fatal). At every rising edge it clocks the model with the pins
// (or resets it with rst); at the falling edge after it compares every output, irq and
// mcu_rdata (at the mcu_addr then) with the model and stops at the first mismatch:
//   tooltouch_scoreboard MISMATCH cycle K (time T): signal S expected 0x.. got 0x.. [at MCU address A]
// then $error and $fatal. Drive the pins away from the rising edge (on the falling edge)
// and mcu_addr away from the falling edge. At the end: tooltouch_scoreboard OK <cycles>.
// Plusarg +tooltouch_nostop: count mismatches and go on (the first is still printed).
`timescale 1ns / 1ns
`default_nettype none

module tooltouch_scoreboard
    import tooltouch_dpi::*;
#(
    parameter integer SCALE_BITS      = 24,  // the configuration's widths (the DUT's ports)
    parameter integer COUNT_BITS      = 11,
    parameter integer CHARGE_BITS     = 16,
    parameter bit     MCU_DIAGNOSTICS = 1'b0 // the DUT was generated with --mcu-diagnostics
) (
    input wire                   clk,
    input wire                   rst,
    input wire                   pin_arm,
    input wire                   pin_contact,
    input wire                   pin_index,
    input wire                   pin_fes,
    input wire                   pin_scale_a,
    input wire                   pin_scale_b,
    input wire [3:0]             mcu_addr,
    input wire [31:0]            mcu_rdata,
    // BEGIN GENERATED ports: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
    input wire                   armed,
    input wire                   contact,
    input wire                   register_now,
    input wire [SCALE_BITS-1:0]  decision_position,
    input wire                   first_contact,
    input wire [SCALE_BITS-1:0]  first_contact_position,
    input wire [SCALE_BITS-1:0]  position,
    input wire [7:0]             scale_errors,
    input wire [COUNT_BITS-1:0]  count,
    input wire [COUNT_BITS-1:0]  last_window_count,
    input wire [CHARGE_BITS-1:0] charge,
    input wire                   density_armed,
    input wire                   density_fired,
    input wire [15:0]            revolutions,
    input wire [31:0]            pulses,
    input wire                   confirmed,
    input wire [6:0]             faults,
    // END GENERATED ports
    input wire                   irq,
    input wire [63:0]            dut_config_hash
);
    chandle      model;
    longint      cycle = -1;      // rising edges seen
    longint      mismatches = 0;
    bit          nostop;
    string       config_path;
    // BEGIN GENERATED signal-indexes: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
    // Signal indexes: 0..16 the outputs in port order, 17 irq, 18 mcu_rdata.
    localparam integer SIGNAL_MCU_RDATA = 18;
    // END GENERATED signal-indexes

    // BEGIN GENERATED signal-name: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
    function automatic string signal_name(input int index);
        case (index)
            0: return "armed";
            1: return "contact";
            2: return "register_now";
            3: return "decision_position";
            4: return "first_contact";
            5: return "first_contact_position";
            6: return "position";
            7: return "scale_errors";
            8: return "count";
            9: return "last_window_count";
            10: return "charge";
            11: return "density_armed";
            12: return "density_fired";
            13: return "revolutions";
            14: return "pulses";
            15: return "confirmed";
            16: return "faults";
            17: return "irq";
            default: return "mcu_rdata";
        endcase
    endfunction
    // END GENERATED signal-name

    // BEGIN GENERATED dut-value: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
    function automatic longint unsigned dut_value(input int index);
        case (index)
            0: return 64'(armed);
            1: return 64'(contact);
            2: return 64'(register_now);
            3: return 64'(decision_position);
            4: return 64'(first_contact);
            5: return 64'(first_contact_position);
            6: return 64'(position);
            7: return 64'(scale_errors);
            8: return 64'(count);
            9: return 64'(last_window_count);
            10: return 64'(charge);
            11: return 64'(density_armed);
            12: return 64'(density_fired);
            13: return 64'(revolutions);
            14: return 64'(pulses);
            15: return 64'(confirmed);
            16: return 64'(faults);
            17: return 64'(irq);
            default: return 64'(mcu_rdata);
        endcase
    endfunction
    // END GENERATED dut-value

    task automatic check_width(input int index, input int width);
        int unsigned want;
        want = tooltouch_output_width(model, index);
        if (want != width)
            $fatal(1, "tooltouch_scoreboard: %s is %0d bits wide here, the configuration %s makes it %0d: set the parameters SCALE_BITS, COUNT_BITS, CHARGE_BITS",
                   signal_name(index), width, config_path, want);
    endtask

    initial begin
        nostop = $test$plusargs("tooltouch_nostop");
        if (!$value$plusargs("tooltouch_config=%s", config_path))
            $fatal(1, "tooltouch_scoreboard: no +tooltouch_config=FILE (tooltouch cosim config --config SETTINGS --out FILE writes it)");
        model = tooltouch_open(config_path, MCU_DIAGNOSTICS);
        if (model == null)
            $fatal(1, "tooltouch_scoreboard: %s", tooltouch_error());
        // BEGIN GENERATED check-widths: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
        check_width(3, SCALE_BITS);
        check_width(8, COUNT_BITS);
        check_width(10, CHARGE_BITS);
        // END GENERATED check-widths
        // The DUT's hash is a constant; #0 lets its port connection settle.
        /* verilator lint_off ZERODLY */
        #0;
        /* verilator lint_on ZERODLY */
        if (tooltouch_config_hash(model) != dut_config_hash)
            $fatal(1, "tooltouch_scoreboard: configuration mismatch: %s gives measure_hash %016h, the DUT's CONFIG_HASH is %016h",
                   config_path, tooltouch_config_hash(model), dut_config_hash);
    end

    always @(posedge clk) begin
        if (model != null) begin
            if (tooltouch_clock(model, {2'b00, pin_scale_b, pin_scale_a, pin_fes, pin_index, pin_contact, pin_arm}, rst) != 0
                    || $isunknown({pin_scale_b, pin_scale_a, pin_fes, pin_index, pin_contact, pin_arm, rst}))
                $fatal(1, "tooltouch_scoreboard: cycle %0d: a pin or rst is X or Z", cycle + 1);
            cycle = cycle + 1;
        end
    end

    always @(negedge clk) begin
        int first;
        int unsigned unknown;
        if (model != null && cycle >= 0) begin
            // BEGIN GENERATED compare: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
            unknown = {13'd0, $isunknown(mcu_rdata) | $isunknown(mcu_addr), $isunknown(irq),
                       $isunknown(faults), $isunknown(confirmed), $isunknown(pulses),
                       $isunknown(revolutions), $isunknown(density_fired),
                       $isunknown(density_armed), $isunknown(charge), $isunknown(last_window_count),
                       $isunknown(count), $isunknown(scale_errors), $isunknown(position),
                       $isunknown(first_contact_position), $isunknown(first_contact),
                       $isunknown(decision_position), $isunknown(register_now), $isunknown(contact),
                       $isunknown(armed)};
            first = tooltouch_compare(model, unknown, 32'(mcu_addr), mcu_rdata, irq, 64'(armed),
                64'(contact), 64'(register_now), 64'(decision_position), 64'(first_contact),
                64'(first_contact_position), 64'(position), 64'(scale_errors), 64'(count),
                64'(last_window_count), 64'(charge), 64'(density_armed), 64'(density_fired),
                64'(revolutions), 64'(pulses), 64'(confirmed), 64'(faults));
            // END GENERATED compare
            if (first >= 0) begin
                if (mismatches == 0) begin
                    if (first == SIGNAL_MCU_RDATA)
                        $display("tooltouch_scoreboard MISMATCH cycle %0d (time %0t ns): signal mcu_rdata expected 0x%0h got 0x%0h at MCU address %0d",
                                 cycle, $time, tooltouch_expected(model, first, 32'(mcu_addr)), mcu_rdata, mcu_addr);
                    else
                        $display("tooltouch_scoreboard MISMATCH cycle %0d (time %0t ns): signal %s expected 0x%0h got 0x%0h",
                                 cycle, $time, signal_name(first), tooltouch_expected(model, first, 32'(mcu_addr)),
                                 dut_value(first));
                end
                mismatches = mismatches + 1;
                if (!nostop) begin
                    $error("tooltouch_scoreboard: %s differs from the golden model at cycle %0d", signal_name(first), cycle);
                    $fatal(1, "tooltouch_scoreboard: stopped at the first mismatch");
                end
            end
        end
    end

    final begin
        if (model != null) begin
            if (mismatches == 0)
                $display("tooltouch_scoreboard OK %0d", cycle + 1);
            else
                $display("tooltouch_scoreboard FAIL %0d mismatching cycles of %0d", mismatches, cycle + 1);
            tooltouch_close(model);
        end
    end
endmodule

`default_nettype wire
