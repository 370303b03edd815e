//! The simulator glue's lists of the front end's outputs, generated from [`output_ports`]:
//! the ports, names, width checks and comparisons of the DPI-C scoreboard
//! (`host/rtl-sim/sv/`, `host/rtl-sim/c/tooltouch_dpi.c`), the VPI scoreboard
//! (`host/rtl-sim/verilog/tooltouch_scoreboard.v`, `host/rtl-sim/c/tooltouch_vpi.c`) and the
//! stimulus-only bench (`host/rtl-sim/verilog/tooltouch_bench.v`).
//!
//! Those files are written by hand except for *generated regions*: the lines between a
//! comment line holding `BEGIN GENERATED <name>` and the next holding
//! `END GENERATED <name>` are [`scoreboard_regions`]' text for that file and name
//! ([`splice`] puts it in). `hdl-gen/tests/scoreboard_lists.rs` fails when a committed
//! region differs from the generated one; `cargo xtask bless-hdl` rewrites them. Adding an
//! output to `MeasureOutputs::LAYOUT` thus changes every list here, and no list is kept by
//! hand. The text does not depend on the configuration: widths are written with the
//! scoreboards' parameters (`SCALE_BITS`, `COUNT_BITS`, `CHARGE_BITS`).
//!
//! Signal indexes, in every scoreboard: `0..FIELD_COUNT` the outputs in port order, then
//! `irq`, then `mcu_rdata`.

use crate::outputs::{output_ports, OutputPort, IRQ_SOURCE};
use tooltouch_model::{MeasureOutputs, OutputWidth};

/// The DPI-C package (repository-relative path).
pub const DPI_PACKAGE: &str = "host/rtl-sim/sv/tooltouch_dpi.sv";
/// The DPI-C scoreboard.
pub const DPI_SCOREBOARD: &str = "host/rtl-sim/sv/tooltouch_scoreboard.sv";
/// The DPI-C functions over the C ABI.
pub const DPI_C: &str = "host/rtl-sim/c/tooltouch_dpi.c";
/// The VPI scoreboard for Icarus.
pub const VPI_SCOREBOARD: &str = "host/rtl-sim/verilog/tooltouch_scoreboard.v";
/// The VPI system functions over the C ABI.
pub const VPI_C: &str = "host/rtl-sim/c/tooltouch_vpi.c";
/// The stimulus-only bench of both scoreboards.
pub const BENCH: &str = "host/rtl-sim/verilog/tooltouch_bench.v";

/// Every file holding generated regions.
pub const SCOREBOARD_FILES: [&str; 6] = [
    DPI_PACKAGE,
    DPI_SCOREBOARD,
    DPI_C,
    VPI_SCOREBOARD,
    VPI_C,
    BENCH,
];

/// The marker before a region's name on its first line.
pub const BEGIN_MARKER: &str = "BEGIN GENERATED ";
/// The marker before a region's name on its last line.
pub const END_MARKER: &str = "END GENERATED ";

/// Lines are wrapped before this column.
const MAX_COLUMNS: usize = 100;

// The scoreboards' `unknown` argument has one bit per signal in a 32-bit word.
const _: () = assert!(MeasureOutputs::FIELD_COUNT + 2 <= 32);

/// One generated region: the lines between its markers in `file`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeneratedRegion {
    /// Repository-relative path of the file ([`SCOREBOARD_FILES`]).
    pub file: &'static str,
    /// The name in its markers.
    pub name: &'static str,
    /// The lines, each ending in a newline.
    pub text: String,
}

/// A region [`splice`] could not put in.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum RegionError {
    /// No line holds `BEGIN GENERATED <name>`.
    #[error("no `{BEGIN_MARKER}{0}` line")]
    NoBegin(String),
    /// A begin marker with no end marker after it.
    #[error("`{BEGIN_MARKER}{0}` at line {1} has no `{END_MARKER}{0}` after it")]
    NoEnd(String, usize),
}

/// Every generated region of every file in [`SCOREBOARD_FILES`].
pub fn scoreboard_regions() -> Vec<GeneratedRegion> {
    let ports = output_ports();
    let region = |file, name, text| GeneratedRegion { file, name, text };
    vec![
        region(DPI_PACKAGE, "signal-indexes", signal_index_comment(&ports)),
        region(DPI_PACKAGE, "compare-outputs", dpi_import_outputs(&ports)),
        region(DPI_SCOREBOARD, "ports", scoreboard_ports(&ports)),
        region(
            DPI_SCOREBOARD,
            "signal-indexes",
            signal_index_params(&ports),
        ),
        region(DPI_SCOREBOARD, "signal-name", signal_name(&ports, Lang::Sv)),
        region(DPI_SCOREBOARD, "dut-value", dut_value(&ports, Lang::Sv)),
        region(DPI_SCOREBOARD, "check-widths", check_widths(&ports)),
        region(DPI_SCOREBOARD, "compare", sv_compare(&ports)),
        region(DPI_C, "irq-source", c_irq_source(&ports)),
        region(DPI_C, "compare-signature", c_compare_signature(&ports)),
        region(DPI_C, "compare-outputs", c_compare_outputs(&ports)),
        region(VPI_SCOREBOARD, "ports", scoreboard_ports(&ports)),
        region(
            VPI_SCOREBOARD,
            "signal-indexes",
            signal_index_params(&ports),
        ),
        region(
            VPI_SCOREBOARD,
            "signal-name",
            signal_name(&ports, Lang::Verilog),
        ),
        region(
            VPI_SCOREBOARD,
            "dut-value",
            dut_value(&ports, Lang::Verilog),
        ),
        region(VPI_SCOREBOARD, "check-widths", check_widths(&ports)),
        region(VPI_SCOREBOARD, "compare", vpi_compare(&ports)),
        region(VPI_C, "irq-source", c_irq_source(&ports)),
        region(VPI_C, "compare-arguments", c_compare_arguments()),
        region(BENCH, "wires", bench_wires(&ports)),
        region(BENCH, "connections", bench_connections(&ports)),
    ]
}

/// `text` with the lines of every `name` region replaced by `body` (a region may occur
/// more than once; the marker lines stay).
pub fn splice(text: &str, name: &str, body: &str) -> Result<String, RegionError> {
    let mut out = String::with_capacity(text.len() + body.len());
    let mut lines = text.split_inclusive('\n').enumerate();
    let mut found = false;
    while let Some((number, line)) = lines.next() {
        out.push_str(line);
        if marker_name(line, BEGIN_MARKER) != Some(name) {
            continue;
        }
        found = true;
        out.push_str(body);
        let end = lines.find(|(_, l)| marker_name(l, END_MARKER) == Some(name));
        match end {
            Some((_, l)) => out.push_str(l),
            None => return Err(RegionError::NoEnd(name.to_string(), number + 1)),
        }
    }
    if found {
        Ok(out)
    } else {
        Err(RegionError::NoBegin(name.to_string()))
    }
}

/// The name after `marker` on `line` (letters, digits and `-`), if the line holds it.
pub fn marker_name<'a>(line: &'a str, marker: &str) -> Option<&'a str> {
    let after = &line[line.find(marker)? + marker.len()..];
    let end = after
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
        .unwrap_or(after.len());
    Some(&after[..end]).filter(|n| !n.is_empty())
}

/// The language of a scoreboard file.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Lang {
    /// SystemVerilog (the DPI-C scoreboard).
    Sv,
    /// Verilog-2005 (the VPI scoreboard, for Icarus).
    Verilog,
}

/// The scoreboards' parameter that sets `width`, if a configuration sets it.
fn parameter(width: OutputWidth) -> Option<&'static str> {
    match width {
        OutputWidth::ScaleBits => Some("SCALE_BITS"),
        OutputWidth::CountBits => Some("COUNT_BITS"),
        OutputWidth::ChargeBits => Some("CHARGE_BITS"),
        OutputWidth::Flag | OutputWidth::Fixed(_) => None,
    }
}

/// The packed range of a port of `width` (empty for one bit).
fn range(width: OutputWidth) -> String {
    match (width, parameter(width)) {
        (_, Some(p)) => format!("[{p}-1:0]"),
        (OutputWidth::Fixed(bits), None) if bits > 1 => format!("[{}:0]", bits - 1),
        _ => String::new(),
    }
}

/// Index of `irq` and of `mcu_rdata` among the signals.
fn irq_index() -> usize {
    MeasureOutputs::FIELD_COUNT
}

fn mcu_rdata_index() -> usize {
    MeasureOutputs::FIELD_COUNT + 1
}

/// The index of the output `irq` copies.
fn irq_source_index(ports: &[OutputPort]) -> usize {
    ports
        .iter()
        .position(|p| p.name == IRQ_SOURCE)
        .expect("IRQ_SOURCE names an output")
}

/// `first` followed by `items` (`, `-separated, the last followed by `end`), wrapped
/// before [`MAX_COLUMNS`] onto lines starting with `indent`; every line ends in a newline.
/// An item follows a `,` with a space and an opening bracket with none.
fn pack(first: &str, indent: &str, items: &[String], end: &str) -> String {
    let mut out = String::new();
    let mut line = if first.is_empty() {
        indent.to_string()
    } else {
        first.to_string()
    };
    for (i, item) in items.iter().enumerate() {
        let piece = if i + 1 == items.len() {
            format!("{item}{end}")
        } else {
            format!("{item},")
        };
        let space = usize::from(line.ends_with(','));
        let fresh = line.trim().is_empty();
        if !fresh && line.len() + space + piece.len() > MAX_COLUMNS {
            out.push_str(&line);
            out.push('\n');
            line = format!("{indent}{piece}");
        } else {
            if space == 1 {
                line.push(' ');
            }
            line.push_str(&piece);
        }
    }
    out.push_str(&line);
    out.push('\n');
    out
}

/// `text` as comment lines starting with `prefix`, wrapped at word boundaries.
fn wrap_comment(prefix: &str, text: &str) -> String {
    let mut out = String::new();
    let mut line = prefix.to_string();
    for word in text.split_whitespace() {
        if line.len() > prefix.len() && line.len() + 1 + word.len() > MAX_COLUMNS - 8 {
            out.push_str(&line);
            out.push('\n');
            line = prefix.to_string();
        }
        if line.len() > prefix.len() {
            line.push(' ');
        }
        line.push_str(word);
    }
    out.push_str(&line);
    out.push('\n');
    out
}

/// The package's comment on the signal indexes.
fn signal_index_comment(ports: &[OutputPort]) -> String {
    let names: Vec<&str> = ports.iter().map(|p| p.name).collect();
    wrap_comment(
        "// ",
        &format!(
            "Signal indexes (tooltouch_compare, tooltouch_expected): 0..{} the outputs in the \
             order of the ports ({}), {} irq, {} mcu_rdata.",
            ports.len() - 1,
            names.join(" "),
            irq_index(),
            mcu_rdata_index()
        ),
    )
}

/// The outputs' arguments of the package's `tooltouch_compare` import, and its end.
fn dpi_import_outputs(ports: &[OutputPort]) -> String {
    let items: Vec<String> = ports
        .iter()
        .map(|p| format!("input longint unsigned {}", p.name))
        .collect();
    pack("", "        ", &items, ");")
}

/// The scoreboards' output ports, in port order.
fn scoreboard_ports(ports: &[OutputPort]) -> String {
    ports
        .iter()
        .map(|p| format!("    input wire {:<18}{},\n", range(p.width), p.name))
        .collect()
}

/// The scoreboards' `SIGNAL_MCU_RDATA`.
fn signal_index_params(ports: &[OutputPort]) -> String {
    format!(
        "    // Signal indexes: 0..{} the outputs in port order, {} irq, {} mcu_rdata.\n    \
         localparam integer SIGNAL_MCU_RDATA = {};\n",
        ports.len() - 1,
        irq_index(),
        mcu_rdata_index(),
        mcu_rdata_index()
    )
}

/// `case` items of a function of the signal index: every output, `irq`, and `default`
/// for `mcu_rdata`; `value` gives the item's value for a signal's name.
fn signal_cases(ports: &[OutputPort], assign: &str, value: &dyn Fn(&str) -> String) -> String {
    let mut out = String::new();
    for (i, name) in ports.iter().map(|p| p.name).chain(["irq"]).enumerate() {
        out.push_str(&format!("            {i}: {assign}{};\n", value(name)));
    }
    out.push_str(&format!(
        "            default: {assign}{};\n",
        value("mcu_rdata")
    ));
    out
}

/// The `signal_name` function: a signal's name from its index.
fn signal_name(ports: &[OutputPort], lang: Lang) -> String {
    let quoted = |n: &str| format!("\"{n}\"");
    match lang {
        Lang::Sv => format!(
            "    function automatic string signal_name(input int index);\n        case (index)\n{}        endcase\n    endfunction\n",
            signal_cases(ports, "return ", &quoted)
        ),
        Lang::Verilog => {
            let longest = ports
                .iter()
                .map(|p| p.name)
                .chain(["irq", "mcu_rdata"])
                .map(str::len)
                .max()
                .unwrap_or(1);
            format!(
                "    function [8*{longest}-1:0] signal_name(input integer index);\n        case (index)\n{}        endcase\n    endfunction\n",
                signal_cases(ports, "signal_name = ", &quoted)
            )
        }
    }
}

/// The `dut_value` function: the DUT's value of a signal from its index.
fn dut_value(ports: &[OutputPort], lang: Lang) -> String {
    match lang {
        Lang::Sv => format!(
            "    function automatic longint unsigned dut_value(input int index);\n        case (index)\n{}        endcase\n    endfunction\n",
            signal_cases(ports, "return ", &|n| format!("64'({n})"))
        ),
        Lang::Verilog => format!(
            "    function [31:0] dut_value(input integer index);\n        case (index)\n{}        endcase\n    endfunction\n",
            signal_cases(ports, "dut_value = ", &|n| n.to_string())
        ),
    }
}

/// `check_width` of the first output each parameter sets, in index order.
fn check_widths(ports: &[OutputPort]) -> String {
    let mut seen = Vec::new();
    let mut out = String::new();
    for (i, p) in ports.iter().enumerate() {
        if let Some(name) = parameter(p.width).filter(|n| !seen.contains(n)) {
            seen.push(name);
            out.push_str(&format!("        check_width({i}, {name});\n"));
        }
    }
    out
}

/// The DPI-C scoreboard's X/Z word and its `tooltouch_compare` call.
fn sv_compare(ports: &[OutputPort]) -> String {
    let mut unknown = vec![
        "$isunknown(mcu_rdata) | $isunknown(mcu_addr)".to_string(),
        "$isunknown(irq)".to_string(),
    ];
    unknown.extend(
        ports
            .iter()
            .rev()
            .map(|p| format!("$isunknown({})", p.name)),
    );
    let padding = 32 - (ports.len() + 2);
    let outputs: Vec<String> = ports.iter().map(|p| format!("64'({})", p.name)).collect();
    pack(
        &format!("            unknown = {{{padding}'d0,"),
        &" ".repeat(23),
        &unknown,
        "};",
    ) + &pack(
        "            first = tooltouch_compare(model, unknown, 32'(mcu_addr), mcu_rdata, irq,",
        &" ".repeat(16),
        &outputs,
        ");",
    )
}

/// The VPI scoreboard's `$tooltouch_compare` call.
fn vpi_compare(ports: &[OutputPort]) -> String {
    let outputs: Vec<String> = ports.iter().map(|p| p.name.to_string()).collect();
    pack(
        "            first = $tooltouch_compare(model, mcu_addr, mcu_rdata, irq,",
        &" ".repeat(16),
        &outputs,
        ");",
    )
}

/// The C files' index of the output `irq` copies.
fn c_irq_source(ports: &[OutputPort]) -> String {
    format!(
        "/* irq is a copy of output {i}, {IRQ_SOURCE} (tt_frontend: `assign irq = {IRQ_SOURCE}`). */\n\
         enum {{ IRQ_SOURCE = {i} }};\n",
        i = irq_source_index(ports)
    )
}

/// The DPI-C `tooltouch_compare`'s signature, up to its opening brace.
fn c_compare_signature(ports: &[OutputPort]) -> String {
    let mut items = vec!["unsigned char irq".to_string()];
    items.extend(ports.iter().map(|p| format!("uint64_t {}", p.name)));
    pack(
        "int32_t tooltouch_compare(void *handle, uint32_t unknown, uint32_t mcu_addr, uint32_t mcu_rdata,",
        &" ".repeat(26),
        &items,
        ") {",
    )
}

/// The DPI-C `tooltouch_compare`'s array of the DUT's outputs.
fn c_compare_outputs(ports: &[OutputPort]) -> String {
    let items: Vec<String> = ports.iter().map(|p| p.name.to_string()).collect();
    pack(
        "    const uint64_t got[TT_OUTPUT_COUNT] = {",
        &" ".repeat(43),
        &items,
        "};",
    )
}

/// The VPI `$tooltouch_compare`'s arguments, as its usage message names them.
fn c_compare_arguments() -> String {
    format!(
        "#define COMPARE_ARGUMENTS \"the model, mcu_addr, mcu_rdata, irq and the {} outputs\"\n",
        MeasureOutputs::FIELD_COUNT
    )
}

/// The bench's output wires.
fn bench_wires(ports: &[OutputPort]) -> String {
    ports
        .iter()
        .map(|p| format!("    wire {:<18}{};\n", range(p.width), p.name))
        .collect()
}

/// The bench's connections of the outputs (each followed by a comma).
fn bench_connections(ports: &[OutputPort]) -> String {
    let items: Vec<String> = ports.iter().map(|p| format!(".{0}({0})", p.name)).collect();
    pack("", "        ", &items, ",")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splice_replaces_every_region_of_the_name_and_keeps_the_markers() {
        let text = "a\n// BEGIN GENERATED x: why\nold\n// END GENERATED x\nb\n/* BEGIN GENERATED x */\n/* END GENERATED x */\n";
        assert_eq!(
            splice(text, "x", "new\n").unwrap(),
            "a\n// BEGIN GENERATED x: why\nnew\n// END GENERATED x\nb\n/* BEGIN GENERATED x */\nnew\n/* END GENERATED x */\n"
        );
        assert_eq!(splice(text, "y", ""), Err(RegionError::NoBegin("y".into())));
        assert_eq!(
            splice("// BEGIN GENERATED x\nold\n", "x", ""),
            Err(RegionError::NoEnd("x".into(), 1))
        );
        // A longer name is another region.
        assert_eq!(
            splice("// BEGIN GENERATED x-y\n// END GENERATED x-y\n", "x", ""),
            Err(RegionError::NoBegin("x".into()))
        );
    }

    #[test]
    fn widths_are_written_with_the_scoreboards_parameters() {
        assert_eq!(range(OutputWidth::Flag), "");
        assert_eq!(range(OutputWidth::Fixed(1)), "");
        assert_eq!(range(OutputWidth::Fixed(8)), "[7:0]");
        assert_eq!(range(OutputWidth::ScaleBits), "[SCALE_BITS-1:0]");
        assert_eq!(range(OutputWidth::CountBits), "[COUNT_BITS-1:0]");
        assert_eq!(range(OutputWidth::ChargeBits), "[CHARGE_BITS-1:0]");
    }

    #[test]
    fn every_region_names_every_output_and_irq_copies_register_now() {
        let ports = output_ports();
        assert_eq!(ports[irq_source_index(&ports)].name, "register_now");
        for r in scoreboard_regions() {
            let lists_outputs = !matches!(
                r.name,
                "irq-source" | "compare-arguments" | "signal-indexes" | "check-widths"
            );
            for p in &ports {
                assert!(
                    !lists_outputs || r.text.contains(p.name),
                    "{} {}: no {}",
                    r.file,
                    r.name,
                    p.name
                );
            }
            assert!(r.text.ends_with('\n'), "{} {}", r.file, r.name);
            assert!(
                r.text.lines().all(|l| l.len() <= MAX_COLUMNS),
                "{} {}",
                r.file,
                r.name
            );
        }
    }

    #[test]
    fn lines_are_packed_before_the_column_limit() {
        let items: Vec<String> = (0..40).map(|i| format!("item{i}")).collect();
        let text = pack("    f(a,", "      ", &items, ");");
        assert!(text.starts_with("    f(a, item0, item1,"), "{text}");
        assert!(text.ends_with("item39);\n"), "{text}");
        assert!(text.lines().count() > 1 && text.lines().all(|l| l.len() <= MAX_COLUMNS));
        assert_eq!(
            pack("x = {", "", &["a".into(), "b".into()], "};"),
            "x = {a, b};\n"
        );
    }
}
