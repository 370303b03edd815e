//! The snapshots read the right field, with the right format, at the right time: each
//! register against the value the kernel's public interface (or a hand computation) gives.

extern crate std;
use super::*;
use crate::force::config::ForceSettings;
use crate::force::control::adaptive::DEFAULT_ADAPTIVE;
use crate::force::control::fuzzy::DEFAULT_FUZZY;
use crate::force::control::pi::DEFAULT_PI;
use crate::force::control::{
    Adaptive, Controller, ControllerSettings, ForceController, Fuzzy, Pi, PiSettings,
};
use crate::force::estimator::settings::{inverse_b, viscous_max, EstimatorSettings};
use crate::force::estimator::Estimator;
use crate::force::events::ForceEvent;
use crate::force::kernel::ForceKernel;
use crate::force::sampling::{AdcCodes, DriveSignals, Sampler};
use crate::force::wear::{allowed_power, ConditionSet, WearMonitor, WearSettings};
use crate::measure::frontend::{pin, FrontEnd, Pins};
use crate::units::Fx;
use crate::MeasureConfig;
use std::vec::Vec;

fn snapshot(k: &dyn Internals) -> Vec<Register> {
    let mut v = Vec::new();
    k.internals(&mut |r| v.push(r));
    v
}

fn get(regs: &[Register], name: &str) -> Register {
    *regs
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("no register {name}"))
}

fn raw(regs: &[Register], name: &str) -> i128 {
    get(regs, name)
        .raw
        .unwrap_or_else(|| panic!("{name} is empty"))
}

fn bits(v: Fx) -> i128 {
    v.to_bits().into()
}

#[test]
fn formats_give_their_words_limits_or_their_clamps() {
    assert_eq!(Format::unsigned(8).limits(), (0, 255));
    assert_eq!(Format::unsigned(32).limits(), (0, u32::MAX.into()));
    assert_eq!(Format::I32F32.limits(), (i64::MIN.into(), i64::MAX.into()));
    assert_eq!(Format::fixed(128, 16).limits(), (i128::MIN, i128::MAX));
    assert_eq!(Format::I32F32.clamped(-3, 7).limits(), (-3, 7));
    assert_eq!(
        (Format::I32F32.frac_bits, Format::I32F32.word_bits),
        (32, 64)
    );
    assert!(Format::I32F32.signed && !Format::unsigned(8).signed);
}

/// Every kernel lists the same registers in the same order, with unique names: the
/// default force kernel's list, and each controller's own.
#[test]
fn names_are_stable_and_unique() {
    let k = ForceKernel::new(&ForceSettings::default().validate().unwrap());
    let names: Vec<&str> = snapshot(&k).iter().map(|r| r.name).collect();
    let channels = ["speed", "power", "force", "volts_sq", "amps_sq"];
    let mut expected: Vec<std::string::String> = Vec::new();
    for part in ["filtered", "sums", "average"] {
        for c in channels {
            expected.push(std::format!("sampler.{part}[{c}]"));
        }
    }
    expected.push("sampler.count".into());
    for e in [
        "omega", "p_o", "v_line", "i_line", "amps_sq", "p_i", "p_g", "p_used", "d_omega", "t_e",
        "t_t", "t_c",
    ] {
        expected.push(std::format!("estimate.{e}"));
    }
    for e in [
        "estimator.no_load.n",
        "estimator.no_load.sw",
        "estimator.no_load.sww",
        "estimator.no_load.sy",
        "estimator.no_load.swy",
        "estimator.viscous",
        "estimator.inv_b",
        "estimator.omega_prev",
        "estimator.hold",
        "pi.integral",
        "wear.filtered",
        "wear.allowed",
        "wear.held",
        "wear.hold_left",
        "wear.over_count",
    ] {
        expected.push(e.into());
    }
    assert_eq!(names, expected);
    let h = Fx::lit("0.05");
    let adaptive = Controller::new(&ControllerSettings::Adaptive(DEFAULT_ADAPTIVE), h, 100);
    let names: Vec<&str> = snapshot(&adaptive).iter().map(|r| r.name).collect();
    assert_eq!(
        names,
        [
            "adaptive.feed",
            "adaptive.gain_estimate",
            "adaptive.controller_gain"
        ]
    );
    let fuzzy = Controller::new(&ControllerSettings::Fuzzy(DEFAULT_FUZZY), h, 100);
    let names: Vec<&str> = snapshot(&fuzzy).iter().map(|r| r.name).collect();
    assert_eq!(names, ["fuzzy.u", "fuzzy.e_prev"]);
    let fe = FrontEnd::new(&MeasureConfig::default());
    let names: Vec<&str> = snapshot(&fe).iter().map(|r| r.name).collect();
    let mut expected: Vec<std::string::String> = pin::NAMES
        .iter()
        .map(|p| std::format!("glitch.stable[{p}]"))
        .collect();
    expected.push("counter.revs_in_window".into());
    expected.push("checks.rev_pulses".into());
    expected.push("checks.confirm_left".into());
    assert_eq!(names, expected);
}

/// The period's sums and count just before a tick are the averages the tick returns;
/// after it the averages are the `average` registers and the sums restart.
#[test]
fn the_samplers_sums_and_count_give_its_averages() {
    let mut s = Sampler::new(2);
    let mut last_speed = 0;
    for k in 0..7u16 {
        let adc = AdcCodes {
            speed: 1000 + 37 * k,
            power: 300 + k * k,
            force: 2048 + 11 * k,
            volts: [2048 + k, 2048 - 2 * k, 2048],
            amps: [2048 + 3 * k, 2048 - k],
        };
        s.on_sample(&adc);
        last_speed = adc.speed;
    }
    let before = snapshot(&s);
    assert_eq!(raw(&before, "sampler.count"), 7);
    let a = s.on_tick();
    for (c, avg) in [
        ("speed", a.speed),
        ("power", a.power),
        ("force", a.force),
        ("volts_sq", a.volts_sq),
        ("amps_sq", a.amps_sq),
    ] {
        let sum = raw(&before, &std::format!("sampler.sums[{c}]"));
        assert_eq!(sum / 7, i128::from(avg), "{c}");
        assert_ne!(sum, 0, "{c}");
    }
    let after = snapshot(&s);
    assert_eq!(raw(&after, "sampler.average[speed]"), i128::from(a.speed));
    assert_eq!(
        raw(&after, "sampler.average[amps_sq]"),
        i128::from(a.amps_sq)
    );
    assert_eq!(raw(&after, "sampler.sums[power]"), 0);
    assert_eq!(raw(&after, "sampler.count"), 0);
    // The low-pass state: below the last code (a rising ramp through a 2^-2 low-pass).
    let y = raw(&after, "sampler.filtered[speed]");
    assert!(y > 1000 << 8 && y < i128::from(last_speed) << 8, "{y}");
    let f = get(&after, "sampler.filtered[speed]").format;
    assert_eq!((f.word_bits, f.frac_bits, f.clamp), (64, 8, None));
}

#[test]
fn the_estimators_no_load_sums_are_its_steady_periods() {
    let h = Fx::lit("0.05");
    let settings = EstimatorSettings::default();
    let mut e = Estimator::new(&settings, h);
    let regs = snapshot(&e);
    assert_eq!(get(&regs, "estimator.omega_prev").raw, None);
    let omega = Fx::const_from_int(60);
    // No measured power, an air-gap power of 1.5·4·50 = 300 W: F9 switches to the fast
    // estimate and holds it.
    let sig = DriveSignals {
        omega,
        p_o: Fx::ZERO,
        force_measured: Fx::ZERO,
        v_line: Fx::const_from_int(50),
        i_line: Fx::const_from_int(4),
        amps_sq: Fx::ZERO,
    };
    e.start_identification();
    let mut est = e.step(&sig);
    for _ in 0..4 {
        est = e.step(&sig);
    }
    // Five steady periods, the first without a steady one before it: four collected.
    let regs = snapshot(&e);
    let w16 = bits(omega) >> 16;
    let y16 = bits(est.p_g.checked_div(omega).unwrap()) >> 16;
    assert_eq!(raw(&regs, "estimator.no_load.n"), 4);
    assert_eq!(raw(&regs, "estimator.no_load.sw"), 4 * w16);
    assert_eq!(raw(&regs, "estimator.no_load.sww"), 4 * w16 * w16);
    assert_eq!(raw(&regs, "estimator.no_load.sy"), 4 * y16);
    assert_eq!(raw(&regs, "estimator.no_load.swy"), 4 * w16 * y16);
    assert_eq!(get(&regs, "estimator.no_load.sww").format.frac_bits, 32);
    assert_eq!(get(&regs, "estimator.no_load.sy").format.frac_bits, 16);
    assert_eq!(raw(&regs, "estimator.omega_prev"), bits(omega));
    assert_eq!(
        raw(&regs, "estimator.hold"),
        i128::from(settings.slip_hold_periods) - 1
    );
    let viscous = get(&regs, "estimator.viscous");
    assert_eq!(viscous.raw, Some(bits(e.viscous())));
    assert_eq!(
        viscous.format.clamp,
        Some((0, bits(viscous_max(settings.inertia, h))))
    );
    assert_eq!(
        raw(&regs, "estimator.inv_b"),
        bits(inverse_b(e.viscous(), settings.inertia, h))
    );
}

#[test]
fn the_controllers_accumulators_are_their_states() {
    let h = Fx::lit("0.05");
    let f = Fx::const_from_int;
    // A PI whose integrator may not pass 120 %: a large error winds it up to the clamp.
    let s = PiSettings {
        integrator_max: f(120),
        ..DEFAULT_PI
    };
    let mut pi = Pi::new(&s, h, 100);
    let regs = snapshot(&pi);
    assert_eq!(raw(&regs, "pi.integral"), bits(f(100)));
    assert_eq!(
        get(&regs, "pi.integral").format.clamp,
        Some((0, bits(f(120))))
    );
    pi.step(f(500), f(480));
    assert_eq!(raw(&snapshot(&pi), "pi.integral"), bits(pi.integral()));
    assert_ne!(pi.integral(), f(100));
    for _ in 0..200 {
        pi.step(f(500), f(300));
    }
    assert_eq!(raw(&snapshot(&pi), "pi.integral"), bits(f(120)));

    let mut a = Adaptive::new(&DEFAULT_ADAPTIVE, h, 100);
    for k in 0..5 {
        a.step(f(500), f(400 + 20 * k));
    }
    let regs = snapshot(&a);
    assert_eq!(raw(&regs, "adaptive.feed"), bits(a.override_state()));
    assert_eq!(
        raw(&regs, "adaptive.gain_estimate"),
        bits(a.gain_estimate())
    );
    assert_eq!(
        raw(&regs, "adaptive.controller_gain"),
        bits(a.controller_gain())
    );
    assert_ne!(a.gain_estimate(), DEFAULT_ADAPTIVE.initial_gain);
    assert_eq!(
        get(&regs, "adaptive.gain_estimate").format.clamp,
        Some((
            bits(DEFAULT_ADAPTIVE.gain_min),
            bits(DEFAULT_ADAPTIVE.gain_max)
        ))
    );
    assert_eq!(
        get(&regs, "adaptive.feed").format.clamp,
        Some((0, bits(f(255))))
    );
    assert_eq!(get(&regs, "adaptive.controller_gain").format.clamp, None);

    let mut z = Fuzzy::new(&DEFAULT_FUZZY, 100);
    assert_eq!(get(&snapshot(&z), "fuzzy.e_prev").raw, None);
    z.step(f(500), f(380));
    let regs = snapshot(&z);
    assert_eq!(raw(&regs, "fuzzy.e_prev"), bits(f(120)));
    assert_eq!(raw(&regs, "fuzzy.u"), bits(z.override_state()));
    assert_ne!(z.override_state(), f(100));
    assert_eq!(get(&regs, "fuzzy.u").format.clamp, Some((0, bits(f(255)))));
}

#[test]
fn the_wear_monitors_registers_follow_a_lowering_selection() {
    let f = Fx::const_from_int;
    let mut s = WearSettings::default();
    s.sets[1] = ConditionSet {
        mean_power_limit: f(800),
        idle_power: f(200),
    };
    s.set_count = 2;
    let mut w = WearMonitor::new(&s);
    assert_eq!(get(&snapshot(&w), "wear.filtered").raw, None);
    let high = w.status().allowed;
    for _ in 0..3 {
        w.step(f(5000));
    }
    let regs = snapshot(&w);
    assert_eq!(raw(&regs, "wear.filtered"), bits(w.status().power));
    assert_eq!(raw(&regs, "wear.over_count"), 3);
    assert_eq!(raw(&regs, "wear.allowed"), bits(high));
    assert_eq!(raw(&regs, "wear.hold_left"), 0);
    assert!(w.select(1));
    w.step(f(100));
    let regs = snapshot(&w);
    // 200 + 800 / 0.8 ≈ 1200 W selected, the previous threshold held one period less.
    let low = allowed_power(&s.sets[1], s.efficiency);
    assert!(low > f(1199) && low < f(1201));
    assert_eq!(raw(&regs, "wear.allowed"), bits(low));
    assert_eq!(raw(&regs, "wear.held"), bits(high));
    assert_eq!(
        raw(&regs, "wear.hold_left"),
        i128::from(s.settle_periods) - 1
    );
    assert_eq!(get(&regs, "wear.over_count").format, Format::unsigned(8));
}

#[test]
fn the_glitch_counters_and_the_revolution_count_are_the_front_ends() {
    let mut fe = FrontEnd::new(&MeasureConfig::default());
    // Armed (after the 3 + 4 clocks of latency), then an index pulse counted while the
    // contact line starts to change.
    for _ in 0..10 {
        fe.clock(Pins(pin::ARM));
    }
    for _ in 0..10 {
        fe.clock(Pins(pin::ARM | pin::INDEX));
    }
    for _ in 0..4 {
        fe.clock(Pins(pin::ARM | pin::CONTACT));
    }
    let regs = snapshot(&fe);
    // CONTACT in sync2 for two clocks: its counter is at 2; INDEX fell two clocks ago.
    assert_eq!(raw(&regs, "glitch.stable[contact]"), 2);
    assert_eq!(raw(&regs, "glitch.stable[index]"), 2);
    assert_eq!(raw(&regs, "glitch.stable[arm]"), 0);
    assert_eq!(
        raw(&regs, "counter.revs_in_window"),
        i128::from(fe.measurement().counter().revs_in_window())
    );
    assert!(fe.outputs().armed);
    assert_eq!(fe.outputs().revolutions, 1);
}

/// The force kernel's estimate registers are the last period's estimate.
#[test]
fn the_force_kernels_estimate_registers_are_the_last_periods() {
    let mut k = ForceKernel::new(&ForceSettings::default().validate().unwrap());
    let adc = AdcCodes {
        speed: 1200,
        power: 400,
        force: 2100,
        volts: [2448, 1848, 1848],
        amps: [2148, 1998],
    };
    for _ in 0..50 {
        k.apply(ForceEvent::Sample(adc));
    }
    k.apply(ForceEvent::Tick);
    let regs = snapshot(&k);
    let e = *k.estimate();
    for (name, v) in [
        ("estimate.omega", e.signals.omega),
        ("estimate.p_o", e.signals.p_o),
        ("estimate.v_line", e.signals.v_line),
        ("estimate.i_line", e.signals.i_line),
        ("estimate.amps_sq", e.signals.amps_sq),
        ("estimate.p_i", e.p_i),
        ("estimate.p_g", e.p_g),
        ("estimate.p_used", e.p_used),
        ("estimate.d_omega", e.d_omega),
        ("estimate.t_e", e.t_e),
        ("estimate.t_t", e.t_t),
        ("estimate.t_c", e.t_c),
    ] {
        assert_eq!(raw(&regs, name), bits(v), "{name}");
    }
    assert_ne!(e.p_i, e.p_g, "distinct values, so a swap shows");
    assert_eq!(raw(&regs, "sampler.average[speed]"), 1200 << 8);
    assert_eq!(raw(&regs, "wear.filtered"), bits(k.outputs().wear_power));
}
