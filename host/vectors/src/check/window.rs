//! The mismatch report of a VCD or FST `check`: a second, short pass over both files up to a few
//! clocks past the first mismatching clock `K` (the comparison itself keeps no history),
//! sampling at `k·P + P/2` like the comparison:
//!
//! - every golden output differing at `K`, with the DUT signal it was compared with;
//! - the golden input pins of the [`PIN_ROWS`] clocks up to `K` (a pin sampled at clock
//!   `k` acts on the outputs at `k + 3 + glitch_cycles`), changes marked `*`;
//! - when the DUT's top scope has `mcu_addr` and `mcu_rdata` (the generated `tt_frontend`'s
//!   MCU port), the word read at `K`, its address, the register it names
//!   (`tooltouch_model::measure::mcu_registers`) and the word the golden outputs give there;
//! - with a window file: a VCD of clocks `K − WINDOW_BEFORE … K + WINDOW_AFTER` of
//!   golden (`golden.inputs`, `golden.outputs`) and DUT (`dut`, under the golden names,
//!   plus its MCU port) side by side, with a 1-bit `differs.<name>` per output, every value
//!   at `k·P`; and beside it (extension `.gtkw`) a GTKWave save file that opens it with golden, DUT and
//!   difference of each output grouped and the cursor (primary marker) on clock `K`, and a
//!   Surfer command file (extension `.sucl`, [`super::surfer`]) that does the same.

use super::resolve::path_of;
use super::surfer::Group;
use super::{golden_period_fs, BadInput, FirstMismatch, Report};
use crate::vcd::{Declarations, Value};
use std::fmt::Write as _;
use std::path::Path;
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::measure::mcu_registers::McuRegister;
use tooltouch_model::MeasureOutputs;

/// Rows of the input-pin table: the clocks `K − PIN_ROWS + 1 … K`.
pub const PIN_ROWS: u64 = 12;
/// Clocks of the window file before `K`.
pub const WINDOW_BEFORE: u64 = 24;
/// Clocks of the window file after `K`.
pub const WINDOW_AFTER: u64 = 8;

/// The values of `paths` (dotted signal paths of the file at `path`) sampled at `k·P + P/2`
/// for every clock `k0 ..= k1`, `[clock][signal]`; `None` for a path the file lacks or a
/// signal without a value yet. Reads the file only up to clock `k1`.
fn sample(
    path: &Path,
    paths: &[String],
    k0: u64,
    k1: u64,
    period_fs: u64,
) -> Result<Vec<Vec<Option<Value>>>, BadInput> {
    let name = path.display().to_string();
    let (d, mut r): (Declarations, _) = super::dump::open_dump(path, &name)?;
    let mut of_code: Vec<Vec<usize>> = vec![Vec::new(); d.codes().len()];
    for (i, p) in paths.iter().enumerate() {
        if let Some(code) = d
            .signals
            .iter()
            .find(|s| path_of(s) == *p)
            .and_then(|s| d.code_index(&s.id))
        {
            of_code[code].push(i);
        }
    }
    r.select(
        &(0..of_code.len())
            .filter(|&c| !of_code[c].is_empty())
            .collect::<Vec<_>>(),
    );
    let half = period_fs / 2;
    let mut now: Vec<Option<Value>> = vec![None; paths.len()];
    let mut rows = Vec::new();
    let mut k = k0;
    while k <= k1 {
        let Some((t, code, v)) = r.next_change()? else {
            break;
        };
        while k <= k1 && k * period_fs + half < t {
            rows.push(now.clone());
            k += 1;
        }
        for &i in &of_code[code] {
            now[i] = Some(v.clone());
        }
    }
    while k <= k1 {
        rows.push(now.clone());
        k += 1;
    }
    Ok(rows)
}

fn text(v: &Option<Value>) -> String {
    match v {
        Some(v) if !v.unknown => format!("0x{}", v.hex_digits()),
        Some(_) => "x".into(),
        None => "-".into(),
    }
}

fn number(v: &Option<Value>) -> Option<u64> {
    v.as_ref().filter(|v| !v.unknown).and_then(Value::to_u64)
}

/// The MCU word at `addr` that the golden outputs `g` (by name: register bits and width)
/// give, with the configuration hash `hash`: the model's register map
/// (`tooltouch_model::measure::mcu_registers`); `None` for an unknown value. A diagnostic
/// counter reads 0 unless the design has them: both are given.
fn mcu_expected(addr: u64, g: &dyn Fn(&str) -> Option<(u64, u32)>, hash: u64) -> Option<String> {
    let Some(register) = u32::try_from(addr).ok().and_then(McuRegister::at) else {
        return Some("0x0".into());
    };
    let word = register.word(hash, |i| g(MeasureOutputs::LAYOUT[i].0))?;
    Some(if register.diagnostic {
        format!("0x0 (0x{word:x} with --mcu-diagnostics)")
    } else {
        format!("0x{word:x}")
    })
}

/// Adds the mismatch report's lines to `report` (and writes the window VCD at `window`,
/// its GTKWave file beside it, when given). `expected`, `dut`: the files compared.
pub fn add_details(
    expected: &Path,
    dut: &Path,
    report: &mut Report,
    window: Option<&Path>,
) -> Result<(), BadInput> {
    let Some(first) = report.first.clone() else {
        return Ok(());
    };
    let en = expected.display().to_string();
    let (ed, e_head) = super::dump::open_dump(expected, &en)?;
    drop(e_head);
    let (hash, _, period_fs) = golden_period_fs(&ed, &en)?;
    let k = first.cycle;
    let k0 = k.saturating_sub(WINDOW_BEFORE);
    let k1 = k + WINDOW_AFTER;
    // Golden: the pins, then the outputs in match order.
    let input_scope = ed
        .signals
        .iter()
        .find(|s| s.scope.last().is_some_and(|l| l == "inputs"))
        .map(|s| s.scope.join("."));
    let pins: Vec<String> = pin::NAMES
        .iter()
        .map(|n| match &input_scope {
            Some(sc) => format!("{sc}.{n}"),
            None => (*n).to_string(),
        })
        .collect();
    let mut golden_paths = pins.clone();
    golden_paths.extend(report.matches.iter().map(|m| m.golden.clone()));
    let scope = report.dut_scope.clone().unwrap_or_default();
    let in_scope = |n: &str| {
        if scope.is_empty() || scope.starts_with('(') {
            n.to_string()
        } else {
            format!("{scope}.{n}")
        }
    };
    let mut dut_paths: Vec<String> = report.matches.iter().map(|m| m.dut.clone()).collect();
    dut_paths.push(in_scope("mcu_addr"));
    dut_paths.push(in_scope("mcu_rdata"));
    let g = sample(expected, &golden_paths, k0, k1, period_fs)?;
    let d = sample(dut, &dut_paths, k0, k1, period_fs)?;
    let row = (k - k0) as usize;
    let n = report.matches.len();
    let name_of = |m: &super::SignalMatch| m.golden.rsplit('.').next().unwrap_or("").to_string();

    let mut lines = Vec::new();
    lines.push(format!(
        "signals differing at cycle {k} ({} of {n}):",
        first.differing.len()
    ));
    let wide = report
        .matches
        .iter()
        .map(|m| m.dut.len())
        .max()
        .unwrap_or(0);
    for dif in &first.differing {
        let dut_path = report
            .matches
            .iter()
            .find(|m| name_of(m) == dif.signal)
            .map_or(String::new(), |m| m.dut.clone());
        let number = |v: &str| {
            v.strip_prefix("0x")
                .and_then(|h| u64::from_str_radix(h, 16).ok())
        };
        lines.push(format!(
            "  {:<22} {dut_path:<wide$}  expected {:<18} got {}{}",
            dif.signal,
            dif.expected,
            dif.got,
            super::fault_names(&dif.signal, number(&dif.expected), number(&dif.got))
        ));
    }
    lines.push(
        "golden input pins of the clocks before it (an output at clock k follows the pins of clock k − 3 − glitch_cycles; * = changed):"
            .to_string(),
    );
    let mut header = format!("  {:>12}", "cycle");
    for n in pin::NAMES {
        let _ = write!(header, " {n:>8}");
    }
    lines.push(header);
    let from = k.saturating_sub(PIN_ROWS - 1).max(k0);
    for c in from..=k {
        let r = (c - k0) as usize;
        let mut line = format!("  {c:>12}");
        for (p, value) in g[r].iter().take(pin::COUNT).enumerate() {
            let v = text(value);
            let v = v.strip_prefix("0x").unwrap_or(&v).to_string();
            let changed = r > 0 && *value != g[r - 1][p];
            let _ = write!(
                line,
                " {:>8}",
                format!("{}{v}", if changed { "*" } else { "" })
            );
        }
        lines.push(line);
    }
    let (addr, rdata) = (&d[row][n], &d[row][n + 1]);
    if addr.is_some() && rdata.is_some() {
        let golden_value = |name: &str| {
            report
                .matches
                .iter()
                .position(|m| name_of(m) == name)
                .and_then(|i| {
                    number(&g[row][pins.len() + i]).map(|v| (v, report.matches[i].widths.0))
                })
        };
        let register = number(addr)
            .and_then(|a| u32::try_from(a).ok())
            .and_then(McuRegister::at);
        let want = number(addr).and_then(|a| mcu_expected(a, &golden_value, hash));
        lines.push(format!(
            "mcu_rdata at cycle {k}: {} read at mcu_addr {} ({}); the golden outputs give {}",
            text(rdata),
            text(addr),
            register.map_or("no register: reads 0".to_string(), |r| format!(
                "{}: {}",
                r.name, r.what
            )),
            want.unwrap_or_else(|| "an unknown value".into())
        ));
    }
    if let Some(path) = window {
        let written = write_window(path, &report.matches, &pins, &g, &d, &first, k0, period_fs)
            .map_err(|e| {
                BadInput(format!(
                    "writing the mismatch window {}: {e:#}",
                    path.display()
                ))
            })?;
        lines.push(format!(
            "window: {} (clocks {k0}..={k1}, golden and DUT side by side); open with `gtkwave {}` or `surfer --command-file {}`",
            written.0.display(),
            written.1.display(),
            written.0.with_extension("sucl").display()
        ));
    }
    report.details = lines;
    Ok(())
}

/// A VCD identifier code for signal `i` of the window file.
fn code(i: usize) -> String {
    let mut s = String::new();
    let mut n = i;
    loop {
        s.push(char::from(b'!' + (n % 94) as u8));
        n /= 94;
        if n == 0 {
            return s;
        }
    }
}

fn change(v: &Option<Value>, width: u32, id: &str) -> String {
    let digits = match v {
        None => "x".to_string(),
        Some(v) if v.unknown => "x".to_string(),
        Some(v) => {
            let mut b: String = v
                .bits
                .iter()
                .rev()
                .map(|b| if *b { '1' } else { '0' })
                .collect();
            if b.is_empty() {
                b.push('0');
            }
            b
        }
    };
    if width == 1 {
        format!("{digits}{id}\n")
    } else {
        format!("b{digits} {id}\n")
    }
}

fn range(width: u32) -> String {
    if width > 1 {
        format!(" [{}:0]", width - 1)
    } else {
        String::new()
    }
}

/// Writes the window VCD at `vcd_path`, its GTKWave save file (extension `.gtkw`) and its
/// Surfer command file (`.sucl`) beside it; returns the paths of the first two.
#[allow(clippy::too_many_arguments)]
fn write_window(
    vcd_path: &Path,
    matches: &[super::SignalMatch],
    pins: &[String],
    g: &[Vec<Option<Value>>],
    d: &[Vec<Option<Value>>],
    first: &FirstMismatch,
    k0: u64,
    period_fs: u64,
) -> anyhow::Result<(std::path::PathBuf, std::path::PathBuf)> {
    let p_ns = period_fs / 1_000_000;
    let names: Vec<String> = matches
        .iter()
        .map(|m| m.golden.rsplit('.').next().unwrap_or("").to_string())
        .collect();
    let n = matches.len();
    // Columns: pins (golden), outputs golden, outputs DUT, differs, mcu_addr, mcu_rdata.
    struct Col {
        scope: &'static str,
        name: String,
        width: u32,
    }
    let mut cols: Vec<Col> = Vec::new();
    for p in pins {
        let name = p.rsplit('.').next().unwrap_or(p).to_string();
        cols.push(Col {
            scope: "golden.inputs",
            name,
            width: 1,
        });
    }
    for (m, name) in matches.iter().zip(&names) {
        cols.push(Col {
            scope: "golden.outputs",
            name: name.clone(),
            width: m.widths.0,
        });
    }
    for (m, name) in matches.iter().zip(&names) {
        cols.push(Col {
            scope: "dut",
            name: name.clone(),
            width: m.widths.1,
        });
    }
    for name in &names {
        cols.push(Col {
            scope: "differs",
            name: name.clone(),
            width: 1,
        });
    }
    let has_mcu = d.iter().any(|r| r[n].is_some());
    if has_mcu {
        cols.push(Col {
            scope: "dut",
            name: "mcu_addr".into(),
            width: tooltouch_hdl_gen::MCU_ADDR_BITS,
        });
        cols.push(Col {
            scope: "dut",
            name: "mcu_rdata".into(),
            width: tooltouch_hdl_gen::MCU_DATA_BITS,
        });
    }
    let row_values = |r: usize| -> Vec<Option<Value>> {
        let mut v: Vec<Option<Value>> = Vec::with_capacity(cols.len());
        v.extend(g[r][..pins.len()].iter().cloned());
        v.extend(g[r][pins.len()..].iter().cloned());
        v.extend(d[r][..n].iter().cloned());
        for i in 0..n {
            let (a, b) = (&g[r][pins.len() + i], &d[r][i]);
            let same = matches!((a, b), (Some(a), Some(b)) if !a.unknown && !b.unknown && a == b);
            v.push(Some(Value::known(u64::from(!same))));
        }
        if has_mcu {
            v.push(d[r][n].clone());
            v.push(d[r][n + 1].clone());
        }
        v
    };
    let mut vcd = String::new();
    let _ = writeln!(vcd, "$comment tooltouch check: first mismatch at cycle {} (time {} ns); golden and DUT sampled at k·P + P/2, written at k·P $end", first.cycle, first.time_ns);
    let _ = writeln!(vcd, "$timescale 1ns $end");
    let mut open: Vec<&str> = Vec::new();
    for (i, c) in cols.iter().enumerate() {
        let want: Vec<&str> = c.scope.split('.').collect();
        while !want.starts_with(&open) {
            vcd.push_str("$upscope $end\n");
            open.pop();
        }
        while open.len() < want.len() {
            let s = want[open.len()];
            let _ = writeln!(vcd, "$scope module {s} $end");
            open.push(s);
        }
        let _ = writeln!(
            vcd,
            "$var wire {} {} {}{} $end",
            c.width,
            code(i),
            c.name,
            range(c.width)
        );
    }
    for _ in &open {
        vcd.push_str("$upscope $end\n");
    }
    vcd.push_str("$enddefinitions $end\n");
    let mut last: Option<Vec<Option<Value>>> = None;
    for r in 0..g.len() {
        let now = row_values(r);
        let t = (k0 + r as u64) * p_ns;
        let mut body = String::new();
        for (i, c) in cols.iter().enumerate() {
            if last.as_ref().is_none_or(|l| l[i] != now[i]) {
                body.push_str(&change(&now[i], c.width, &code(i)));
            }
        }
        if r == 0 {
            let _ = write!(vcd, "#{t}\n$dumpvars\n{body}$end\n");
        } else if !body.is_empty() {
            let _ = write!(vcd, "#{t}\n{body}");
        }
        last = Some(now);
    }
    let _ = writeln!(vcd, "#{}", (k0 + g.len() as u64) * p_ns);
    crate::output::write_file(vcd_path, vcd.as_bytes())?;
    let vcd_name = vcd_path
        .file_name()
        .map_or_else(|| "window.vcd".into(), |n| n.to_string_lossy().into_owned());

    // GTKWave save file: the dump, the time range, the primary marker on clock K, then the
    // traces (`@28` binary for 1-bit, `@22` hex for vectors, `@200` a comment row).
    let marker = first.cycle * p_ns;
    let mut gtkw = String::new();
    let _ = writeln!(
        gtkw,
        "[*] tooltouch check: first mismatch at cycle {} ({} ns)",
        first.cycle, first.time_ns
    );
    let _ = writeln!(gtkw, "[dumpfile] \"{vcd_name}\"");
    let _ = writeln!(gtkw, "[timestart] {}", k0 * p_ns);
    let _ = writeln!(
        gtkw,
        "*-{:.6} {marker}{}",
        (p_ns.max(1) as f64).log2() + 2.0,
        " -1".repeat(26)
    );
    let sig = |scope: &str, name: &str, width: u32| {
        format!(
            "{scope}.{name}{}",
            if width > 1 {
                format!("[{}:0]", width - 1)
            } else {
                String::new()
            }
        )
    };
    let differing: Vec<&str> = first.differing.iter().map(|d| d.signal.as_str()).collect();
    let _ = writeln!(gtkw, "@200\n-differing at cycle {}", first.cycle);
    // The Surfer command file's groups, in the save file's order.
    let mut groups = vec![Group {
        title: format!("differing at cycle {}", first.cycle),
        variables: Vec::new(),
    }];
    let ordered = names
        .iter()
        .zip(matches)
        .filter(|(nm, _)| differing.contains(&nm.as_str()))
        .chain(
            names
                .iter()
                .zip(matches)
                .filter(|(nm, _)| !differing.contains(&nm.as_str())),
        );
    let mut others_started = false;
    for (name, m) in ordered {
        if !differing.contains(&name.as_str()) && !others_started {
            let _ = writeln!(gtkw, "@200\n-the other outputs");
            groups.push(Group {
                title: "the other outputs".into(),
                variables: Vec::new(),
            });
            others_started = true;
        }
        let fmt = |w: u32| if w > 1 { "@22" } else { "@28" };
        let _ = writeln!(
            gtkw,
            "{}\n{}",
            fmt(m.widths.0),
            sig("golden.outputs", name, m.widths.0)
        );
        let _ = writeln!(
            gtkw,
            "{}\n{}",
            fmt(m.widths.1),
            sig("dut", name, m.widths.1)
        );
        let _ = writeln!(gtkw, "@28\n{}", sig("differs", name, 1));
        if let Some(g) = groups.last_mut() {
            for scope in ["golden.outputs", "dut", "differs"] {
                g.variables.push(format!("{scope}.{name}"));
            }
        }
    }
    let _ = writeln!(gtkw, "@200\n-golden input pins");
    groups.push(Group {
        title: "golden input pins".into(),
        variables: pins
            .iter()
            .map(|p| format!("golden.inputs.{}", p.rsplit('.').next().unwrap_or(p)))
            .collect(),
    });
    for p in pins {
        let _ = writeln!(
            gtkw,
            "@28\n{}",
            sig("golden.inputs", p.rsplit('.').next().unwrap_or(p), 1)
        );
    }
    if has_mcu {
        let _ = writeln!(gtkw, "@200\n-DUT MCU port");
        groups.push(Group {
            title: "DUT MCU port".into(),
            variables: vec!["dut.mcu_addr".into(), "dut.mcu_rdata".into()],
        });
        let _ = writeln!(
            gtkw,
            "@22\n{}",
            sig("dut", "mcu_addr", tooltouch_hdl_gen::MCU_ADDR_BITS)
        );
        let _ = writeln!(
            gtkw,
            "@22\n{}",
            sig("dut", "mcu_rdata", tooltouch_hdl_gen::MCU_DATA_BITS)
        );
    }
    let gtkw_path = vcd_path.with_extension("gtkw");
    crate::output::write_file(&gtkw_path, gtkw.as_bytes())?;
    let sucl = super::surfer::command_file(&vcd_name, &groups, marker);
    crate::output::write_file(&vcd_path.with_extension("sucl"), sucl.as_bytes())?;
    Ok((vcd_path.to_path_buf(), gtkw_path))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The golden outputs by name, as the report reads them from the dump.
    fn golden(name: &str) -> Option<(u64, u32)> {
        Some(match name {
            "armed" | "confirmed" => (1, 1),
            "faults" => (0b100_0010, 7),
            "decision_position" => (0xff_fffe, 24),
            "charge" => return None,
            _ => (0, 1),
        })
    }

    #[test]
    fn the_expected_word_is_the_register_maps() {
        // STATUS: armed (bit 0), confirmed (bit 6) and the faults word from bit 8.
        assert_eq!(
            mcu_expected(0, &golden, 0).as_deref(),
            Some(format!("0x{:x}", 0b100_0010 << 8 | 1 << 6 | 1).as_str())
        );
        assert_eq!(mcu_expected(2, &golden, 0).as_deref(), Some("0xfffffffe"));
        assert_eq!(mcu_expected(6, &golden, 0), None, "an unknown charge");
        assert_eq!(
            mcu_expected(11, &golden, 0xabcd_0000_0000_0000).as_deref(),
            Some("0xabcd0000")
        );
        assert_eq!(
            mcu_expected(7, &golden, 0).as_deref(),
            Some("0x0 (0x0 with --mcu-diagnostics)")
        );
        assert_eq!(mcu_expected(14, &golden, 0).as_deref(), Some("0x0"));
        assert_eq!(mcu_expected(1 << 40, &golden, 0).as_deref(), Some("0x0"));
    }
}
