//! The estimator's settings (docs/domain.md §3): the drive's electrical and mechanical constants,
//! the friction model F7–F8 and the F9 switch, with their defaults and ranges, and the two
//! derived quantities that depend only on them and the control period (`1/b` of F6 and the
//! largest viscous friction its series allows).

use crate::units::{
    Fx, KilogramSquareMetres, Metres, NewtonMetres, NmsPerRad, Ohms, RadPerSec, Seconds,
};
use crate::validation::{check_range, positive, ForceConfigError};

/// Estimator settings (docs/domain.md §3), all I32F32 in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EstimatorSettings {
    /// Stator resistance per phase R_s, Ω, `[0, 100]`.
    pub stator_resistance: Ohms,
    /// Rotor + spindle inertia J, kg·m², `(0, 100]`.
    pub inertia: KilogramSquareMetres,
    /// Nominal viscous friction B (used until identified), N·m·s/rad, `[0, J/(2h)]`.
    pub viscous_nominal: NmsPerRad,
    /// Nominal Coulomb friction T_fco (used until identified), N·m, `[0, 1000]`.
    pub coulomb_nominal: NewtonMetres,
    /// Load-dependent friction f(ω) = f0 + f1·ω (F8): `[f0, f1]`, f0 in `[-0.5, 1]`,
    /// f1 in s/rad `[-0.01, 0.01]`.
    pub friction_f: [Fx; 2],
    /// Load-dependent friction g(ω) = g0 + g1·ω (F8): `[g0, g1]`, g0 in 1/(N·m)
    /// `[-1, 1]`, g1 in s/(rad·N·m) `[-0.01, 0.01]`.
    pub friction_g: [Fx; 2],
    /// Below this speed the torque is taken as 0 (F4 would divide by ~0), rad/s, `(0, 100]`.
    pub min_speed: RadPerSec,
    /// Switch threshold Δ_th of F9 (relative), `(0, 10]`.
    pub switch_threshold: Fx,
    /// Slip-compensation gain applied to the fast estimate (F9), `(0, 2]`.
    pub slip_gain: Fx,
    /// Periods the fast estimate is held after F9 triggers, `1..=100` (4 = 0.2 s at 20 Hz).
    pub slip_hold_periods: u8,
    /// Workpiece radius at the cut, m, `(0, 1]`.
    pub workpiece_radius: Metres,
}

impl Default for EstimatorSettings {
    /// The default plant's drive (`tooltouch control`): 0.5 Ω stator, a 0.05 kg·m²
    /// spindle, nominal friction B = 0.005 N·m·s/rad and T_fco = 1 N·m, F8's f0 = 0.05 and
    /// g0 = 0.002 /(N·m), F9 switching at 10 % with slip gain 0.97 held 4 periods, 20 mm
    /// workpiece radius.
    fn default() -> Self {
        EstimatorSettings {
            stator_resistance: const { Fx::lit("0.5") },
            inertia: const { Fx::lit("0.05") },
            viscous_nominal: const { Fx::lit("0.005") },
            coulomb_nominal: Fx::ONE,
            friction_f: [const { Fx::lit("0.05") }, Fx::ZERO],
            friction_g: [const { Fx::lit("0.002") }, Fx::ZERO],
            min_speed: Fx::const_from_int(5),
            switch_threshold: const { Fx::lit("0.1") },
            slip_gain: const { Fx::lit("0.97") },
            slip_hold_periods: 4,
            workpiece_radius: const { Fx::lit("0.02") },
        }
    }
}

impl EstimatorSettings {
    /// Checks every field (names as `estimator.<field>`); `h` is the control period.
    pub fn validate(&self, h: Seconds) -> Result<(), ForceConfigError> {
        const HUNDRED: Fx = Fx::const_from_int(100);
        const ONE: Fx = Fx::ONE;
        const F1: Fx = Fx::lit("0.01");
        check_range(
            "estimator.stator_resistance",
            self.stator_resistance,
            Fx::ZERO,
            HUNDRED,
        )?;
        positive("estimator.inertia", self.inertia, HUNDRED)?;
        let b_max = viscous_max(self.inertia, h);
        check_range(
            "estimator.viscous_nominal",
            self.viscous_nominal,
            Fx::ZERO,
            b_max,
        )?;
        check_range(
            "estimator.coulomb_nominal",
            self.coulomb_nominal,
            Fx::ZERO,
            Fx::const_from_int(1000),
        )?;
        check_range(
            "estimator.friction_f[0]",
            self.friction_f[0],
            const { Fx::lit("-0.5") },
            ONE,
        )?;
        check_range("estimator.friction_f[1]", self.friction_f[1], -F1, F1)?;
        check_range("estimator.friction_g[0]", self.friction_g[0], -ONE, ONE)?;
        check_range("estimator.friction_g[1]", self.friction_g[1], -F1, F1)?;
        positive("estimator.min_speed", self.min_speed, HUNDRED)?;
        positive(
            "estimator.switch_threshold",
            self.switch_threshold,
            Fx::const_from_int(10),
        )?;
        positive("estimator.slip_gain", self.slip_gain, Fx::const_from_int(2))?;
        check_range(
            "estimator.slip_hold_periods",
            Fx::from_num(self.slip_hold_periods),
            ONE,
            HUNDRED,
        )?;
        positive("estimator.workpiece_radius", self.workpiece_radius, ONE)?;
        Ok(())
    }
}

/// Largest B for which `x = Bh/J ≤ 1/2` (the series for 1/b is valid): `J/(2h)`.
pub fn viscous_max(inertia: KilogramSquareMetres, h: Seconds) -> NmsPerRad {
    // An explicit positive divisor keeps the firmware free of a division-by-zero panic
    // path the optimiser cannot see through (h > 0 for every validated configuration).
    let two_h = h.saturating_add(h);
    if two_h <= Fx::ZERO {
        return Fx::ZERO;
    }
    inertia.checked_div(two_h).unwrap_or(Fx::ZERO)
}

/// `1/b` of F6 for viscous friction `b_visc`, inertia `j` and period `h`:
/// `(J/h)·(1 + x/2 + x²/12 − x⁴/720)`, `x = Bh/J`; N·m·s/rad, I32F32, saturating.
pub fn inverse_b(b_visc: NmsPerRad, j: KilogramSquareMetres, h: Seconds) -> Fx {
    let j_over_h = j.checked_div(h).unwrap_or(Fx::ZERO);
    let x = b_visc.saturating_mul(h).checked_div(j).unwrap_or(Fx::ZERO);
    let x2 = x.saturating_mul(x);
    let series = Fx::ONE
        .saturating_add(x / 2)
        .saturating_add(x2 / 12)
        .saturating_sub(x2.saturating_mul(x2) / 720);
    j_over_h.saturating_mul(series)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_b_tends_to_j_over_h() {
        let j = Fx::lit("0.05");
        let h = Fx::lit("0.05");
        assert_eq!(inverse_b(Fx::ZERO, j, h), Fx::ONE);
        // B = 0.01: x = 0.01, 1/b = 1·(1 + 0.005 + 0.0000083) ≈ 1.0050083
        let ib = inverse_b(Fx::lit("0.01"), j, h);
        assert!(
            (ib - Fx::lit("1.0050083")).abs() < Fx::lit("0.000001"),
            "{ib}"
        );
    }

    /// Every term of the series at x = Bh/J = 1 (B = 1 N·m·s/rad, J = 1 kg·m², h = 1 s, so
    /// J/h = 1): 1 + 1/2 + 1/12 − 1/720 = (720 + 360 + 60 − 1)/720 = 1139/720 ≈ 1.581944,
    /// close to the exact x/(1 − e^−x) = 1.581977 the series stands for.
    #[test]
    fn inverse_b_series_at_x_equal_one() {
        let one = Fx::ONE;
        let ib = inverse_b(one, one, one);
        let expected = Fx::const_from_int(1139) / 720;
        assert!(
            (ib - expected).abs() < Fx::lit("0.000000004"),
            "{ib} against 1139/720 = {expected}"
        );
    }
}
