//! Random configurations and random run-length pin stimuli for co-simulation property
//! tests: bursts of contact, FES and index pulses, quadrature scale moves (and illegal
//! double steps), arm toggles, glitches shorter than the filter, and several pins
//! changing in the same clock so same-clock edges reach the kernel together.

use crate::stimulus::Stimulus;
use rand::Rng;
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_model::{MeasureConfig, MeasureSettings};

/// A random valid configuration. Ranges are the full valid ones, biased toward values
/// that make things happen within a short stimulus (few pulses per window, small i_def,
/// short glitch filters), with an occasional large one.
pub fn random_config(rng: &mut impl Rng) -> MeasureConfig {
    let pulses_per_rev: u16 = if rng.gen_bool(0.85) {
        rng.gen_range(16..=48)
    } else {
        rng.gen_range(16..=16384)
    };
    let window_revs: u8 = if rng.gen_bool(0.7) {
        rng.gen_range(1..=3)
    } else {
        rng.gen_range(1..=16)
    };
    let window = u32::from(pulses_per_rev) * u32::from(window_revs);
    let i_def = if rng.gen_bool(0.8) {
        rng.gen_range(0..window.min(24))
    } else {
        rng.gen_range(0..window)
    };
    let charge_bits: u8 = rng.gen_range(4..=24);
    let full = (1u32 << charge_bits) - 1;
    let charge_law = if rng.gen_bool(0.5) {
        let step = |rng: &mut dyn rand::RngCore| -> u32 {
            if rng.gen_bool(0.8) {
                (full / rng.gen_range(2..=16)).max(1)
            } else {
                rng.gen_range(1..=full)
            }
        };
        ChargeLaw::Linear {
            charge_step: step(rng),
            discharge_step: step(rng),
        }
    } else {
        let shift = |rng: &mut dyn rand::RngCore| -> u8 {
            if rng.gen_bool(0.8) {
                rng.gen_range(0..=4.min(charge_bits))
            } else {
                rng.gen_range(0..=charge_bits)
            }
        };
        ChargeLaw::Exponential {
            charge_shift: shift(rng),
            discharge_shift: shift(rng),
        }
    };
    let fire_threshold = rng.gen_range(1..=full);
    let rearm_threshold = if rng.gen_bool(0.1) {
        0
    } else {
        rng.gen_range(0..fire_threshold)
    };
    let glitch_cycles: u8 = if rng.gen_bool(0.85) {
        rng.gen_range(0..=6)
    } else {
        rng.gen_range(0..=255)
    };
    let settings = MeasureSettings {
        pulses_per_rev,
        i_def,
        window_revs,
        contact_rule: if rng.gen_bool(0.5) {
            ContactRule::Sampled
        } else {
            ContactRule::Sticky
        },
        charge_bits,
        charge_law,
        fire_threshold,
        rearm_threshold,
        glitch_cycles,
        scale_bits: rng.gen_range(8..=32),
        method: match rng.gen_range(0..3) {
            0 => DecisionMethod::SinglePulse,
            1 => DecisionMethod::Counter,
            _ => DecisionMethod::Density,
        },
    };
    // Every field was drawn inside its documented range.
    settings
        .validate()
        .unwrap_or_else(|e| unreachable!("random settings out of range: {e}"))
}

/// Phase order of the scale lines for positive motion, as pin bits (A leads B).
const SCALE_PHASES: [u8; 4] = [0, pin::SCALE_A, pin::SCALE_A | pin::SCALE_B, pin::SCALE_B];

/// A random pin stimulus of at least `cycles` clocks at `clock_hz` for `config`. Segment
/// lengths scale with the glitch filter (`glitch_cycles + 1` clocks pass it); about one
/// segment in eight is a glitch shorter than that.
pub fn random_stimulus(
    rng: &mut impl Rng,
    config: &MeasureConfig,
    clock_hz: u32,
    cycles: u64,
) -> Stimulus {
    let pass = u64::from(config.settings().glitch_cycles) + 1;
    let mut s = Stimulus::new(clock_hz);
    let mut pins: u8 = 0;
    let mut phase = 0usize;
    s.push(Pins(0), rng.gen_range(1..=8));
    // Arm early, often together with other edges.
    pins |= pin::ARM;
    while s.total_cycles() < cycles {
        let len = if pass > 1 && rng.gen_bool(0.12) {
            rng.gen_range(1..pass)
        } else {
            pass + rng.gen_range(0..=2 * pass + 3)
        };
        s.push(Pins(pins), len);
        // Next levels: several pins may change together.
        if rng.gen_bool(0.6) {
            pins ^= pin::FES;
        }
        if rng.gen_bool(0.2) {
            pins ^= pin::CONTACT;
        }
        if rng.gen_bool(0.06) {
            pins ^= pin::INDEX;
        }
        if rng.gen_bool(0.012) {
            pins ^= pin::ARM;
        }
        if rng.gen_bool(0.3) {
            phase = if rng.gen_bool(0.03) {
                (phase + 2) % 4 // illegal double change
            } else if rng.gen_bool(0.6) {
                (phase + 1) % 4
            } else {
                (phase + 3) % 4
            };
            pins = (pins & !(pin::SCALE_A | pin::SCALE_B)) | SCALE_PHASES[phase];
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use tooltouch_model::FrontEnd;

    #[test]
    fn stimuli_exercise_every_kernel() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let config = MeasureSettings {
            pulses_per_rev: 16,
            i_def: 4,
            ..Default::default()
        }
        .validate()
        .unwrap();
        let s = random_stimulus(&mut rng, &config, 50_000_000, 20_000);
        assert!(s.total_cycles() >= 20_000);
        let mut fe = FrontEnd::new(&config);
        let (mut decided, mut moved, mut counted) = (false, false, false);
        for p in s.cycles() {
            fe.clock(p);
            let o = fe.outputs();
            decided |= o.register_now;
            moved |= o.position != 0;
            counted |= o.count > 0;
        }
        assert!(decided && moved && counted, "{decided} {moved} {counted}");
    }
}
