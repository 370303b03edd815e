//! `tooltouch ranges`' internal registers: they appear beside the outputs with plausible
//! bounds (the PI integrator inside its clamp, and at it when a tighter clamp makes the
//! scenario saturate it; the no-load sums filled by the identification; headroom worked by
//! hand), and the snapshots are the kernel's live state, not a stale or a neighbouring
//! field (the period averages worked from the snapshotted sums are the kernel's outputs).

use tooltouch_model::force::config::{ForceConfig, ForceSettings};
use tooltouch_model::force::control::{ControllerSettings, PiSettings};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::internals::{Internals, Register};
use tooltouch_model::units::Fx;
use tooltouch_model::MeasureConfig;
use tooltouch_plant::drive::scenario::{run, ControlScenario, Engine};
use tooltouch_tune::ranges::{self, Kind, Ranges, RegisterRange};
use tooltouch_tune::scenario::ApproachSettings;

fn ranges_of(force: &ForceConfig) -> Ranges {
    ranges::ranges(
        &MeasureConfig::default(),
        force,
        &ApproachSettings::default(),
        1,
    )
    .unwrap()
}

fn reg<'a>(r: &'a Ranges, name: &str) -> &'a RegisterRange {
    r.registers
        .iter()
        .find(|x| x.name == name)
        .unwrap_or_else(|| panic!("no register {name}"))
}

fn default_force() -> ForceConfig {
    ForceSettings::default().validate().unwrap()
}

#[test]
fn internal_registers_appear_beside_the_outputs_with_plausible_bounds() {
    let r = ranges_of(&default_force());
    assert_eq!(r.format, "tooltouch-ranges-2");
    let internal: Vec<&RegisterRange> = r
        .registers
        .iter()
        .filter(|x| x.kind == Kind::Internal)
        .collect();
    assert!(internal.len() >= 40, "{}", internal.len());
    assert!(internal.iter().any(|x| x.path == "measure"));
    for x in &r.registers {
        assert!(x.samples > 0 && x.min <= x.max, "{x:?}");
        assert!(x.limits.0 <= x.min && x.max <= x.limits.1, "{x:?}");
    }
    // The PI integrator stays inside its clamp (default 0..=255) and, unclamped by the
    // default scenario, never sits at it.
    let pi = reg(&r, "pi.integral");
    assert_eq!(
        (pi.kind, pi.format.as_str(), pi.limits),
        (Kind::Internal, "I32F32 clamp 0..255", (0.0, 255.0))
    );
    assert!(pi.min > 0.0 && pi.max < 255.0 && pi.max > 100.0, "{pi:?}");
    assert_eq!(pi.saturations, 0);
    // The identification (0.1–2.5 s) fills the no-load sums: at 600 and 800 rpm
    // (62.8 and 83.8 rad/s) Σω/n lies between the two speeds.
    let n = reg(&r, "estimator.no_load.n");
    assert!(n.max >= 10.0, "{n:?}");
    let sw = reg(&r, "estimator.no_load.sw");
    assert!(
        sw.max > 60.0 * n.max && sw.max < 84.0 * n.max,
        "{sw:?} {n:?}"
    );
    for s in ["sww", "sy", "swy"] {
        let x = reg(&r, &format!("estimator.no_load.{s}"));
        assert!(x.max > 0.0 && x.format.starts_with('I'), "{x:?}");
    }
    assert_eq!(reg(&r, "estimator.no_load.sww").format, "I96F32");
    // Headroom by hand: a period holds 50 samples (6 of the u16's bits), the glitch
    // counters reach the default 4-clock filter (3 of 8 bits), the no-load sum Σω in
    // I112F16 needs the bits of its integer part and a sign.
    let count = reg(&r, "sampler.count");
    assert_eq!((count.max, count.format.as_str()), (50.0, "u16"));
    assert_eq!(count.headroom_bits, 10);
    let glitch = reg(&r, "glitch.stable[contact]");
    assert_eq!((glitch.max, glitch.headroom_bits), (4.0, 5));
    let need = 64 - (sw.max.floor() as u64).leading_zeros() as i32 + 1;
    assert_eq!(sw.headroom_bits, 112 - need);
    // The sums of a period: at most 50 filtered speeds of at most the largest filtered
    // speed, and more than one of them.
    let (sum, filtered) = (
        reg(&r, "sampler.sums[speed]"),
        reg(&r, "sampler.filtered[speed]"),
    );
    assert!(sum.max <= 50.0 * filtered.max && sum.max > 40.0 * filtered.min);
    // Nothing internal saturates or wraps by default.
    let warned: Vec<&str> = r.saturated().iter().map(|x| x.name.as_str()).collect();
    assert_eq!(warned, ["charge"]);
}

#[test]
fn a_tighter_pi_clamp_holds_the_integrator_at_it() {
    // By default the integrator climbs to about 113 % after the depth step; clamped at
    // 105 % it sits there, and the report says so.
    let mut s = ForceSettings::default();
    let ControllerSettings::Pi(pi) = s.controller else {
        panic!("the default controller is PI")
    };
    s.controller = ControllerSettings::Pi(PiSettings {
        integrator_max: Fx::const_from_int(105),
        ..pi
    });
    let r = ranges_of(&s.validate().unwrap());
    let pi = reg(&r, "pi.integral");
    assert_eq!(pi.format, "I32F32 clamp 0..105");
    assert_eq!(pi.max, 105.0, "{pi:?}");
    assert!(pi.min >= 0.0);
    assert!(pi.saturations > 10, "{pi:?}");
    assert!(r.saturated().iter().any(|x| x.name == "pi.integral"));
}

fn snapshot(k: &ForceKernel) -> Vec<Register> {
    let mut v = Vec::new();
    k.internals(&mut |r| v.push(r));
    v
}

fn raw(regs: &[Register], name: &str) -> i128 {
    regs.iter()
        .find(|r| r.name == name)
        .and_then(|r| r.raw)
        .unwrap_or_else(|| panic!("{name} missing or empty"))
}

/// Over the whole control scenario: the dynamometer's period average worked from the
/// sums and count snapshotted just before each tick is the `force_measured` output after
/// it (and the `sampler.average[force]` register); the PI integrator, the wear filter and
/// the estimator's B are what the kernel's public accessors and outputs say.
#[test]
fn the_snapshots_are_the_kernels_live_registers() {
    let config = default_force();
    let scales = config.settings().scales;
    let recorded = run(&ControlScenario::new(config), Engine::Model, true);
    let mut k = ForceKernel::new(&config);
    let (mut ticks, mut nonzero) = (0, 0);
    for &(_, ev) in &recorded.events {
        let before = snapshot(&k);
        k.apply(ev);
        let after = snapshot(&k);
        let o = k.outputs();
        if ev == ForceEvent::Tick {
            let (sum, n) = (
                raw(&before, "sampler.sums[force]"),
                raw(&before, "sampler.count"),
            );
            assert_eq!(n, i128::from(config.settings().samples_per_period));
            let avg = i64::try_from(sum / n).unwrap();
            assert_eq!(raw(&after, "sampler.average[force]"), i128::from(avg));
            let fx = Fx::from_bits(avg << 24).saturating_mul(scales.force_per_lsb);
            assert_eq!(fx, o.force_measured);
            assert_eq!(raw(&after, "sampler.sums[force]"), 0);
            assert_eq!(
                raw(&after, "wear.filtered"),
                i128::from(o.wear_power.to_bits())
            );
            ticks += 1;
            nonzero += usize::from(avg != 0);
        }
        let pi = match k.controller() {
            tooltouch_model::force::control::Controller::Pi(p) => p.integral(),
            c => panic!("{c:?}"),
        };
        assert_eq!(raw(&after, "pi.integral"), i128::from(pi.to_bits()));
        assert_eq!(
            raw(&after, "estimator.viscous"),
            i128::from(k.estimator().viscous().to_bits())
        );
        assert_eq!(
            raw(&after, "estimate.t_c"),
            i128::from(k.estimate().t_c.to_bits())
        );
    }
    assert_eq!(ticks, 260);
    assert!(nonzero > 150, "{nonzero}");
}
