//! Criterion benches of the force path: ns per control period for each controller (its
//! 20 Hz `step` alone), the kernel's tick (one ADC sample + the tick: estimator,
//! controller, wear monitor), and one ADC sample (the 1 kHz handler's work).
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::force::control::adaptive::DEFAULT_ADAPTIVE;
use tooltouch_model::force::control::fuzzy::DEFAULT_FUZZY;
use tooltouch_model::force::control::pi::DEFAULT_PI;
use tooltouch_model::force::control::{Controller, ControllerSettings, ForceController};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::force::sampling::AdcCodes;
use tooltouch_model::units::Fx;

fn controllers(c: &mut Criterion) {
    let h = Fx::lit("0.05");
    for settings in [
        ControllerSettings::Pi(DEFAULT_PI),
        ControllerSettings::Adaptive(DEFAULT_ADAPTIVE),
        ControllerSettings::Fuzzy(DEFAULT_FUZZY),
    ] {
        // a force sequence that exercises the whole rule table / gain update
        let forces: Vec<Fx> = (0..64i32)
            .map(|i| Fx::from_num(500 + (i * 37) % 120 - 60 + if i % 16 < 8 { 150 } else { -150 }))
            .collect();
        c.bench_function(&format!("control_period_{}", settings.name()), |b| {
            let mut ctl = Controller::new(&settings, h, 100);
            let mut i = 0usize;
            b.iter(|| {
                i = (i + 1) % forces.len();
                black_box(ctl.step(black_box(Fx::from_num(500)), black_box(forces[i])))
            })
        });
    }
}

fn kernel_period(c: &mut Criterion) {
    for (name, settings) in [
        ("pi", ControllerSettings::Pi(DEFAULT_PI)),
        ("adaptive", ControllerSettings::Adaptive(DEFAULT_ADAPTIVE)),
        ("fuzzy", ControllerSettings::Fuzzy(DEFAULT_FUZZY)),
    ] {
        let config = ForceSettings {
            controller: settings,
            ..Default::default()
        }
        .validate()
        .unwrap();
        c.bench_function(&format!("kernel_tick_{name}"), |b| {
            let mut k = ForceKernel::new(&config);
            k.apply(ForceEvent::Control(true));
            let codes = AdcCodes {
                speed: 1676,
                power: 480,
                force: 2548,
                volts: [3000, 1500, 1600],
                amps: [2500, 1700],
            };
            b.iter(|| {
                k.apply(ForceEvent::Sample(black_box(codes)));
                k.apply(ForceEvent::Tick);
                black_box(k.outputs())
            })
        });
    }
    c.bench_function("kernel_sample", |b| {
        let mut k = ForceKernel::new(&ForceSettings::default().validate().unwrap());
        let codes = AdcCodes::default();
        b.iter(|| k.apply(ForceEvent::Sample(black_box(codes))))
    });
}

criterion_group!(benches, controllers, kernel_period);
criterion_main!(benches);
