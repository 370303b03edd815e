// tooltouch_spi_bench: drives the board top tt_fpga_spi from a command file, clock by
// clock and SPI bit by bit, and prints what it reads; the Rust side (tests/spi.rs of
// tooltouch-rtl-sim) writes the commands and compares the printout with the golden model.
//
// Commands (+commands=FILE), one per line, numbers in hex:
//   H <clocks> <pins>               hold the six input pins (bit 0 arm ... bit 5 scale_b)
//   F <cmd> <data> <bits> <half>    one SPI mode-0 frame of <bits> bits (command byte
//                                   <cmd>, then <data> MSB first) at SCK half-period
//                                   <half> FPGA clocks; CS falls 4 clocks before the first
//                                   edge and rises <half> clocks after the last falling one
//   P                               print the output pins
// Output lines (stdout), numbers in hex:
//   F <cmd> <status byte> <word> <clock>   MISO during the command byte and the data bits
//                                          (bits 31.. of <word> first; a short frame leaves
//                                          the rest 0), <clock>: FPGA clocks before CS rose
//   P <register_now> <irq> <fault> <clock>
//   DONE <clock>
`timescale 1ns / 1ns
`default_nettype none

module tooltouch_spi_bench;
    reg clk = 1'b0;
    reg [5:0] pins = 6'd0;
    reg sck = 1'b0;
    reg cs_n = 1'b1;
    reg mosi = 1'b0;
    wire miso, register_now_out, irq_out, fault_out;
    reg [63:0] clocks = 64'd0;

    tt_fpga_spi dut (
        .clk(clk),
        .pin_arm(pins[0]), .pin_contact(pins[1]), .pin_index(pins[2]), .pin_fes(pins[3]),
        .pin_scale_a(pins[4]), .pin_scale_b(pins[5]),
        .spi_sck(sck), .spi_cs_n(cs_n), .spi_mosi(mosi), .spi_miso(miso),
        .register_now_out(register_now_out), .irq_out(irq_out), .fault_out(fault_out)
    );

    // One FPGA clock: the bench changes its outputs at the falling edge, away from the
    // rising edge the design samples at.
    task tick;
        begin
            #5 clk = 1'b1;
            clocks = clocks + 64'd1;
            #5 clk = 1'b0;
        end
    endtask

    task ticks(input [63:0] n);
        reg [63:0] i;
        begin
            for (i = 0; i < n; i = i + 1) tick;
        end
    endtask

    integer fd, code, bit_index;
    reg [8*2-1:0] op;
    reg [63:0] n;
    reg [31:0] cmd, data, bits, half;
    reg [39:0] frame_out, frame_in;

    reg [8*256-1:0] path;
    initial begin
        if (!$value$plusargs("commands=%s", path)) begin
            $display("ERROR no +commands=FILE");
            $finish;
        end
        fd = $fopen(path, "r");
        if (fd == 0) begin
            $display("ERROR cannot open the command file");
            $finish;
        end
        while (!$feof(fd)) begin
            code = $fscanf(fd, " %c", op[7:0]);
            if (code == 1) begin
                case (op[7:0])
                    "H": begin
                        code = $fscanf(fd, " %h %h", n, data);
                        pins = data[5:0];
                        ticks(n);
                    end
                    "F": begin
                        code = $fscanf(fd, " %h %h %h %h", cmd, data, bits, half);
                        frame_out = {cmd[7:0], data};
                        frame_in = 40'd0;
                        cs_n = 1'b0;
                        ticks(4);
                        for (bit_index = 0; bit_index < bits; bit_index = bit_index + 1) begin
                            mosi = frame_out[39 - bit_index];
                            ticks(half);
                            // The master samples MISO at its rising edge.
                            frame_in[39 - bit_index] = miso;
                            sck = 1'b1;
                            ticks(half);
                            sck = 1'b0;
                        end
                        ticks(half);
                        $display("F %02h %02h %08h %0h", cmd[7:0], frame_in[39:32],
                                 frame_in[31:0], clocks);
                        cs_n = 1'b1;
                        mosi = 1'b0;
                        ticks(4);
                    end
                    "P": $display("P %0d %0d %0d %0h", register_now_out, irq_out, fault_out,
                                  clocks);
                    default: begin
                        $display("ERROR unknown command %c", op[7:0]);
                        $finish;
                    end
                endcase
            end
        end
        $display("DONE %0h", clocks);
        $finish;
    end
endmodule

`default_nettype wire
