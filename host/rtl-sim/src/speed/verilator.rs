//! Verilator with nothing around it: the generated design (written by
//! [`crate::write_design`] from `tooltouch_hdl_gen::generate`) compiled with a minimal
//! C++ loop that sets the pins of each stimulus segment and toggles the clock, no
//! testbench, no per-cycle compare, no timing scheduler — the fastest Verilator can clock
//! this design, so the fairest yardstick for "cycles per second". C++ at `-O3`
//! (docs/architecture.md, pitfalls). The loop alone is timed (in C++, `steady_clock`); correctness
//! is checked on the outputs after the last clock, against the model's.
//!
//! The co-simulation runner ([`crate::runner`]) has no such mode (its testbench
//! always compares), hence this one build function; everything else is the runner's.

use super::hdl::HdlSpeed;
use crate::runner::{find_tool, Simulator};
use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use tooltouch_hdl_gen::{generate, output_fields, output_values, Options, TOP};
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::MeasureConfig;
use tooltouch_model::MeasureOutputs;
use tooltouch_plant::stimulus::Stimulus;

fn main_cpp(config: &MeasureConfig) -> String {
    let mut set_pins = String::new();
    for (i, n) in pin::NAMES.iter().enumerate() {
        let _ = writeln!(set_pins, "        top->pin_{n} = (pins >> {i}) & 1;");
    }
    let mut print = String::new();
    for f in output_fields(config) {
        let _ = writeln!(
            print,
            "    printf(\" %llx\", (unsigned long long)top->{});",
            f.name
        );
    }
    format!(
        r#"// Bare Verilator loop for tooltouch's speed table: pins per segment, clock, no compare.
#include "V{TOP}.h"
#include "verilated.h"
#include <chrono>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {{
    Verilated::commandArgs(argc, argv);
    if (argc < 2) {{ fprintf(stderr, "usage: bare SEGMENTS\n"); return 2; }}
    FILE* f = fopen(argv[1], "r");
    if (!f) {{ perror(argv[1]); return 2; }}
    std::vector<std::pair<unsigned, unsigned long long>> segs;
    unsigned p; unsigned long long n;
    while (fscanf(f, "%x %llu", &p, &n) == 2) segs.push_back({{p, n}});
    fclose(f);
    V{TOP}* top = new V{TOP};
    top->clk = 0; top->rst = 0; top->mcu_addr = 0;
    top->eval();
    unsigned long long k = 0;
    auto t0 = std::chrono::steady_clock::now();
    for (auto& s : segs) {{
        unsigned pins = s.first;
{set_pins}        for (unsigned long long i = 0; i < s.second; ++i) {{
            top->clk = 1; top->eval();
            top->clk = 0; top->eval();
        }}
        k += s.second;
    }}
    auto t1 = std::chrono::steady_clock::now();
    double secs = std::chrono::duration<double>(t1 - t0).count();
    printf("BARE %llu %.9f", k, secs);
{print}    printf("\n");
    top->final();
    delete top;
    return 0;
}}
"#
    )
}

/// Builds the bare Verilator loop in `work` and runs it on `stimulus`; fails when its
/// outputs after the last clock differ from `expected` (the model's).
pub fn time_bare_verilator(
    config: &MeasureConfig,
    stimulus: &Stimulus,
    expected: &MeasureOutputs,
    work: &Path,
) -> Result<HdlSpeed> {
    find_tool("verilator")?;
    let rtl = work.join("rtl");
    let design = generate(config, &Options::default());
    let files = crate::write_design(&rtl, &design, None)?;
    let main = work.join("bare_main.cpp");
    std::fs::write(&main, main_cpp(config)).with_context(|| format!("{}", main.display()))?;
    let mut segs = String::new();
    for s in &stimulus.segments {
        let _ = writeln!(segs, "{:x} {}", s.pins.0, s.cycles);
    }
    let seg_file = work.join("segments.txt");
    std::fs::write(&seg_file, segs).with_context(|| format!("{}", seg_file.display()))?;
    let mdir = work.join("obj_bare");
    let t = std::time::Instant::now();
    let out = Command::new("verilator")
        .args([
            "--cc",
            "--exe",
            "--build",
            "-O3",
            "-j",
            "2",
            "--top-module",
            TOP,
        ])
        .arg("-Mdir")
        .arg(&mdir)
        .args([
            "-o",
            "bare",
            "-MAKEFLAGS",
            "OPT_FAST=-O3 OPT_GLOBAL=-O3 OPT_SLOW=-O3",
        ])
        .args(&files)
        .arg(&main)
        .output()
        .context("starting verilator")?;
    if !out.status.success() {
        bail!(
            "verilator (bare loop) failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let build_seconds = t.elapsed().as_secs_f64();
    let out = Command::new(mdir.join("bare"))
        .arg(&seg_file)
        .output()
        .context("running the bare Verilator loop")?;
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("BARE "))
        .with_context(|| format!("bare Verilator loop printed no result: {text}"))?;
    let w: Vec<&str> = line.split_whitespace().collect();
    let cycles: u64 = w.get(1).and_then(|s| s.parse().ok()).context("cycles")?;
    let seconds: f64 = w.get(2).and_then(|s| s.parse().ok()).context("seconds")?;
    let want = output_values(config, expected);
    for (i, f) in output_fields(config).iter().enumerate() {
        let got = w
            .get(3 + i)
            .and_then(|s| u64::from_str_radix(s, 16).ok())
            .with_context(|| format!("output {}", f.name))?;
        if got != want[i] {
            bail!(
                "bare Verilator after cycle {}: signal {} expected {:#x} got {got:#x}",
                cycles.saturating_sub(1),
                f.name,
                want[i]
            );
        }
    }
    Ok(HdlSpeed {
        simulator: Simulator::Verilator,
        cycles,
        seconds,
        build_seconds,
    })
}
