//! Reading speed of `tooltouch check` on a large DUT dump: the generated RTL under
//! Verilator, dumped once as FST (`--trace-fst`, `+fst`) and once as VCD (`--trace`,
//! `+vcd`), each checked against the golden VCD of the same stimulus: the stress stimulus
//! of the default configuration (seed 1) with `TOOLTOUCH_CHECK_BENCH_CYCLES` clocks of
//! constrained-random tail (default 2 000 000), whose outputs change often (the lathe
//! run's first millions of clocks hardly change an output).
//!
//! `cargo bench --bench check_read` prints, per format, the dump's size, the compared
//! changes in it (DUT side), and MB/s of DUT file and changes/s of the whole `check`
//! (golden file included: the golden VCD, and for the FST dump also the same golden trace
//! as FST; FST best of three, VCD one run), then runs the criterion benches of the FST path
//! (throughput in bytes of the DUT file; the VCD path takes tens of seconds a run).
//! Building the two Verilator testbenches and running them takes a minute or two before
//! the first figure.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tooltouch_model::MeasureConfig;
use tooltouch_rtl_sim::cosim::{cosim, CosimPlan};
use tooltouch_rtl_sim::runner::{CxxOpt, Simulator, Trace};
use tooltouch_vectors::check::{check_files, CheckOptions, Verdict};
use tooltouch_vectors::vcd::{output_signals, Changes, Declarations, VcdReader};

/// The DUT's top scope in a Verilator dump of the generated testbench.
const DUT_SCOPE: &str = "TOP.tt_testbench.dut";

struct Fixture {
    _work: tempfile::TempDir,
    golden: PathBuf,
    /// The same golden trace as FST.
    golden_fst: PathBuf,
    dumps: Vec<(&'static str, PathBuf)>,
}

fn fixture() -> Fixture {
    let cycles: u64 = std::env::var("TOOLTOUCH_CHECK_BENCH_CYCLES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2_000_000);
    let config = MeasureConfig::default();
    let size = tooltouch_plant::stress::StressSize {
        random_cycles: cycles,
        ..Default::default()
    };
    let stim = tooltouch_plant::stress::stress_stimulus(&config, 1, 50_000_000, &size);
    let work = tempfile::tempdir().expect("temporary folder");
    let golden = work.path().join("golden.vcd");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&golden).expect("golden.vcd"));
    tooltouch_vectors::vcd::write_golden(&mut f, &stim, &config, None).expect("golden.vcd");
    drop(f);
    let golden_fst = work.path().join("golden.fst");
    let f = std::io::BufWriter::new(std::fs::File::create(&golden_fst).expect("golden.fst"));
    tooltouch_vectors::fst::write_golden_fst(f, &stim, &config, None).expect("golden.fst");
    let mut dumps = Vec::new();
    for (format, trace, plusarg, file) in [
        ("FST", Trace::Fst, "+fst", "dut.fst"),
        ("VCD", Trace::Vcd, "+vcd", "dut.vcd"),
    ] {
        let dir = work.path().join(format);
        let plan = CosimPlan {
            simulators: vec![Simulator::Verilator],
            opt: CxxOpt::O1,
            plusargs: vec![plusarg.into()],
            trace,
            ..CosimPlan::default()
        };
        let t = Instant::now();
        let report = cosim(&config, std::slice::from_ref(&stim), &dir, &plan)
            .unwrap_or_else(|e| panic!("Verilator {format} run: {e}"));
        assert!(report.runs[0].passed, "{}", report.runs[0].output);
        eprintln!(
            "Verilator --trace{}: {} clocks built and run in {:.1} s",
            if trace == Trace::Fst { "-fst" } else { "" },
            stim.total_cycles(),
            t.elapsed().as_secs_f64()
        );
        dumps.push((format, dir.join("case0").join(file)));
    }
    Fixture {
        _work: work,
        golden,
        golden_fst,
        dumps,
    }
}

/// The code indexes of the DUT's outputs in `d`.
fn compared(d: &Declarations) -> Vec<usize> {
    let config = MeasureConfig::default();
    let names: HashSet<&str> = output_signals(&config).iter().map(|(n, _)| *n).collect();
    d.signals
        .iter()
        .filter(|s| s.scope.join(".") == DUT_SCOPE && names.contains(s.name.as_str()))
        .filter_map(|s| d.code_index(&s.id))
        .collect()
}

/// The changes of the compared DUT outputs in the dump at `path`.
fn compared_changes(path: &Path) -> u64 {
    let name = path.display().to_string();
    let mut n = 0u64;
    if path.extension().is_some_and(|e| e == "fst") {
        let (d, mut c) = tooltouch_vectors::fst::open(path, &name).expect("dut.fst");
        c.select(&compared(&d));
        while c.next_change().expect("dut.fst").is_some() {
            n += 1;
        }
    } else {
        let file = std::fs::File::open(path).expect("dut.vcd");
        let mut r = VcdReader::new(std::io::BufReader::with_capacity(1 << 20, file), &name)
            .expect("dut.vcd");
        let wanted: HashSet<usize> = compared(r.declarations()).into_iter().collect();
        while let Some((_, code, _)) = r.next_change().expect("dut.vcd") {
            n += u64::from(wanted.contains(&code));
        }
    }
    n
}

fn check(golden: &Path, dut: &Path) {
    let report = check_files(golden, dut, &CheckOptions::default()).expect("check");
    assert!(
        matches!(report.verdict, Verdict::Match(_)),
        "{:?}",
        report.verdict
    );
}

fn table(f: &Fixture) {
    println!(
        "check reading speed (golden {:.1} MB VCD, {:.1} MB FST):",
        size(&f.golden) as f64 / 1e6,
        size(&f.golden_fst) as f64 / 1e6
    );
    println!(
        "  {:<4} {:<6} {:>10} {:>14} {:>10} {:>10} {:>14}",
        "dump", "golden", "MB", "changes", "s", "MB/s", "changes/s"
    );
    for (format, path) in &f.dumps {
        let changes = compared_changes(path);
        let goldens: &[(&str, &PathBuf)] = if *format == "FST" {
            &[("VCD", &f.golden), ("FST", &f.golden_fst)]
        } else {
            &[("VCD", &f.golden)]
        };
        for (golden_format, golden) in goldens {
            let runs = if *format == "FST" { 3 } else { 1 };
            let best = (0..runs)
                .map(|_| {
                    let t = Instant::now();
                    check(golden, path);
                    t.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min);
            let mb = size(path) as f64 / 1e6;
            println!(
                "  {format:<4} {golden_format:<6} {mb:>10.1} {changes:>14} {best:>10.3} {:>10.0} {:>14.3e}",
                mb / best,
                changes as f64 / best
            );
        }
    }
}

fn size(path: &Path) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}

fn read(c: &mut Criterion) {
    let f = fixture();
    table(&f);
    let mut g = c.benchmark_group("check_read");
    g.sample_size(10);
    for (format, path) in f.dumps.iter().filter(|(f, _)| *f == "FST") {
        g.throughput(Throughput::Bytes(size(path)));
        g.bench_function(format!("verilator_{format}_golden_vcd"), |b| {
            b.iter(|| check(&f.golden, path))
        });
        g.bench_function(format!("verilator_{format}_golden_fst"), |b| {
            b.iter(|| check(&f.golden_fst, path))
        });
    }
    g.finish();
}

criterion_group!(benches, read);
criterion_main!(benches);
