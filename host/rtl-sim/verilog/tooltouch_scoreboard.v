// tooltouch_scoreboard (VPI): the golden model beside your tt_frontend, every clock, under
// Icarus (which has no DPI): Verilog-2005 over the system functions of
// host/rtl-sim/c/tooltouch_vpi.c (vvp -M DIR -m tooltouch). The same module, ports,
// parameters, plusargs, checks and messages as the DPI-C scoreboard host/rtl-sim/sv/
// tooltouch_scoreboard.sv:
//
//   tooltouch_scoreboard #(.SCALE_BITS(24), .COUNT_BITS(11), .CHARGE_BITS(16)) sb (
//       .clk(clk), .rst(rst), .pin_arm(pin_arm), ... , .irq(irq),
//       .dut_config_hash(dut.CONFIG_HASH));
//
// +tooltouch_config=FILE (from `tooltouch cosim config`); at time 0 a configuration whose
// hash is not the DUT's CONFIG_HASH, or widths not the configuration's, is refused
// ($fatal); the model is clocked at every rising edge and compared at the falling edge
// after it; the first mismatch prints
//   tooltouch_scoreboard MISMATCH cycle K (time T): signal S expected 0x.. got 0x.. [at MCU address A]
// then $fatal (+tooltouch_nostop: go on); the end of the simulation prints
// `tooltouch_scoreboard OK <cycles>`.
`timescale 1ns / 1ns
`default_nettype none

module tooltouch_scoreboard #(
    parameter integer SCALE_BITS      = 24,
    parameter integer COUNT_BITS      = 11,
    parameter integer CHARGE_BITS     = 16,
    parameter         MCU_DIAGNOSTICS = 0
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
    integer model = -1;
    integer cycle = -1;          // rising edges seen
    integer mismatches = 0;
    integer first;
    integer width;
    reg     nostop;
    reg [8*512-1:0] config_path;  // up to 512 characters
    reg [63:0] model_hash;
    // BEGIN GENERATED signal-indexes: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
    // Signal indexes: 0..16 the outputs in port order, 17 irq, 18 mcu_rdata.
    localparam integer SIGNAL_MCU_RDATA = 18;
    // END GENERATED signal-indexes

    // BEGIN GENERATED signal-name: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
    function [8*22-1:0] signal_name(input integer index);
        case (index)
            0: signal_name = "armed";
            1: signal_name = "contact";
            2: signal_name = "register_now";
            3: signal_name = "decision_position";
            4: signal_name = "first_contact";
            5: signal_name = "first_contact_position";
            6: signal_name = "position";
            7: signal_name = "scale_errors";
            8: signal_name = "count";
            9: signal_name = "last_window_count";
            10: signal_name = "charge";
            11: signal_name = "density_armed";
            12: signal_name = "density_fired";
            13: signal_name = "revolutions";
            14: signal_name = "pulses";
            15: signal_name = "confirmed";
            16: signal_name = "faults";
            17: signal_name = "irq";
            default: signal_name = "mcu_rdata";
        endcase
    endfunction
    // END GENERATED signal-name

    // BEGIN GENERATED dut-value: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
    function [31:0] dut_value(input integer index);
        case (index)
            0: dut_value = armed;
            1: dut_value = contact;
            2: dut_value = register_now;
            3: dut_value = decision_position;
            4: dut_value = first_contact;
            5: dut_value = first_contact_position;
            6: dut_value = position;
            7: dut_value = scale_errors;
            8: dut_value = count;
            9: dut_value = last_window_count;
            10: dut_value = charge;
            11: dut_value = density_armed;
            12: dut_value = density_fired;
            13: dut_value = revolutions;
            14: dut_value = pulses;
            15: dut_value = confirmed;
            16: dut_value = faults;
            17: dut_value = irq;
            default: dut_value = mcu_rdata;
        endcase
    endfunction
    // END GENERATED dut-value

    task check_width(input integer index, input integer wanted_here);
        begin
            width = $tooltouch_output_width(model, index);
            if (width != wanted_here) begin
                $display("tooltouch_scoreboard: %0s is %0d bits wide here, the configuration %0s makes it %0d: set the parameters SCALE_BITS, COUNT_BITS, CHARGE_BITS",
                         signal_name(index), wanted_here, config_path, width);
                $fatal(1, "tooltouch_scoreboard: widths");
            end
        end
    endtask

    initial begin
        nostop = $test$plusargs("tooltouch_nostop");
        if (!$value$plusargs("tooltouch_config=%s", config_path)) begin
            $display("tooltouch_scoreboard: no +tooltouch_config=FILE (tooltouch cosim config --config SETTINGS --out FILE writes it)");
            $fatal(1, "tooltouch_scoreboard: no configuration");
        end
        model = $tooltouch_open(config_path, MCU_DIAGNOSTICS);
        if (model < 0) $fatal(1, "tooltouch_scoreboard: no model");
        // BEGIN GENERATED check-widths: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
        check_width(3, SCALE_BITS);
        check_width(8, COUNT_BITS);
        check_width(10, CHARGE_BITS);
        // END GENERATED check-widths
        #0;  // the DUT's hash is a constant; let its port connection settle
        model_hash = {$tooltouch_config_hash_hi(model), $tooltouch_config_hash_lo(model)};
        if (model_hash !== dut_config_hash) begin
            $display("tooltouch_scoreboard: configuration mismatch: %0s gives measure_hash %h, the DUT's CONFIG_HASH is %h",
                     config_path, model_hash, dut_config_hash);
            $fatal(1, "tooltouch_scoreboard: configuration mismatch");
        end
    end

    always @(posedge clk) begin
        if (model >= 0) begin
            if ($tooltouch_clock(model, {pin_scale_b, pin_scale_a, pin_fes, pin_index, pin_contact, pin_arm}, rst) != 0) begin
                $display("tooltouch_scoreboard: cycle %0d: a pin or rst is X or Z", cycle + 1);
                $fatal(1, "tooltouch_scoreboard: unknown pin");
            end
            cycle = cycle + 1;
        end
    end

    always @(negedge clk) begin
        if (model >= 0 && cycle >= 0) begin
            // BEGIN GENERATED compare: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
            first = $tooltouch_compare(model, mcu_addr, mcu_rdata, irq, armed, contact,
                register_now, decision_position, first_contact, first_contact_position, position,
                scale_errors, count, last_window_count, charge, density_armed, density_fired,
                revolutions, pulses, confirmed, faults);
            // END GENERATED compare
            if (first >= 0) begin
                if (mismatches == 0) begin
                    if (first == SIGNAL_MCU_RDATA)
                        $display("tooltouch_scoreboard MISMATCH cycle %0d (time %0t ns): signal mcu_rdata expected 0x%0h got 0x%0h at MCU address %0d",
                                 cycle, $time, $tooltouch_expected(model, first, mcu_addr), mcu_rdata, mcu_addr);
                    else
                        $display("tooltouch_scoreboard MISMATCH cycle %0d (time %0t ns): signal %0s expected 0x%0h got 0x%0h",
                                 cycle, $time, signal_name(first), $tooltouch_expected(model, first, mcu_addr),
                                 dut_value(first));
                end
                mismatches = mismatches + 1;
                if (!nostop) $fatal(1, "tooltouch_scoreboard: %0s differs from the golden model at cycle %0d", signal_name(first), cycle);
            end
        end
    end
endmodule

`default_nettype wire
