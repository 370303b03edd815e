//! The clock-by-clock replay of a counterexample: the design driven in Icarus with the
//! counterexample's own pins, `rst` and `mcu_addr` at every clock (a small testbench
//! written here, [`bench`]), its `mcu_rdata` and outputs printed before every clock
//! edge, and each compared with the golden model's cycle level (`FrontEnd`, restarted
//! from its reset state after a clock with `rst` high) and its MCU register map
//! (`tooltouch_hdl_gen::MCU_REGISTERS`, [`mcu_word`]).
//!
//! This covers what the golden vectors cannot carry: the stimulus holds the six pins only
//! and the generated testbench drives `rst` low and reads `mcu_addr = k mod 16`, so a
//! difference that needs a mid-run reset, or shows only in `mcu_rdata` at the address of
//! one clock, is replayed here.

use super::error::{io, FormalError};
use super::inputs::Counterexample;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tooltouch_hdl_gen::{output_fields, MCU_REGISTERS, TESTBENCH};
use tooltouch_model::measure::frontend::{FrontEnd, Pins};
use tooltouch_model::{MeasureConfig, MeasureOutputs};
use tooltouch_rtl_sim::runner::{build, run, CxxOpt, Simulator};

/// File the replay testbench prints to: per clock `frame mcu_rdata output…` in hex.
pub const REPLAY_TEXT: &str = "replay.txt";
/// File name of the replay testbench.
pub const REPLAY_BENCH: &str = "tt_formal_replay.v";

/// The first difference of the clocked replay.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClockedMismatch {
    /// The cycle (as `tooltouch check` counts: the value registered by clock `cycle`,
    /// 0-based) at which it shows.
    pub cycle: usize,
    /// The signal (`mcu_rdata` or an output's name).
    pub signal: String,
    /// For `mcu_rdata`: the address and the register's name (`-` for an unlisted one).
    pub register: Option<(u32, &'static str)>,
    /// The design's value (hex; `x` when it is not 0/1).
    pub design: String,
    /// The golden model's value (hex).
    pub model: u64,
}

impl std::fmt::Display for ClockedMismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.register {
            Some((addr, name)) => write!(
                f,
                "cycle {}: mcu_rdata at address {addr} ({name}): design 0x{}, model 0x{:x}",
                self.cycle, self.design, self.model
            ),
            None => write!(
                f,
                "cycle {}: {}: design 0x{}, model 0x{:x}",
                self.cycle, self.signal, self.design, self.model
            ),
        }
    }
}

/// The MCU word at `addr` of a front end whose outputs' register bits are `values`
/// ([`tooltouch_hdl_gen::output_values`] order), as the model's register map defines it
/// (`tooltouch_model::measure::mcu_registers`): the diagnostic counters 0 unless
/// `diagnostics`, an unlisted address 0.
pub fn mcu_word(
    config: &MeasureConfig,
    values: &[u64; MeasureOutputs::FIELD_COUNT],
    addr: u32,
    diagnostics: bool,
) -> u32 {
    tooltouch_model::measure::mcu_registers::mcu_word(
        config,
        config.hash(),
        values,
        addr,
        diagnostics,
    )
}

/// The replay testbench (module `tt_testbench`, Verilog-2005) of `cex` on the design's
/// `top`: frame `f` sets the pins sampled by clock `f`, `rst` and `mcu_addr` of frame
/// `f`, prints `f mcu_rdata outputs…` a quarter period later (the state after `f`
/// clocks), then raises the clock. With `vcd`, dumps everything to `vcd` as well.
pub fn bench(
    config: &MeasureConfig,
    cex: &Counterexample,
    top: &str,
    clock_hz: u32,
    vcd: Option<&str>,
) -> String {
    let quarter = (250_000_000 / clock_hz.max(1)).max(1);
    let fields = output_fields(config);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "// tooltouch formal: the counterexample replayed clock by clock (pins, rst, mcu_addr).\n\
         `timescale 1ns/1ps\nmodule {TESTBENCH};\n    reg clk = 1'b0, rst = 1'b0;\n    reg [5:0] pins = 6'd0;\n    reg [3:0] mcu_addr = 4'd0;\n    wire [31:0] mcu_rdata;\n    wire irq;"
    );
    for f in &fields {
        let _ = writeln!(s, "    wire [{}:0] {};", f.width - 1, f.name);
    }
    let _ = writeln!(
        s,
        "    {top} dut (\n        .clk(clk), .rst(rst),\n        .pin_arm(pins[0]), .pin_contact(pins[1]), .pin_index(pins[2]),\n        .pin_fes(pins[3]), .pin_scale_a(pins[4]), .pin_scale_b(pins[5]),\n        .mcu_addr(mcu_addr), .mcu_rdata(mcu_rdata), .irq(irq),"
    );
    let conns: Vec<String> = fields
        .iter()
        .map(|f| format!("        .{0}({0})", f.name))
        .collect();
    let _ = writeln!(s, "{}\n    );", conns.join(",\n"));
    let _ = writeln!(s, "    integer fd;\n    task frame(input integer f, input [5:0] p, input r, input [3:0] a);\n    begin\n        pins = p; rst = r; mcu_addr = a;\n        #{quarter};");
    let formats = vec!["%h"; fields.len() + 1].join(" ");
    let names: Vec<&str> = fields.iter().map(|f| f.name).collect();
    let _ = writeln!(
        s,
        "        $fdisplay(fd, \"%0d {formats}\", f, mcu_rdata, {});\n        #{quarter} clk = 1'b1;\n        #{} clk = 1'b0;\n    end\n    endtask",
        names.join(", "),
        2 * quarter
    );
    let _ = writeln!(
        s,
        "    initial begin\n        fd = $fopen(\"{REPLAY_TEXT}\", \"w\");"
    );
    if let Some(v) = vcd {
        let _ = writeln!(
            s,
            "        $dumpfile(\"{v}\");\n        $dumpvars(0, {TESTBENCH});"
        );
    }
    for f in 0..=cex.clocks() {
        let p = cex.pins.get(f).copied().unwrap_or(0);
        let r = u8::from(cex.rst.get(f).copied().unwrap_or(false));
        let a = cex.mcu_addr.get(f).copied().unwrap_or(0);
        let _ = writeln!(s, "        frame({f}, 6'h{p:02x}, 1'b{r}, 4'h{a:x});");
    }
    let _ = writeln!(
        s,
        "        $fclose(fd);\n        $display(\"TESTBENCH OK {}\");\n        $finish;\n    end\nendmodule",
        cex.clocks()
    );
    s
}

/// Replays `cex` on the design `files` (top `top`) in `dir`: runs [`bench`] in Icarus and
/// compares, after every clock `1 …`, `mcu_rdata` at that clock's address and the
/// outputs with the golden model. Returns the first difference (`None`: none).
#[allow(clippy::too_many_arguments)]
pub fn replay_clocked(
    config: &MeasureConfig,
    mcu_diagnostics: bool,
    cex: &Counterexample,
    clock_hz: u32,
    files: &[PathBuf],
    top: &str,
    dir: &Path,
    vcd: Option<&str>,
) -> Result<Option<ClockedMismatch>, FormalError> {
    let build_dir = dir.join("build_replay");
    std::fs::create_dir_all(&build_dir).map_err(io(&build_dir))?;
    let bench_path = dir.join(REPLAY_BENCH);
    std::fs::write(&bench_path, bench(config, cex, top, clock_hz, vcd)).map_err(io(&bench_path))?;
    let mut all: Vec<PathBuf> = files.to_vec();
    all.push(bench_path);
    let b = build(Simulator::Icarus, &all, &build_dir, CxxOpt::O1).map_err(hdl_error)?;
    run(&b, dir, &[]).map_err(hdl_error)?;
    let _ = std::fs::remove_dir_all(&build_dir);
    let text_path = dir.join(REPLAY_TEXT);
    let text = std::fs::read_to_string(&text_path).map_err(io(&text_path))?;
    compare(config, mcu_diagnostics, cex, &text)
}

/// One value compared: signal, the design's text, the model's value, the MCU register.
type Check<'a> = (&'a str, &'a str, u64, Option<(u32, &'static str)>);

/// Compares the replay testbench's printout `text` with the golden model driven by `cex`.
pub fn compare(
    config: &MeasureConfig,
    mcu_diagnostics: bool,
    cex: &Counterexample,
    text: &str,
) -> Result<Option<ClockedMismatch>, FormalError> {
    let fields = output_fields(config);
    let mut model = FrontEnd::new(config);
    let mut lines = text.lines();
    for f in 0..=cex.clocks() {
        let line = lines.next().ok_or_else(|| {
            FormalError::Tool(format!(
                "the replay's {REPLAY_TEXT} ends before clock {f} of {}",
                cex.clocks()
            ))
        })?;
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.len() != fields.len() + 2 || words[0] != f.to_string() {
            return Err(FormalError::Tool(format!(
                "the replay's {REPLAY_TEXT}: line `{line}` is not frame {f} with mcu_rdata and {} outputs",
                fields.len()
            )));
        }
        if f > 0 {
            let values = model.outputs().register_bits(config);
            let addr = cex.mcu_addr.get(f).copied().unwrap_or(0);
            let word = u64::from(mcu_word(config, &values, addr, mcu_diagnostics));
            let name = MCU_REGISTERS
                .iter()
                .find(|r| r.addr == addr)
                .map_or("unlisted, reads 0", |r| r.name);
            let mut checks: Vec<Check> = fields
                .iter()
                .enumerate()
                .map(|(i, field)| (field.name, words[i + 2], values[i], None))
                .collect();
            checks.push(("mcu_rdata", words[1], word, Some((addr, name))));
            for (signal, design, model_value, register) in checks {
                let parsed = u64::from_str_radix(design, 16).ok();
                if parsed != Some(model_value) {
                    return Ok(Some(ClockedMismatch {
                        cycle: f - 1,
                        signal: signal.to_string(),
                        register,
                        design: parsed.map_or_else(|| design.to_string(), |v| format!("{v:x}")),
                        model: model_value,
                    }));
                }
            }
        }
        if f < cex.clocks() {
            if cex.rst.get(f).copied().unwrap_or(false) {
                model = FrontEnd::new(config);
            } else {
                model.clock(Pins(cex.pins[f]));
            }
        }
    }
    Ok(None)
}

fn hdl_error(e: tooltouch_rtl_sim::HdlError) -> FormalError {
    match e {
        tooltouch_rtl_sim::HdlError::ToolMissing { tool } => FormalError::ToolMissing(tool),
        other => FormalError::Tool(format!(
            "replaying the counterexample clock by clock: {other}"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_hdl_gen::{mask, output_values};

    #[test]
    fn the_mcu_words_follow_the_register_map() {
        let c = MeasureConfig::default();
        let fe = FrontEnd::new(&c);
        let v = output_values(&c, &fe.outputs());
        // At reset only density_armed (STATUS bit 4) is set.
        assert_eq!(mcu_word(&c, &v, 0, false), 1 << 4);
        assert_eq!(mcu_word(&c, &v, 10, false), c.hash() as u32);
        assert_eq!(mcu_word(&c, &v, 11, false), (c.hash() >> 32) as u32);
        assert_eq!(mcu_word(&c, &v, 15, false), 0);
        let fields = output_fields(&c);
        let mut v2 = v;
        let i = fields.iter().position(|f| f.name == "position").unwrap();
        v2[i] = mask(u32::from(c.settings().scale_bits)); // -1
        assert_eq!(mcu_word(&c, &v2, 1, false), u32::MAX);
        let p = fields.iter().position(|f| f.name == "pulses").unwrap();
        v2[p] = 7;
        assert_eq!(mcu_word(&c, &v2, 8, false), 0);
        assert_eq!(mcu_word(&c, &v2, 8, true), 7);
    }

    #[test]
    fn the_comparison_names_clock_address_register_and_both_values() {
        let c = MeasureConfig::default();
        let cex = Counterexample {
            pins: vec![0, 0],
            mcu_addr: vec![0, 0, 10],
            rst: vec![false, true, false],
        };
        let zeros = vec!["0"; MeasureOutputs::FIELD_COUNT].join(" ");
        // density_armed is 1 after reset: the outputs line must carry it.
        let fields = output_fields(&c);
        let line = |f: usize, rdata: &str| {
            let outs: Vec<&str> = fields
                .iter()
                .map(|x| if x.name == "density_armed" { "1" } else { "0" })
                .collect();
            format!("{f} {rdata} {}", outs.join(" "))
        };
        let good = format!(
            "{}\n{}\n{}\n",
            line(0, "0"),
            line(1, "10"),
            line(2, &format!("{:x}", c.hash() as u32))
        );
        assert_eq!(compare(&c, false, &cex, &good).unwrap(), None);
        let bad = format!("{}\n{}\n{}\n", line(0, "0"), line(1, "10"), line(2, "0"));
        let m = compare(&c, false, &cex, &bad).unwrap().expect("a mismatch");
        assert_eq!(m.cycle, 1);
        assert_eq!(m.register, Some((10, "CONFIG_HASH_LO")));
        assert!(m.to_string().contains("design 0x0"), "{m}");
        assert!(compare(&c, false, &cex, &format!("0 0 {zeros}\n")).is_err());
    }
}
