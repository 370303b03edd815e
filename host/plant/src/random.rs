//! Random configurations and random run-length pin stimuli for co-simulation property
//! tests: bursts of contact, FES and index pulses, quadrature scale moves (and illegal
//! double steps), arm toggles, glitches shorter than the filter, and several pins
//! changing in the same clock so same-clock edges reach the kernel together.

use crate::stimulus::Stimulus;
use rand::{Rng, RngExt};
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_model::{testing, MeasureConfig};

/// A random valid configuration, drawn by the model's test kit with its HDL co-simulation
/// profile (few pulses per window, small `i_def`, short glitch filters, an occasional
/// value across the whole valid range) from one `u64` of `rng`.
pub fn random_config(rng: &mut impl Rng) -> MeasureConfig {
    testing::draw_measure(&testing::MeasureProfile::HDL_COSIM, rng.random())
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
    s.push(Pins(0), rng.random_range(1..=8));
    // Arm early, often together with other edges.
    pins |= pin::ARM;
    while s.total_cycles() < cycles {
        let len = if pass > 1 && rng.random_bool(0.12) {
            rng.random_range(1..pass)
        } else {
            pass + rng.random_range(0..=2 * pass + 3)
        };
        s.push(Pins(pins), len);
        // Next levels: several pins may change together.
        if rng.random_bool(0.6) {
            pins ^= pin::FES;
        }
        if rng.random_bool(0.2) {
            pins ^= pin::CONTACT;
        }
        if rng.random_bool(0.06) {
            pins ^= pin::INDEX;
        }
        if rng.random_bool(0.012) {
            pins ^= pin::ARM;
        }
        if rng.random_bool(0.3) {
            phase = if rng.random_bool(0.03) {
                (phase + 2) % 4 // illegal double change
            } else if rng.random_bool(0.6) {
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
    use tooltouch_model::{FrontEnd, MeasureSettings};

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
