//! Speed of the golden model against Verilator and Icarus on one realistic measurement
//! stimulus (see `tooltouch_rtl_sim::speed`).
//!
//! `cargo bench --bench speed` runs the criterion benches (model plain, fast-forward,
//! event level, controllers). `cargo bench --bench speed -- --table` (what
//! `cargo xtask bench` runs) prints the comparison table, HDL simulators included.

use criterion::{criterion_group, Criterion, Throughput};
use std::path::PathBuf;
use std::time::Instant;
use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::MeasureConfig;
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_rtl_sim::runner::Simulator;
use tooltouch_rtl_sim::speed::{self, hdl::time_simulator, verilator::time_bare_verilator};

/// Measurements of the closed-loop cycle in the realistic stimulus.
const REPEATS: u32 = 2;
/// Clocks of the stimulus given to Icarus (about 0.5 M clocks/s: the whole stimulus would
/// take minutes).
const ICARUS_CYCLES: u64 = 2_000_000;

fn stimulus(config: &MeasureConfig) -> Stimulus {
    match speed::realistic_stimulus(config, REPEATS) {
        Ok(s) => s,
        Err(e) => panic!("the realistic stimulus: {e:#}"),
    }
}

fn model(c: &mut Criterion) {
    let config = MeasureConfig::default();
    let stim = stimulus(&config);
    let short = speed::prefix(&stim, 20_000_000);
    let mut g = c.benchmark_group("measurement");
    g.sample_size(10);
    g.throughput(Throughput::Elements(short.total_cycles()));
    g.bench_function("cycle_plain_20M", |b| {
        b.iter(|| speed::run_plain(&short, &config))
    });
    g.throughput(Throughput::Elements(stim.total_cycles()));
    g.bench_function("cycle_fast_forward_whole", |b| {
        b.iter(|| speed::run_fast_forward(&stim, &config))
    });
    let events = speed::events(&stim, &config);
    g.throughput(Throughput::Elements(events.len() as u64));
    g.bench_function("event_level_whole", |b| {
        b.iter(|| speed::run_events(&events, &config))
    });
    g.finish();
}

fn control(c: &mut Criterion) {
    let forces = speed::force_sequence(1000);
    let mut g = c.benchmark_group("control_period");
    g.throughput(Throughput::Elements(forces.len() as u64));
    for s in speed::controllers() {
        g.bench_function(format!("{}_step_x1000", s.name()), |b| {
            b.iter(|| speed::run_controller(&s, &forces))
        });
    }
    g.finish();
}

criterion_group!(benches, model, control);

fn row(name: &str, cycles: u64, seconds: f64, verilator: Option<f64>) {
    let cps = cycles as f64 / seconds.max(1e-12);
    let ratio = verilator.map_or("-".to_string(), |v| format!("{:.1}×", cps / v));
    println!(
        "| {name:<50} | {cycles:>12} | {seconds:>9.4} | {:>10.2} | {ratio:>17} |",
        cps / 1e6
    );
}

fn table() {
    let config = MeasureConfig::default();
    let t = Instant::now();
    let stim = stimulus(&config);
    let events = speed::events(&stim, &config);
    println!(
        "stimulus: lathe closed-loop measurement cycle (LatheScenario::default(), {REPEATS} \
         measurements), default MeasureConfig: {} clocks at {} Hz ({:.2} s of machine time), \
         {} segments, {} events; generated in {:.1} s",
        stim.total_cycles(),
        stim.clock_hz,
        stim.total_cycles() as f64 / f64::from(stim.clock_hz),
        stim.segments.len(),
        events.len(),
        t.elapsed().as_secs_f64()
    );
    // Model runs; all must agree.
    let (plain, t_plain) = speed::time(1.0, || speed::run_plain(&stim, &config));
    let ((ff, clocked), t_ff) =
        speed::time(1.0, || speed::run_fast_forward_counted(&stim, &config));
    let (ev_out, t_ev) = speed::time(1.0, || speed::run_events(&events, &config));
    assert_eq!(plain, ff, "fast-forward differs from the plain cycle model");
    assert_eq!(
        ev_out, plain.outputs,
        "event level differs from the cycle level"
    );
    println!(
        "model runs agree: plain and fast-forward give the same edges on every clock (digest \
         {:016x}, {} edge clocks) and the same final outputs as the event level",
        plain.digest, plain.edge_clocks
    );
    // HDL simulators, through the co-simulation runner.
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("speed");
    let bare = time_bare_verilator(&config, &stim, &plain.outputs, &work.join("bare"));
    let verilator = time_simulator(
        Simulator::Verilator,
        &config,
        &stim,
        &work.join("verilator"),
    );
    let icarus_stim = speed::prefix(&stim, ICARUS_CYCLES);
    let icarus = time_simulator(
        Simulator::Icarus,
        &config,
        &icarus_stim,
        &work.join("icarus"),
    );
    // The ratios are against the bare Verilator loop (the fastest Verilator clocks it).
    let v_cps = bare.as_ref().ok().map(|v| v.cycles_per_second());
    println!();
    println!("| engine                                             |       clocks |         s | M clocks/s | vs Verilator bare |");
    println!("|----------------------------------------------------|-------------:|----------:|-----------:|------------------:|");
    row("model, cycle level, plain", plain.cycles, t_plain, v_cps);
    row(
        &format!(
            "model, cycle level, fast-forward ({:.3} % clocked)",
            100.0 * clocked as f64 / ff.cycles as f64
        ),
        ff.cycles,
        t_ff,
        v_cps,
    );
    match &bare {
        Ok(v) => row(
            &format!(
                "Verilator -O3, bare C++ loop (build {:.0} s)",
                v.build_seconds
            ),
            v.cycles,
            v.seconds,
            v_cps,
        ),
        Err(e) => println!("| Verilator bare loop: {e:#}"),
    }
    match &verilator {
        Ok(v) => row(
            &format!("Verilator -O3 testbench (build {:.0} s)", v.build_seconds),
            v.cycles,
            v.seconds,
            v_cps,
        ),
        Err(e) => println!("| Verilator: {e:#}"),
    }
    match &icarus {
        Ok(v) => row(
            &format!(
                "Icarus testbench (first {} M clocks)",
                ICARUS_CYCLES / 1_000_000
            ),
            v.cycles,
            v.seconds,
            v_cps,
        ),
        Err(e) => println!("| Icarus: {e:#}"),
    }
    println!();
    println!(
        "event level: {} events in {:.4} s = {:.1} M events/s",
        events.len(),
        t_ev,
        events.len() as f64 / t_ev / 1e6
    );
    let forces = speed::force_sequence(10_000);
    println!("control period (h = 0.05 s), ns per period:");
    let fs = ForceSettings::default();
    for s in speed::controllers() {
        let (_, t_c) = speed::time(0.3, || speed::run_controller(&s, &forces));
        let settings = ForceSettings {
            controller: s,
            ..fs
        };
        let ev = speed::force_events(&settings, 1000);
        let (_, t_k) = speed::time(0.3, || speed::run_force_kernel(&settings, &ev));
        println!(
            "  {:<9} controller step {:>7.1} ns; whole force kernel (50 ADC samples + tick) {:>8.1} ns",
            s.name(),
            t_c / forces.len() as f64 * 1e9,
            t_k / 1000.0 * 1e9
        );
    }
    println!("state, bytes (size_of):");
    for (name, bytes) in speed::state_bytes() {
        println!("  {name:<40} {bytes:>5}");
    }
    if bare.is_err() || verilator.is_err() || icarus.is_err() {
        std::process::exit(1);
    }
}

fn main() {
    if std::env::args().any(|a| a == "--table") {
        table();
        return;
    }
    benches();
    criterion::Criterion::default()
        .configure_from_args()
        .final_summary();
}
