//! Fuzzy PI force controller, Mamdani inference in exact integer arithmetic (docs/domain.md §3,
//! controller 3).
//!
//! Inputs: error `e = F_r − F̂_c` and its change `Δe = e(i) − e(i−1)` (N), scaled by `ge`
//! and `gde` to the normalized universe `[−3·SPAN, 3·SPAN]` (rounded to integers, then
//! clamped). Output: the change of override `Δu`, in normalized units, scaled by `gdu` (%
//! per unit) and added to the override state (incremental = PI form: in the linear region
//! `Δu ≈ gdu·(ge·e + gde·Δe)`, i.e. `K_i·h = gdu·ge`, `K_p = gdu·gde`).
//!
//! - Memberships: 7 triangular sets NB, NM, NS, ZE, PS, PM, PB centred at
//!   `(k − 3)·SPAN`, each reaching 0 at its neighbours' centres: `μ_k(x) = max(0, SPAN −
//!   |x − c_k|)`, integers `0..=SPAN` (SPAN = 1.0). The inputs are clamped to the outer
//!   centres, so the outer sets need no shoulders.
//! - Rules: a 7×7 table `rules[e][Δe]` of output-set offsets `−3..=3` or [`NO_RULE`]; the
//!   standard fuzzy PI table is [`STANDARD_RULES`] (`clamp(e + Δe, −3, 3)`, the diagonal
//!   table of MacVicar-Whelan).
//! - Inference: Mamdani min–max — a rule fires with `min(μ_e, μ_Δe)`; each output set's
//!   strength is the max over its rules.
//! - Defuzzification: centroid over the output universe discretized at
//!   `OUTPUT_STEPS_PER_SET` points per set spacing (25 points from −3 to +3):
//!   `Σ u_p·μ(u_p) / Σ μ(u_p)` with `μ(u_p) = max_o min(strength_o, μ_o(u_p))`, `i64` sums
//!   (≤ 25·3072·1024 < 2^27), the quotient truncated toward zero; no firing rule gives 0.
//!
//! Everything after the input scaling is integer, so firmware and model agree bit for bit.

use super::interface::{clamp_override, quantize, ControlOutput, ForceController, Percent};
use crate::units::{Fx, Newtons};
use crate::validation::{check_range, positive, ForceConfigError};

/// Number of fuzzy sets per variable.
pub const SETS: usize = 7;
/// Set spacing and membership full scale in normalized units (1.0).
pub const SPAN: i32 = 1024;
/// Inputs are clamped to `±LIMIT` (the outer sets' centres).
pub const LIMIT: i32 = 3 * SPAN;
/// Discretization of the output universe, points per set spacing.
pub const OUTPUT_STEPS_PER_SET: i32 = 4;
/// A rule-table entry with no rule.
pub const NO_RULE: i8 = i8::MIN;

/// The standard fuzzy PI rule table: output set `clamp(e + Δe, −3, 3)`, rows e = NB..PB,
/// columns Δe = NB..PB.
pub const STANDARD_RULES: [[i8; SETS]; SETS] = {
    let mut t = [[0i8; SETS]; SETS];
    let mut i = 0;
    while i < SETS {
        let mut j = 0;
        while j < SETS {
            let v = i as i8 + j as i8 - 6;
            t[i][j] = if v < -3 {
                -3
            } else if v > 3 {
                3
            } else {
                v
            };
            j += 1;
        }
        i += 1;
    }
    t
};

/// Fuzzy PI settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FuzzySettings {
    /// Error scaling GE, normalized units (1/1024 of a set spacing) per N, `(0, 10^6]`.
    pub ge: Fx,
    /// Error-change scaling GΔE, normalized units per N, `(0, 10^6]`.
    pub gde: Fx,
    /// Output scaling GΔU, % per normalized unit, `(0, 100]`.
    pub gdu: Fx,
    /// Rule table `rules[e][Δe]`: output set `−3..=3` or [`NO_RULE`]; at least one rule.
    pub rules: [[i8; SETS]; SETS],
}

impl FuzzySettings {
    /// Checks every field (`fuzzy.<field>`): positive scalings, rule entries in `−3..=3`
    /// or [`NO_RULE`], and a non-empty table.
    pub fn validate(&self) -> Result<(), ForceConfigError> {
        let big = Fx::const_from_int(1_000_000);
        positive("fuzzy.ge", self.ge, big)?;
        positive("fuzzy.gde", self.gde, big)?;
        positive("fuzzy.gdu", self.gdu, Fx::const_from_int(100))?;
        let mut count = 0i32;
        for &r in self.rules.iter().flatten() {
            if r == NO_RULE {
                continue;
            }
            check_range(
                "fuzzy.rules",
                Fx::from_num(r),
                Fx::const_from_int(-3),
                Fx::const_from_int(3),
            )?;
            count = count.saturating_add(1);
        }
        check_range(
            "fuzzy.rules",
            Fx::from_num(count),
            Fx::ONE,
            Fx::const_from_int(49),
        )
    }
}

/// Default fuzzy PI: e saturates the universe at ±300 N (GE = 3072/300), and GΔU, GΔE
/// reproduce [`crate::force::control::pi::DEFAULT_PI`] in the linear region
/// (`K_i·h = GΔU·GE`, `K_p = GΔU·GΔE`).
pub const DEFAULT_FUZZY: FuzzySettings = FuzzySettings {
    ge: Fx::lit("10.24"),
    gde: Fx::lit("51.2"),
    gdu: Fx::lit("0.003125"),
    rules: STANDARD_RULES,
};

/// Memberships of `x` (clamped to `±LIMIT`) in the 7 sets, `0..=SPAN`.
pub fn memberships(x: i32) -> [i32; SETS] {
    let x = x.clamp(-LIMIT, LIMIT);
    let mut mu = [0i32; SETS];
    let mut centre = -LIMIT;
    for m in mu.iter_mut() {
        *m = SPAN
            .saturating_sub(x.saturating_sub(centre).saturating_abs())
            .max(0);
        centre = centre.saturating_add(SPAN);
    }
    mu
}

/// Mamdani min–max inference and centroid defuzzification: `Δu` in normalized units
/// (`−LIMIT..=LIMIT`) for normalized inputs `e` and `de`.
pub fn infer(rules: &[[i8; SETS]; SETS], e: i32, de: i32) -> i32 {
    let mu_e = memberships(e);
    let mu_de = memberships(de);
    let mut strength = [0i32; SETS];
    for (row, &me) in rules.iter().zip(mu_e.iter()) {
        if me == 0 {
            continue;
        }
        for (&out, &md) in row.iter().zip(mu_de.iter()) {
            let w = me.min(md);
            if w == 0 || out == NO_RULE {
                continue;
            }
            let idx = usize::try_from(i32::from(out).saturating_add(3)).unwrap_or(SETS);
            if let Some(s) = strength.get_mut(idx) {
                *s = (*s).max(w);
            }
        }
    }
    let mut num: i64 = 0;
    let mut den: i64 = 0;
    let steps = 3 * OUTPUT_STEPS_PER_SET;
    for p in -steps..=steps {
        let u = p.saturating_mul(SPAN) / OUTPUT_STEPS_PER_SET;
        let mut mu = 0i32;
        for (&s, m) in strength.iter().zip(memberships(u)) {
            mu = mu.max(s.min(m));
        }
        num = num.saturating_add(i64::from(u).saturating_mul(i64::from(mu)));
        den = den.saturating_add(i64::from(mu));
    }
    let q = num.checked_div(den).unwrap_or(0);
    i32::try_from(q.clamp(i64::from(-LIMIT), i64::from(LIMIT))).unwrap_or(0)
}

/// Scales a physical input to the normalized universe: `round(g·x)` clamped to `±LIMIT`.
pub fn normalize(g: Fx, x: Fx) -> i32 {
    let v: i64 = g.saturating_mul(x).saturating_round().to_bits() >> 32;
    i32::try_from(v.clamp(i64::from(-LIMIT), i64::from(LIMIT))).unwrap_or(0)
}

/// The fuzzy PI kernel's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Fuzzy {
    s: FuzzySettings,
    e_prev: Option<Newtons>,
    u: Percent,
}

impl Fuzzy {
    /// A controller for validated `s`, starting at `override_pct`.
    pub fn new(s: &FuzzySettings, override_pct: u8) -> Fuzzy {
        let mut f = Fuzzy {
            s: *s,
            e_prev: None,
            u: Fx::ZERO,
        };
        f.reset(override_pct);
        f
    }

    /// The override state (the last period's clamped demand, before rounding), %, I32F32.
    pub fn override_state(&self) -> Percent {
        self.u
    }

    /// The previous period's error F_r − F̂_c, N, I32F32; `None` before the first period
    /// after a reset.
    pub fn previous_error(&self) -> Option<Newtons> {
        self.e_prev
    }
}

impl ForceController for Fuzzy {
    /// Normalizes e and Δe (Δe = 0 in the first period), infers Δu, adds `gdu·Δu` to the
    /// override state (saturating, then clamped to `[0, 255]`).
    fn step(&mut self, reference: Newtons, force: Newtons) -> ControlOutput {
        let e = reference.saturating_sub(force);
        let de = e.saturating_sub(self.e_prev.unwrap_or(e));
        self.e_prev = Some(e);
        let du = infer(
            &self.s.rules,
            normalize(self.s.ge, e),
            normalize(self.s.gde, de),
        );
        let demand = self
            .u
            .saturating_add(self.s.gdu.saturating_mul(Fx::from_num(du)));
        let (u, saturated) = clamp_override(demand);
        self.u = u;
        ControlOutput {
            override_pct: quantize(u),
            saturated,
        }
    }

    /// Override state to `override_pct`; forgets the previous error.
    fn reset(&mut self, override_pct: u8) {
        self.u = Fx::from_num(override_pct);
        self.e_prev = None;
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for Fuzzy {
    /// The override state `fuzzy.u` (I32F32 clamped to `0..=255`) and the previous
    /// period's error `fuzzy.e_prev` (I32F32; none before the first period after a reset).
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        let max = super::interface::OVERRIDE_MAX_FX.to_bits().into();
        f(Register::fx(
            "fuzzy.u",
            Format::I32F32.clamped(0, max),
            self.u,
        ));
        f(Register {
            name: "fuzzy.e_prev",
            format: Format::I32F32,
            raw: self.e_prev.map(|e| e.to_bits().into()),
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memberships_partition_unity() {
        for x in (-LIMIT..=LIMIT).step_by(37) {
            let mu = memberships(x);
            assert_eq!(mu.iter().sum::<i32>(), SPAN, "x = {x}");
        }
    }

    #[test]
    fn inference_is_odd_and_zero_at_rest() {
        assert_eq!(infer(&STANDARD_RULES, 0, 0), 0);
        for (e, de) in [(500, 0), (1500, -200), (3072, 3072), (-700, 100)] {
            assert_eq!(
                infer(&STANDARD_RULES, e, de),
                -infer(&STANDARD_RULES, -e, -de)
            );
        }
        assert!(infer(&STANDARD_RULES, 1024, 0) > 0);
        // only PB fires: the discretized centroid of its half triangle on [2, 3] (points
        // 2.25, 2.5, 2.75, 3 weighted 1..4) is 2.75
        assert_eq!(infer(&STANDARD_RULES, LIMIT, LIMIT), 11 * SPAN / 4);
    }

    #[test]
    fn empty_rule_table_is_rejected() {
        let s = FuzzySettings {
            ge: Fx::ONE,
            gde: Fx::ONE,
            gdu: Fx::ONE,
            rules: [[NO_RULE; SETS]; SETS],
        };
        let e = s.validate().unwrap_err();
        assert_eq!(e.field, "fuzzy.rules");
    }
}
