//! Cutting-force estimator from the spindle drive's electrical signals (docs/domain.md §3, eq.
//! F1–F9), one step per control period, plus the no-load identification of B and T_fco.
//!
//! Per period, from the sampling chain's averages in physical units
//! ([`crate::force::sampling::DriveSignals`]):
//!
//! 1. line voltage and current `V = √(Σv²/3)`, `I = √(Σi²/3)` by an exact integer square
//!    root ([`sqrt_fx`], `fixed`'s square root: the floor of the true root, in I32F32);
//! 2. input power `P_i = √3·I·V·cos(π/6) = (3/2)·I·V` (F3; the constant is exact), stator
//!    loss `P_s = R_s·Σi²` (= 3·R_s·I²), air-gap power `P_g = P_i − P_s` (F2);
//! 3. synthesized power (F9): the measured power P_o (smooth, lagging ~0.3 s) unless
//!    `|P_g − P_o| > Δ_th·|P_o|` (paper F's eq. (9), tested without division; both signs:
//!    the paper switches "to know the start and the end of cutting" — P_g runs ahead of the
//!    lagging P_o when the load rises and falls below it when the load drops), which selects
//!    the fast electrical estimate `k_slip·P_g` for `slip_hold_periods` periods (re-triggered
//!    while it holds);
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
//! No-load identification (before the tool touches) fits F5 at no load, `y = B·ω + T_fco`,
//! by least squares over the window's *steady-speed* periods: `y = P_g/ω − (J/h)(ω(i) −
//! ω(i−1))`, the electrical torque (P_o lags too much after a speed change) less the small
//! inertia torque left while the speed settles. A period counts as steady when its inertia
//! torque is at most 1/16 of that torque, `16·|(J/h)·Δω| ≤ |P_g/ω|` ([`STEADY_SHIFT`]), and
//! it is collected only when the period before it was steady too. Why: ω is a period
//! *average*, so `(J/h)·Δω` is the inertia torque around the boundary between the two
//! periods, half a period earlier than the torque average it is subtracted from; during a
//! run-up that misalignment adds ±J·a/2 summed over the periods where the acceleration a
//! starts and stops — at the low and the high speed, so it tilts the fitted line (B came out
//! at about half the plant's value). At steady speed there is nothing to misalign. The slip
//! gain is not applied either: it corrects P_g/ω_M for the slip under load, which at no load
//! is a fraction of a percent (applied, it scaled B and T_fco by it). When the window ends,
//! B and T_fco are solved from the sums (in `i128`, values reduced to 16 fractional bits).
//! The window therefore needs steady periods at two or more speeds (before and after a
//! spindle run-up): if the collected speeds' variance is below 1 (rad/s)², B keeps its value
//! and only T_fco = mean(y) − B·mean(ω) is identified; with no steady period nothing changes.
//!
//! All quantities are I32F32 ([`Fx`]) in SI units; every product and sum saturates.

pub mod settings;

use crate::force::estimator::settings::{inverse_b, viscous_max, EstimatorSettings};
use crate::force::sampling::DriveSignals;
use crate::units::{Fx, NewtonMetres, Newtons, NmsPerRad, RadPerSec, Seconds, Watts};

/// A period is steady for the identification when `|(J/h)·Δω| · 2^STEADY_SHIFT ≤ |P_g/ω|`:
/// its inertia torque is at most 1/16 of the motor torque (at the default drive's idle
/// torque of 1.4 N·m: 1.75 rad/s², where the speed channel's noise moves Δω by about
/// 0.3 rad/s² rms).
pub const STEADY_SHIFT: u32 = 4;

/// Square root of a non-negative I32F32 value, I32F32: `fixed`'s own square root, the floor
/// of the true root in the last bit (tests/force/sqrt.rs proves it equal to the exact
/// integer square root of the raw bits shifted by 32). Negative inputs give 0.
pub fn sqrt_fx(x: Fx) -> Fx {
    // `checked_sqrt` is `None` only for a negative input (I32F32 has integer bits, so the
    // root never overflows).
    x.checked_sqrt().unwrap_or(Fx::ZERO)
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
    /// Speed change since the previous period `ω(i) − ω(i−1)` (0 in the first), rad/s.
    pub d_omega: RadPerSec,
    /// Motor torque T_e (F4), N·m.
    pub t_e: NewtonMetres,
    /// External torque T̂_t (F6), N·m.
    pub t_t: NewtonMetres,
    /// Cutting torque T̂_c (F7–F8), N·m.
    pub t_c: NewtonMetres,
    /// Cutting force F̂_c = T̂_c / r, N.
    pub force: Newtons,
}

/// F4–F8 for one power: the torques and the force they give.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TorqueChain {
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
    /// The previous period was steady (see [`STEADY_SHIFT`]).
    steady_prev: bool,
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
            steady_prev: false,
            sums: NoLoadSums::default(),
        }
    }

    /// The settings it was made with.
    pub fn settings(&self) -> &EstimatorSettings {
        &self.s
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

    /// F4–F8 with the B and T_fco in use: the force that `power` (W) gives at speed `omega`
    /// after a speed change `d_omega` (rad/s) since the previous period. [`Estimator::step`]
    /// calls it with F9's choice; the host calls it with P_o or k_slip·P_g alone to
    /// characterize the two estimates F9 chooses between.
    pub fn torque_chain(&self, power: Watts, omega: RadPerSec, d_omega: RadPerSec) -> TorqueChain {
        let t_e = self.torque(power, omega);
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
        TorqueChain {
            t_e,
            t_t,
            t_c,
            force: t_c.saturating_mul(self.inv_radius),
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
        // F9 without division: |P_g − P_o| > Δ_th·|P_o| (a cut's start and its end).
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
        let omega_prev = self.omega_prev.unwrap_or(omega);
        self.omega_prev = Some(omega);
        let d_omega = omega.saturating_sub(omega_prev);
        // No-load identification on steady periods (module header).
        let j_over_h = self.s.inertia.checked_div(self.h).unwrap_or(Fx::ZERO);
        let t_g = self.torque(p_g, omega);
        let inertia_torque = j_over_h.saturating_mul(d_omega);
        let steady = inertia_torque
            .saturating_abs()
            .saturating_mul(Fx::const_from_int(1 << STEADY_SHIFT))
            <= t_g.saturating_abs();
        if self.identifying && steady && self.steady_prev {
            let y = t_g.saturating_sub(inertia_torque);
            let w16 = i128::from(omega.to_bits() >> 16);
            let y16 = i128::from(y.to_bits() >> 16);
            let s = &mut self.sums;
            s.n = s.n.saturating_add(1);
            s.sw = s.sw.saturating_add(w16);
            s.sww = s.sww.saturating_add(w16.saturating_mul(w16));
            s.sy = s.sy.saturating_add(y16);
            s.swy = s.swy.saturating_add(w16.saturating_mul(y16));
        }
        self.steady_prev = steady;
        let chain = self.torque_chain(p_used, omega, d_omega);
        Estimate {
            signals: *sig,
            p_i,
            p_g,
            p_used,
            fast,
            d_omega,
            t_e: chain.t_e,
            t_t: chain.t_t,
            t_c: chain.t_c,
            force: chain.force,
        }
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for Estimator {
    /// The no-load identification's least-squares sums `estimator.no_load.n` (`u32`),
    /// `.sw`, `.sy` (Σω, Σy: `i128` with 16 fractional bits, I112F16) and `.sww`, `.swy`
    /// (Σω², Σωy: 32 fractional bits, I96F32), all saturating; the viscous friction B in use
    /// `estimator.viscous` (I32F32 clamped to `0..=J/(2h)`), its `1/b` of F6
    /// `estimator.inv_b`, the previous period's speed `estimator.omega_prev` (I32F32) and
    /// F9's hold counter `estimator.hold` (`u8`). T_fco is the `coulomb` output.
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        let s = &self.sums;
        f(Register::new(
            "estimator.no_load.n",
            Format::unsigned(32),
            s.n.into(),
        ));
        let (q16, q32) = (Format::fixed(128, 16), Format::fixed(128, 32));
        f(Register::new("estimator.no_load.sw", q16, s.sw));
        f(Register::new("estimator.no_load.sww", q32, s.sww));
        f(Register::new("estimator.no_load.sy", q16, s.sy));
        f(Register::new("estimator.no_load.swy", q32, s.swy));
        let b_max = viscous_max(self.s.inertia, self.h);
        f(Register::fx(
            "estimator.viscous",
            Format::I32F32.clamped(0, b_max.to_bits().into()),
            self.viscous,
        ));
        f(Register::fx("estimator.inv_b", Format::I32F32, self.inv_b));
        f(Register {
            name: "estimator.omega_prev",
            format: Format::I32F32,
            raw: self.omega_prev.map(|w| w.to_bits().into()),
        });
        f(Register::new(
            "estimator.hold",
            Format::unsigned(8),
            self.hold.into(),
        ));
    }
}

#[cfg(test)]
mod worked_examples;

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
        let (b, t_fco) = (Fx::lit("0.005"), Fx::ONE);
        let j_over_h = Fx::ONE; // 0.05 / 0.05
        let step = Fx::lit("0.5");
        // 10 periods at 60 rad/s, a ramp of 0.5 rad/s per period to 80 rad/s (inertia
        // torque 0.5 N·m, more than 1/16 of the ~1.8 N·m torque: not steady), 10 at 80.
        let run_up = |e: &mut Estimator, plateaus: bool| {
            let mut omega = Fx::const_from_int(60);
            let reps = if plateaus { 10 } else { 1 };
            for _ in 0..reps {
                let _ = e.step(&signals(omega, b * omega + t_fco));
            }
            for _ in 0..40 {
                omega += step;
                let _ = e.step(&signals(omega, b * omega + t_fco + j_over_h * step));
            }
            for _ in 0..reps {
                let _ = e.step(&signals(omega, b * omega + t_fco));
            }
        };
        let mut e = Estimator::new(&settings(), h);
        e.start_identification();
        run_up(&mut e, true);
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
        // The ramp with one period before and after it has no two steady periods in a row:
        // nothing is collected, B and T_fco keep their nominal values.
        let mut e = Estimator::new(&settings(), h);
        e.start_identification();
        run_up(&mut e, false);
        e.finish_identification();
        assert!(!e.identified());
        assert_eq!((e.viscous(), e.coulomb()), (Fx::lit("0.02"), Fx::ZERO));
    }

    #[test]
    fn torque_chain_is_the_steps_force_for_its_power() {
        let h = Fx::lit("0.05");
        let mut e = Estimator::new(&settings(), h);
        let _ = e.step(&signals(Fx::const_from_int(80), Fx::const_from_int(3)));
        let est = e.step(&signals(Fx::const_from_int(82), Fx::const_from_int(12)));
        assert_eq!(est.d_omega, Fx::const_from_int(2));
        let chain = e.torque_chain(est.p_used, est.signals.omega, est.d_omega);
        assert_eq!(
            (chain.t_e, chain.t_t, chain.t_c, chain.force),
            (est.t_e, est.t_t, est.t_c, est.force)
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
