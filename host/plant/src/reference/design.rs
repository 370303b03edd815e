//! Controller design on the nominal turning process F10 (docs/domain.md §3), in float, once,
//! outside the hot path; the results are converted to the model's fixed-point settings.
//!
//! F10: `F_c(s)/f(s) = K_s·a/(τ_p s + 1)`. With the feed expressed as override percent of
//! the programmed feed `f_0`, the static gain is `K = K_s·a·f_0/100` N per %. The digital
//! loop adds a dead time `L`: half a period for the averaging of the force over the
//! period, one period from the sample that closes it to the override acting through the
//! CNC's zero-order hold — we take `L = 1.5·h` (our choice; the papers are silent).
//! Ziegler–Nichols (reaction curve) PI for a first order plus dead time:
//! `K_p = 0.9·τ_p/(K·L)`, `T_i = L/0.3`, `K_i = K_p/T_i`.

use tooltouch_model::force::control::fuzzy::{LIMIT, STANDARD_RULES};
use tooltouch_model::force::control::{AdaptiveSettings, FuzzySettings, PiSettings};
use tooltouch_model::units::Fx;

/// The nominal process F10 and the loop's timing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NominalProcess {
    /// Specific cutting force K_s, N/mm².
    pub ks: f64,
    /// Depth of cut a, mm.
    pub depth_mm: f64,
    /// Programmed feed f_0 at 100 % override, mm/rev.
    pub feed_mm_per_rev: f64,
    /// Process time constant τ_p, s.
    pub tau_p: f64,
    /// Control period h, s.
    pub period: f64,
}

impl Default for NominalProcess {
    /// 2000 N/mm², 1 mm, 0.3 mm/rev, τ_p = 0.08 s, h = 0.05 s: K = 6 N/%.
    fn default() -> Self {
        NominalProcess {
            ks: 2000.0,
            depth_mm: 1.0,
            feed_mm_per_rev: 0.3,
            tau_p: 0.08,
            period: 0.05,
        }
    }
}

impl NominalProcess {
    /// Static process gain K, N per % override.
    pub fn gain(&self) -> f64 {
        self.ks * self.depth_mm * self.feed_mm_per_rev / 100.0
    }

    /// Loop dead time L = 1.5·h, s.
    pub fn dead_time(&self) -> f64 {
        1.5 * self.period
    }

    /// Ziegler–Nichols PI gains `(K_p %/N, K_i %/(N·s))`.
    pub fn ziegler_nichols_pi(&self) -> (f64, f64) {
        let l = self.dead_time();
        let kp = 0.9 * self.tau_p / (self.gain() * l);
        let ti = l / 0.3;
        (kp, kp / ti)
    }
}

/// PI settings from gains, integrator clamped to the whole override range.
pub fn pi_settings(kp: f64, ki: f64) -> PiSettings {
    PiSettings {
        kp: Fx::from_num(kp),
        ki: Fx::from_num(ki),
        integrator_min: Fx::ZERO,
        integrator_max: Fx::from_num(255),
    }
}

/// Fuzzy PI scaling factors matching a PI in the linear region: the error universe
/// covers `±e_max` N, `GΔU = K_i·h/GE`, `GΔE = K_p/GΔU`.
pub fn fuzzy_from_pi(kp: f64, ki: f64, h: f64, e_max: f64) -> FuzzySettings {
    let ge = f64::from(LIMIT) / e_max;
    let gdu = ki * h / ge;
    FuzzySettings {
        ge: Fx::from_num(ge),
        gde: Fx::from_num(kp / gdu),
        gdu: Fx::from_num(gdu),
        rules: STANDARD_RULES,
    }
}

/// Adaptive F11 settings: open-loop gain `k_ol` (1/s), process gain between a tenth and
/// twenty times the nominal, starting at the nominal.
pub fn adaptive_settings(k_ol: f64, nominal_gain: f64) -> AdaptiveSettings {
    AdaptiveSettings {
        open_loop_gain: Fx::from_num(k_ol),
        gain_min: Fx::from_num(nominal_gain / 10.0),
        gain_max: Fx::from_num(nominal_gain * 20.0),
        initial_gain: Fx::from_num(nominal_gain),
        gain_filter_shift: 2,
        min_override: Fx::from_num(5),
        min_force: Fx::from_num(50),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zn_gives_the_model_defaults() {
        let (kp, ki) = NominalProcess::default().ziegler_nichols_pi();
        assert!(
            (kp - 0.16).abs() < 1e-12 && (ki - 0.64).abs() < 1e-12,
            "{kp} {ki}"
        );
        let d = tooltouch_model::force::control::pi::DEFAULT_PI;
        assert!((d.kp.to_num::<f64>() - kp).abs() < 1e-9);
        assert!((d.ki.to_num::<f64>() - ki).abs() < 1e-9);
        let z = fuzzy_from_pi(kp, ki, 0.05, 300.0);
        let dz = tooltouch_model::force::control::fuzzy::DEFAULT_FUZZY;
        assert!((z.gde.to_num::<f64>() - dz.gde.to_num::<f64>()).abs() < 1e-6);
        assert!((z.gdu.to_num::<f64>() - dz.gdu.to_num::<f64>()).abs() < 1e-6);
    }
}
