//! Criterion benches of the golden model.
use criterion::{criterion_group, criterion_main, Criterion};
use tooltouch_model::{FrontEnd, MeasureConfig, Pins};

fn cycle_level(c: &mut Criterion) {
    let config = MeasureConfig::default();
    c.bench_function("frontend_clock_idle_1k", |b| {
        let mut fe = FrontEnd::new(&config);
        b.iter(|| {
            for k in 0..1000u32 {
                fe.clock(Pins((k >> 4) as u8 & 0x3f));
            }
        })
    });
}

criterion_group!(benches, cycle_level);
criterion_main!(benches);
