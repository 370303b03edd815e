//! The fixed-point model against the float reference on the tuning scenarios: a fine
//! configuration follows the reference closely, and coarse choices show up as error.

use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod, MeasureSettings};
use tooltouch_tune::evaluate::{evaluate, model_decision, Outcome};
use tooltouch_tune::reference::{decision_cycle, Intent};
use tooltouch_tune::scenario::{approach, Approach, ApproachSettings};

fn scenarios() -> Vec<Approach> {
    let s = ApproachSettings {
        rpm: 3000.0,
        pulses_per_rev: 256,
        revolutions: 12,
        ..Default::default()
    };
    (1..=3).map(|seed| approach(&s, seed)).collect()
}

fn settings() -> MeasureSettings {
    MeasureSettings {
        pulses_per_rev: 256,
        i_def: 128,
        ..Default::default()
    }
}

fn errors(s: MeasureSettings, a: &[Approach]) -> Vec<(i64, f64)> {
    let c = s.validate().unwrap();
    a.iter()
        .map(|a| match evaluate(a, &c, &Intent::of(&c)) {
            Outcome::Both {
                revolution_error,
                diameter_error_um,
            } => (revolution_error, diameter_error_um),
            other => panic!("{other:?}"),
        })
        .collect()
}

#[test]
fn counter_with_sticky_contact_follows_the_ideal_contact_fraction() {
    let a = scenarios();
    for (rev, diam) in errors(settings(), &a) {
        // The decision lands in the same or an adjacent revolution, within a revolution's
        // feed (1 µm radius, 2 µm diameter) plus a scale count.
        assert!(rev.abs() <= 1, "revolution error {rev}");
        assert!(diam.abs() < 2.2, "diameter error {diam} µm");
    }
}

#[test]
fn density_detector_follows_the_analog_capacitor() {
    let a = scenarios();
    let s = MeasureSettings {
        method: DecisionMethod::Density,
        ..settings()
    };
    for (rev, diam) in errors(s, &a) {
        assert!(rev.abs() <= 1, "revolution error {rev}");
        assert!(diam.abs() < 2.2, "diameter error {diam} µm");
    }
}

#[test]
fn a_glitch_filter_shorter_than_the_spikes_lets_them_decide() {
    // Single-pulse: any contact edge decides. Spikes of up to 3 clocks pass a filter of 0
    // but not one of 4, so the unfiltered model decides on noise, long before the clean
    // first contact.
    let a = scenarios();
    let single = |glitch| MeasureSettings {
        method: DecisionMethod::SinglePulse,
        glitch_cycles: glitch,
        ..settings()
    };
    let filtered: f64 = errors(single(4), &a).iter().map(|e| e.1.abs()).sum();
    let raw: f64 = errors(single(0), &a).iter().map(|e| e.1.abs()).sum();
    assert!(filtered < 1.0 * a.len() as f64, "filtered {filtered}");
    assert!(
        raw > 2.0 * filtered + 1.0,
        "raw {raw} vs filtered {filtered}"
    );
}

#[test]
fn sampled_contact_counts_fewer_pulses_than_sticky() {
    // Sticky counts a pulse with any contact in it, sampled only contact at the edge: the
    // sampled counter decides later (or at the same clock), never earlier.
    let a = scenarios();
    for sc in &a {
        let c = |rule| {
            let s = MeasureSettings {
                contact_rule: rule,
                ..settings()
            };
            model_decision(sc, &s.validate().unwrap()).unwrap().cycle
        };
        assert!(c(ContactRule::Sampled) >= c(ContactRule::Sticky));
        assert!(decision_cycle(sc, &Intent::of(&settings().validate().unwrap())).is_some());
    }
}

#[test]
fn a_four_bit_capacitor_is_coarser_than_a_sixteen_bit_one() {
    let a = scenarios();
    let density = |bits: u8| {
        let full = (1u32 << bits) - 1;
        MeasureSettings {
            method: DecisionMethod::Density,
            charge_bits: bits,
            charge_law: ChargeLaw::Exponential {
                charge_shift: 3,
                discharge_shift: 4,
            },
            fire_threshold: full * 3 / 4,
            rearm_threshold: full / 4,
            ..settings()
        }
    };
    let e = |bits| -> f64 { errors(density(bits), &a).iter().map(|e| e.1.abs()).sum() };
    let (coarse, fine) = (e(4), e(16));
    assert!(coarse > fine, "4-bit {coarse} µm vs 16-bit {fine} µm");
}
