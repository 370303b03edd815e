//! Cutting-force estimator from the spindle drive's electrical signals (SPEC 3, F1–F9), one
//! step per control period, plus the no-load identification of B and T_fco.
//!
//! Per period, from the sampling chain's averages ([`crate::sampling::Averages`]):
//!
//! 1. line voltage and current `V = √(Σv²/3)`, `I = √(Σi²/3)` by an exact integer square
//!    root ([`sqrt_fx`], `u128::isqrt`: the floor of the true root, in I32F32);
//! 2. input power `P_i = √3·I·V·cos(π/6) = (3/2)·I·V` (F3; the constant is exact), stator
//!    loss `P_s = R_s·Σi²` (= 3·R_s·I²), air-gap power `P_g = P_i − P_s` (F2);
//! 3. synthesized power (F9): the measured power P_o (smooth, lagging ~0.3 s) unless
//!    `|P_g − P_o| > Δ_th·|P_o|` (tested without division), which selects the fast electrical
//!    estimate `k_slip·P_g` for `slip_hold_periods` periods (re-triggered while it holds);
//! 4. motor torque `T_e = P / ω_M` (F4; 0 below `min_speed`, so never a division by ~0);
//! 5. external torque `T̂_t = T_e − (1/b)(ω(i) − ω(i−1)) − B·ω(i)` (F6), where
//!    `1/b = B / (1 − e^(−Bh/J)) = (J/h)·x/(1 − e^(−x))`, `x = Bh/J`, evaluated by its
//!    Bernoulli series `1 + x/2 + x²/12 − x⁴/720` (error < x⁶/30240 < 2·10⁻⁶ for the allowed
//!    `x ≤ 1/2`; B is clamped to `0..=J/(2h)`) — no exponential in fixed point;
//! 6. cutting torque from F7–F8: `T̂_t = T_fco + f(ω)T̂_c + g(ω)T̂_c² + T̂_c`, i.e.
//!    `g·T̂_c² + (1+f)·T̂_c − c = 0` with `c = T̂_t − T_fco`, `f = f0 + f1·ω`, `g = g0 + g1·ω`,
//!    solved in closed form in the cancellation-free rationalized way
//!    `T̂_c = 2c / ((1+f) + √((1+f)² + 4gc))`: exact for g = 0, the integer square root is
//!    the only rounding besides the I32F32 products, a negative discriminant is clamped to
//!    0 (the parabola's vertex, continuous with the real roots), and `1+f` is clamped to at
//!    least 1/2 so the denominator is never below 1/2;
//! 7. force `F̂_c = T̂_c / r` (multiplied by the precomputed `1/r`).
//!
//! No-load identification (before the tool touches): while on, every period adds
//! `(ω(i), y(i))` with `y = k_slip·P_g/ω − (J/h)(ω(i) − ω(i−1))` (the fast electrical
//! torque: P_o lags too much during a speed change) to least-squares sums of the model
//! `y = B·ω + T_fco` (F5 at no load). When it ends, B and T_fco are solved from the sums
//! (in `i128`, values reduced to 16 fractional bits). Needs a speed change during the
//! window (spindle run-up): if the speed variance is below 1 (rad/s)², B keeps its
//! nominal value and only T_fco = mean(y) − B·mean(ω) is identified.
//!
//! All quantities are I32F32 ([`Fx`]) in SI units; every product and sum saturates.

use crate::force::{
    Amps, ForceConfigError, Fx, Metres, NewtonMetres, Newtons, Ohms, RadPerSec, Seconds, Volts,
    Watts,
};
use crate::sampling::{Averages, FILTER_FRAC_BITS};

/// Moment of inertia, kg·m², I32F32.
pub type KilogramSquareMetres = Fx;
/// Viscous friction coefficient B, N·m·s/rad, I32F32.
pub type NmsPerRad = Fx;

/// Square root of a non-negative I32F32 value, I32F32, by the exact integer square root of
/// the raw bits shifted by 32 (the floor of the true root in the last bit). Negative
/// inputs give 0.
pub fn sqrt_fx(x: Fx) -> Fx {
    let bits = x.to_bits();
    if bits <= 0 {
        return Fx::ZERO;
    }
    let root = ((bits as u128) << 32).isqrt();
    // root < 2^48: always fits.
    Fx::from_bits(i64::try_from(root).unwrap_or(i64::MAX))
}

/// ADC scales of the sampling chain (SPEC 3), I32F32 units per LSB.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AdcScales {
    /// Motor speed per LSB, rad/s, `(0, 1]`.
    pub speed_per_lsb: RadPerSec,
    /// Measured power per LSB, W, `(0, 100]`.
    pub power_per_lsb: Watts,
    /// Dynamometer force per LSB, N, `(0, 100]`.
    pub force_per_lsb: Newtons,
    /// Phase voltage per LSB, V, `(0, 10]`.
    pub volts_per_lsb: Volts,
    /// Phase current per LSB, A, `(0, 1]`.
    pub amps_per_lsb: Amps,
}

/// The period's averaged signals in physical units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DriveSignals {
    /// Motor speed ω_M, rad/s.
    pub omega: RadPerSec,
    /// Measured (lagging) power P_o, W.
    pub p_o: Watts,
    /// Dynamometer force, N.
    pub force_measured: Newtons,
    /// Line voltage V_line = √(Σv²/3), V.
    pub v_line: Volts,
    /// Line current I_line = √(Σi²/3), A.
    pub i_line: Amps,
    /// Σi² = i_u² + i_v² + i_w², A².
    pub amps_sq: Fx,
}

fn code_to_fx(avg: i64) -> Fx {
    // avg has FILTER_FRAC_BITS fractional bits; I32F32 has 32. Saturating shift by multiply.
    Fx::from_bits(avg.saturating_mul(1 << (32 - FILTER_FRAC_BITS)))
}

fn rms_of_sum3(avg_sq: i64) -> Fx {
    // √(x/3) with x = avg·2^−8: bits = √(avg·2^56/3). avg ≥ 0 and < 2^34, so this fits.
    let avg = u128::try_from(avg_sq).unwrap_or(0);
    let root = ((avg << (64 - FILTER_FRAC_BITS)) / 3).isqrt();
    Fx::from_bits(i64::try_from(root).unwrap_or(i64::MAX))
}

impl AdcScales {
    /// Converts the period's averages to physical units (saturating products).
    pub fn convert(&self, a: &Averages) -> DriveSignals {
        DriveSignals {
            omega: code_to_fx(a.speed).saturating_mul(self.speed_per_lsb),
            p_o: code_to_fx(a.power).saturating_mul(self.power_per_lsb),
            force_measured: code_to_fx(a.force).saturating_mul(self.force_per_lsb),
            v_line: rms_of_sum3(a.volts_sq).saturating_mul(self.volts_per_lsb),
            i_line: rms_of_sum3(a.amps_sq).saturating_mul(self.amps_per_lsb),
            amps_sq: code_to_fx(a.amps_sq)
                .saturating_mul(self.amps_per_lsb)
                .saturating_mul(self.amps_per_lsb),
        }
    }
}

/// Estimator settings (SPEC 3), all I32F32 in SI units.
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

/// `v` must be in `min..=max`, else an error naming `field`.
pub(crate) fn check_range(
    field: &'static str,
    v: Fx,
    min: Fx,
    max: Fx,
) -> Result<(), ForceConfigError> {
    if v < min || v > max {
        Err(ForceConfigError {
            field,
            value: v,
            min,
            max,
        })
    } else {
        Ok(())
    }
}

/// `v` must be in `(0, max]`: reported with the smallest positive value as the minimum.
pub(crate) fn positive(field: &'static str, v: Fx, max: Fx) -> Result<(), ForceConfigError> {
    check_range(field, v, Fx::DELTA, max)
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

/// One period's estimate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Estimate {
    /// The period's signals.
    pub signals: DriveSignals,
    /// Input power P_i (F3), W.
    pub p_i: Watts,
    /// Air-gap power P_g (F2), W.
    pub p_g: Watts,
    /// Power used for the torque (F9's choice), W.
    pub p_used: Watts,
    /// F9 selected the fast electrical estimate this period.
    pub fast: bool,
    /// Motor torque T_e (F4), N·m.
    pub t_e: NewtonMetres,
    /// External torque T̂_t (F6), N·m.
    pub t_t: NewtonMetres,
    /// Cutting torque T̂_c (F7–F8), N·m.
    pub t_c: NewtonMetres,
    /// Cutting force F̂_c = T̂_c / r, N.
    pub force: Newtons,
}

/// Least-squares sums of the no-load identification, values with 16 fractional bits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
struct NoLoadSums {
    n: u32,
    sw: i128,
    sww: i128,
    sy: i128,
    swy: i128,
}

/// The estimator's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Estimator {
    s: EstimatorSettings,
    h: Seconds,
    inv_radius: Fx,
    viscous: NmsPerRad,
    coulomb: NewtonMetres,
    inv_b: Fx,
    omega_prev: Option<RadPerSec>,
    hold: u8,
    identifying: bool,
    identified: bool,
    sums: NoLoadSums,
}

impl Estimator {
    /// A new estimator with the nominal B and T_fco. `settings` must have passed
    /// [`EstimatorSettings::validate`] with the same `h`.
    pub fn new(settings: &EstimatorSettings, h: Seconds) -> Estimator {
        Estimator {
            s: *settings,
            h,
            inv_radius: Fx::ONE
                .checked_div(settings.workpiece_radius)
                .unwrap_or(Fx::ZERO),
            viscous: settings.viscous_nominal,
            coulomb: settings.coulomb_nominal,
            inv_b: inverse_b(settings.viscous_nominal, settings.inertia, h),
            omega_prev: None,
            hold: 0,
            identifying: false,
            identified: false,
            sums: NoLoadSums::default(),
        }
    }

    /// Viscous friction B in use, N·m·s/rad.
    pub fn viscous(&self) -> NmsPerRad {
        self.viscous
    }
    /// Coulomb friction T_fco in use, N·m.
    pub fn coulomb(&self) -> NewtonMetres {
        self.coulomb
    }
    /// B and T_fco come from a finished no-load identification.
    pub fn identified(&self) -> bool {
        self.identified
    }
    /// No-load identification is running.
    pub fn identifying(&self) -> bool {
        self.identifying
    }

    /// Starts the no-load identification (clears its sums).
    pub fn start_identification(&mut self) {
        self.identifying = true;
        self.sums = NoLoadSums::default();
    }

    /// Ends the no-load identification and solves B and T_fco (see the module header).
    /// With no period collected the values in use are kept.
    pub fn finish_identification(&mut self) {
        if !self.identifying {
            return;
        }
        self.identifying = false;
        let s = self.sums;
        if s.n == 0 {
            return;
        }
        let n = i128::from(s.n);
        // det and the numerator have 32 fractional bits.
        let det = n
            .saturating_mul(s.sww)
            .saturating_sub(s.sw.saturating_mul(s.sw));
        let num = n
            .saturating_mul(s.swy)
            .saturating_sub(s.sw.saturating_mul(s.sy));
        // Variance of ω at least 1 (rad/s)²: det ≥ n²·2^32.
        let min_det = n.saturating_mul(n).saturating_mul(1i128 << 32);
        let b_max = viscous_max(self.s.inertia, self.h);
        if det >= min_det {
            let b_bits = num
                .saturating_mul(1i128 << 32)
                .checked_div(det)
                .unwrap_or(0);
            let b = Fx::from_bits(i64::try_from(b_bits).unwrap_or(if b_bits < 0 {
                i64::MIN
            } else {
                i64::MAX
            }));
            self.viscous = b.max(Fx::ZERO).min(b_max);
        }
        // T_fco = (Σy − B·Σω)/n: B has 32 fractional bits, Σω 16 → 48; Σy 16 → shift 32.
        let b_sw = i128::from(self.viscous.to_bits()).saturating_mul(s.sw);
        let t48 =
            s.sy.saturating_mul(1i128 << 32)
                .saturating_sub(b_sw)
                .checked_div(n)
                .unwrap_or(0);
        let t_bits = i64::try_from(t48 >> 16).unwrap_or(0);
        self.coulomb = Fx::from_bits(t_bits).clamp(Fx::ZERO, Fx::const_from_int(1000));
        self.inv_b = inverse_b(self.viscous, self.s.inertia, self.h);
        self.identified = true;
    }

    fn torque(&self, p: Watts, omega: RadPerSec) -> NewtonMetres {
        if omega < self.s.min_speed {
            Fx::ZERO
        } else {
            p.checked_div(omega).unwrap_or(Fx::ZERO)
        }
    }

    /// One control period: F1–F9 from the period's signals (see the module header).
    pub fn step(&mut self, sig: &DriveSignals) -> Estimate {
        const THREE_HALVES: Fx = Fx::lit("1.5");
        let omega = sig.omega;
        let p_i = THREE_HALVES
            .saturating_mul(sig.i_line)
            .saturating_mul(sig.v_line);
        let p_s = self.s.stator_resistance.saturating_mul(sig.amps_sq);
        let p_g = p_i.saturating_sub(p_s);
        // F9 without division: |P_g − P_o| > Δ_th·|P_o|.
        let diff = p_g.saturating_sub(sig.p_o).saturating_abs();
        if diff
            > self
                .s
                .switch_threshold
                .saturating_mul(sig.p_o.saturating_abs())
        {
            self.hold = self.s.slip_hold_periods;
        }
        let fast_power = self.s.slip_gain.saturating_mul(p_g);
        let fast = self.hold > 0;
        let p_used = if fast { fast_power } else { sig.p_o };
        self.hold = self.hold.saturating_sub(1);
        let t_e = self.torque(p_used, omega);
        let omega_prev = self.omega_prev.unwrap_or(omega);
        self.omega_prev = Some(omega);
        let d_omega = omega.saturating_sub(omega_prev);
        if self.identifying {
            let j_over_h = self.s.inertia.checked_div(self.h).unwrap_or(Fx::ZERO);
            let y = self
                .torque(fast_power, omega)
                .saturating_sub(j_over_h.saturating_mul(d_omega));
            let w16 = i128::from(omega.to_bits() >> 16);
            let y16 = i128::from(y.to_bits() >> 16);
            let s = &mut self.sums;
            s.n = s.n.saturating_add(1);
            s.sw = s.sw.saturating_add(w16);
            s.sww = s.sww.saturating_add(w16.saturating_mul(w16));
            s.sy = s.sy.saturating_add(y16);
            s.swy = s.swy.saturating_add(w16.saturating_mul(y16));
        }
        // F6
        let t_t = t_e
            .saturating_sub(self.inv_b.saturating_mul(d_omega))
            .saturating_sub(self.viscous.saturating_mul(omega));
        // F7–F8
        let c = t_t.saturating_sub(self.coulomb);
        let f = self.s.friction_f[0].saturating_add(self.s.friction_f[1].saturating_mul(omega));
        let g = self.s.friction_g[0].saturating_add(self.s.friction_g[1].saturating_mul(omega));
        let one_f = Fx::ONE.saturating_add(f).max(const { Fx::lit("0.5") });
        let disc = one_f
            .saturating_mul(one_f)
            .saturating_add(g.saturating_mul(c).saturating_mul(Fx::const_from_int(4)));
        let denom = one_f.saturating_add(sqrt_fx(disc));
        let t_c = c
            .saturating_mul(Fx::const_from_int(2))
            .checked_div(denom)
            .unwrap_or(Fx::ZERO);
        let force = t_c.saturating_mul(self.inv_radius);
        Estimate {
            signals: *sig,
            p_i,
            p_g,
            p_used,
            fast,
            t_e,
            t_t,
            t_c,
            force,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sqrt_is_exact_floor() {
        assert_eq!(sqrt_fx(Fx::const_from_int(4)), Fx::const_from_int(2));
        assert_eq!(sqrt_fx(Fx::lit("0.25")), Fx::lit("0.5"));
        assert_eq!(sqrt_fx(Fx::const_from_int(-1)), Fx::ZERO);
        let r = sqrt_fx(Fx::const_from_int(2));
        assert!(r.saturating_mul(r) <= Fx::const_from_int(2));
        let up = r + Fx::DELTA;
        assert!(up.wide_mul(up) > Fx::const_from_int(2).wide_mul(Fx::ONE));
    }

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

    fn settings() -> EstimatorSettings {
        EstimatorSettings {
            stator_resistance: Fx::ZERO,
            inertia: Fx::lit("0.05"),
            viscous_nominal: Fx::lit("0.02"),
            coulomb_nominal: Fx::ZERO,
            friction_f: [Fx::lit("0.05"), Fx::ZERO],
            friction_g: [Fx::lit("0.002"), Fx::ZERO],
            min_speed: Fx::const_from_int(5),
            switch_threshold: Fx::lit("0.1"),
            slip_gain: Fx::ONE,
            slip_hold_periods: 4,
            workpiece_radius: Fx::lit("0.02"),
        }
    }

    /// Signals whose fast torque P_g/ω is `t_e` at speed `omega` (R_s = 0, V = 1 V).
    fn signals(omega: Fx, t_e: Fx) -> DriveSignals {
        let p_g = t_e * omega;
        DriveSignals {
            omega,
            p_o: p_g,
            force_measured: Fx::ZERO,
            v_line: Fx::ONE,
            i_line: p_g / Fx::lit("1.5"),
            amps_sq: Fx::ZERO,
        }
    }

    #[test]
    fn no_load_identification_recovers_b_and_coulomb() {
        let h = Fx::lit("0.05");
        let mut e = Estimator::new(&settings(), h);
        let (b, t_fco) = (Fx::lit("0.005"), Fx::ONE);
        let j_over_h = Fx::ONE; // 0.05 / 0.05
        e.start_identification();
        let mut omega = Fx::const_from_int(60);
        let step = Fx::lit("0.5");
        // one period at constant speed, then a ramp of 0.5 rad/s per period
        let _ = e.step(&signals(omega, b * omega + t_fco));
        for _ in 0..40 {
            omega += step;
            let _ = e.step(&signals(omega, b * omega + t_fco + j_over_h * step));
        }
        e.finish_identification();
        assert!(e.identified());
        assert!(
            (e.viscous() - b).abs() < Fx::lit("0.0001"),
            "B = {}",
            e.viscous()
        );
        assert!(
            (e.coulomb() - t_fco).abs() < Fx::lit("0.01"),
            "T_fco = {}",
            e.coulomb()
        );
    }

    #[test]
    fn friction_quadratic_is_solved() {
        // steady speed, B = 0.02 (nominal), T_fco = 0: T_t = T_e − Bω, and F8 with
        // f = 0.05, g = 0.002 must give back T_c with T_t = T_c + f·T_c + g·T_c².
        let h = Fx::lit("0.05");
        let mut e = Estimator::new(&settings(), h);
        let omega = Fx::const_from_int(80);
        for t_c in [0i32, 2, 10, 25] {
            let t_c = Fx::from_num(t_c);
            let t_t = t_c + Fx::lit("0.05") * t_c + Fx::lit("0.002") * t_c * t_c;
            let est = e.step(&signals(omega, t_t + Fx::lit("0.02") * omega));
            assert!(
                (est.t_c - t_c).abs() < Fx::lit("0.001"),
                "{} vs {t_c}",
                est.t_c
            );
            assert!((est.force - t_c * 50).abs() < Fx::lit("0.05"));
        }
    }
}
