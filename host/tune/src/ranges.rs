//! Range instrumentation (`tooltouch ranges`): every fixed-point register of the
//! measurement and force paths that the kernels expose, observed over the tuning scenarios
//! — its smallest and largest value, how often it saturated (reached a limit of its format
//! or of its clamp) and wrapped (a step of more than half its range), and its headroom in
//! bits against its format.
//!
//! The counting lives here, outside the kernels: a runner clocks the model
//! ([`FrontEnd::clock`], [`ForceKernel`] through the control scenario) and reads the public
//! outputs after every clock or event, so the kernels' code, the firmware and the model's
//! bit-for-bit tests are untouched.

use crate::scenario::{self, Approach, ApproachSettings};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::{FrontEnd, MeasureConfig};
use tooltouch_plant::drive::scenario::{run, ControlScenario, Engine};

/// Format tag of `ranges.json`.
pub const FORMAT: &str = "tooltouch-ranges-1";

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
    /// The register (an output's name).
    pub name: String,
    /// Its format: `u8`, `s16` (two's complement), `I32F32` …
    pub format: String,
    /// Bits of its format (integer bits for a fixed-point value, sign included).
    pub bits: u32,
    /// Signed.
    pub signed: bool,
    /// What it does at its limits.
    pub overflow: Overflow,
    /// The limits it saturates at (the format's, or the clamp's), as integers of the
    /// register (a fixed-point value's integer part).
    pub limits: (i64, i64),
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

/// Accumulates one register.
#[derive(Clone, Debug)]
struct Counter {
    reg: RegisterRange,
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
                name: name.into(),
                format: format!("{}{bits}", if signed { "s" } else { "u" }),
                bits,
                signed,
                overflow,
                limits,
                min: f64::INFINITY,
                max: f64::NEG_INFINITY,
                saturations: 0,
                wraps: 0,
                headroom_bits: 0,
                samples: 0,
            },
            last: None,
        }
    }

    fn observe(&mut self, v: f64) {
        let r = &mut self.reg;
        r.samples += 1;
        r.min = r.min.min(v);
        r.max = r.max.max(v);
        match r.overflow {
            Overflow::Saturates => {
                let (lo, hi) = r.limits;
                // A limit of 0 for an unsigned register is its rest, not a saturation.
                if v >= hi as f64 || (v <= lo as f64 && lo != 0) {
                    r.saturations += 1;
                }
            }
            Overflow::Wraps => {
                if let Some(last) = self.last {
                    let half = 2f64.powi(r.bits as i32 - 1);
                    if (v - last).abs() > half {
                        r.wraps += 1;
                    }
                }
            }
        }
        self.last = Some(v);
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
/// change no register) and counts its registers.
fn measure_scenario(a: &Approach, config: &MeasureConfig) -> Vec<Counter> {
    let mut counters = measure_counters(config);
    let mut fe = FrontEnd::new(config);
    let observe = |fe: &FrontEnd, counters: &mut Vec<Counter>, clocks: u64| {
        let v = measure_values(&fe.outputs());
        for (c, v) in counters.iter_mut().zip(v) {
            // A settled stretch: the registers hold, each clock of it a sample.
            for _ in 0..clocks.min(1) {
                c.observe(v);
            }
            c.reg.samples += clocks.saturating_sub(1);
            if c.reg.overflow == Overflow::Saturates && clocks > 1 {
                let (lo, hi) = c.reg.limits;
                if v >= hi as f64 || (v <= lo as f64 && lo != 0) {
                    c.reg.saturations += clocks - 1;
                }
            }
        }
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

/// Runs the force path's control scenario (the model kernel) and counts its registers
/// after every tick and command; the controller's own clamp of its demand to `0..=255`
/// is the `saturated` output, counted as `controller_demand`'s saturations.
fn force_ranges(config: &ForceConfig) -> Vec<RegisterRange> {
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
    for (_, o) in &r.outputs {
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
    counters.into_iter().map(Counter::finish).collect()
}

/// The ranges of `measure` over the tuning scenarios (seeds `1..=scenarios` of
/// `approach`, with the configuration's pulses per revolution) and of `force` over the
/// control scenario of `tooltouch control`.
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
    for p in &per {
        for (t, c) in total.iter_mut().zip(p) {
            t.merge(c);
        }
    }
    let mut registers: Vec<RegisterRange> = total.into_iter().map(Counter::finish).collect();
    registers.extend(force_ranges(force));
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
}
