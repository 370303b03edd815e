//! Float reference of the measurement front end: the decision the papers' analog devices
//! would take on the *clean* contact signal in continuous time — no synchronizer, no glitch
//! filter, no encoder quantisation, no finite word length — with the *intended* rates and
//! thresholds ([`Intent`]: "charge over 32 pulses, fire at 75 %"), not the integer steps a
//! given `charge_bits` can hold. The fixed-point model's error is measured against it, so
//! a word length too short for the intended law shows up as error.
//!
//! - **Counter** (docs/domain.md §2.3, eq. S9): the ideal contact fraction of the current
//!   window; the decision is the instant the contact time since the window's index pulse
//!   exceeds `i_def / window_pulses` of the window's duration.
//! - **Density** (docs/domain.md §2.4): an analog RC capacitor over spindle angle (so, like the
//!   digital one, independent of speed), charge `q ∈ [0, 1]` of full scale: linear law
//!   `dq/dθ = +1/charge_pulses` per pulse angle in contact, `−1/discharge_pulses`
//!   without; exponential law `dq/dθ = (1 − q)/τ_c` and `−q/τ_d` with
//!   `τ = −1/ln(1 − 2^−shift)` pulses (the continuous law whose per-pulse step is the
//!   digital `distance >> shift`; shift 0 jumps to the end at once). The decision is the
//!   first upward crossing of the fire fraction.
//! - **Single pulse** (docs/domain.md §2.1): the first clean contact after the arm.

use super::scenario::Approach;
use tooltouch_model::measure::config::{ChargeLaw, DecisionMethod, MeasureConfig};

/// The analog capacitor's law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnalogLaw {
    /// Constant rates, fraction of full scale per pulse angle.
    Linear {
        /// Charging rate.
        charge_per_pulse: f64,
        /// Discharging rate.
        discharge_per_pulse: f64,
    },
    /// RC-like, time constants from the shifts.
    Exponential {
        /// Charge shift.
        charge_shift: u8,
        /// Discharge shift.
        discharge_shift: u8,
    },
}

/// What a configuration is meant to do, in real numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intent {
    /// Decision method.
    pub method: DecisionMethod,
    /// Counting window, revolutions.
    pub window_revs: u8,
    /// Counter: decide when the window's contact fraction exceeds this.
    pub count_fraction: f64,
    /// Density: the capacitor's law.
    pub law: AnalogLaw,
    /// Density: fire when the charge reaches this fraction of full scale.
    pub fire_fraction: f64,
}

impl Intent {
    /// The intent a configuration's integers stand for exactly (steps/full, threshold/full).
    pub fn of(config: &MeasureConfig) -> Intent {
        let s = config.settings();
        let full = f64::from(config.full_charge());
        Intent {
            method: s.method,
            window_revs: s.window_revs,
            count_fraction: f64::from(s.i_def) / f64::from(config.window_pulses()),
            law: match s.charge_law {
                ChargeLaw::Linear {
                    charge_step,
                    discharge_step,
                } => AnalogLaw::Linear {
                    charge_per_pulse: f64::from(charge_step) / full,
                    discharge_per_pulse: f64::from(discharge_step) / full,
                },
                ChargeLaw::Exponential {
                    charge_shift,
                    discharge_shift,
                } => AnalogLaw::Exponential {
                    charge_shift,
                    discharge_shift,
                },
            },
            fire_fraction: f64::from(s.fire_threshold) / full,
        }
    }
}

/// The reference decision instant, fractional clocks from power-on, or `None` when the
/// reference never decides within the approach.
pub fn decision_cycle(a: &Approach, intent: &Intent) -> Option<f64> {
    let arm = a.arm_cycle as f64;
    let end = a.stimulus.total_cycles() as f64;
    match intent.method {
        DecisionMethod::SinglePulse => a.contact.iter().map(|&(x, _)| x).find(|&x| x >= arm),
        DecisionMethod::Counter => {
            let w = usize::from(intent.window_revs);
            let fraction = intent.count_fraction;
            let mut i = 0;
            while i < a.index_cycles.len() {
                let start = a.index_cycles[i] as f64;
                let stop = a.index_cycles.get(i + w).map_or(end, |&k| k as f64);
                let limit = fraction * (stop - start);
                let mut acc = 0.0;
                for &(x, y) in &a.contact {
                    let (x, y) = (x.max(start), y.min(stop));
                    if x >= y {
                        continue;
                    }
                    if acc + (y - x) > limit {
                        return Some(x + (limit - acc));
                    }
                    acc += y - x;
                }
                i += w;
            }
            None
        }
        DecisionMethod::Density => {
            let fire = intent.fire_fraction;
            let cpp = a.cycles_per_rev / f64::from(a.pulses_per_rev);
            let tau = |shift: u8| {
                if shift == 0 {
                    0.0
                } else {
                    -1.0 / (1.0 - 0.5f64.powi(i32::from(shift))).ln()
                }
            };
            let mut q = 0.0f64;
            let mut t = arm;
            // Alternate pieces without and with contact, in pulse angles.
            let mut pieces = Vec::new();
            for &(x, y) in &a.contact {
                let (x, y) = (x.max(arm), y.min(end));
                if x >= y {
                    continue;
                }
                if x > t {
                    pieces.push((t, x, false));
                }
                pieces.push((x, y, true));
                t = y;
            }
            if t < end {
                pieces.push((t, end, false));
            }
            for (x, y, contact) in pieces {
                let d = (y - x) / cpp;
                match (intent.law, contact) {
                    (
                        AnalogLaw::Linear {
                            charge_per_pulse: rate,
                            ..
                        },
                        true,
                    ) => {
                        if q + rate * d >= fire {
                            return Some(x + (fire - q).max(0.0) / rate * cpp);
                        }
                        q = (q + rate * d).min(1.0);
                    }
                    (
                        AnalogLaw::Linear {
                            discharge_per_pulse: rate,
                            ..
                        },
                        false,
                    ) => {
                        q = (q - rate * d).max(0.0);
                    }
                    (AnalogLaw::Exponential { charge_shift, .. }, true) => {
                        let tc = tau(charge_shift);
                        let next = if tc == 0.0 {
                            1.0
                        } else {
                            1.0 - (1.0 - q) * (-d / tc).exp()
                        };
                        if next >= fire {
                            let dt = if tc == 0.0 || q >= fire {
                                0.0
                            } else {
                                tc * ((1.0 - q) / (1.0 - fire)).ln()
                            };
                            return Some(x + dt * cpp);
                        }
                        q = next;
                    }
                    (
                        AnalogLaw::Exponential {
                            discharge_shift, ..
                        },
                        false,
                    ) => {
                        let td = tau(discharge_shift);
                        q = if td == 0.0 { 0.0 } else { q * (-d / td).exp() };
                    }
                }
            }
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::MeasureSettings;
    use tooltouch_plant::stimulus::Stimulus;

    /// Revolutions of 1000 clocks, 10 pulses each; contact from 0.2 into rev 1 on.
    fn approach() -> Approach {
        Approach {
            stimulus: {
                let mut s = Stimulus::new(50_000_000);
                s.push(Default::default(), 5000);
                s
            },
            arm_cycle: 1000,
            index_cycles: vec![1000, 2000, 3000, 4000],
            contact: vec![(1200.0, 1300.0), (2000.0, 5000.0)],
            start_um: 0.0,
            feed_um_per_cycle: 0.0,
            cycles_per_rev: 1000.0,
            scale_resolution_um: 0.1,
            pulses_per_rev: 10,
        }
    }

    fn config(method: DecisionMethod, law: ChargeLaw) -> MeasureConfig {
        MeasureSettings {
            pulses_per_rev: 16,
            i_def: 8,
            method,
            charge_bits: 8,
            charge_law: law,
            fire_threshold: 128,
            rearm_threshold: 10,
            ..Default::default()
        }
        .validate()
        .unwrap()
    }

    const LIN: ChargeLaw = ChargeLaw::Linear {
        charge_step: 51,
        discharge_step: 51,
    };

    #[test]
    fn counter_decides_when_half_the_window_is_in_contact() {
        // Rev 1 (1000..2000) has 10 % contact; rev 2 is in contact from its start, so
        // its fraction exceeds 8/16 half way through.
        let c = config(DecisionMethod::Counter, LIN);
        assert_eq!(decision_cycle(&approach(), &Intent::of(&c)), Some(2500.0));
    }

    #[test]
    fn linear_capacitor_integrates_the_contact_angle() {
        // 51/255 = 0.2 per pulse (100 clocks); fire at 128/255 ≈ 0.502. The first burst
        // charges to 0.2, 700 clocks without contact discharge it to 0; the second burst
        // reaches 0.502 after 251 clocks.
        let c = config(DecisionMethod::Density, LIN);
        let t = decision_cycle(&approach(), &Intent::of(&c)).unwrap();
        assert!((t - (2000.0 + 0.502 / 0.2 * 100.0)).abs() < 0.1, "{t}");
    }

    #[test]
    fn single_pulse_is_the_first_contact() {
        let c = config(DecisionMethod::SinglePulse, LIN);
        assert_eq!(decision_cycle(&approach(), &Intent::of(&c)), Some(1200.0));
    }

    #[test]
    fn exponential_capacitor_with_shift_zero_fires_at_once() {
        let law = ChargeLaw::Exponential {
            charge_shift: 0,
            discharge_shift: 3,
        };
        let c = config(DecisionMethod::Density, law);
        assert_eq!(decision_cycle(&approach(), &Intent::of(&c)), Some(1200.0));
    }
}
