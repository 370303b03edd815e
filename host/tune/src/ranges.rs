//! Range instrumentation (`tooltouch ranges`): every fixed-point register of the
//! measurement and force paths — the kernels' outputs and their internal registers —
//! observed over the tuning scenarios: its smallest and largest value, how often it
//! saturated (reached a limit of its format or of its clamp) and wrapped (a step of more
//! than half its range), and its headroom in bits against its format.
//!
//! The counting lives here, outside the kernels: a runner clocks the model
//! ([`FrontEnd::clock`], [`ForceKernel`] through the control scenario) and after every
//! clock or event reads the public outputs and the snapshot of the internal registers
//! that the model's `internals` feature gives ([`tooltouch_model::internals`]: read-only
//! accessors, compiled only for the host). The kernels' arithmetic, the firmware images
//! (built without the feature) and the model's bit-for-bit tests are untouched.

use crate::scenario::{self, Approach, ApproachSettings};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::internals::{self, Internals, Register};
use tooltouch_model::{FrontEnd, MeasureConfig};
use tooltouch_plant::drive::scenario::{run, ControlScenario, Engine};

/// Format tag of `ranges.json` (`-2`: rows carry their `kind`, and `limits` are numbers of
/// the register, not integers).
pub const FORMAT: &str = "tooltouch-ranges-2";

/// Where a register sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// A public output of the kernel, read after every clock or event.
    Output,
    /// A register inside the kernel (the model's `internals` snapshot).
    Internal,
}

/// How a register behaves at the end of its range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Overflow {
    /// It holds at its limits: a saturation is a clock or event at which it sits at one.
    Saturates,
    /// It wraps modulo 2^bits: a wrap is a step of more than half the range.
    Wraps,
}

/// One register's observed range.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RegisterRange {
    /// `measure` or `force`.
    pub path: String,
    /// An output or an internal register.
    pub kind: Kind,
    /// The register: an output's name, or an internal register's stable name
    /// (`sampler.sums[power]`, `estimator.no_load.sww`, `pi.integral`, …).
    pub name: String,
    /// Its format: `u8`, `s16` (two's complement), `I32F32`, `I56F8` (an `i64` with 8
    /// fractional bits) …, and for a clamped register its clamp: `I32F32 clamp 0..255`.
    pub format: String,
    /// Bits of its format (integer bits for a fixed-point value, sign included).
    pub bits: u32,
    /// Signed.
    pub signed: bool,
    /// What it does at its limits.
    pub overflow: Overflow,
    /// The limits it saturates at (the format's, or the clamp's), as numbers of the
    /// register (an output's format: its integers; a fixed-point word: its integer part's
    /// range).
    pub limits: (f64, f64),
    /// Smallest value observed (a fixed-point value as its number).
    pub min: f64,
    /// Largest value observed.
    pub max: f64,
    /// Clocks or events at which it sat at a limit (a saturating register).
    pub saturations: u64,
    /// Wraps observed (a wrapping register).
    pub wraps: u64,
    /// Bits of its format the observed values never needed:
    /// `bits − bits needed for max(|min|, |max|)` (a sign bit counted for a signed one).
    pub headroom_bits: i32,
    /// Clocks or events observed.
    pub samples: u64,
}

/// The report: every register over every scenario.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ranges {
    /// [`FORMAT`].
    pub format: String,
    /// Scenarios of the measurement path (seeds `1..=scenarios`).
    pub scenarios: u32,
    /// The registers.
    pub registers: Vec<RegisterRange>,
}

impl Ranges {
    /// The registers that saturated at a format's limit or wrapped.
    pub fn saturated(&self) -> Vec<&RegisterRange> {
        self.registers
            .iter()
            .filter(|r| r.saturations > 0 || r.wraps > 0)
            .collect()
    }
}

/// Bits a register needs to hold `v` (its integer part, `floor(v)`): the magnitude's bits,
/// and a sign bit for a signed one (two's complement: −2^(n−1) fits n bits).
fn bits_needed(v: f64, signed: bool) -> u32 {
    let whole = v.floor();
    let magnitude = if whole < 0.0 {
        (-whole) as u64 - 1
    } else {
        whole as u64
    };
    64 - magnitude.leading_zeros() + u32::from(signed)
}

/// A clamp's limit for a format's name: an integer as such, else at most 4 decimals
/// (the exact limits are the row's `limits`).
fn short(v: f64) -> String {
    if v.fract() == 0.0 {
        format!("{v:.0}")
    } else {
        let t = format!("{v:.4}");
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// Accumulates one register.
#[derive(Clone, Debug)]
struct Counter {
    reg: RegisterRange,
    /// The lower limit is the register's rest (an unsigned count at 0), not a saturation.
    rest_at_lower: bool,
    /// An internal register's value is `raw / scale` (`2^frac_bits`).
    scale: f64,
    last: Option<f64>,
}

impl Counter {
    fn new(path: &str, name: &str, bits: u32, signed: bool, overflow: Overflow) -> Counter {
        let limits = if signed {
            (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1)
        } else {
            (0, ((1u128 << bits) - 1) as i64)
        };
        Counter::with_limits(path, name, bits, signed, overflow, limits)
    }

    fn with_limits(
        path: &str,
        name: &str,
        bits: u32,
        signed: bool,
        overflow: Overflow,
        limits: (i64, i64),
    ) -> Counter {
        Counter {
            reg: RegisterRange {
                path: path.into(),
                kind: Kind::Output,
                name: name.into(),
                format: format!("{}{bits}", if signed { "s" } else { "u" }),
                bits,
                signed,
                overflow,
                limits: (limits.0 as f64, limits.1 as f64),
                min: f64::INFINITY,
                max: f64::NEG_INFINITY,
                saturations: 0,
                wraps: 0,
                headroom_bits: 0,
                samples: 0,
            },
            // A limit of 0 for an unsigned register is its rest, not a saturation.
            rest_at_lower: limits.0 == 0,
            scale: 1.0,
            last: None,
        }
    }

    /// A counter for an internal register of `path` as the model's snapshot gives it:
    /// its integer bits are the word's less the fraction's, its limits the clamp's or the
    /// word's; an unsigned word without a clamp rests at 0.
    fn internal(path: &str, r: &Register) -> Counter {
        let f = r.format;
        let frac = u32::from(f.frac_bits);
        let bits = u32::from(f.word_bits).saturating_sub(frac);
        let scale = 2f64.powi(frac as i32);
        let (lo, hi) = f.limits();
        let limits = (lo as f64 / scale, hi as f64 / scale);
        let base = match (frac, f.signed) {
            (0, true) => format!("s{bits}"),
            (0, false) => format!("u{bits}"),
            (_, true) => format!("I{bits}F{frac}"),
            (_, false) => format!("U{bits}F{frac}"),
        };
        let format = match f.clamp {
            Some(_) => format!("{base} clamp {}..{}", short(limits.0), short(limits.1)),
            None => base,
        };
        Counter {
            reg: RegisterRange {
                path: path.into(),
                kind: Kind::Internal,
                name: r.name.into(),
                format,
                bits,
                signed: f.signed,
                overflow: match f.overflow {
                    internals::Overflow::Saturates => Overflow::Saturates,
                    internals::Overflow::Wraps => Overflow::Wraps,
                },
                limits,
                min: f64::INFINITY,
                max: f64::NEG_INFINITY,
                saturations: 0,
                wraps: 0,
                headroom_bits: 0,
                samples: 0,
            },
            rest_at_lower: !f.signed && f.clamp.is_none(),
            scale,
            last: None,
        }
    }

    fn at_limit(&self, v: f64) -> bool {
        let (lo, hi) = self.reg.limits;
        v >= hi || (v <= lo && !self.rest_at_lower)
    }

    fn observe(&mut self, v: f64) {
        self.reg.samples += 1;
        self.reg.min = self.reg.min.min(v);
        self.reg.max = self.reg.max.max(v);
        match self.reg.overflow {
            Overflow::Saturates => {
                if self.at_limit(v) {
                    self.reg.saturations += 1;
                }
            }
            Overflow::Wraps => {
                if let Some(last) = self.last {
                    let half = 2f64.powi(self.reg.bits as i32 - 1);
                    if (v - last).abs() > half {
                        self.reg.wraps += 1;
                    }
                }
            }
        }
        self.last = Some(v);
    }

    /// `clocks` samples at which the register holds `v` (a settled stretch: no step, so
    /// no wrap after the first).
    fn observe_held(&mut self, v: f64, clocks: u64) {
        if clocks == 0 {
            return;
        }
        self.observe(v);
        let rest = clocks - 1;
        self.reg.samples += rest;
        if self.reg.overflow == Overflow::Saturates && rest > 0 && self.at_limit(v) {
            self.reg.saturations += rest;
        }
    }

    /// An internal register's snapshot (an empty one is no sample).
    fn observe_raw(&mut self, r: &Register, clocks: u64) {
        debug_assert_eq!(r.name, self.reg.name);
        if let Some(raw) = r.raw {
            self.observe_held(raw as f64 / self.scale, clocks);
        }
    }

    fn merge(&mut self, o: &Counter) {
        let (r, s) = (&mut self.reg, &o.reg);
        r.samples += s.samples;
        r.min = r.min.min(s.min);
        r.max = r.max.max(s.max);
        r.saturations += s.saturations;
        r.wraps += s.wraps;
    }

    fn finish(mut self) -> RegisterRange {
        let r = &mut self.reg;
        if r.samples == 0 {
            r.min = 0.0;
            r.max = 0.0;
        }
        let need = bits_needed(r.min, r.signed).max(bits_needed(r.max, r.signed));
        r.headroom_bits = r.bits as i32 - need as i32;
        self.reg
    }
}

/// Counters for the internal registers of `kernel` (as its snapshot lists them).
fn internal_counters(path: &str, kernel: &dyn Internals) -> Vec<Counter> {
    let mut v = Vec::new();
    kernel.internals(&mut |r| v.push(Counter::internal(path, &r)));
    v
}

/// Counts the snapshot of `kernel`'s internal registers, held for `clocks` samples.
fn observe_internals(kernel: &dyn Internals, counters: &mut [Counter], clocks: u64) {
    let mut it = counters.iter_mut();
    kernel.internals(&mut |r| {
        if let Some(c) = it.next() {
            c.observe_raw(&r, clocks);
        }
    });
}

fn measure_counters(config: &MeasureConfig) -> Vec<Counter> {
    let s = config.settings();
    let scale = u32::from(s.scale_bits);
    let count = u32::from(config.count_bits());
    let m = "measure";
    vec![
        Counter::new(m, "position", scale, true, Overflow::Wraps),
        Counter::new(m, "decision_position", scale, true, Overflow::Wraps),
        Counter::new(m, "first_contact_position", scale, true, Overflow::Wraps),
        Counter::new(m, "count", count, false, Overflow::Saturates),
        Counter::new(m, "last_window_count", count, false, Overflow::Saturates),
        Counter::new(
            m,
            "charge",
            u32::from(s.charge_bits),
            false,
            Overflow::Saturates,
        ),
        Counter::new(m, "scale_errors", 8, false, Overflow::Saturates),
        Counter::new(m, "revolutions", 16, false, Overflow::Saturates),
        Counter::new(m, "pulses", 32, false, Overflow::Wraps),
    ]
}

fn measure_values(o: &tooltouch_model::MeasureOutputs) -> [f64; 9] {
    [
        f64::from(o.position),
        f64::from(o.decision_position),
        f64::from(o.first_contact_position),
        f64::from(o.count),
        f64::from(o.last_window_count),
        f64::from(o.charge),
        f64::from(o.scale_errors),
        f64::from(o.revolutions),
        f64::from(o.pulses),
    ]
}

/// Clocks the front end over one approach (every clock, the settled ones skipped: they
/// change no register) and counts its output registers and then its internal ones.
fn measure_scenario(a: &Approach, config: &MeasureConfig) -> Vec<Counter> {
    let mut counters = measure_counters(config);
    let outputs = counters.len();
    let mut fe = FrontEnd::new(config);
    counters.extend(internal_counters("measure", &fe));
    let observe = |fe: &FrontEnd, counters: &mut Vec<Counter>, clocks: u64| {
        let (out, int) = counters.split_at_mut(outputs);
        let v = measure_values(&fe.outputs());
        // A settled stretch: the registers hold, each clock of it a sample.
        for (c, v) in out.iter_mut().zip(v) {
            c.observe_held(v, clocks);
        }
        observe_internals(fe, int, clocks);
    };
    for seg in &a.stimulus.segments {
        let mut left = u64::from(seg.cycles);
        while left > 0 {
            if fe.is_settled(seg.pins) {
                observe(&fe, &mut counters, left);
                break;
            }
            fe.clock(seg.pins);
            observe(&fe, &mut counters, 1);
            left -= 1;
        }
    }
    counters
}

fn force_counters() -> Vec<Counter> {
    let f = "force";
    let mut v = vec![Counter::new(
        f,
        "override_pct",
        8,
        false,
        Overflow::Saturates,
    )];
    v[0].reg.format = "u8".into();
    for name in [
        "force_estimate",
        "force_measured",
        "wear_power",
        "wear_allowed",
        "coulomb",
    ] {
        let mut c = Counter::new(f, name, 32, true, Overflow::Saturates);
        c.reg.format = "I32F32".into();
        v.push(c);
    }
    let mut c = Counter::new(f, "bad_events", 8, false, Overflow::Saturates);
    c.reg.format = "u8".into();
    v.push(c);
    v
}

/// Runs the force path's control scenario (the model kernel) and counts its output
/// registers after every tick and command; the controller's own clamp of its demand to
/// `0..=255` is the `saturated` output, counted as `controller_demand`'s saturations. The
/// internal registers are counted after every event, samples included (the sampling
/// chain's sums change per sample): the scenario's recorded events replayed through a
/// kernel of the same configuration, whose outputs must be the run's.
fn force_ranges(config: &ForceConfig) -> anyhow::Result<Vec<RegisterRange>> {
    let sc = ControlScenario::new(*config);
    let r = run(&sc, Engine::Model, true);
    let mut counters = force_counters();
    let mut demand = Counter::with_limits(
        "force",
        "controller_demand",
        8,
        false,
        Overflow::Saturates,
        (0, 255),
    );
    demand.reg.format = "u8 (clamped demand)".into();
    let mut kernel = ForceKernel::new(config);
    let mut inside = internal_counters("force", &kernel);
    let mut recorded = r.outputs.iter();
    for &(k, ev) in &r.events {
        kernel.apply(ev);
        observe_internals(&kernel, &mut inside, 1);
        if matches!(ev, ForceEvent::Sample(_)) {
            continue;
        }
        let o = kernel.outputs();
        if recorded.next().map(|(_, o)| o) != Some(&o) {
            anyhow::bail!(
                "the control scenario replayed for the internal registers left its run at \
                 sample {k}"
            );
        }
        let values = [
            f64::from(o.override_pct),
            o.force_estimate.to_num(),
            o.force_measured.to_num(),
            o.wear_power.to_num(),
            o.wear_allowed.to_num(),
            o.coulomb.to_num(),
            f64::from(o.bad_events),
        ];
        for (c, v) in counters.iter_mut().zip(values) {
            c.observe(v);
        }
        demand.reg.samples += 1;
        demand.reg.min = demand.reg.min.min(f64::from(o.override_pct));
        demand.reg.max = demand.reg.max.max(f64::from(o.override_pct));
        if o.saturated {
            demand.reg.saturations += 1;
        }
    }
    counters.push(demand);
    counters.extend(inside);
    Ok(counters.into_iter().map(Counter::finish).collect())
}

/// The ranges of `measure` over the tuning scenarios (seeds `1..=scenarios` of
/// `approach`, with the configuration's pulses per revolution) and of `force` over the
/// control scenario of `tooltouch control`: per path the outputs, then the internal
/// registers.
pub fn ranges(
    measure: &MeasureConfig,
    force: &ForceConfig,
    approach: &ApproachSettings,
    scenarios: u32,
) -> anyhow::Result<Ranges> {
    let config = *measure;
    let approach = &ApproachSettings {
        pulses_per_rev: config.settings().pulses_per_rev,
        ..approach.clone()
    };
    if !(1..=1000).contains(&scenarios) {
        anyhow::bail!("scenarios: {scenarios} is out of range: allowed 1..=1000");
    }
    let per: Vec<Vec<Counter>> = (1..=u64::from(scenarios))
        .into_par_iter()
        .map(|seed| measure_scenario(&scenario::approach(approach, seed), &config))
        .collect();
    let mut total = measure_counters(&config);
    total.extend(internal_counters("measure", &FrontEnd::new(&config)));
    for p in &per {
        for (t, c) in total.iter_mut().zip(p) {
            t.merge(c);
        }
    }
    let mut registers: Vec<RegisterRange> = total.into_iter().map(Counter::finish).collect();
    registers.extend(force_ranges(force)?);
    Ok(Ranges {
        format: FORMAT.into(),
        scenarios,
        registers,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wrapping_register_counts_its_wraps_and_a_saturating_one_its_limits() {
        let mut w = Counter::new("t", "w", 8, true, Overflow::Wraps);
        for v in [120.0, 127.0, -128.0, -120.0, 127.0] {
            w.observe(v);
        }
        let r = w.finish();
        assert_eq!(
            (r.wraps, r.min, r.max, r.headroom_bits),
            (2, -128.0, 127.0, 0)
        );
        let mut s = Counter::new("t", "s", 8, false, Overflow::Saturates);
        for v in [0.0, 3.0, 255.0, 255.0, 7.0] {
            s.observe(v);
        }
        let r = s.finish();
        assert_eq!((r.saturations, r.headroom_bits), (2, 0));
        let mut h = Counter::new("t", "h", 16, false, Overflow::Saturates);
        h.observe(1000.0);
        assert_eq!(h.finish().headroom_bits, 6);
    }

    /// An internal register's format, limits, headroom and saturations, from the model's
    /// snapshot of it.
    #[test]
    fn an_internal_register_is_counted_against_its_word_and_its_clamp() {
        use tooltouch_model::internals::Format;
        use tooltouch_model::units::Fx;
        let fx = |v: &str| i128::from(v.parse::<Fx>().unwrap().to_bits());
        // I32F32 clamped to 0.5..=100: both clamp ends are saturations, headroom is
        // against the word (100 needs 7 bits and a sign: 32 − 8 = 24).
        let f = Format::I32F32.clamped(fx("0.5"), fx("100"));
        let reg = |v: Option<&str>| Register {
            name: "t.gain",
            format: f,
            raw: v.map(fx),
        };
        let mut c = Counter::internal("force", &reg(None));
        for v in [None, Some("0.5"), Some("3.25"), Some("100"), Some("99.75")] {
            c.observe_raw(&reg(v), 1);
        }
        let r = c.finish();
        assert_eq!(r.format, "I32F32 clamp 0.5..100");
        assert_eq!((r.kind, r.bits, r.signed), (Kind::Internal, 32, true));
        assert_eq!(r.limits, (0.5, 100.0));
        assert_eq!((r.min, r.max, r.samples), (0.5, 100.0, 4));
        assert_eq!((r.saturations, r.headroom_bits), (2, 24));
        // An i64 with 8 fractional bits holding 1000.5 (raw 256 128): 56 integer bits,
        // 11 needed with the sign, held for 10 clocks.
        let q8 = Register::new("t.sum", Format::fixed(64, 8), 256_128);
        let mut c = Counter::internal("force", &q8);
        c.observe_raw(&q8, 10);
        let r = c.finish();
        assert_eq!((r.format.as_str(), r.min, r.samples), ("I56F8", 1000.5, 10));
        assert_eq!((r.headroom_bits, r.saturations), (45, 0));
        assert_eq!(r.limits, (-(2f64.powi(55)), 2f64.powi(55)));
        // An unsigned word rests at 0 and saturates at its top.
        let u8 = |v| Register::new("t.count", Format::unsigned(8), v);
        let mut c = Counter::internal("measure", &u8(0));
        for v in [0, 0, 7, 255, 255] {
            c.observe_raw(&u8(v), 1);
        }
        let r = c.finish();
        assert_eq!(
            (r.format.as_str(), r.saturations, r.headroom_bits),
            ("u8", 2, 0)
        );
        // The 128-bit sums: 112 integer bits for 16 fractional ones.
        let sw = Register::new("t.sw", Format::fixed(128, 16), 3 << 16);
        let mut c = Counter::internal("force", &sw);
        c.observe_raw(&sw, 1);
        let r = c.finish();
        assert_eq!(
            (r.format.as_str(), r.max, r.headroom_bits),
            ("I112F16", 3.0, 109)
        );
    }
}
