//! Criterion benches of the golden model on a full default `tooltouch measure` stimulus
//! (10 measurements, D = 40 mm, 800 rpm, 50 MHz: about 5·10^8 FPGA clocks).
//!
//! Throughput is in FPGA clocks per second of the stimulus (events per second for the
//! event level):
//! - `cycle_every_clock/first_measurement`: `FrontEnd::clock` once per clock, the RTL
//!   semantics as a plain loop, over the first measurement (≈ 5·10^7 clocks; the whole
//!   run one clock at a time is too long for criterion's samples; the rate is the same);
//! - `cycle_settled_skipping/full_run`: the same results with settled clocks skipped
//!   (`FrontEnd::is_settled`), over the whole run;
//! - `event_level/full_run`: `Measurement::apply` over the run's extracted events;
//! - `closed_loop/full_run`: the lathe simulator and the CNC driver producing the run.
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use tooltouch_model::{FrontEnd, MeasureConfig, Measurement};
use tooltouch_plant::lathe::LatheScenario;
use tooltouch_plant::measurement_cycle::{self, slice};
use tooltouch_plant::stimulus::Stimulus;
use tooltouch_vectors::{clock_through, events_from_stimulus};

fn full_run(c: &mut Criterion) {
    let config = MeasureConfig::default();
    let scenario = LatheScenario::default();
    let run = measurement_cycle::run(&scenario, &config, &mut |_| {}).expect("default run");
    let stimulus = run.stimulus;
    let first = Stimulus {
        clock_hz: stimulus.clock_hz,
        segments: slice(&stimulus, 0, run.measurements[0].end_cycle),
    };
    let events = events_from_stimulus(&stimulus, &config);

    let mut g = c.benchmark_group("cycle_every_clock");
    g.sample_size(10);
    g.throughput(Throughput::Elements(first.total_cycles()));
    g.bench_function("first_measurement", |b| {
        b.iter(|| {
            let mut fe = FrontEnd::new(&config);
            for seg in &first.segments {
                for _ in 0..seg.cycles {
                    black_box(fe.clock(seg.pins));
                }
            }
            black_box(fe.outputs())
        })
    });
    g.finish();

    let mut g = c.benchmark_group("cycle_settled_skipping");
    g.sample_size(10);
    g.throughput(Throughput::Elements(stimulus.total_cycles()));
    g.bench_function("full_run", |b| {
        b.iter(|| {
            black_box(clock_through(&stimulus, &config, |_, _, _, e| {
                black_box(e);
            }))
        })
    });
    g.finish();

    let mut g = c.benchmark_group("event_level");
    g.sample_size(10);
    g.throughput(Throughput::Elements(events.len() as u64));
    g.bench_function("full_run", |b| {
        b.iter(|| {
            let mut m = Measurement::new(&config);
            for e in &events {
                m.apply(e.event);
            }
            black_box(m.outputs())
        })
    });
    g.finish();

    let mut g = c.benchmark_group("closed_loop");
    g.sample_size(10);
    g.throughput(Throughput::Elements(stimulus.total_cycles()));
    g.bench_function("full_run", |b| {
        b.iter(|| black_box(measurement_cycle::run(&scenario, &config, &mut |_| {})))
    });
    g.finish();
}

criterion_group!(benches, full_run);
criterion_main!(benches);
