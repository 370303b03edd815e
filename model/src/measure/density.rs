//! Device 2, the contact-density detector (docs/domain.md §2.4): a digital capacitor charged per
//! FES pulse in contact and discharged per pulse without, firing on an upward threshold
//! crossing, with hysteresis.
//!
//! Updating once per FES pulse puts the capacitor in the angle domain, so the decision
//! does not depend on spindle speed. The charge is an unsigned integer in LSBs of a
//! `charge_bits`-wide register (UQ0.`charge_bits` of full scale); every step saturates at
//! zero and at full scale.

use crate::measure::config::{ChargeLaw, MeasureConfig};

/// The digital capacitor with its fire/re-arm hysteresis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DensityDetector {
    law: ChargeLaw,
    full: u32,
    fire_threshold: u32,
    rearm_threshold: u32,
    /// Charge, LSBs, `0..=full`.
    charge: u32,
    /// Ready to fire; cleared by a fire, set again once the charge falls below the re-arm
    /// threshold.
    armed: bool,
    /// Fired at least once since the last reset.
    fired: bool,
}

impl DensityDetector {
    /// An empty, armed capacitor for `config`.
    pub fn new(config: &MeasureConfig) -> Self {
        let s = config.settings();
        DensityDetector {
            law: s.charge_law,
            full: config.full_charge(),
            fire_threshold: s.fire_threshold,
            rearm_threshold: s.rearm_threshold,
            charge: 0,
            armed: true,
            fired: false,
        }
    }

    /// Empties and re-arms the capacitor.
    #[inline]
    pub fn reset(&mut self) {
        self.charge = 0;
        self.armed = true;
        self.fired = false;
    }

    /// Next charge after one pulse with contact bit `contact`. Saturating at `0` and `full`.
    ///
    /// The charge is always in `0..=full` and `full < 2^24` (`charge_bits <= 24`), every
    /// step at most `full`, and an exponential step at most the distance it covers, so
    /// the sums and differences below cannot wrap: they are written wrapping, and only
    /// the clamps at `0` and `full` are compared (this runs once per pulse in every fold
    /// of the exponential law).
    #[inline]
    pub fn next_charge(&self, contact: bool) -> u32 {
        let q = self.charge;
        match (self.law, contact) {
            (ChargeLaw::Linear { charge_step, .. }, true) => {
                q.wrapping_add(charge_step).min(self.full)
            }
            (
                ChargeLaw::Linear {
                    discharge_step: step,
                    ..
                },
                false,
            ) => q.saturating_sub(step),
            (ChargeLaw::Exponential { charge_shift, .. }, true) => {
                let room = self.full.wrapping_sub(q);
                q.wrapping_add(exp_step(room, charge_shift))
            }
            (
                ChargeLaw::Exponential {
                    discharge_shift, ..
                },
                false,
            ) => q.wrapping_sub(exp_step(q, discharge_shift)),
        }
    }

    /// One FES pulse. Updates the charge, then fires if armed and the charge has reached
    /// the fire threshold (returns `true` on that pulse only), or re-arms if disarmed and
    /// the charge is below the re-arm threshold.
    #[inline]
    pub fn on_pulse(&mut self, contact: bool) -> bool {
        self.charge = self.next_charge(contact);
        if self.armed {
            if self.charge >= self.fire_threshold {
                self.armed = false;
                self.fired = true;
                return true;
            }
        } else if self.charge < self.rearm_threshold {
            self.armed = true;
        }
        false
    }

    /// `n` FES pulses, the first with contact bit `first`, the others with `rest` (a run at
    /// one contact level, whose first pulse may carry the sticky bit): the same state as
    /// `n` calls of [`DensityDetector::on_pulse`]. Returns `true` if one of them fired.
    ///
    /// Linear law: constant time. Exponential law: one step per pulse until a pulse
    /// changes nothing (the charge has settled at `0` or full scale), so at most `n`
    /// steps; the firmware bounds `n` by folding at least every
    /// `tooltouch_firmware::handlers::FES_FOLD_LIMIT` pulses.
    pub fn on_pulses(&mut self, first: bool, rest: bool, n: u32) -> bool {
        if n == 0 {
            return false;
        }
        let mut fired = self.on_pulse(first);
        let others = n.saturating_sub(1);
        if others == 0 {
            return fired;
        }
        match self.law {
            ChargeLaw::Linear {
                charge_step,
                discharge_step,
            } => {
                // After any pulse: armed => charge < fire threshold (else it would have
                // fired), disarmed => charge >= re-arm threshold (else it would have
                // re-armed), and re-arm < fire (validated). A run moves the charge one
                // way only, so it can fire only if armed and charging, re-arm only if
                // disarmed and discharging, each at most once, and does so exactly when
                // the run's final charge crosses the threshold.
                if rest {
                    let rise = charge_step.saturating_mul(others);
                    self.charge = self.charge.saturating_add(rise).min(self.full);
                    if self.armed && self.charge >= self.fire_threshold {
                        self.armed = false;
                        self.fired = true;
                        fired = true;
                    }
                } else {
                    let fall = discharge_step.saturating_mul(others);
                    self.charge = self.charge.saturating_sub(fall);
                    if !self.armed && self.charge < self.rearm_threshold {
                        self.armed = true;
                    }
                }
            }
            ChargeLaw::Exponential { .. } => {
                for _ in 0..others {
                    let (charge, armed) = (self.charge, self.armed);
                    fired |= self.on_pulse(rest);
                    // A pulse that changed nothing is a fixed point: so is every later
                    // one of the run (same state, same contact bit).
                    if self.charge == charge && self.armed == armed {
                        break;
                    }
                }
            }
        }
        fired
    }

    /// How many FES pulses of a run (first with contact bit `first`, then `rest`) the
    /// detector needs to fire: `Some(k)` when the `k`-th would fire, `1 <= k <= limit`;
    /// `None` when none of the next `limit` pulses fires. Linear law: constant time;
    /// exponential law: up to `limit` charge steps.
    pub fn pulses_to_fire(&self, first: bool, rest: bool, limit: u32) -> Option<u32> {
        if limit == 0 {
            return None;
        }
        let mut d = *self;
        if d.on_pulse(first) {
            return Some(1);
        }
        // Only an armed capacitor that charges can fire (the invariants of
        // [`DensityDetector::on_pulses`]).
        if !(d.armed && rest) {
            return None;
        }
        let k = match d.law {
            ChargeLaw::Linear { charge_step, .. } => {
                // Armed: charge < fire threshold <= full, so the steps needed are at least
                // one and the clamp at full scale never stops the climb short.
                let missing = d.fire_threshold.saturating_sub(d.charge);
                let steps = missing.div_ceil(charge_step.max(1));
                steps.saturating_add(1)
            }
            ChargeLaw::Exponential { .. } => {
                let mut k = 1u32;
                loop {
                    if k >= limit {
                        return None;
                    }
                    k += 1;
                    if d.on_pulse(true) {
                        break k;
                    }
                }
            }
        };
        (k <= limit).then_some(k)
    }

    /// Charge, LSBs of full scale.
    #[inline]
    pub fn charge(&self) -> u32 {
        self.charge
    }
    /// Whether the detector can fire.
    #[inline]
    pub fn armed(&self) -> bool {
        self.armed
    }
    /// Whether it has fired since the last reset.
    #[inline]
    pub fn fired(&self) -> bool {
        self.fired
    }
}

/// Exponential step: `max(1, distance >> shift)`, or 0 when the distance is 0.
fn exp_step(distance: u32, shift: u8) -> u32 {
    if distance == 0 {
        0
    } else {
        (distance >> shift).max(1)
    }
}

#[cfg(test)]
mod worked_examples;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::config::MeasureSettings;
    use proptest::prelude::*;

    fn detector(law: ChargeLaw) -> DensityDetector {
        let s = MeasureSettings {
            charge_bits: 8,
            charge_law: law,
            fire_threshold: 192,
            rearm_threshold: 64,
            ..Default::default()
        };
        DensityDetector::new(&s.validate().unwrap())
    }

    const LINEAR: ChargeLaw = ChargeLaw::Linear {
        charge_step: 32,
        discharge_step: 16,
    };

    #[test]
    fn linear_fires_on_the_sixth_contact_pulse() {
        let mut d = detector(LINEAR);
        for _ in 0..5 {
            assert!(!d.on_pulse(true));
        }
        assert!(d.on_pulse(true));
        assert_eq!(d.charge(), 192);
    }

    #[test]
    fn exponential_reaches_both_ends_exactly() {
        let mut d = detector(ChargeLaw::Exponential {
            charge_shift: 3,
            discharge_shift: 2,
        });
        for _ in 0..200 {
            d.on_pulse(true);
        }
        assert_eq!(d.charge(), 255);
        for _ in 0..200 {
            d.on_pulse(false);
        }
        assert_eq!(d.charge(), 0);
    }

    #[test]
    fn no_refire_without_falling_below_rearm() {
        let mut d = detector(LINEAR);
        let fires = (0..20).filter(|_| d.on_pulse(true)).count();
        assert_eq!(fires, 1);
        // Fall to 80 (above re-arm 64), climb again: no second fire.
        for _ in 0..11 {
            d.on_pulse(false);
        }
        assert_eq!(d.charge(), 79);
        assert_eq!((0..20).filter(|_| d.on_pulse(true)).count(), 0);
        // Fall below 64: re-armed, fires again.
        for _ in 0..20 {
            d.on_pulse(false);
        }
        assert!(d.armed());
        assert_eq!((0..20).filter(|_| d.on_pulse(true)).count(), 1);
    }

    /// docs/domain.md §2.4's charge law with every step saturating: the reference for
    /// [`DensityDetector::next_charge`], which leaves out the saturations that cannot
    /// happen.
    fn next_charge_reference(law: ChargeLaw, full: u32, q: u32, contact: bool) -> u32 {
        match (law, contact) {
            (ChargeLaw::Linear { charge_step, .. }, true) => {
                q.saturating_add(charge_step).min(full)
            }
            (ChargeLaw::Linear { discharge_step, .. }, false) => q.saturating_sub(discharge_step),
            (ChargeLaw::Exponential { charge_shift, .. }, true) => {
                q.saturating_add(exp_step(full.saturating_sub(q), charge_shift))
            }
            (
                ChargeLaw::Exponential {
                    discharge_shift, ..
                },
                false,
            ) => q.saturating_sub(exp_step(q, discharge_shift)),
        }
    }

    proptest! {
        #[test]
        fn next_charge_equals_the_saturating_reference(
            charge_bits in 4u8..=24, exp in any::<bool>(), a in any::<u32>(), b in any::<u32>(),
            big in any::<bool>(), bits in proptest::collection::vec(any::<bool>(), 0..400),
        ) {
            let full = (1u32 << charge_bits) - 1;
            let shifts = u32::from(charge_bits) + 1;
            // Steps up to full scale (`big`), where an unchecked sum would matter most.
            let step = |x: u32| if big { full - x % 8 } else { 1 + x % full };
            let law = if exp {
                ChargeLaw::Exponential {
                    charge_shift: (a % shifts) as u8,
                    discharge_shift: (b % shifts) as u8,
                }
            } else {
                ChargeLaw::Linear { charge_step: step(a), discharge_step: step(b) }
            };
            let s = MeasureSettings {
                charge_bits,
                charge_law: law,
                fire_threshold: full,
                rearm_threshold: full / 2,
                ..Default::default()
            };
            let mut d = DensityDetector::new(&s.validate().unwrap());
            for (i, bit) in bits.into_iter().enumerate() {
                let expected = next_charge_reference(law, full, d.charge(), bit);
                prop_assert_eq!(d.next_charge(bit), expected, "pulse {}", i);
                d.on_pulse(bit);
                prop_assert_eq!(d.charge(), expected, "pulse {}", i);
            }
        }

        #[test]
        fn charge_stays_in_bounds_and_fires_only_when_armed(
            bits in proptest::collection::vec(any::<bool>(), 0..600),
            exp in any::<bool>(), a in 0u8..9, b in 0u8..9, up in 1u32..256, down in 1u32..256,
        ) {
            let law = if exp {
                ChargeLaw::Exponential { charge_shift: a, discharge_shift: b }
            } else {
                ChargeLaw::Linear { charge_step: up.min(255), discharge_step: down.min(255) }
            };
            let mut d = detector(law);
            let mut armed_before = d.armed();
            for bit in bits {
                let fired = d.on_pulse(bit);
                prop_assert!(d.charge() <= 255);
                if fired {
                    prop_assert!(armed_before, "fired while disarmed");
                    prop_assert!(d.charge() >= 192);
                }
                if !armed_before && d.armed() {
                    prop_assert!(d.charge() < 64);
                }
                armed_before = d.armed();
            }
        }
    }
}
