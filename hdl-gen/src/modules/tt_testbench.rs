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
//! compared half a period after it. Under Icarus the testbench makes its own clock; under
//! Verilator (built without `--timing`) the C++ driver of [`crate::verilator_main`] clocks it.
//! Plusargs: `+vcd` dumps the design to `dut.vcd` (Icarus);
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

/// What a testbench is built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TestbenchSpec {
    /// Clock frequency, Hz; must divide 1e9 and give a period of at least 2 ns.
    pub clock_hz: u32,
    /// Memory depth for `stim.hex`, words (header included): the longest stimulus the
    /// compiled testbench accepts.
    pub stim_depth: usize,
    /// Memory depth for `expect.hex`, words (header included).
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
}

/// Name of the testbench module (and its file, `tt_testbench.v`).
pub const TESTBENCH: &str = "tt_testbench";

/// Writes the testbench for `config` (file `tt_testbench.v`). Returns `None` when the
/// clock is not usable (see [`TestbenchSpec::period_ns`]).
pub fn testbench(
    config: &MeasureConfig,
    spec: &TestbenchSpec,
) -> Option<crate::design::VerilogFile> {
    let period = spec.period_ns()?;
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
        wires.push_str(&format!("    wire {range}{};\n", f.name));
        expected.push_str(&format!(
            "    wire {range}exp_{0} = expected[{hi}:{lo}];\n",
            f.name
        ));
        conns.push_str(&format!("        .{0}({0}),\n", f.name));
        compare.push_str(&format!(
            "            if ({0} !== exp_{0}) report(\"{0}\", {{{pad}exp_{0}}}, {{{pad}{0}}});\n",
            f.name,
            pad = if f.width < 64 {
                format!("{}'d0, ", 64 - f.width)
            } else {
                String::new()
            }
        ));
    }
    let words = mcu_words(config, "exp_", spec.mcu_diagnostics);
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
// directory; compares every output on every cycle. Clock {clock_hz} Hz, period {period} ns:
// rising edge k at time k*{period} ns. Plusargs: +vcd (dump dut.vcd), +nostop.
`timescale 1ns / 1ns
`default_nettype none

`ifdef VERILATOR
module {TESTBENCH} (clk);
`else
module {TESTBENCH};
`endif
    localparam integer PERIOD       = {period};
    localparam integer HIGH         = {high};
    localparam integer STIM_DEPTH   = {stim_depth};
    localparam integer EXPECT_DEPTH = {expect_depth};

    reg [{sw1}:0] stim_mem   [0:STIM_DEPTH-1];
    reg [{ew1}:0] expect_mem [0:EXPECT_DEPTH-1];

`ifdef VERILATOR
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
    reg [31:0] left;         // clocks left in the current segment
    reg [{sw1}:0] stim_word;
    reg [{ew1}:0] expect_word;
    reg [31:0] next_cycle;   // cycle of the next expected word
    reg        nostop;

    task report(input [8*24-1:0] name, input [63:0] want, input [63:0] got);
        begin
            if (bad_cycles == 0 && bad_signals == 0)
                $display("MISMATCH cycle %0d (time %0t ns): signal %0s expected 0x%0h got 0x%0h",
                         k, $time, name, want, got);
            bad_signals = bad_signals + 1;
        end
    endtask

    initial begin
        $readmemh("{STIM_HEX}", stim_mem);
        $readmemh("{EXPECT_HEX}", expect_mem);
        nostop = $test$plusargs("nostop");
`ifndef VERILATOR
        if ($test$plusargs("vcd")) begin
            $dumpfile("dut.vcd");
            $dumpvars(0, dut);
        end
`endif
        stim_word   = stim_mem[0];
        segments    = stim_word[31:0];
        expect_word = expect_mem[0];
        entries     = expect_word[{ew1}:{w}];
        if (segments < 1 || segments >= STIM_DEPTH || entries < 1 || entries >= EXPECT_DEPTH) begin
            $display("TESTBENCH ERROR bad vector headers: %0d segments (depth %0d), %0d entries (depth %0d)",
                     segments, STIM_DEPTH, entries, EXPECT_DEPTH);
            $fatal(1, "bad vectors");
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
    end

`ifndef VERILATOR
    // The clock (Verilator: driven by tt_testbench_main.cpp, without --timing): rising
    // edge k at time k*PERIOD; #0 lets every process reach its event control first.
    initial begin
        #0;
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
            if (entry <= entries) begin
                $display("TESTBENCH ERROR %0d expected entries left unused after %0d cycles",
                         entries - entry + 1, k);
                $fatal(1, "expected response longer than the stimulus");
            end
            if (bad_cycles != 0)
                $display("TESTBENCH FAIL %0d %0d", bad_cycles, k);
            else
                $display("TESTBENCH OK %0d", k);
            $finish;
        end
    end
endmodule

`default_nettype wire
"#,
        hash = config.hash(),
        summary = describe(config),
        clock_hz = spec.clock_hz,
        high = period / 2,
        stim_depth = spec.stim_depth.max(2),
        expect_depth = spec.expect_depth.max(2),
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
        concat = fields.iter().map(|f| f.name).collect::<Vec<_>>().join(", "),
    );
    Some(crate::design::VerilogFile {
        name: format!("{TESTBENCH}.v"),
        text,
    })
}
