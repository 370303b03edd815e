//! The miter of a user's `tt_frontend` against the reference written from the model's
//! semantics (`tooltouch_hdl_gen::reference`), as an AIGER file for ABC.
//!
//! [`read_interface`] reads the design with yosys and checks its ports against the
//! contract (every port present, input or output as it should be, with the contract's
//! width), so a wrong design is refused with the port's name before any proof.
//! [`wrapper`] writes the miter's top module: both designs driven by the same pins and MCU
//! address and the same `rst` every clock (a free input: the proof covers a reset at any
//! clock, including none), the power-on state of each (its initializers), and one
//! output `differ` that is 1 after a clock at which any output, `irq` or `mcu_rdata` (at the
//! address of that clock, any of the 16) differs. [`build_aiger`] flattens it with yosys
//! to an And-Inverter graph (`miter.aig`, zero-initialized latches) and its symbol map.
//!
//! The comparison starts after the first clock: the golden VCD holds the value registered
//! after each clock, so every difference the miter reports is one `tooltouch check` can
//! replay. A register without an initializer gets an arbitrary power-on value (yosys
//! `write_aiger -zinit` makes its initial value a free input), so a design that relies on
//! `rst` to start fails the proof rather than passing on a lucky zero.

use super::error::{tail, FormalError};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use tooltouch_hdl_gen::{output_fields, MCU_ADDR_BITS, MCU_DATA_BITS, REFERENCE_TOP};
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::MeasureConfig;

/// Module name of the miter's top.
pub const MITER_TOP: &str = "tt_formal_top";
/// Module name the user's top is renamed to inside the miter (so it cannot clash with the
/// reference's).
pub const DUT_MODULE: &str = "tt_formal_dut";
/// File name of the miter's top module.
pub const WRAPPER_FILE: &str = "tt_formal_top.v";
/// File name of the reference.
pub const REFERENCE_FILE: &str = "tt_frontend_ref.v";
/// File name of the And-Inverter graph.
pub const AIGER_FILE: &str = "miter.aig";
/// File name of yosys's map of the AIGER's inputs, latches and outputs to signal names.
pub const MAP_FILE: &str = "miter.map";

/// Direction of a port.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Input.
    Input,
    /// Output.
    Output,
}

/// A port of the contract's `tt_frontend`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Port {
    /// Name.
    pub name: String,
    /// Direction.
    pub direction: Direction,
    /// Width, bits.
    pub width: u32,
}

/// The ports the contract's `tt_frontend` has for `config` (docs/CONTRACT.md): `clk`,
/// `rst`, the six `pin_*`, `mcu_addr`, `mcu_rdata`, the outputs of `MeasureOutputs::LAYOUT`
/// and `irq`.
pub fn contract_ports(config: &MeasureConfig) -> Vec<Port> {
    let port = |name: &str, direction, width| Port {
        name: name.to_string(),
        direction,
        width,
    };
    let mut out = vec![
        port("clk", Direction::Input, 1),
        port("rst", Direction::Input, 1),
    ];
    for n in pin::NAMES {
        out.push(port(&format!("pin_{n}"), Direction::Input, 1));
    }
    out.push(port("mcu_addr", Direction::Input, MCU_ADDR_BITS));
    out.push(port("mcu_rdata", Direction::Output, MCU_DATA_BITS));
    for f in output_fields(config) {
        out.push(port(f.name, Direction::Output, f.width));
    }
    out.push(port("irq", Direction::Output, 1));
    out
}

/// Runs yosys on `script` in `dir` (log `log_name`); returns the log. A failure whose log
/// names an error in a design file is bad input, reported with yosys's error lines.
pub(crate) fn run_yosys(dir: &Path, script: &str, name: &str) -> Result<String, FormalError> {
    super::error::find("yosys")?;
    let ys = dir.join(format!("{name}.ys"));
    std::fs::write(&ys, script).map_err(super::error::io(&ys))?;
    let log_name = format!("{name}.log");
    let out = Command::new("yosys")
        .args(["-q", "-l", &log_name, "-s", &format!("{name}.ys")])
        .current_dir(dir)
        .output()
        .map_err(super::error::io(Path::new("yosys")))?;
    let log = std::fs::read_to_string(dir.join(&log_name)).unwrap_or_default();
    if !out.status.success() {
        let text = format!("{log}\n{}", String::from_utf8_lossy(&out.stderr));
        let mut errors: Vec<&str> = Vec::new();
        for l in text.lines() {
            if (l.contains("ERROR") || l.contains("error:")) && !errors.contains(&l) {
                errors.push(l);
            }
        }
        return Err(FormalError::Design(if errors.is_empty() {
            format!("yosys failed reading the design:\n{}", tail(&text, 20))
        } else {
            errors.join("\n")
        }));
    }
    Ok(log)
}

/// The `read_verilog` lines of `files` (SystemVerilog allowed, `-formal` so that
/// assertion-only constructs parse).
fn read_lines(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|f| format!("read_verilog -sv -formal {}\n", quoted(f)))
        .collect()
}

fn quoted(p: &Path) -> String {
    format!("\"{}\"", p.display())
}

/// Reads `files` with yosys in `dir`, elaborates `top`, and checks its ports against
/// [`contract_ports`]: a missing port, one of the wrong direction or width, or an extra
/// input is bad input naming the port. Extra outputs (debug ports) are allowed and not
/// compared.
pub fn read_interface(
    config: &MeasureConfig,
    files: &[PathBuf],
    top: &str,
    dir: &Path,
) -> Result<Vec<String>, FormalError> {
    let script = format!(
        "{}hierarchy -check -top {top}\nproc\nwrite_json interface.json\n",
        read_lines(files)
    );
    run_yosys(dir, &script, "interface").map_err(|e| match e {
        FormalError::Design(errors) => FormalError::Design(format!(
            "reading --dut {} with --top {top}:\n{errors}",
            files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(" ")
        )),
        other => other,
    })?;
    let path = dir.join("interface.json");
    let text = std::fs::read_to_string(&path).map_err(super::error::io(&path))?;
    let json: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| FormalError::Tool(format!("yosys's {}: {e}", path.display())))?;
    let ports = json["modules"][top]["ports"]
        .as_object()
        .ok_or_else(|| FormalError::BadInput(format!("module {top}: no ports found")))?;
    let mut problems = Vec::new();
    let expected = contract_ports(config);
    for p in &expected {
        let Some(found) = ports.get(&p.name) else {
            problems.push(format!(
                "port `{}` is missing (the contract's {} of {} bit{})",
                p.name,
                dir_name(p.direction),
                p.width,
                if p.width == 1 { "" } else { "s" }
            ));
            continue;
        };
        let direction = found["direction"].as_str().unwrap_or("?");
        let width = found["bits"].as_array().map_or(0, Vec::len) as u32;
        if direction != dir_name(p.direction) {
            problems.push(format!(
                "port `{}` is an {direction}: the contract's is an {}",
                p.name,
                dir_name(p.direction)
            ));
        } else if width != p.width {
            problems.push(format!(
                "port `{}` is {width} bits wide: the contract's is {} bits for this configuration",
                p.name, p.width
            ));
        }
    }
    let mut extra_outputs = Vec::new();
    for (name, found) in ports {
        if expected.iter().any(|p| &p.name == name) {
            continue;
        }
        if found["direction"].as_str() == Some("output") {
            extra_outputs.push(name.clone());
        } else {
            problems.push(format!(
                "port `{name}` is not in the contract (an {} the miter cannot drive)",
                found["direction"].as_str().unwrap_or("unknown port")
            ));
        }
    }
    if problems.is_empty() {
        Ok(extra_outputs)
    } else {
        Err(FormalError::BadInput(format!(
            "module {top} ({}): {}",
            files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(" "),
            problems.join("; ")
        )))
    }
}

fn dir_name(d: Direction) -> &'static str {
    match d {
        Direction::Input => "input",
        Direction::Output => "output",
    }
}

/// The miter's top module: the reference and the DUT (renamed [`DUT_MODULE`]) on the
/// same pins, `mcu_addr` and `rst` (synchronous, at any clock); `differ` is 1 when, after at least one clock, any
/// compared port differs.
pub fn wrapper(config: &MeasureConfig) -> String {
    let ports = contract_ports(config);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "// Miter of tooltouch formal: the design under test against the reference written\n\
         // from the model (tt_frontend_ref), same pins, MCU address and rst every clock,\n\
         // from power-on. differ = 1 after a clock at which any output differs."
    );
    let _ = writeln!(
        s,
        "module {MITER_TOP} (\n    input wire clk,\n    input wire rst,"
    );
    for n in pin::NAMES {
        let _ = writeln!(s, "    input wire pin_{n},");
    }
    let _ = writeln!(
        s,
        "    input wire [{}:0] mcu_addr,\n    output wire differ\n);",
        MCU_ADDR_BITS - 1
    );
    let outputs: Vec<&Port> = ports
        .iter()
        .filter(|p| p.direction == Direction::Output)
        .collect();
    for side in ["ref", "dut"] {
        for p in &outputs {
            let _ = writeln!(s, "    wire [{}:0] {side}_{};", p.width - 1, p.name);
        }
    }
    // Comparison from the second frame on: `clocked` is 0 at power-on, 1 after a clock.
    let _ = writeln!(s, "    reg clocked = 1'b0;");
    let _ = writeln!(s, "    always @(posedge clk) clocked <= 1'b1;");
    for (side, module) in [("ref", REFERENCE_TOP), ("dut", DUT_MODULE)] {
        let _ = writeln!(s, "    {module} u_{side} (\n        .clk(clk), .rst(rst),");
        for n in pin::NAMES {
            let _ = writeln!(s, "        .pin_{n}(pin_{n}),");
        }
        let _ = writeln!(s, "        .mcu_addr(mcu_addr),");
        let conns: Vec<String> = outputs
            .iter()
            .map(|p| format!("        .{0}({side}_{0})", p.name))
            .collect();
        let _ = writeln!(s, "{}\n    );", conns.join(",\n"));
    }
    let diffs: Vec<String> = outputs
        .iter()
        .map(|p| format!("(ref_{0} != dut_{0})", p.name))
        .collect();
    let _ = writeln!(
        s,
        "    assign differ = clocked && ({});\nendmodule",
        diffs.join("\n        || ")
    );
    s
}

/// Writes the reference and the wrapper into `dir` and builds [`AIGER_FILE`] and
/// [`MAP_FILE`] there from the DUT `files` (top `top`): the DUT is read and flattened on
/// its own (its module names cannot clash with the reference's), renamed
/// [`DUT_MODULE`], then the miter is flattened, asynchronous resets made synchronous,
/// and mapped to AND gates and positive-edge flip-flops. Returns yosys's log.
pub fn build_aiger(
    config: &MeasureConfig,
    mcu_diagnostics: bool,
    files: &[PathBuf],
    top: &str,
    dir: &Path,
) -> Result<String, FormalError> {
    let options = tooltouch_hdl_gen::Options {
        mcu_diagnostics,
        ..Default::default()
    };
    let reference = tooltouch_hdl_gen::reference(config, &options, REFERENCE_TOP);
    let ref_path = dir.join(REFERENCE_FILE);
    std::fs::write(&ref_path, &reference.text).map_err(super::error::io(&ref_path))?;
    let wrap_path = dir.join(WRAPPER_FILE);
    std::fs::write(&wrap_path, wrapper(config)).map_err(super::error::io(&wrap_path))?;
    let script = format!(
        "read_verilog {REFERENCE_FILE}\n\
         hierarchy -check -top {REFERENCE_TOP}\n\
         proc\n\
         flatten\n\
         design -stash reference\n\
         {reads}\
         hierarchy -check -top {top}\n\
         proc\n\
         flatten\n\
         hierarchy -top {top}\n\
         rename {top} {DUT_MODULE}\n\
         design -stash dut\n\
         design -copy-from reference -as {REFERENCE_TOP} {REFERENCE_TOP}\n\
         design -copy-from dut -as {DUT_MODULE} {DUT_MODULE}\n\
         read_verilog {WRAPPER_FILE}\n\
         hierarchy -check -top {MITER_TOP}\n\
         proc\n\
         flatten\n\
         opt_clean\n\
         check -assert\n\
         async2sync\n\
         dffunmap\n\
         techmap\n\
         opt -fast\n\
         dfflegalize -cell $_DFF_P_ 01\n\
         abc -g AND\n\
         opt_clean\n\
         stat\n\
         write_aiger -zinit -map {MAP_FILE} {AIGER_FILE}\n",
        reads = read_lines(files)
    );
    run_yosys(dir, &script, "miter")
}

/// The AIGER's inputs from yosys's map: `(input index, bit, signal name)`.
pub fn map_inputs(map: &str) -> Vec<(usize, u32, String)> {
    map.lines()
        .filter_map(|l| {
            let mut w = l.split_whitespace();
            if w.next()? != "input" {
                return None;
            }
            let index = w.next()?.parse().ok()?;
            let bit = w.next()?.parse().ok()?;
            Some((index, bit, w.next()?.to_string()))
        })
        .collect()
}

/// The counts of the AIGER header (`aig M I L O A`): inputs, latches, outputs, ANDs.
pub fn aiger_counts(aig: &[u8]) -> Option<[u64; 4]> {
    let end = aig.iter().position(|&b| b == b'\n')?;
    let head = std::str::from_utf8(&aig[..end]).ok()?;
    let n: Vec<u64> = head
        .split_whitespace()
        .skip(2)
        .map(|w| w.parse().ok())
        .collect::<Option<_>>()?;
    Some([*n.first()?, *n.get(1)?, *n.get(2)?, *n.get(3)?])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wrapper_compares_every_output_port() {
        let c = MeasureConfig::default();
        let w = wrapper(&c);
        for p in contract_ports(&c) {
            if p.direction == Direction::Output {
                assert!(
                    w.contains(&format!("(ref_{0} != dut_{0})", p.name)),
                    "{}",
                    p.name
                );
            }
        }
        assert_eq!(w.matches(".rst(rst)").count(), 2);
        assert!(w.contains("input wire rst,"));
    }

    #[test]
    fn the_map_and_the_header_read_back() {
        let map = "input 0 0 clk\ninput 1 0 pin_arm\ninput 7 2 mcu_addr\nlatch 0 0 x\noutput 0 0 differ\n";
        assert_eq!(
            map_inputs(map),
            vec![
                (0, 0, "clk".to_string()),
                (1, 0, "pin_arm".to_string()),
                (7, 2, "mcu_addr".to_string())
            ]
        );
        assert_eq!(
            aiger_counts(b"aig 10 11 428 1 2948\n..."),
            Some([11, 428, 1, 2948])
        );
    }
}
