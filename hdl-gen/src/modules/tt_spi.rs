//! `tt_spi.v`: the SPI register interface ([`crate::spi`]): an SPI mode-0 slave with SCK,
//! CS and MOSI sampled in the FPGA clock, the read mux of the SPI map (the MCU words
//! through `tt_frontend`'s own read mux, the extra output words, the thresholds, status
//! and settings CRC), and the run-time threshold registers with their range checks and
//! the write interlock.

use crate::design::VerilogFile;
use crate::emit::{fill, lit, Context};
use crate::spi::{
    extra_outputs, settings_crc, status, Threshold, SPI_ADDR_BITS, SPI_CONTROL_ADDR,
    SPI_EXTRA_BASE, SPI_FRAME_BITS, SPI_MIN_PHASE_CLOCKS, SPI_MODULE, SPI_SETTINGS_CRC_ADDR,
    SPI_STATUS_ADDR,
};

/// The register file's name for a threshold's register.
fn reg(t: Threshold) -> String {
    format!("{}_q", t.port())
}

/// The SPI register interface.
pub(crate) fn emit(ctx: &Context) -> VerilogFile {
    let c = &ctx.config;
    let s = c.settings();
    let a = |addr: u8| lit(SPI_ADDR_BITS, addr.into());
    let extras = extra_outputs(c);
    let mut ports = String::new();
    for f in &extras {
        ports.push_str(&format!(
            "    input  wire [{}:0] {},  // output word at {}\n",
            f.width - 1,
            f.name,
            a(SPI_EXTRA_BASE)
        ));
    }
    let mut regs = String::new();
    let mut read_arms = String::new();
    let mut checks = String::new();
    let mut writes = String::new();
    let mut restore = String::new();
    let zext = |name: &str, w: u32| {
        if w >= 32 {
            name.to_string()
        } else {
            format!("{{{}'d0, {name}}}", 32 - w)
        }
    };
    for (i, f) in extras.iter().enumerate() {
        read_arms.push_str(&format!(
            "            {}: rd_word = {};  // {}\n",
            a(SPI_EXTRA_BASE + i as u8),
            zext(f.name, f.width),
            f.name.to_ascii_uppercase()
        ));
    }
    for t in Threshold::ALL {
        let w = t.width(c);
        let reset = lit(w, t.value(s).into());
        let r = reg(t);
        ports.push_str(&format!(
            "    output wire [{}:0] {},  // run-time threshold, resets to {}\n",
            w - 1,
            t.port(),
            t.value(s)
        ));
        regs.push_str(&format!(
            "    reg  [{}:0] {r} = {reset};\n    assign {} = {r};\n",
            w - 1,
            t.port()
        ));
        read_arms.push_str(&format!(
            "            {}: rd_word = {};  // {}\n",
            a(t.addr()),
            zext(&r, w),
            t.name()
        ));
        let min = t.min(c);
        let mut ok = format!("(data_q <= 32'd{})", t.max(c));
        if min > 0 {
            ok.push_str(&format!(" && (data_q >= 32'd{min})"));
        }
        match t {
            Threshold::FireThreshold => ok.push_str(&format!(
                " && (data_q > {})",
                zext(&reg(Threshold::RearmThreshold), w)
            )),
            Threshold::RearmThreshold => ok.push_str(&format!(
                " && (data_q < {})",
                zext(&reg(Threshold::FireThreshold), w)
            )),
            _ => {}
        }
        checks.push_str(&format!("    wire ok_{} = {ok};\n", t.port()));
        writes.push_str(&format!(
            "                {}: begin  // {}\n\
             \x20                   if (interlock) errors_q <= errors_q | ERR_ARMED;\n\
             \x20                   else if (!ok_{p}) errors_q <= errors_q | ERR_RANGE;\n\
             \x20                   else begin\n\
             \x20                       {r} <= data_q[{w1}:0];\n\
             \x20                       writes_q <= writes_q + 8'd1;\n\
             \x20                   end\n\
             \x20               end\n",
            a(t.addr()),
            t.name(),
            p = t.port(),
            w1 = w - 1
        ));
        restore.push_str(&format!("                        {r} <= {reset};\n"));
    }
    let body = fill(
        r#"// SPI register interface, mode 0 (CPOL 0, CPHA 0), MSB first. A frame is CS low for
// exactly ${FRAME} SCK cycles: a command byte (bit 7: write, bits 6..0: address) and a
// 32-bit data word. During the command byte MISO shifts out the status word's low byte,
// then the addressed word (reads; zeros for writes), captured at the command's last
// bit. A write acts when CS rises after exactly ${FRAME} bits, SCK never faster than
// allowed: otherwise nothing is written and the status says why. SCK, CS and MOSI are
// sampled in the FPGA clock: each SCK phase must last at least ${MINPH} clocks
// (SCK <= f_clk / 4), CS must fall 4 clocks before the first SCK edge.
module ${MODULE} (
    input  wire        clk,
    input  wire        spi_sck,
    input  wire        spi_cs_n,
    input  wire        spi_mosi,
    output wire        spi_miso,
    input  wire        arm_level,   // filtered arm level: threshold writes wait for disarm
    input  wire        armed,
    output wire [3:0]  mcu_addr,    // the MCU register map, read through tt_frontend
    input  wire [31:0] mcu_rdata,
${PORTS}    output reg         kernel_rst   // CONTROL bit 0: one clock of the kernel's reset
);
    localparam [5:0] FRAME_BITS = 6'd${FRAME};
    localparam [4:0] ERR_READ_ONLY = 5'd${E_RO};
    localparam [4:0] ERR_RANGE     = 5'd${E_RANGE};
    localparam [4:0] ERR_ARMED     = 5'd${E_ARMED};
    localparam [4:0] ERR_TORN      = 5'd${E_TORN};
    localparam [4:0] ERR_SCK_FAST  = 5'd${E_FAST};

    // Two flip-flops each for SCK, CS and MOSI (the same delay, so MOSI is read at the
    // synchronized rising edge, where the master holds it stable).
    reg [1:0] sck_s  = 2'b00;
    reg [1:0] cs_s   = 2'b11;
    reg [1:0] mosi_s = 2'b00;
    reg       sck_q  = 1'b0;  // synchronized SCK, one clock earlier
    reg       cs_q   = 1'b1;  // synchronized CS, one clock earlier
    always @(posedge clk) begin
        sck_s  <= {sck_s[0], spi_sck};
        cs_s   <= {cs_s[0], spi_cs_n};
        mosi_s <= {mosi_s[0], spi_mosi};
        sck_q  <= sck_s[1];
        cs_q   <= cs_s[1];
    end
    wire sck         = sck_s[1];
    wire cs_n        = cs_s[1];
    wire mosi        = mosi_s[1];
    wire sck_edge    = sck != sck_q;
    wire sck_rise    = sck && !sck_q && !cs_n;
    wire frame_start = !cs_n && cs_q;
    wire frame_end   = cs_n && !cs_q;

    reg [5:0]  bits_q   = 6'd0;   // bits of this frame, saturating at 63
    reg [7:0]  cmd_q    = 8'd0;   // the command byte
    reg [31:0] data_q   = 32'd0;  // the data word shifted in
    reg [31:0] out_q    = 32'd0;  // shifted out, MSB first on MISO
    reg [1:0]  phase_q  = 2'd3;   // clocks the synchronized SCK has held its level, saturating
    reg        fast_q   = 1'b0;   // an SCK phase of this frame was shorter than ${MINPH} clocks
    reg [4:0]  errors_q = 5'd0;   // sticky error flags (status bits 4..0)
    reg [7:0]  writes_q = 8'd0;   // accepted threshold writes, wrapping (status bits 15..8)
    wire [31:0] status  = {16'd0, writes_q, 3'd0, errors_q};

    assign spi_miso = out_q[31];

    // The run-time thresholds, at the configured values from power-on.
${REGS}
    // Settings CRC: CRC-32/MPEG-2 from all ones over the six threshold words in address
    // order (an affine function of their bits, written out), registered.
    wire [31:0] crc_next;
${CRC}    reg  [31:0] crc_q = 32'h${CRC0};

    // The word the command byte addresses, decoded at its eighth rising edge from the
    // seven bits held and the eighth on MOSI.
    wire [6:0] rd_addr = {cmd_q[5:0], mosi};
    assign mcu_addr = rd_addr[3:0];
    reg [31:0] rd_word;
    always @* begin
        case (rd_addr)
${READ_ARMS}            ${A_STATUS}: rd_word = status;  // SPI_STATUS
            ${A_CRC}: rd_word = crc_q;  // SETTINGS_CRC
            default: rd_word = (rd_addr[6:4] == 3'd0) ? mcu_rdata : 32'd0;  // MCU words
        endcase
    end

    always @(posedge clk) begin
        crc_q <= crc_next;
        // SCK phase lengths inside a frame.
        if (sck_edge) begin
            if (!cs_n && phase_q < 2'd${MINPH}) fast_q <= 1'b1;
            phase_q <= 2'd1;
        end else if (phase_q != 2'd3) begin
            phase_q <= phase_q + 2'd1;
        end
        if (frame_start) begin
            bits_q <= 6'd0;
            fast_q <= 1'b0;
            out_q  <= {status[7:0], 24'd0};
        end else if (sck_rise) begin
            if (bits_q != 6'd63) bits_q <= bits_q + 6'd1;
            if (bits_q < 6'd8) cmd_q <= {cmd_q[6:0], mosi};
            else data_q <= {data_q[30:0], mosi};
            out_q <= (bits_q == 6'd7) ? (cmd_q[6] ? 32'd0 : rd_word) : {out_q[30:0], 1'b0};
        end
    end

    // Range checks of the data word for each threshold (rearm < fire against the
    // other register in force), and the interlock: no threshold write while armed.
${CHECKS}    wire interlock = arm_level || armed;

    // The end of a frame: a torn or too fast frame is reported; a complete write acts.
    always @(posedge clk) begin
        kernel_rst <= 1'b0;
        if (frame_end && bits_q != 6'd0) begin
            if (bits_q != FRAME_BITS) errors_q <= errors_q | ERR_TORN;
            else if (fast_q) errors_q <= errors_q | ERR_SCK_FAST;
            else if (cmd_q[7]) begin
                case (cmd_q[6:0])
${WRITES}                ${A_STATUS}: errors_q <= errors_q & ~data_q[4:0];  // SPI_STATUS
                ${A_CONTROL}: begin  // CONTROL
                    kernel_rst <= data_q[0];
                    if (data_q[1]) begin
${RESTORE}                    end
                end
                default: errors_q <= errors_q | ERR_READ_ONLY;
                endcase
            end
        end
    end
endmodule
"#,
        &[
            ("MODULE", SPI_MODULE.to_string()),
            ("FRAME", SPI_FRAME_BITS.to_string()),
            ("MINPH", SPI_MIN_PHASE_CLOCKS.to_string()),
            ("E_RO", status::READ_ONLY.to_string()),
            ("E_RANGE", status::RANGE.to_string()),
            ("E_ARMED", status::ARMED.to_string()),
            ("E_TORN", status::TORN.to_string()),
            ("E_FAST", status::SCK_FAST.to_string()),
            ("PORTS", ports),
            ("REGS", regs),
            ("CRC", crc_logic(ctx)),
            (
                "CRC0",
                format!(
                    "{:08x}",
                    settings_crc(&crate::spi::threshold_words(c.settings()))
                ),
            ),
            ("READ_ARMS", read_arms),
            ("A_STATUS", a(SPI_STATUS_ADDR)),
            ("A_CRC", a(SPI_SETTINGS_CRC_ADDR)),
            ("A_CONTROL", a(SPI_CONTROL_ADDR)),
            ("CHECKS", checks),
            ("WRITES", writes),
            ("RESTORE", restore),
        ],
    );
    ctx.file(SPI_MODULE, "the SPI register interface", &body)
}

/// `assign crc_next[j] = …;` for every CRC bit: the CRC of all-zero words XOR the
/// columns of the register bits that can be set (CRC is linear in the message).
fn crc_logic(ctx: &Context) -> String {
    let c = &ctx.config;
    let zero = settings_crc(&[0; 6]);
    let mut terms: Vec<Vec<String>> = vec![Vec::new(); 32];
    for (k, t) in Threshold::ALL.iter().enumerate() {
        for b in 0..t.width(c) {
            let mut words = [0u32; 6];
            words[k] = 1 << b;
            let column = settings_crc(&words) ^ zero;
            for (j, bit_terms) in terms.iter_mut().enumerate() {
                if column >> j & 1 == 1 {
                    bit_terms.push(format!("{}[{b}]", reg(*t)));
                }
            }
        }
    }
    terms
        .iter()
        .enumerate()
        .map(|(j, bit_terms)| {
            let mut expr = format!("1'b{}", zero >> j & 1);
            for term in bit_terms {
                expr.push_str(" ^ ");
                expr.push_str(term);
            }
            format!("    assign crc_next[{j}] = {expr};\n")
        })
        .collect()
}
