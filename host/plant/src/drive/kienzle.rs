//! A nonlinear, time-varying turning process (docs/control.md, "The nonlinear process"):
//! the steady cutting force of the Kienzle form
//!
//! `F_ss = K_s(t) · a^x · f_ref · (f / f_ref)^y`
//!
//! with depth of cut a (mm), feed f (mm/rev), the exponents of the turning literature —
//! x = 1 (the force is proportional to the chip width, a/sin κ) and y = 1 − m_c = 0.75
//! (Kienzle's m_c ≈ 0.25 for steels; the classical handbook power law for the main cutting
//! force of steel turned with carbide has the same x = 1.0 and y = 0.75) — normalized at the
//! programmed feed f_ref so that at 1 mm and f_ref it equals the linear F10 the controllers
//! are designed on. Its local gain dF/df = y·F/f is 25 % below F10's at f_ref and falls as
//! the feed rises. F10's first-order lag `τ_p dF/dt = F_ss − F` stays; K_s drifts as
//! [`super::ProcessParams::ks_drift`] and wanders ±`ks_wander` (hardness along the bar,
//! a sine of period `ks_wander_period`), and τ_p drifts as [`super::ProcessParams::tau_drift`]
//! (the scenario sets a non-zero drift with this process).

use std::f64::consts::PI;

/// Relative drift of τ_p with this process, 1/s: τ_p grows from 0.08 s to 0.11 s over the
/// 13 s run (our choice: the chip-formation lag changes with the tool's condition and the
/// temperature; a third over a cut makes the change matter to the controllers).
pub const KIENZLE_TAU_DRIFT: f64 = 0.03;

/// The Kienzle-type process law (see the module header).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KienzleProcess {
    /// Exponent x of the depth of cut.
    pub depth_exponent: f64,
    /// Exponent y of the feed (1 − m_c).
    pub feed_exponent: f64,
    /// Feed at which the law equals F10 at 1 mm depth, mm/rev.
    pub reference_feed: f64,
    /// Relative amplitude of K_s's wander.
    pub ks_wander: f64,
    /// Period of K_s's wander, s.
    pub ks_wander_period: f64,
}

impl Default for KienzleProcess {
    /// x = 1, y = 0.75 at 0.3 mm/rev, K_s wandering ±5 % over 5 s.
    fn default() -> Self {
        KienzleProcess {
            depth_exponent: 1.0,
            feed_exponent: 0.75,
            reference_feed: 0.3,
            ks_wander: 0.05,
            ks_wander_period: 5.0,
        }
    }
}

impl KienzleProcess {
    /// K_s's wander factor at time `t` s (1 ± `ks_wander`).
    pub fn wander(&self, t: f64) -> f64 {
        1.0 + self.ks_wander * (2.0 * PI * t / self.ks_wander_period.max(1e-3)).sin()
    }

    /// Steady force, N, for K_s `ks` (N/mm², already drifted), depth `depth` mm and feed
    /// `feed` mm/rev at time `t` s (0 for a feed ≤ 0).
    pub fn steady_force(&self, ks: f64, depth: f64, feed: f64, t: f64) -> f64 {
        if feed <= 0.0 || depth <= 0.0 {
            return 0.0;
        }
        let f_ref = self.reference_feed.max(1e-6);
        ks * self.wander(t)
            * depth.powf(self.depth_exponent)
            * f_ref
            * (feed / f_ref).powf(self.feed_exponent)
    }
}

impl KienzleProcess {
    /// The linear F10 that has this law's gain at force `force_n` N on the nominal cut
    /// (K_s, 1 mm, τ_p of [`crate::reference::design::NominalProcess::default`], feed at
    /// 100 % = `reference_feed`): the override there is `u = 100·(F/(K_s·f_ref))^(1/y)` and
    /// the local gain `dF/du = y·F/u` N/%, expressed as the K_s of a linear process with
    /// that gain (the controllers' designs take a linear process).
    pub fn linearized(&self, force_n: f64) -> crate::reference::design::NominalProcess {
        let nominal = crate::reference::design::NominalProcess::default();
        let full = nominal.ks * nominal.depth_mm.powf(self.depth_exponent) * self.reference_feed;
        let y = self.feed_exponent.max(1e-3);
        let u = 100.0 * (force_n / full).powf(1.0 / y);
        let gain = y * force_n / u.max(1e-3);
        crate::reference::design::NominalProcess {
            ks: gain * 100.0 / (nominal.depth_mm * nominal.feed_mm_per_rev),
            ..nominal
        }
    }
}
