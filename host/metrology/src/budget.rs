//! The error budget of the decided diameter, predicted from the settings (docs/accuracy.md):
//! for each method and contact rule, the systematic error and the scatter, term by term,
//! from the papers' formulas (docs/domain.md §2):
//!
//! - **S9** (pulse counter): the decision comes when the revolution's contact share reaches
//!   `(i_def + 1) / window pulses`; on a surface whose seen radius has the distribution of
//!   the form error plus roughness, that share is reached at one *level*, the share's
//!   quantile of the surface. Against the true mean this is the method's first bias.
//! - **Δ1** (paper E): the difference between the spindle paths while machining and while
//!   measuring, here the non-cancelling fraction of the per-revolution errors
//!   (`repeating_mismatch`): it changes the seen surface, so its quantile and its largest
//!   radius.
//! - **contact rule**: the sticky rule counts a pulse when contact touched any part of it,
//!   so the count at one level is larger than the plain share (the roughness fragments the
//!   contact): the decision comes earlier, higher.
//! - **decision lag**: the counter decides on the pulse that completes the count, in the
//!   window after the one the level was first crossed in; the tool has fed on meanwhile:
//!   lag in revolutions × f_r.
//! - **S4, S5** (single pulse): the first contact reads the largest seen radius, within one
//!   step of the feed per revolution Δf = k·f_r,min/n (S5).
//! - **S10** (Δ_M = e_Σ(T > 2π)): only the spindle errors slower than one revolution scatter
//!   the decision; averaged over the deciding revolution their amplitude shrinks by
//!   `sin(π/T)/(π/T)` (T in revolutions). They also bias it: the first window that reaches
//!   the share is more often one where they lift the surface (or, where they delay it
//!   more than they hasten it, lower: the term's label follows its sign).
//! - **Δ2** (paper E): the random part, the roughness drawn at every Z, and the scale's
//!   quantization (one count, uniform: `2·res/√12` on the diameter).
//! - **the mean of m at one Z**: m measurements at one Z average the parts that change
//!   between them (slow errors, quantization) as `σ/√m`; the roughness of that Z stays (it
//!   is the same surface). S8 states this law for the fast-feed single pulse's profile
//!   scatter; the cycle here starts every approach on an index, so that scatter does not
//!   arise (docs/accuracy.md).
//!
//! How it is evaluated: the surface model is the settings' own — the form harmonics, the
//! per-revolution errors times the mismatch, a Gaussian roughness of `random_um` per
//! roughness cell (`ROUGHNESS_CELLS_PER_REV`, linearly interpolated), the tool's start
//! point and feed. The probability that a pulse carries contact at a tool level is
//! Gaussian (the roughness), exact for the sampled rule and for the sticky rule's points
//! within a pulse (a linear segment's largest value is at an end); the count of a window is
//! their sum, its spread their Bernoulli variances, carried from window to window with
//! their correlation (the same surface); the slow errors enter as their
//! harmonics with the phase at the approach's start unknown, averaged over
//! [`PHASE_SAMPLES`] phases (a low-discrepancy set, not random draws). No contact
//! electrics, clock, glitch filter or golden model is involved, and no number is fitted
//! to the simulator: `tooltouch budget --simulate N` and `tests/measure/budget.rs`
//! compare the two.
//!
//! Where these formulas do not describe the decision, [`predict`] says so
//! ([`Outcome::Refused`]) instead of guessing: the density detector, an approach that starts
//! within reach of the surface, a feed that crosses the whole profile within one window
//! (the fast-feed regime of S6–S7), slow errors large against the feed per window
//! ([`SLOW_TO_FEED_LIMIT`]),
//! contact electrics or a glitch filter that remove a
//! noticeable part of the contact, an approach that may not decide.

use serde::Serialize;
use std::f64::consts::{PI, TAU};
use tooltouch_model::measure::config::{ContactRule, DecisionMethod};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::lathe::surface::ROUGHNESS_CELLS_PER_REV;
use tooltouch_plant::lathe::LatheScenario;

/// Slow-error phases the prediction averages over (a Kronecker low-discrepancy set in the
/// harmonics' phases and amplitude jitters).
pub const PHASE_SAMPLES: usize = 256;

/// A method and contact rule the budget is made for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Variant {
    /// The decision method.
    pub method: DecisionMethod,
    /// The contact rule (the single pulse and the density detector read it too, but the
    /// single pulse decides on the first contact edge whatever the rule).
    pub rule: ContactRule,
}

impl Variant {
    /// The variants `budget` reports: the counter with both rules, the single pulse, the
    /// density detector (refused).
    pub const ALL: [Variant; 4] = [
        Variant {
            method: DecisionMethod::Counter,
            rule: ContactRule::Sampled,
        },
        Variant {
            method: DecisionMethod::Counter,
            rule: ContactRule::Sticky,
        },
        Variant {
            method: DecisionMethod::SinglePulse,
            rule: ContactRule::Sticky,
        },
        Variant {
            method: DecisionMethod::Density,
            rule: ContactRule::Sticky,
        },
    ];

    /// A short name: `counter/sampled`, `counter/sticky`, `single-pulse`, `density`.
    pub fn name(&self) -> String {
        match self.method {
            DecisionMethod::Counter => format!(
                "counter/{}",
                match self.rule {
                    ContactRule::Sampled => "sampled",
                    ContactRule::Sticky => "sticky",
                }
            ),
            DecisionMethod::SinglePulse => "single-pulse".into(),
            DecisionMethod::Density => "density".into(),
        }
    }

    /// What the method reads: the mean diameter (counter, density) or the largest (single
    /// pulse).
    pub fn reference(&self) -> Reference {
        match self.method {
            DecisionMethod::SinglePulse => Reference::Largest,
            _ => Reference::Mean,
        }
    }
}

/// The true diameter an error is taken against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reference {
    /// The workpiece's true mean diameter at the measured Z.
    Mean,
    /// Its true largest diameter.
    Largest,
}

/// Whether a term shifts the result or scatters it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TermKind {
    /// A systematic error, µm on the diameter (signed).
    Bias,
    /// A standard deviation, µm on the diameter (1σ).
    Sigma,
}

/// One term of the budget.
#[derive(Clone, Debug, Serialize)]
pub struct Term {
    /// What it is.
    pub name: &'static str,
    /// The formula it comes from (docs/domain.md's equation names).
    pub formula: &'static str,
    /// Bias or scatter.
    pub kind: TermKind,
    /// Its value on the diameter, µm.
    pub value_um: f64,
    /// How it was obtained, with the numbers that went in.
    pub detail: String,
}

/// A prediction for one variant.
#[derive(Clone, Debug, Serialize)]
pub struct Prediction {
    /// The variant.
    pub variant: Variant,
    /// The diameter the bias is taken against.
    pub reference: Reference,
    /// What the decided diameter is, in words: the largest diameter (single pulse), the
    /// mean (the counter near the 50 % share, S9), or the diameter at the counter's share
    /// level and its distance from the mean (elsewhere: a 25 % share reads high).
    pub reads: String,
    /// Every term.
    pub terms: Vec<Term>,
    /// Total systematic error against [`Self::reference`], µm on the diameter.
    pub bias_um: f64,
    /// Total 1σ scatter of the decided diameter, µm.
    pub sigma_um: f64,
    /// The largest diameter minus the mean, µm (expected): converts a bias against one
    /// reference into the other.
    pub largest_minus_mean_um: f64,
    /// Revolutions from the tool crossing the decision level to the decision (counter), or
    /// from crossing the largest radius to the first contact (single pulse).
    pub lag_revs: f64,
    /// The part of the scatter that averages over repeats at one Z (slow errors,
    /// quantization), 1σ, µm.
    pub sigma_averaging_um: f64,
    /// The part that does not (the roughness of that Z and the decision grid), 1σ, µm.
    pub sigma_fixed_per_z_um: f64,
}

impl Prediction {
    /// The 2σ repeatability, µm.
    pub fn repeatability_2sigma_um(&self) -> f64 {
        2.0 * self.sigma_um
    }

    /// The bias against the other reference, µm.
    pub fn bias_vs(&self, reference: Reference) -> f64 {
        match (self.reference, reference) {
            (a, b) if a == b => self.bias_um,
            (Reference::Mean, Reference::Largest) => self.bias_um - self.largest_minus_mean_um,
            _ => self.bias_um + self.largest_minus_mean_um,
        }
    }

    /// The 1σ of the mean of `m` measurements at one Z, µm (S8's law, here for what changes
    /// between approaches):
    /// `√(σ_averaging²/m + σ_fixed²)`.
    pub fn sigma_of_mean_um(&self, m: u32) -> f64 {
        let m = f64::from(m.max(1));
        (self.sigma_averaging_um.powi(2) / m + self.sigma_fixed_per_z_um.powi(2)).sqrt()
    }
}

/// The budget for one variant: a prediction, or why there is none.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "outcome", rename_all = "kebab-case")]
pub enum Outcome {
    /// Predicted.
    Predicted(Prediction),
    /// Not predicted, and why.
    Refused {
        /// The variant.
        variant: Variant,
        /// Why the formulas do not describe this regime.
        reason: String,
    },
}

impl Outcome {
    /// The prediction, if any.
    pub fn prediction(&self) -> Option<&Prediction> {
        match self {
            Outcome::Predicted(p) => Some(p),
            Outcome::Refused { .. } => None,
        }
    }
    /// The variant.
    pub fn variant(&self) -> Variant {
        match self {
            Outcome::Predicted(p) => p.variant,
            Outcome::Refused { variant, .. } => *variant,
        }
    }
}

/// The standard normal distribution function; `Φ(±∞)` = 1, 0.
fn phi(z: f64) -> f64 {
    if z == f64::INFINITY {
        1.0
    } else if z == f64::NEG_INFINITY {
        0.0
    } else {
        0.5 * libm::erfc(-z / std::f64::consts::SQRT_2)
    }
}

/// `P(value < level)` for a value of mean `mean` and standard deviation `sd` (a step at
/// `sd = 0`).
fn below(level: f64, mean: f64, sd: f64) -> f64 {
    if sd > 0.0 {
        phi((level - mean) / sd)
    } else if level > mean {
        1.0
    } else {
        0.0
    }
}

/// A point of the seen surface: its angle (fraction of a turn), its mean radius and the
/// roughness's standard deviation there, µm from R0.
#[derive(Clone, Copy, Debug)]
struct Point {
    turn: f64,
    mean: f64,
    sd: f64,
}

/// The slow spindle errors of one phase sample: `Σ A_i cos(2π τ / T_i + ψ_i)`, τ in
/// revolutions from the approach's start.
#[derive(Clone, Debug, Default)]
struct Slow {
    harmonics: Vec<(f64, f64, f64)>,
}

impl Slow {
    fn at(&self, tau: f64) -> f64 {
        self.harmonics
            .iter()
            .map(|&(a, t, psi)| a * (TAU * tau / t + psi).cos())
            .sum()
    }
}

/// The phase samples of the scenario's slow errors (one empty sample without any).
fn slow_samples(scenario: &LatheScenario, with_slow: bool) -> Vec<Slow> {
    let list: Vec<_> = scenario
        .slow
        .iter()
        .filter(|h| h.amplitude_um != 0.0)
        .collect();
    if !with_slow || list.is_empty() {
        return vec![Slow::default()];
    }
    // Kronecker sequence in 2·K dimensions (phase and jitter per harmonic): the
    // generalised golden ratio (Roberts' R_d), a deterministic, evenly spread set.
    let d = 2 * list.len();
    let mut g = 2.0f64;
    for _ in 0..50 {
        g = (1.0 + g).powf(1.0 / (d as f64 + 1.0));
    }
    let alpha: Vec<f64> = (1..=d).map(|k| (1.0 / g.powi(k as i32)).fract()).collect();
    (0..PHASE_SAMPLES)
        .map(|n| {
            let u = |k: usize| (0.5 + alpha[k] * (n as f64 + 1.0)).fract();
            Slow {
                harmonics: list
                    .iter()
                    .enumerate()
                    .map(|(i, h)| {
                        let jitter = 2.0 * u(2 * i + 1) - 1.0;
                        (
                            h.amplitude_um * (1.0 + h.amplitude_jitter * jitter),
                            h.period_revs,
                            TAU * u(2 * i),
                        )
                    })
                    .collect(),
            }
        })
        .collect()
}

/// The seen surface as the budget models it, µm from R0.
struct SurfaceModel {
    /// Mean seen radius at each roughness node (form minus the mismatch's share of the
    /// per-revolution errors).
    seen: Vec<f64>,
    /// Mean true radius at each node (form only).
    truth: Vec<f64>,
    /// Roughness standard deviation at a node.
    sigma: f64,
}

impl SurfaceModel {
    /// `mismatch`: the non-cancelling fraction of the per-revolution errors; `path`: with
    /// the spindle path's difference from its loads ([`LatheScenario::spindle_path`]).
    fn new(s: &LatheScenario, mismatch: f64, path: bool) -> SurfaceModel {
        let c = ROUGHNESS_CELLS_PER_REV;
        let difference = s.spindle_path.difference(s.rpm);
        let mut seen = Vec::with_capacity(c);
        let mut truth = Vec::with_capacity(c);
        for k in 0..c {
            let phi = TAU * k as f64 / c as f64;
            let form: f64 = s.profile.iter().map(|h| h.at(phi)).sum();
            let rep: f64 = s.repeating.iter().map(|h| h.at(phi)).sum();
            truth.push(form);
            let loads = if path { difference.at(phi) } else { 0.0 };
            seen.push(form - mismatch * rep + loads);
        }
        SurfaceModel {
            seen,
            truth,
            sigma: s.random_um,
        }
    }

    /// The seen surface at `turn` (0..1): linear between nodes, as the roughness is.
    fn point(&self, turn: f64) -> Point {
        let c = self.seen.len();
        let x = turn.rem_euclid(1.0) * c as f64;
        let i = (x.floor() as usize).min(c - 1);
        let a = x - i as f64;
        let (m0, m1) = (self.seen[i], self.seen[(i + 1) % c]);
        Point {
            turn,
            mean: m0 + (m1 - m0) * a,
            sd: self.sigma * ((1.0 - a).powi(2) + a * a).sqrt(),
        }
    }

    fn highest_seen(&self) -> f64 {
        self.seen.iter().copied().fold(f64::MIN, f64::max)
    }
    fn lowest_seen(&self) -> f64 {
        self.seen.iter().copied().fold(f64::MAX, f64::min)
    }

    /// `E[max_k (mean_k + σ Z_k)]` of `means` (independent Gaussian nodes), µm.
    fn expected_max(means: &[f64], sigma: f64) -> f64 {
        let top = means.iter().copied().fold(f64::MIN, f64::max);
        if sigma <= 0.0 {
            return top;
        }
        let near: Vec<f64> = means
            .iter()
            .copied()
            .filter(|&m| m > top - 9.0 * sigma)
            .collect();
        // E[M] = lo + ∫_lo^hi (1 − F(u)) du, F(u) = Π Φ((u − m)/σ); below `lo` F ≈ 0.
        let (lo, hi) = (top - 2.0 * sigma, top + 9.0 * sigma);
        let steps = 2000;
        let du = (hi - lo) / steps as f64;
        let cdf = |u: f64| -> f64 { near.iter().map(|&m| phi((u - m) / sigma)).product() };
        let mut sum = 0.0;
        let mut prev = 1.0 - cdf(lo);
        for k in 1..=steps {
            let cur = 1.0 - cdf(lo + k as f64 * du);
            sum += 0.5 * (prev + cur) * du;
            prev = cur;
        }
        lo + sum
    }
}

/// The approach: start point above R0 and feed, µm and µm per revolution.
#[derive(Clone, Copy, Debug)]
struct Approach {
    home: f64,
    feed: f64,
}

impl Approach {
    fn new(s: &LatheScenario) -> Approach {
        // As the lathe places it: the middle of the home count's cell, the count a
        // multiple of 4 at or below R0 + clearance.
        let res = s.scale_resolution_um;
        let r0 = s.radius_um();
        let home_count = ((r0 + s.cycle.clearance_um) / res).floor() as i64;
        let home_count = home_count.div_euclid(4) * 4;
        Approach {
            home: (home_count as f64 + 0.5) * res - r0,
            feed: s.feed_mm_per_rev * 1000.0,
        }
    }
    fn at(&self, tau: f64) -> f64 {
        self.home - self.feed * tau
    }
}

/// First and second moments of a decided radius (µm from R0), and of the lag.
#[derive(Clone, Copy, Debug, Default)]
struct Moments {
    mean: f64,
    mean_sq: f64,
    undecided: f64,
}

impl Moments {
    fn var(&self) -> f64 {
        (self.mean_sq - self.mean * self.mean).max(0.0)
    }
    fn combine(parts: &[Moments]) -> Moments {
        let n = parts.len().max(1) as f64;
        Moments {
            mean: parts.iter().map(|m| m.mean).sum::<f64>() / n,
            mean_sq: parts.iter().map(|m| m.mean_sq).sum::<f64>() / n,
            undecided: parts.iter().map(|m| m.undecided).sum::<f64>() / n,
        }
    }
}

/// The points whose contact makes pulse `j` count (fractions of a turn): the sampled rule
/// reads the level at the pulse's edge `j/N`; the sticky rule any contact since the
/// previous edge, so the surface's nodes inside `((j−1)/N, j/N)` and both ends.
fn pulse_points(model: &SurfaceModel, n: u32, rule: ContactRule) -> Vec<Vec<Point>> {
    let c = model.seen.len() as f64;
    (0..n)
        .map(|j| {
            let end = f64::from(j) / f64::from(n);
            match rule {
                ContactRule::Sampled => vec![model.point(end)],
                ContactRule::Sticky => {
                    let start = (f64::from(j) - 1.0) / f64::from(n);
                    let mut pts = vec![model.point(start)];
                    let mut k = (start * c).floor() + 1.0;
                    while k < end * c {
                        pts.push(model.point(k / c));
                        k += 1.0;
                    }
                    pts.push(model.point(end));
                    pts
                }
            }
        })
        .collect()
}

/// The probability that a pulse whose points are `pts` counts, the tool at `level(turn)`.
fn pulse_probability(pts: &[Point], level: impl Fn(f64) -> f64) -> f64 {
    1.0 - pts
        .iter()
        .map(|p| below(level(p.turn), p.mean, p.sd))
        .product::<f64>()
}

/// The level at which a window's expected count, the tool not moving and no slow errors,
/// reaches `i_def + ½` (the S9 share), µm from R0.
fn static_level(points: &[Vec<Point>], window_revs: u32, i_def: u32) -> f64 {
    let target = f64::from(i_def) + 0.5;
    let count = |level: f64| {
        f64::from(window_revs)
            * points
                .iter()
                .map(|p| pulse_probability(p, |_| level))
                .sum::<f64>()
    };
    let (mut lo, mut hi) = (-2000.0f64, 2000.0f64);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if count(mid) >= target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Grid of the roughness's frozen count deviation, in standard deviations.
const Z_GRID: usize = 41;

/// The counter's decided radius for one slow-error sample: windows of `window_revs`
/// revolutions from the approach's start; in each, the expected count and its variance
/// pulse by pulse. The roughness is the same surface in every window, so the count's
/// deviation from its mean is one Gaussian carried from window to window with the
/// correlation of the pulses both windows count (`Σ min(p, p') − p·p'` over their
/// variances): a forward pass over a grid of that deviation. A window decides for the
/// deviations that take its count past `i_def`, at the pulse where the count does.
fn counter_moments(
    points: &[Vec<Point>],
    approach: Approach,
    slow: &Slow,
    window_revs: u32,
    i_def: u32,
    first_window: u64,
    max_windows: u64,
) -> Moments {
    let n = points.len();
    let target = f64::from(i_def) + 0.5;
    let z: Vec<f64> = (0..Z_GRID)
        .map(|k| -4.0 + 8.0 * k as f64 / (Z_GRID - 1) as f64)
        .collect();
    let mut mass: Vec<f64> = z.iter().map(|&z| (-0.5 * z * z).exp()).collect();
    let total: f64 = mass.iter().sum();
    mass.iter_mut().for_each(|m| *m /= total);
    let mut m = Moments::default();
    let mut previous: Option<(Vec<f64>, f64)> = None;
    let pulses = n * window_revs as usize;
    let mut probs = vec![0.0f64; pulses];
    let mut mu = vec![0.0f64; pulses];
    let mut sd = vec![0.0f64; pulses];
    for w in first_window..max_windows {
        let (mut acc_mu, mut acc_var) = (0.0, 0.0);
        for r in 0..window_revs as usize {
            // The arming index pulse already counts as one of the first window's, so
            // windows begin `window_revs − 1` revolutions after the approach's start.
            let rev = (w as usize * window_revs as usize + r) as f64 + f64::from(window_revs - 1);
            for (j, pts) in points.iter().enumerate() {
                // A sticky start point's `turn` may be negative (the previous revolution's end).
                let p = pulse_probability(pts, |turn| {
                    let tau = rev + turn;
                    approach.at(tau) - slow.at(tau)
                });
                let i = r * n + j;
                probs[i] = p;
                acc_mu += p;
                acc_var += p * (1.0 - p);
                mu[i] = acc_mu;
                sd[i] = acc_var.sqrt();
            }
        }
        let total_sd = acc_var.sqrt();
        // Carry the deviation from the previous window with their correlation.
        if let Some((prev_probs, prev_sd)) = &previous {
            let cov: f64 = prev_probs
                .iter()
                .zip(&probs)
                .map(|(&a, &b)| a.min(b) - a * b)
                .sum();
            let rho = if prev_sd * total_sd > 0.0 {
                (cov / (prev_sd * total_sd)).clamp(-1.0, 1.0)
            } else {
                1.0
            };
            if rho < 0.999 {
                let cond = (1.0 - rho * rho).sqrt();
                let mut next = vec![0.0; Z_GRID];
                for (k, &mk) in mass.iter().enumerate() {
                    if mk == 0.0 {
                        continue;
                    }
                    let row: Vec<f64> = z
                        .iter()
                        .map(|&zm| (-0.5 * ((zm - rho * z[k]) / cond).powi(2)).exp())
                        .collect();
                    let norm: f64 = row.iter().sum();
                    if norm > 0.0 {
                        for (nm, r) in next.iter_mut().zip(row) {
                            *nm += mk * r / norm;
                        }
                    }
                }
                mass = next;
            }
        }
        for k in 0..Z_GRID {
            if mass[k] == 0.0 || acc_mu + total_sd * z[k] < target {
                continue;
            }
            let i = (0..pulses)
                .find(|&i| mu[i] + sd[i] * z[k] >= target)
                .unwrap_or(pulses - 1);
            let tau = (w as usize * window_revs as usize) as f64
                + f64::from(window_revs - 1)
                + i as f64 / n as f64;
            let x = approach.at(tau);
            m.mean += mass[k] * x;
            m.mean_sq += mass[k] * x * x;
            mass[k] = 0.0;
        }
        let left: f64 = mass.iter().sum();
        if left < 1e-9 {
            break;
        }
        previous = Some((probs.clone(), total_sd));
    }
    let survive: f64 = mass.iter().sum();
    let decided = 1.0 - survive;
    if decided > 0.0 {
        m.mean /= decided;
        m.mean_sq /= decided;
    }
    m.undecided = survive;
    m
}

/// The single pulse's first-contact radius for one slow-error sample: node by node in the
/// order the tool passes them, the probability that the node's (Gaussian) radius reaches
/// the tool at this pass and not at its previous one.
// `k` indexes the surface nodes, the previous pass and the node's time together.
#[allow(clippy::needless_range_loop)]
fn single_pulse_moments(
    model: &SurfaceModel,
    approach: Approach,
    slow: &Slow,
    first_rev: u64,
    max_revs: u64,
) -> Moments {
    let c = model.seen.len();
    let mut below_prev = vec![1.0f64; c];
    let mut survive = 1.0f64;
    let mut m = Moments::default();
    'revs: for r in first_rev..max_revs {
        for k in 0..c {
            let tau = r as f64 + k as f64 / c as f64;
            let level = approach.at(tau) - slow.at(tau);
            let b = below(level, model.seen[k], model.sigma);
            let prev = below_prev[k];
            if prev <= 0.0 {
                continue;
            }
            // Not reached yet means below the lowest level of every pass so far.
            let keep = (b / prev).min(1.0);
            let hit = survive * (1.0 - keep);
            if hit > 0.0 {
                let x = approach.at(tau);
                m.mean += hit * x;
                m.mean_sq += hit * x * x;
                survive *= keep;
            }
            below_prev[k] = prev.min(b);
            if survive < 1e-12 {
                break 'revs;
            }
        }
    }
    let decided = 1.0 - survive;
    if decided > 0.0 {
        m.mean /= decided;
        m.mean_sq /= decided;
    }
    m.undecided = survive;
    m
}

/// `sin(x)/x`.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-12 {
        1.0
    } else {
        x.sin() / x
    }
}

/// S10's closed form: the 1σ of the slow errors averaged over one revolution, µm (radius):
/// `√(Σ (a_i · sinc(π/T_i))² · (1 + j_i²/3) / 2)`.
pub fn slow_sigma_closed_form(scenario: &LatheScenario) -> f64 {
    scenario
        .slow
        .iter()
        .map(|h| {
            (h.amplitude_um * sinc(PI / h.period_revs)).powi(2)
                * (1.0 + h.amplitude_jitter.powi(2) / 3.0)
                / 2.0
        })
        .sum::<f64>()
        .sqrt()
}

/// Why the budget does not predict `variant` on these settings, if it does not.
fn refusal(config: &MeasureConfig, s: &LatheScenario, variant: Variant) -> Option<String> {
    let model = SurfaceModel::new(s, s.repeating_mismatch, true);
    let approach = Approach::new(s);
    let slow_bound: f64 = s
        .slow
        .iter()
        .map(|h| h.amplitude_um.abs() * (1.0 + h.amplitude_jitter))
        .sum();
    if variant.method == DecisionMethod::Density {
        return Some(
            "the density detector's capacitor integrates contact across revolutions with its \
             own charge law; the papers give no formula for where it fires, so the budget \
             does not predict it (simulate it: `tooltouch measure --method density`)"
                .into(),
        );
    }
    let reach = model.highest_seen() + slow_bound + 4.0 * s.random_um;
    if approach.home <= reach {
        return Some(format!(
            "the approach starts {:.2} µm above R0, within reach of the surface (its highest \
             point {:.2} µm, slow errors {:.2} µm, roughness 4σ {:.2} µm): the first contact \
             is the start, not a measurement; raise clearance_um",
            approach.home,
            model.highest_seen(),
            slow_bound,
            4.0 * s.random_um
        ));
    }
    let rev_us = 60e6 / s.rpm;
    let e = &s.electrics;
    let first_touch_us =
        f64::from(e.bounce_pulses) * (e.bounce_on_us + e.bounce_off_us) + e.non_conduction_us;
    if variant.method == DecisionMethod::Counter && first_touch_us > 0.02 * rev_us {
        return Some(format!(
            "the bounce and non-conduction after first touch last {first_touch_us:.0} µs, \
             {:.1} % of a revolution (over 2 %): the count loses contact the surface model \
             does not know of",
            100.0 * first_touch_us / rev_us
        ));
    }
    let cell_us = rev_us / ROUGHNESS_CELLS_PER_REV as f64;
    let glitch_us = f64::from(config.settings().glitch_cycles) / f64::from(s.clock_hz) * 1e6;
    if s.random_um > 0.0 && glitch_us > 0.1 * cell_us {
        return Some(format!(
            "the glitch filter ({glitch_us:.2} µs) is over a tenth of a roughness cell \
             ({cell_us:.2} µs at {} rpm): it removes short contacts the surface model counts",
            s.rpm
        ));
    }
    let window = f64::from(config.settings().window_revs);
    let depth = model.highest_seen() - model.lowest_seen() + 2.0 * slow_bound;
    if variant.method == DecisionMethod::Counter && approach.feed * window > 0.5 * depth {
        return Some(format!(
            "fast-feed regime (S6–S7): the tool feeds {:.2} µm per window, over half the \
             surface's depth {depth:.2} µm (form, mismatch and slow errors): the share of \
             contact in a window is set by the feed, not by the surface's 50 % level (S9)",
            approach.feed * window
        ));
    }
    let slow_sigma = slow_sigma_closed_form(s);
    if slow_sigma > SLOW_TO_FEED_LIMIT * approach.feed * window {
        return Some(format!(
            "slow-error regime: the slow spindle errors averaged over a revolution (S10, \
             {slow_sigma:.2} µm 1σ on the radius) exceed {SLOW_TO_FEED_LIMIT} × the feed per \
             window ({:.2} µm): the decision then follows the slow errors more than the \
             feed, and the budget's phase average overstates the simulated scatter by \
             15–22 % (docs/accuracy.md)",
            approach.feed * window
        ));
    }
    None
}

/// Above this ratio of the slow errors' revolution-averaged 1σ (S10, radius) to the feed
/// per window the budget refuses. Measured against the simulation (400 measurements, the
/// slow errors' phase drawn per approach): up to 2.5 every case agreed within the sampling
/// error (the default errors at 0.0005–0.0007 mm/rev, ratio 0.4–0.6; 4.5 times them at
/// 0.0005 mm/rev, 2.5, within 6 %); beyond it some do not (six times them at
/// 0.0005 mm/rev, 3.4: the single pulse's 1σ 18 % over; 5.7: 15 %; 8.5: 22 %) and some
/// still do (4.2: within 3 %). The ratio names the regime; it is not a sharp law.
pub const SLOW_TO_FEED_LIMIT: f64 = 2.5;

/// The spindle path term's detail: its loads and what they make of the path.
fn path_detail(s: &LatheScenario) -> String {
    let path = s.spindle_path.difference(s.rpm);
    if s.spindle_path.loads {
        format!(
            "supports b {} mm, a {} mm, play {} µm; F_p {} N machining only, belt {} N, \
             unbalance {:.1} N machining / {:.1} N measuring: offset {:+.3} µm, \
             1st harmonic {:.3} µm (radius)",
            s.spindle_path.span_mm,
            s.spindle_path.overhang_mm,
            s.spindle_path.clearance_um,
            s.spindle_path.cutting_force_n,
            s.spindle_path.belt_load_n,
            path.unbalance_machining_n,
            path.unbalance_measuring_n,
            path.offset_um,
            path.first_harmonic.amplitude_um
        )
    } else {
        "no loads (`loads = false`): the measuring path is the machining path".to_string()
    }
}

/// The decided diameter's moments of `variant`'s approaches, with or without the slow
/// errors, over the phases of [`slow_samples`]; contact is possible from revolution
/// `first_rev`, the approach gives up after `max_revs`.
fn approach_moments(
    config: &MeasureConfig,
    s: &LatheScenario,
    variant: Variant,
    model: &SurfaceModel,
    approach: Approach,
    (first_rev, max_revs): (u64, u64),
    with_slow: bool,
) -> Moments {
    let samples = slow_samples(s, with_slow);
    let parts: Vec<Moments> = match variant.method {
        DecisionMethod::Counter => {
            let w = u32::from(config.settings().window_revs);
            let points = pulse_points(model, config.pulses_per_rev(), variant.rule);
            samples
                .iter()
                .map(|slow| {
                    counter_moments(
                        &points,
                        approach,
                        slow,
                        w,
                        config.settings().i_def,
                        first_rev / u64::from(w),
                        max_revs.div_ceil(u64::from(w)),
                    )
                })
                .collect()
        }
        _ => samples
            .iter()
            .map(|slow| single_pulse_moments(model, approach, slow, first_rev, max_revs))
            .collect(),
    };
    Moments::combine(&parts)
}

/// What the bias terms of a variant are computed from.
struct BiasInputs<'a> {
    config: &'a MeasureConfig,
    s: &'a LatheScenario,
    variant: Variant,
    /// The seen surface, with the spindle path's loads.
    model: &'a SurfaceModel,
    /// The seen surface without the loads.
    unloaded: &'a SurfaceModel,
    /// The surface with the per-revolution errors matched (no trajectory mismatch).
    matched: &'a SurfaceModel,
    approach: Approach,
    /// The decided diameter's moments with the slow errors, and without.
    full: Moments,
    still: Moments,
}

/// A variant's bias terms: what it reads, the lag of its decision (revolutions) and the
/// terms.
struct Biases {
    reference: Reference,
    reads: String,
    lag_revs: f64,
    terms: Vec<Term>,
}

/// How far from 50 % the counter's share may be for its reading to be called the mean
/// diameter (S9): 40–60 %. On the default form the level moves 0.55 µm (radius) from the
/// mean at 50 %; at 25 % it reads the surface's upper quartile instead.
pub const MEAN_SHARE_BAND: f64 = 0.1;

/// The pulse counter's bias terms: the share level, then what moves the decision off it.
fn counter_biases(b: &BiasInputs) -> Biases {
    let BiasInputs {
        config,
        s,
        variant,
        model,
        unloaded,
        matched,
        approach,
        full,
        still,
    } = *b;
    let mut terms = Vec::new();
    let w = u32::from(config.settings().window_revs);
    let i_def = config.settings().i_def;
    let share = (f64::from(i_def) + 1.0) / f64::from(config.window_pulses());
    let n = config.pulses_per_rev();
    let level_matched = static_level(&pulse_points(matched, n, ContactRule::Sampled), w, i_def);
    let level_unloaded = static_level(&pulse_points(unloaded, n, ContactRule::Sampled), w, i_def);
    let level_seen = static_level(&pulse_points(model, n, ContactRule::Sampled), w, i_def);
    let level_rule = static_level(&pulse_points(model, n, variant.rule), w, i_def);
    let lag_revs = (level_rule - still.mean) / approach.feed;
    terms.push(Term {
        name: "share level",
        formula: "S9",
        kind: TermKind::Bias,
        value_um: 2.0 * level_matched,
        detail: format!(
            "the level where {:.1} % of the revolution is in contact ((i_def + 1)/{} \
             pulses), form and roughness, against the mean",
            100.0 * share,
            config.window_pulses()
        ),
    });
    terms.push(Term {
        name: "trajectory mismatch",
        formula: "Δ1 (E)",
        kind: TermKind::Bias,
        value_um: 2.0 * (level_unloaded - level_matched),
        detail: format!(
            "repeating_mismatch {} of the per-revolution errors changes the seen \
             surface's share level",
            s.repeating_mismatch
        ),
    });
    terms.push(Term {
        name: "spindle path from its loads",
        formula: "Δ1 (E, Fig. 1)",
        kind: TermKind::Bias,
        value_um: 2.0 * (level_seen - level_unloaded),
        detail: path_detail(s),
    });
    terms.push(Term {
        name: "contact rule",
        formula: "S9, rule",
        kind: TermKind::Bias,
        value_um: 2.0 * (level_rule - level_seen),
        detail: match variant.rule {
            ContactRule::Sampled => "sampled: the level at each FES edge".into(),
            ContactRule::Sticky => {
                "sticky: a pulse counts if contact touched any part of it".into()
            }
        },
    });
    terms.push(Term {
        name: "decision lag",
        formula: "lag × f_r",
        kind: TermKind::Bias,
        value_um: 2.0 * (still.mean - level_rule),
        detail: format!(
            "{lag_revs:.2} rev × {:.4} µm/rev: the window that completes the count \
             comes after the level is crossed (start {:.2} µm above R0, windows of {w} rev)",
            approach.feed, approach.home
        ),
    });
    let slow_shift = 2.0 * (full.mean - still.mean);
    let (name, detail) = if slow_shift >= 0.0 {
        (
            "slow errors, first window up",
            "the first window to reach the share is more often one the slow errors lift: \
             the decision comes higher",
        )
    } else {
        (
            "slow errors, first window down",
            "the slow errors delay the window that reaches the share more often than they \
             hasten it: the decision comes lower",
        )
    };
    terms.push(Term {
        name,
        formula: "S10",
        kind: TermKind::Bias,
        value_um: slow_shift,
        detail: detail.into(),
    });
    let reads = if (share - 0.5).abs() <= MEAN_SHARE_BAND {
        format!("the mean diameter (a {:.1} % share, S9)", 100.0 * share)
    } else {
        format!(
            "the diameter at the {:.1} % contact share, not the mean (S9 reads the mean \
             near 50 %): that level lies {:+.2} µm from the mean",
            100.0 * share,
            2.0 * level_matched
        )
    };
    Biases {
        reference: Reference::Mean,
        reads,
        lag_revs,
        terms,
    }
}

/// The first contact's bias terms: the largest diameter, then what moves the contact off it.
fn largest_biases(b: &BiasInputs) -> Biases {
    let BiasInputs {
        s,
        model,
        unloaded,
        approach,
        full,
        still,
        ..
    } = *b;
    let true_largest = SurfaceModel::expected_max(&model.truth, model.sigma);
    let seen_largest = SurfaceModel::expected_max(&model.seen, model.sigma);
    let unloaded_largest = SurfaceModel::expected_max(&unloaded.seen, unloaded.sigma);
    let mut terms = Vec::new();
    let lag_revs = (seen_largest - still.mean) / approach.feed;
    terms.push(Term {
        name: "largest diameter read",
        formula: "S4",
        kind: TermKind::Bias,
        value_um: 0.0,
        detail: format!(
            "Δ_f = e + Δφ: the first contact reads the largest diameter, {:+.2} µm \
             from the mean (form and roughness)",
            2.0 * true_largest
        ),
    });
    terms.push(Term {
        name: "trajectory mismatch",
        formula: "Δ1 (E)",
        kind: TermKind::Bias,
        value_um: 2.0 * (unloaded_largest - true_largest),
        detail: format!(
            "repeating_mismatch {}: the largest seen radius against the true one",
            s.repeating_mismatch
        ),
    });
    terms.push(Term {
        name: "spindle path from its loads",
        formula: "Δ1 (E, Fig. 1)",
        kind: TermKind::Bias,
        value_um: 2.0 * (seen_largest - unloaded_largest),
        detail: path_detail(s),
    });
    terms.push(Term {
        name: "feed step",
        formula: "S5",
        kind: TermKind::Bias,
        value_um: 2.0 * (still.mean - seen_largest),
        detail: format!(
            "Δf = k·f_r,min/n = {:.4} µm per revolution: the first contact comes \
             {lag_revs:.2} rev after the tool passes the largest radius",
            approach.feed
        ),
    });
    let slow_shift = 2.0 * (full.mean - still.mean);
    terms.push(Term {
        name: "slow errors, e at first contact",
        formula: "S4 (e), S10",
        kind: TermKind::Bias,
        value_um: slow_shift,
        detail: if slow_shift >= 0.0 {
            "the first contact comes where the slow errors lift the surface: higher"
        } else {
            "the slow errors delay the first contact past the surface's peak more often \
             than they hasten it: lower"
        }
        .into(),
    });
    Biases {
        reference: Reference::Largest,
        reads: "the largest diameter (S4)".into(),
        lag_revs,
        terms,
    }
}

/// The budget of `variant` on the settings `config` and `scenario`.
pub fn predict(config: &MeasureConfig, s: &LatheScenario, variant: Variant) -> Outcome {
    if let Some(reason) = refusal(config, s, variant) {
        return Outcome::Refused { variant, reason };
    }
    let model = SurfaceModel::new(s, s.repeating_mismatch, true);
    let unloaded = SurfaceModel::new(s, s.repeating_mismatch, false);
    let matched = SurfaceModel::new(s, 0.0, false);
    let approach = Approach::new(s);
    let res = s.scale_resolution_um;
    let quantization = 2.0 * res / 12f64.sqrt();
    let slow_bound: f64 = s
        .slow
        .iter()
        .map(|h| h.amplitude_um.abs() * (1.0 + h.amplitude_jitter))
        .sum();
    // Revolutions before any contact is possible, and the last one allowed.
    let reach = model.highest_seen() + slow_bound + 6.0 * s.random_um;
    let first_rev = ((approach.home - reach) / approach.feed).floor().max(0.0) as u64;
    let max_revs = u64::from(s.cycle.max_approach_revs);
    let true_largest = SurfaceModel::expected_max(&model.truth, model.sigma);
    let slow_closed = 2.0 * slow_sigma_closed_form(s);
    let moments = |with_slow| {
        approach_moments(
            config,
            s,
            variant,
            &model,
            approach,
            (first_rev, max_revs),
            with_slow,
        )
    };
    let (full, still) = (moments(true), moments(false));
    if full.undecided > 1e-3 {
        return Outcome::Refused {
            variant,
            reason: format!(
                "{:.1} % of the approaches would not decide within max_approach_revs {}: \
                 the budget of the decided ones would not describe the run",
                100.0 * full.undecided,
                s.cycle.max_approach_revs
            ),
        };
    }
    let sigma_slow = 2.0 * (full.var() - still.var()).max(0.0).sqrt();
    let sigma_still = 2.0 * still.var().sqrt();
    let slow_detail = format!(
        "spindle errors slower than one revolution, {} harmonic(s), averaged over {} phases; \
         closed form 2·√(Σ (a·sinc(π/T))²·(1 + j²/3)/2) = {slow_closed:.3} µm",
        s.slow.iter().filter(|h| h.amplitude_um != 0.0).count(),
        PHASE_SAMPLES
    );
    let inputs = BiasInputs {
        config,
        s,
        variant,
        model: &model,
        unloaded: &unloaded,
        matched: &matched,
        approach,
        full,
        still,
    };
    let Biases {
        reference,
        reads,
        lag_revs,
        mut terms,
    } = match variant.method {
        DecisionMethod::Counter => counter_biases(&inputs),
        _ => largest_biases(&inputs),
    };
    terms.push(Term {
        name: "slow errors",
        formula: "S10",
        kind: TermKind::Sigma,
        value_um: sigma_slow,
        detail: slow_detail,
    });
    terms.push(Term {
        name: "roughness and decision grid",
        formula: "Δ2 (E)",
        kind: TermKind::Sigma,
        value_um: sigma_still,
        detail: format!(
            "roughness σ {} µm drawn per Z, the decision's place on the revolution grid",
            s.random_um
        ),
    });
    terms.push(Term {
        name: "scale quantization",
        formula: "2·res/√12",
        kind: TermKind::Sigma,
        value_um: quantization,
        detail: format!("one count of {res} µm on the radius, uniform"),
    });
    let bias_um: f64 = terms
        .iter()
        .filter(|t| t.kind == TermKind::Bias)
        .map(|t| t.value_um)
        .sum();
    let sigma_averaging = (sigma_slow.powi(2) + quantization.powi(2)).sqrt();
    Outcome::Predicted(Prediction {
        variant,
        reference,
        reads,
        bias_um,
        sigma_um: (sigma_averaging.powi(2) + sigma_still.powi(2)).sqrt(),
        largest_minus_mean_um: 2.0 * true_largest,
        lag_revs,
        sigma_averaging_um: sigma_averaging,
        sigma_fixed_per_z_um: sigma_still,
        terms,
    })
}

/// The budget of every variant of [`Variant::ALL`].
pub fn predict_all(config: &MeasureConfig, s: &LatheScenario) -> Vec<Outcome> {
    Variant::ALL
        .iter()
        .map(|&v| predict(config, s, v))
        .collect()
}
