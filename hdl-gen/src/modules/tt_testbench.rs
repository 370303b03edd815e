//! `tt_testbench.v`, the self-checking testbench: reads the run-length pin stimulus and the expected
//! response (written by the golden model) with `$readmemh`, clocks the design, and
//! compares every output bit on every cycle.
//!
//! Files, read from the simulator's working directory:
//!
//! - `stim.hex`: words of [`STIM_WORD_BITS`] bits, `{pins[7:0], cycles[31:0]}`; word 0 is
//!   `{8'd0, segment_count}`; each further word holds the pins for `cycles` clocks.
//! - `expect.hex`: words of `32 + outputs_width` bits, `{cycle[31:0], outputs}` with the
//!   outputs concatenated in [`crate::output_fields`] order (the first field in the most
//!   significant bits); word 0 is `{entry_count, 0}`; each further word holds the outputs
//!   registered after rising edge `cycle` and every later edge until the next entry. The
//!   first entry is at cycle 0.
//!
//! Rising edge `k` of the clock is at time `k·P` ns (`P = 1e9 / clock_hz`), as the VCD
//! contract asks; pins for clock `k` are applied half a period before it; outputs are
//! compared half a period after it. The testbench makes its own clock under Icarus and
//! under Verilator with `--timing` (`verilator --binary`); a Verilator build without
//! `--timing` (quicker to build and to run) gets its clock from the C++ driver of
//! [`crate::verilator_main`].
//!
//! Before `$readmemh` reads a file, the testbench reads it once character by character
//! (`$fgetc`), because `$readmemh` says nothing useful when a file is missing, short or
//! holds X: Icarus fills what is missing with X, Verilator (two-state) with 0 or random
//! bits. So every run first checks, and stops with `TESTBENCH ERROR <file>: …` and
//! `$fatal` (a non-zero exit under both simulators), that each file opens; holds only
//! whitespace-separated hex words (an X, Z or other character is named with its line),
//! none wider than its word; no more words than the memory holds; as many words after
//! the header as the header says; stimulus segments of at least one clock, at most
//! [`MAX_CYCLES`] in all; expected entries from cycle 0 on, in increasing cycle order.
//! Depths are checked where they are set: [`testbench`] refuses a depth outside
//! `2..=`[`MAX_DEPTH`].
//!
//! Plusargs: `+vcd` dumps the design to `dut.vcd`, `+fst` to `dut.fst` (`+vcd=FILE`,
//! `+fst=FILE`: to FILE); the simulator picks the format (Icarus: VCD, FST with `vvp -fst`;
//! Verilator: the one its build traces, `--trace` VCD, `--trace-fst` FST, no dump without
//! either). The testbench's own copies of the outputs are `dut_<name>`, so a dump of the
//! whole testbench holds the golden names only in the DUT's scope;
//! `+nostop` keeps running after a mismatch (to get a whole trace) instead of `$fatal`.
//! The last line is `TESTBENCH OK <cycles>`, or `TESTBENCH FAIL <mismatching cycles>
//! <cycles>` with `+nostop`.

use crate::design::TOP;
use crate::emit::{describe, lit};
use crate::mcu::mcu_words;
use crate::mcu::{MCU_ADDR_BITS, MCU_DATA_BITS};
use crate::outputs::{output_fields, outputs_width};
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::MeasureConfig;

/// Stimulus file name.
pub const STIM_HEX: &str = "stim.hex";
/// Expected-response file name.
pub const EXPECT_HEX: &str = "expect.hex";
/// Bits per stimulus word: `{pins[7:0], cycles[31:0]}`.
pub const STIM_WORD_BITS: u32 = 40;
/// Largest memory depth of the testbench, words (2^26): far inside its 32-bit Verilog
/// `integer` indices, and 2^26 words are already 0.5 GB of simulator memory.
pub const MAX_DEPTH: usize = 1 << 26;
/// Most clock cycles one stimulus may hold (2^31 - 1): the testbench counts cycles in a
/// Verilog `integer` (32-bit signed).
pub const MAX_CYCLES: u64 = i32::MAX as u64;

/// What a testbench is built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TestbenchSpec {
    /// Clock frequency, Hz; must divide 1e9 and give a period of at least 2 ns.
    pub clock_hz: u32,
    /// Memory depth for `stim.hex`, words (header included): the longest stimulus the
    /// compiled testbench accepts; `2..=`[`MAX_DEPTH`].
    pub stim_depth: usize,
    /// Memory depth for `expect.hex`, words (header included); `2..=`[`MAX_DEPTH`].
    pub expect_depth: usize,
    /// The design was generated with [`crate::Options::mcu_diagnostics`]: the expected
    /// MCU words include the diagnostic counters.
    pub mcu_diagnostics: bool,
}

impl TestbenchSpec {
    /// Clock period, ns, or `None` when `clock_hz` does not divide 1e9 or the period is
    /// below 2 ns.
    pub fn period_ns(&self) -> Option<u32> {
        if self.clock_hz == 0 || 1_000_000_000 % self.clock_hz != 0 {
            return None;
        }
        let p = 1_000_000_000 / self.clock_hz;
        (p >= 2).then_some(p)
    }

    /// Whether both depths are in `2..=`[`MAX_DEPTH`].
    pub fn depths_fit(&self) -> bool {
        let fits = |d: usize| (2..=MAX_DEPTH).contains(&d);
        fits(self.stim_depth) && fits(self.expect_depth)
    }
}

/// Name of the testbench module (and its file, `tt_testbench.v`).
pub const TESTBENCH: &str = "tt_testbench";

/// Writes the testbench for `config` (file `tt_testbench.v`). Returns `None` when the
/// clock is not usable (see [`TestbenchSpec::period_ns`]) or a depth is out of range
/// (see [`TestbenchSpec::depths_fit`]).
pub fn testbench(
    config: &MeasureConfig,
    spec: &TestbenchSpec,
) -> Option<crate::design::VerilogFile> {
    let period = spec.period_ns()?;
    if !spec.depths_fit() {
        return None;
    }
    let fields = output_fields(config);
    let width = outputs_width(config);
    let ew = width + 32;
    let mut wires = String::new();
    let mut expected = String::new();
    let mut conns = String::new();
    let mut compare = String::new();
    let mut lo = width;
    for f in &fields {
        let range = if f.width == 1 {
            String::new()
        } else {
            format!("[{}:0] ", f.width - 1)
        };
        let hi = lo - 1;
        lo -= f.width;
        // `dut_` names: a dump of the whole testbench (Verilator's) must not hold the
        // golden output names outside the DUT's scope.
        wires.push_str(&format!("    wire {range}dut_{};\n", f.name));
        expected.push_str(&format!(
            "    wire {range}exp_{0} = expected[{hi}:{lo}];\n",
            f.name
        ));
        conns.push_str(&format!("        .{0}(dut_{0}),\n", f.name));
        compare.push_str(&format!(
            "            if (dut_{0} !== exp_{0}) report(\"{0}\", {{{pad}exp_{0}}}, {{{pad}dut_{0}}});\n",
            f.name,
            pad = if f.width < 64 {
                format!("{}'d0, ", 64 - f.width)
            } else {
                String::new()
            }
        ));
    }
    let words = mcu_words(config, config.hash(), "exp_", spec.mcu_diagnostics);
    let mcu_names: String = crate::mcu::MCU_REGISTERS
        .iter()
        .map(|r| {
            format!(
                "            {}: mcu_name = \"{}\";\n",
                crate::emit::lit(MCU_ADDR_BITS, r.addr.into()),
                r.name
            )
        })
        .collect();
    let mut mcu = String::new();
    for (i, w) in words.iter().enumerate() {
        mcu.push_str(&format!(
            "            {}: exp_rdata = {w};\n",
            lit(MCU_ADDR_BITS, i as u64)
        ));
    }
    let pin_conns: String = pin::NAMES
        .iter()
        .enumerate()
        .map(|(i, n)| format!("        .pin_{n}(pins[{i}]),\n"))
        .collect();
    let text = format!(
        r#"// {TESTBENCH}: self-checking testbench of {TOP}
// Generated by tooltouch-hdl-gen from MeasureConfig hash {hash:016x}
// ({summary}).
// Reads {STIM_HEX} and {EXPECT_HEX} (written by the golden model) from the working
// directory after checking them (a missing file, an X, Z or non-hex character, a word too
// wide, more words than the depth or not as many as the header says: TESTBENCH ERROR and
// $fatal); compares every output on every cycle. Clock {clock_hz} Hz, period {period} ns:
// rising edge k at time k*{period} ns. Plusargs: +nostop, +vcd[=FILE] (dump dut.vcd),
// +fst[=FILE] (dump dut.fst: vvp tb -fst +fst, or Verilator built with --trace-fst).
// Run in that directory with Icarus,    iverilog -g2005 -o tb *.v && vvp tb
//                     or with Verilator 5, verilator --binary --top-module {TESTBENCH} -o tb *.v && obj_dir/tb
`timescale 1ns / 1ns
`default_nettype none

// Built by Verilator without --timing, the testbench gets its clock from the C++ driver
// tt_testbench_main.cpp.
`ifdef VERILATOR
`ifndef VERILATOR_TIMING
`define TT_TESTBENCH_EXTERNAL_CLOCK
`endif
`endif

`ifdef TT_TESTBENCH_EXTERNAL_CLOCK
module {TESTBENCH} (clk);
`else
module {TESTBENCH};
`endif
    localparam integer PERIOD        = {period};
    localparam integer HIGH          = {high};
    localparam integer STIM_DEPTH    = {stim_depth};
    localparam integer EXPECT_DEPTH  = {expect_depth};
    localparam [63:0]  MAX_CYCLES    = 64'd{max_cycles};  // the cycle counter is an integer

    reg [{sw1}:0] stim_mem   [0:STIM_DEPTH-1];
    reg [{ew1}:0] expect_mem [0:EXPECT_DEPTH-1];

`ifdef TT_TESTBENCH_EXTERNAL_CLOCK
    input  wire clk;   // driven by tt_testbench_main.cpp
`else
    reg        clk = 1'b0;
`endif
    reg        rst = 1'b0;
    reg [{n1}:0]  pins = {n}'d0;
    reg [{ab1}:0]  mcu_addr = {ab}'d0;
    wire [{db1}:0] mcu_rdata;
    wire       irq;
{wires}
    reg [{w1}:0] expected = {w}'d0;
{expected}
    reg [{db1}:0] exp_rdata;
    always @* begin
        case (mcu_addr)
{mcu}            default: exp_rdata = {db}'d0;
        endcase
    end
    reg [8*24-1:0] mcu_name;  // the register mcu_addr names, for the mismatch report
    always @* begin
        case (mcu_addr)
{mcu_names}            default: mcu_name = "unmapped, reads 0";
        endcase
    end

    {TOP} dut (
        .clk(clk), .rst(rst),
{pin_conns}        .mcu_addr(mcu_addr), .mcu_rdata(mcu_rdata),
{conns}        .irq(irq)
    );

    integer    k;            // rising edge index
    integer    segment;      // current stimulus word
    integer    segments;     // stimulus words after the header
    integer    entry;        // next expected word
    integer    entries;      // expected words after the header
    integer    bad_cycles;   // cycles with at least one mismatch
    integer    bad_signals;  // mismatches in this cycle
    integer    stim_words;   // words in {STIM_HEX}, header included
    integer    expect_words; // words in {EXPECT_HEX}, header included
    integer    i;
    reg [63:0] total;        // clocks of the stimulus
    reg [31:0] left;         // clocks left in the current segment
    reg [{sw1}:0] stim_word;
    reg [{ew1}:0] expect_word;
    reg [31:0] next_cycle;   // cycle of the next expected word
    reg [31:0] previous_cycle;
    reg        nostop;
    reg [8*256-1:0] dump_file; // +vcd=FILE / +fst=FILE
    reg        ready = 1'b0; // the vectors are read and checked

    reg [63:0] k_time;       // k*PERIOD ns: the time `tooltouch check` names clock k by

    task report(input [8*24-1:0] name, input [63:0] want, input [63:0] got);
        begin
            k_time = {{32'd0, k}} * {{32'd0, PERIOD}};
            if (bad_cycles == 0 && bad_signals == 0)
                $display("MISMATCH cycle %0d (time %0d ns): signal %0s expected 0x%0h got 0x%0h",
                         k, k_time, name, want, got);
            bad_signals = bad_signals + 1;
        end
    endtask

    // Reads the vector file `name` once before $readmemh does, because $readmemh fills what
    // is missing with X (Icarus) or 0 (Verilator) without a word, and Verilator reads an X
    // digit as 0: the file must open and hold only whitespace-separated hex words (no X or
    // Z digit, comment or address) of at most `bits` bits, at most `depth` of them.
    // `words`: how many it holds. Verilator reads it character by character (compiled,
    // quick); Icarus word by word ($fscanf keeps X and Z digits as X bits).
    task scan(input [8*10-1:0] name, input integer bits, input integer depth,
              output integer words);
        integer fd;
`ifdef VERILATOR
        integer c;       // character read, -1 at the end of the file
        integer n;       // digits of the word being read
        integer lead;    // value of its first digit
        integer digits;  // hex digits of a full word
`else
        integer r;       // $fscanf's count
        reg [{scan_msb}:0] value;
`endif
        begin
            fd = $fopen(name, "r");
            if (fd == 0) begin
                $display("TESTBENCH ERROR %0s: cannot open it in the working directory (tooltouch hdl --vectors or tooltouch vectors writes it)",
                         name);
                $fatal(1, "missing vector file");
            end
            words = 0;
`ifdef VERILATOR
            digits = (bits + 3) / 4;
            n      = 0;
            lead   = 0;
            c      = $fgetc(fd);
            while (c != -1) begin
                if (c == 32 || c == 9 || c == 13 || c == 10) begin  // space, tab, CR, LF
                    if (n > 0) words = words + 1;
                    n = 0;
                end else if ((c >= 48 && c <= 57) || (c >= 65 && c <= 70) || (c >= 97 && c <= 102)) begin
                    if (n == 0 && words == depth) too_long(name, depth);
                    if (n == 0) lead = (c <= 57) ? c - 48 : (c | 32) - 87;
                    n = n + 1;
                    if (n > digits || (n == digits && lead >= (1 << (bits - 4 * (digits - 1)))))
                        too_wide(name, words, bits);
                end else if (c == 120 || c == 88 || c == 122 || c == 90 || c == 63) begin  // x X z Z ?
                    x_or_z(name, words);
                end else begin
                    not_hex(name, words);
                end
                c = $fgetc(fd);
            end
            if (n > 0) words = words + 1;
`else
            r = $fscanf(fd, "%h", value);
            while (r == 1) begin
                if (words == depth) too_long(name, depth);
                if (^value === 1'bx) x_or_z(name, words);
                if ((value >> bits) != 0) too_wide(name, words, bits);
                words = words + 1;
                r = $fscanf(fd, "%h", value);
            end
            if (!$feof(fd)) not_hex(name, words);
`endif
            $fclose(fd);
            if (words < 2) begin
                $display("TESTBENCH ERROR %0s: %0d words; it needs its header and at least one more",
                         name, words);
                $fatal(1, "vector file too short");
            end
        end
    endtask

    // The errors `scan` reports; `word` counts from 0 (the header), as $readmemh addresses.
    task too_long(input [8*10-1:0] name, input integer depth);
        begin
            $display("TESTBENCH ERROR %0s: more than %0d words, the depth this testbench was generated for (tooltouch hdl sizes it: --stim-depth, --expect-depth)",
                     name, depth);
            $fatal(1, "vector file longer than the memory");
        end
    endtask
    task too_wide(input [8*10-1:0] name, input integer word, input integer bits);
        begin
            $display("TESTBENCH ERROR %0s word %0d: wider than %0d bits", name, word, bits);
            $fatal(1, "vector word too wide");
        end
    endtask
    task x_or_z(input [8*10-1:0] name, input integer word);
        begin
            $display("TESTBENCH ERROR %0s word %0d: an X or Z digit; every word must be a number",
                     name, word);
            $fatal(1, "X or Z in a vector file");
        end
    endtask
    task not_hex(input [8*10-1:0] name, input integer word);
        begin
            $display("TESTBENCH ERROR %0s word %0d: a character that is not a hex digit", name, word);
            $fatal(1, "not a hex digit in a vector file");
        end
    endtask

    initial begin
        scan("{STIM_HEX}", {sw}, STIM_DEPTH, stim_words);
        scan("{EXPECT_HEX}", {ew}, EXPECT_DEPTH, expect_words);
        $readmemh("{STIM_HEX}", stim_mem, 0, stim_words - 1);
        $readmemh("{EXPECT_HEX}", expect_mem, 0, expect_words - 1);
        nostop = $test$plusargs("nostop");
        // +fst[=FILE] / +vcd[=FILE]: dump the design. The simulator picks the format:
        // Icarus writes VCD unless run with -fst (vvp tb -fst +fst), Verilator the one its
        // build traces (--trace-fst: FST, --trace: VCD; without either no dump).
        if ($value$plusargs("fst=%s", dump_file)) begin
            $dumpfile(dump_file);
            $dumpvars(0, dut);
        end else if ($test$plusargs("fst")) begin
            $dumpfile("dut.fst");
            $dumpvars(0, dut);
        end else if ($value$plusargs("vcd=%s", dump_file)) begin
            $dumpfile(dump_file);
            $dumpvars(0, dut);
        end else if ($test$plusargs("vcd")) begin
            $dumpfile("dut.vcd");
            $dumpvars(0, dut);
        end
        // Headers: word 0 counts the words after it.
        segments    = stim_words - 1;
        entries     = expect_words - 1;
        stim_word   = stim_mem[0];
        if (stim_word[31:0] != segments) begin
            $display("TESTBENCH ERROR {STIM_HEX}: its header says %0d segments, the file holds %0d words after it",
                     stim_word[31:0], segments);
            $fatal(1, "stimulus shorter or longer than its header");
        end
        expect_word = expect_mem[0];
        if (expect_word[{ew1}:{w}] != entries) begin
            $display("TESTBENCH ERROR {EXPECT_HEX}: its header says %0d entries, the file holds %0d words after it",
                     expect_word[{ew1}:{w}], entries);
            $fatal(1, "expected response shorter or longer than its header");
        end
        // Segments of at least one clock, at most MAX_CYCLES in all.
        total = 64'd0;
        for (i = 1; i <= segments; i = i + 1) begin
            stim_word = stim_mem[i];
            if (stim_word[31:0] == 32'd0) begin
                $display("TESTBENCH ERROR {STIM_HEX} word %0d: a segment of 0 clocks", i);
                $fatal(1, "empty stimulus segment");
            end
            total = total + {{32'd0, stim_word[31:0]}};
        end
        if (total > MAX_CYCLES) begin
            $display("TESTBENCH ERROR {STIM_HEX}: %0d clocks, more than the testbench counts (%0d)",
                     total, MAX_CYCLES);
            $fatal(1, "stimulus too long");
        end
        // Entries from cycle 0 on, in increasing order, within the stimulus.
        for (i = 1; i <= entries; i = i + 1) begin
            expect_word = expect_mem[i];
            next_cycle  = expect_word[{ew1}:{w}];
            if ((i == 1 && next_cycle != 32'd0) || (i > 1 && next_cycle <= previous_cycle)
                    || {{32'd0, next_cycle}} >= total) begin
                $display("TESTBENCH ERROR {EXPECT_HEX} word %0d: an entry for cycle %0d; entries run from cycle 0 in increasing order, before cycle %0d (the stimulus's length)",
                         i, next_cycle, total);
                $fatal(1, "expected entry out of order");
            end
            previous_cycle = next_cycle;
        end
        segment     = 1;
        stim_word   = stim_mem[1];
        pins        = stim_word[{pin_hi}:32];
        left        = stim_word[31:0];
        entry       = 1;
        expect_word = expect_mem[1];
        next_cycle  = expect_word[{ew1}:{w}];
        bad_cycles  = 0;
        k           = 0;
        ready       = 1'b1;
    end

`ifndef TT_TESTBENCH_EXTERNAL_CLOCK
    // The clock (Verilator without --timing: driven by tt_testbench_main.cpp): rising edge
    // k at time k*PERIOD, the first once the vectors are read; #0 lets every process reach
    // its event control before that edge (Verilator resumes after a #0 in a later
    // evaluation of the same time step, not in the inactive region: the same here).
    initial begin
        wait (ready);
        /* verilator lint_off ZERODLY */
        #0;
        /* verilator lint_on ZERODLY */
        forever begin
            clk = 1'b1;
            #(HIGH);
            clk = 1'b0;
            #(PERIOD - HIGH);
        end
    end
`endif

    // Rising edge k: the address of the MCU read, and the outputs the model registered at
    // edge k (the exp_* wires settle before the compare at the falling edge).
    always @(posedge clk) begin
        mcu_addr = k[{ab1}:0];
        if (entry <= entries && next_cycle == k[31:0]) begin
            expect_word = expect_mem[entry];
            expected    = expect_word[{w1}:0];
            entry       = entry + 1;
            if (entry <= entries) begin
                expect_word = expect_mem[entry];
                next_cycle  = expect_word[{ew1}:{w}];
            end
        end
    end

    // Falling edge after edge k: compare, then the pins for clock k+1.
    always @(negedge clk) begin
        // One compare of every output bit; the field-by-field report only on a mismatch.
        if ({{{concat}}} !== expected || irq !== exp_register_now || mcu_rdata !== exp_rdata) begin
            bad_signals = 0;
{compare}            if (irq !== exp_register_now) report("irq", {{63'd0, exp_register_now}}, {{63'd0, irq}});
            if (mcu_rdata !== exp_rdata) report("mcu_rdata", {{{dpad}exp_rdata}}, {{{dpad}mcu_rdata}});
            if (mcu_rdata !== exp_rdata && bad_cycles == 0)
                $display("  mcu_rdata read at mcu_addr %0d: %0s", mcu_addr, mcu_name);
            bad_cycles = bad_cycles + 1;
            if (!nostop) $fatal(1, "TESTBENCH FAIL at cycle %0d", k);
        end
        left = left - 32'd1;
        if (left == 32'd0) begin
            segment = segment + 1;
            if (segment <= segments) begin
                stim_word = stim_mem[segment];
                pins      = stim_word[{pin_hi}:32];
                left      = stim_word[31:0];
            end
        end
        k = k + 1;
        if (segment > segments) begin
            if (bad_cycles != 0)
                $display("TESTBENCH FAIL %0d %0d", bad_cycles, k);
            else
                $display("TESTBENCH OK %0d", k);
            $finish;
        end
    end
endmodule

`undef TT_TESTBENCH_EXTERNAL_CLOCK
`default_nettype wire
"#,
        hash = config.hash(),
        summary = describe(config),
        clock_hz = spec.clock_hz,
        high = period / 2,
        stim_depth = spec.stim_depth,
        expect_depth = spec.expect_depth,
        sw = STIM_WORD_BITS,
        ew = ew,
        scan_msb = ew.max(STIM_WORD_BITS) + 63,
        max_cycles = MAX_CYCLES,
        sw1 = STIM_WORD_BITS - 1,
        pin_hi = 32 + pin::COUNT - 1,
        ew1 = ew - 1,
        w = width,
        w1 = width - 1,
        n = pin::COUNT,
        n1 = pin::COUNT - 1,
        ab = MCU_ADDR_BITS,
        ab1 = MCU_ADDR_BITS - 1,
        db = MCU_DATA_BITS,
        db1 = MCU_DATA_BITS - 1,
        dpad = format!("{}'d0, ", 64 - MCU_DATA_BITS),
        concat = fields
            .iter()
            .map(|f| format!("dut_{}", f.name))
            .collect::<Vec<_>>()
            .join(", "),
    );
    Some(crate::design::VerilogFile {
        name: format!("{TESTBENCH}.v"),
        text,
    })
}
