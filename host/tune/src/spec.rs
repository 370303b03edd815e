//! The sweep specification: which values of each parameter to try, from a TOML file and/or
//! command-line flags, expanded into the list of sweep points.
//!
//! A parameter's values are written as a TOML array (`charge_bits = [8, 12, 16]`) or as
//! text, in a file or a flag: `"8,12,16"`, a single value `"16"`, or an inclusive range
//! with an optional step `"8..=16"`, `"8..=16:4"`. Every bad value is an error naming the
//! parameter: an empty list or range, a zero step, text that is not a number, a name that
//! is not a method/law/rule, and any point the model's configuration rejects.

use super::reference::{AnalogLaw, Intent};
use super::scenario::ApproachSettings;
use serde::{Deserialize, Serialize};
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod, MeasureSettings};
use tooltouch_model::MeasureChecks;
use tooltouch_settings::force_design::ForceSpec;
use tooltouch_settings::values::{check_sweep_size, err, Names, SpecError, Values};

/// One sweep point: the configuration under test and the device it is meant to be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// The fixed-point configuration (validated).
    pub settings: MeasureSettings,
    /// The intended rates and thresholds, for the float reference.
    pub intent: Intent,
}

/// Which charge law a point uses (its steps come from the `*_pulses` / `*_shift` lists).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Law {
    /// Linear steps.
    Linear,
    /// Exponential shifts.
    Exponential,
}

const METHODS: [(&str, DecisionMethod); 3] = [
    ("counter", DecisionMethod::Counter),
    ("density", DecisionMethod::Density),
    ("single-pulse", DecisionMethod::SinglePulse),
];
const RULES: [(&str, ContactRule); 2] = [
    ("sticky", ContactRule::Sticky),
    ("sampled", ContactRule::Sampled),
];
const LAWS: [(&str, Law); 2] = [("linear", Law::Linear), ("exponential", Law::Exponential)];

/// Name of a method as written in specs and results.
pub fn method_name(m: DecisionMethod) -> &'static str {
    METHODS
        .iter()
        .find(|(_, v)| *v == m)
        .map_or("?", |(n, _)| n)
}
/// Name of a contact rule as written in specs and results.
pub fn rule_name(r: ContactRule) -> &'static str {
    RULES.iter().find(|(_, v)| *v == r).map_or("?", |(n, _)| n)
}

/// The measurement front end's sweep: every combination of the listed values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SweepSpec {
    /// Scenarios (seeds `1..=scenarios`) every point is run on, `1..=1000`.
    pub scenarios: u32,
    /// The approach every scenario simulates.
    pub approach: ApproachSettings,
    /// Decision methods: `counter`, `density`, `single-pulse`.
    pub method: Names,
    /// Contact rules: `sticky`, `sampled`.
    pub contact_rule: Names,
    /// Capacitor width, bits (`4..=24`).
    pub charge_bits: Values,
    /// Scale position width, bits (`8..=32`).
    pub scale_bits: Values,
    /// Glitch filter length, clocks (`0..=255`).
    pub glitch_cycles: Values,
    /// Counter threshold, contact pulses per window.
    pub i_def: Values,
    /// Counting window, revolutions (`1..=16`).
    pub window_revs: Values,
    /// Charge laws: `linear`, `exponential`.
    pub law: Names,
    /// Linear law: pulses of contact from empty to full (`charge_step = full / this`).
    pub charge_pulses: Values,
    /// Linear law: pulses without contact from full to empty.
    pub discharge_pulses: Values,
    /// Exponential law: charge shifts.
    pub charge_shift: Values,
    /// Exponential law: discharge shifts.
    pub discharge_shift: Values,
    /// Fire threshold, percent of full scale (`1..=100`).
    pub fire_percent: Values,
    /// Re-arm threshold, percent of full scale (`0..=99`, below the fire threshold).
    pub rearm_percent: Values,
    /// The force-control gain sweep (`[force]`; `controller = []` skips it).
    pub force: ForceSpec,
}

impl Default for SweepSpec {
    /// The default sweep (324 points × 8 scenarios of 12 revolutions): the three decision
    /// methods, both contact rules, capacitor widths 6/10/16, the linear law (charge over 32
    /// pulses, discharge over 64) and the exponential one (charge shift 4, discharge shift
    /// 4 or 6), glitch filters 0/2/4 (the scenarios' spikes last up to 3 clocks), scale
    /// 16/24 bits; counter at 50 % of one revolution, fire at 75 %, re-arm at 25 %.
    fn default() -> Self {
        SweepSpec {
            scenarios: 8,
            approach: ApproachSettings::default(),
            method: Names::List(vec![
                "counter".into(),
                "density".into(),
                "single-pulse".into(),
            ]),
            contact_rule: Names::List(vec!["sticky".into(), "sampled".into()]),
            charge_bits: Values::List(vec![6, 10, 16]),
            scale_bits: Values::List(vec![16, 24]),
            glitch_cycles: Values::List(vec![0, 2, 4]),
            i_def: Values::One(512),
            window_revs: Values::One(1),
            law: Names::List(vec!["linear".into(), "exponential".into()]),
            charge_pulses: Values::One(32),
            discharge_pulses: Values::One(64),
            charge_shift: Values::One(4),
            discharge_shift: Values::List(vec![4, 6]),
            fire_percent: Values::One(75),
            rearm_percent: Values::One(25),
            force: ForceSpec::default(),
        }
    }
}

/// Flag overrides of a spec's parameters (`None`: keep the spec's).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Overrides {
    /// `--scenarios`.
    pub scenarios: Option<u32>,
    /// `--revolutions`.
    pub revolutions: Option<u32>,
    /// `(parameter, text)` pairs, e.g. `("charge_bits", "8..=16:4")`.
    pub values: Vec<(String, String)>,
}

impl SweepSpec {
    /// Parses a TOML spec (missing parameters keep their defaults).
    pub fn from_toml(text: &str) -> Result<SweepSpec, SpecError> {
        toml::from_str(text).map_err(|e| {
            let msg = e.message().to_string();
            let param = msg
                .split('`')
                .nth(1)
                .filter(|_| msg.contains("unknown field"))
                .unwrap_or("(file)");
            err(param, msg.trim().to_string())
        })
    }

    /// Applies flag overrides.
    pub fn apply(&mut self, o: &Overrides) -> Result<(), SpecError> {
        if let Some(n) = o.scenarios {
            self.scenarios = n;
        }
        if let Some(n) = o.revolutions {
            self.approach.revolutions = n;
        }
        for (p, t) in &o.values {
            match p.as_str() {
                "method" => self.method = Names::Text(t.clone()),
                "contact_rule" => self.contact_rule = Names::Text(t.clone()),
                "law" => self.law = Names::Text(t.clone()),
                "charge_bits" => self.charge_bits = Values::text(t),
                "scale_bits" => self.scale_bits = Values::text(t),
                "glitch_cycles" => self.glitch_cycles = Values::text(t),
                "i_def" => self.i_def = Values::text(t),
                "window_revs" => self.window_revs = Values::text(t),
                "charge_pulses" => self.charge_pulses = Values::text(t),
                "discharge_pulses" => self.discharge_pulses = Values::text(t),
                "charge_shift" => self.charge_shift = Values::text(t),
                "discharge_shift" => self.discharge_shift = Values::text(t),
                "fire_percent" => self.fire_percent = Values::text(t),
                "rearm_percent" => self.rearm_percent = Values::text(t),
                "force.controller" => self.force.controller = Names::Text(t.clone()),
                "force.kp_percent" => self.force.kp_percent = Values::text(t),
                "force.ki_percent" => self.force.ki_percent = Values::text(t),
                "force.force_source" => self.force.force_source = Names::Text(t.clone()),
                other => return Err(err(other, "no such sweep parameter")),
            }
        }
        Ok(())
    }

    /// Every point of the sweep, in a fixed order (the point's index is its position),
    /// each validated by the model's configuration.
    pub fn points(&self) -> Result<Vec<Point>, SpecError> {
        if !(1..=1000).contains(&self.scenarios) {
            return Err(err(
                "scenarios",
                format!("{} is out of range: allowed 1..=1000", self.scenarios),
            ));
        }
        let a = &self.approach;
        if !(1..=10_000).contains(&a.revolutions) {
            return Err(err(
                "approach.revolutions",
                format!("{} is out of range: allowed 1..=10000", a.revolutions),
            ));
        }
        let Axes {
            methods,
            rules,
            laws,
            charge_bits,
            scale_bits,
            glitch,
            i_def,
            window,
            cp,
            dp,
            cs,
            ds,
            fire,
            rearm,
        } = self.axes()?;
        let linear = laws.iter().filter(|l| **l == Law::Linear).count();
        let exponential = laws.len() - linear;
        let factors: [(&str, usize); 10] = [
            ("method", methods.len()),
            ("contact_rule", rules.len()),
            ("charge_bits", charge_bits.len()),
            (
                "law × steps",
                (linear.saturating_mul(cp.len()).saturating_mul(dp.len())).saturating_add(
                    exponential
                        .saturating_mul(cs.len())
                        .saturating_mul(ds.len()),
                ),
            ),
            ("fire_percent", fire.len()),
            ("rearm_percent", rearm.len()),
            ("glitch_cycles", glitch.len()),
            ("scale_bits", scale_bits.len()),
            ("window_revs", window.len()),
            ("i_def", i_def.len()),
        ];
        check_sweep_size("measurement sweep", &factors)?;
        let mut out = Vec::new();
        for &method in &methods {
            for &rule in &rules {
                for &cb in &charge_bits {
                    let full = (1u32 << cb) - 1;
                    let mut law_list = Vec::new();
                    for &law in &laws {
                        match law {
                            Law::Linear => {
                                for &c in &cp {
                                    for &d in &dp {
                                        law_list.push((
                                            ChargeLaw::Linear {
                                                charge_step: (full / c).max(1),
                                                discharge_step: (full / d).max(1),
                                            },
                                            AnalogLaw::Linear {
                                                charge_per_pulse: 1.0 / f64::from(c),
                                                discharge_per_pulse: 1.0 / f64::from(d),
                                            },
                                        ));
                                    }
                                }
                            }
                            Law::Exponential => {
                                for &c in &cs {
                                    for &d in &ds {
                                        let (c, d) = (c as u8, d as u8);
                                        law_list.push((
                                            ChargeLaw::Exponential {
                                                charge_shift: c,
                                                discharge_shift: d,
                                            },
                                            AnalogLaw::Exponential {
                                                charge_shift: c,
                                                discharge_shift: d,
                                            },
                                        ));
                                    }
                                }
                            }
                        }
                    }
                    for (law, analog) in law_list {
                        for &fp in &fire {
                            for &rp in &rearm {
                                for &g in &glitch {
                                    for &sb in &scale_bits {
                                        for &w in &window {
                                            for &i in &i_def {
                                                let s = MeasureSettings {
                                                    pulses_per_rev: a.pulses_per_rev,
                                                    i_def: i,
                                                    window_revs: w as u8,
                                                    contact_rule: rule,
                                                    charge_bits: cb as u8,
                                                    charge_law: law,
                                                    fire_threshold: (u64::from(full)
                                                        * u64::from(fp)
                                                        / 100)
                                                        .max(1)
                                                        as u32,
                                                    rearm_threshold: (u64::from(full)
                                                        * u64::from(rp)
                                                        / 100)
                                                        as u32,
                                                    glitch_cycles: g as u8,
                                                    scale_bits: sb as u8,
                                                    method,
                                                    // The checks change no decision
                                                    // (they add the status outputs).
                                                    checks: MeasureChecks::default(),
                                                };
                                                s.validate().map_err(|e| {
                                                    let param = match e.field {
                                                        "fire_threshold" => "fire_percent",
                                                        "rearm_threshold" => "rearm_percent",
                                                        "charge_step" => "charge_pulses",
                                                        "discharge_step" => "discharge_pulses",
                                                        f => f,
                                                    };
                                                    err(param, e.to_string())
                                                })?;
                                                let window =
                                                    f64::from(a.pulses_per_rev) * f64::from(w);
                                                out.push(Point {
                                                    settings: s,
                                                    intent: Intent {
                                                        method,
                                                        window_revs: w as u8,
                                                        count_fraction: f64::from(i) / window,
                                                        law: analog,
                                                        fire_fraction: f64::from(fp) / 100.0,
                                                    },
                                                });
                                            }
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        Ok(out)
    }
}

/// Every parameter's values, expanded and range-checked (in the spec's order; not combined).
#[derive(Clone, Debug, PartialEq)]
pub struct Axes {
    /// Decision methods.
    pub methods: Vec<DecisionMethod>,
    /// Contact rules.
    pub rules: Vec<ContactRule>,
    /// Charge laws.
    pub laws: Vec<Law>,
    /// Capacitor widths, bits.
    pub charge_bits: Vec<u32>,
    /// Scale widths, bits.
    pub scale_bits: Vec<u32>,
    /// Glitch filter lengths, clocks.
    pub glitch: Vec<u32>,
    /// Counter thresholds, pulses.
    pub i_def: Vec<u32>,
    /// Windows, revolutions.
    pub window: Vec<u32>,
    /// Linear law: pulses from empty to full.
    pub cp: Vec<u32>,
    /// Linear law: pulses from full to empty.
    pub dp: Vec<u32>,
    /// Exponential law: charge shifts.
    pub cs: Vec<u32>,
    /// Exponential law: discharge shifts.
    pub ds: Vec<u32>,
    /// Fire thresholds, percent.
    pub fire: Vec<u32>,
    /// Re-arm thresholds, percent.
    pub rearm: Vec<u32>,
}

impl SweepSpec {
    /// Every parameter's values, each checked against its range (an error names the
    /// parameter), without making any point.
    pub fn axes(&self) -> Result<Axes, SpecError> {
        Ok(Axes {
            methods: self.method.expand("method", &METHODS)?,
            rules: self.contact_rule.expand("contact_rule", &RULES)?,
            laws: self.law.expand("law", &LAWS)?,
            charge_bits: self.charge_bits.expand("charge_bits", 4, 24)?,
            scale_bits: self.scale_bits.expand("scale_bits", 8, 32)?,
            glitch: self.glitch_cycles.expand("glitch_cycles", 0, 255)?,
            i_def: self.i_def.expand("i_def", 0, i64::from(u32::MAX))?,
            window: self.window_revs.expand("window_revs", 1, 16)?,
            cp: self.charge_pulses.expand("charge_pulses", 1, 1 << 24)?,
            dp: self
                .discharge_pulses
                .expand("discharge_pulses", 1, 1 << 24)?,
            cs: self.charge_shift.expand("charge_shift", 0, 24)?,
            ds: self.discharge_shift.expand("discharge_shift", 0, 24)?,
            fire: self.fire_percent.expand("fire_percent", 1, 100)?,
            rearm: self.rearm_percent.expand("rearm_percent", 0, 99)?,
        })
    }
}

/// One slice of a sweep: points whose index `% n == k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This slice, `0..n`.
    pub k: u32,
    /// Number of slices, at least 1.
    pub n: u32,
}

impl std::str::FromStr for Shard {
    type Err = SpecError;
    /// Parses `K/N`.
    fn from_str(s: &str) -> Result<Shard, SpecError> {
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| err("shard", format!("`{s}` is not K/N")))?;
        let whole = |what: &str, t: &str| -> Result<u32, SpecError> {
            let t = t.trim();
            t.parse::<u32>().map_err(|e| {
                let why = match e.kind() {
                    std::num::IntErrorKind::PosOverflow => {
                        format!("is out of range: allowed 0..={}", u32::MAX)
                    }
                    _ => "is not a whole number".to_string(),
                };
                err("shard", format!("{what} `{t}` in `--shard {s}` {why}"))
            })
        };
        let (k, n) = (whole("K", k)?, whole("N", n)?);
        if n == 0 {
            return Err(err("shard", "N must be at least 1"));
        }
        if k >= n {
            return Err(err("shard", format!("K = {k} must be below N = {n}")));
        }
        Ok(Shard { k, n })
    }
}

impl Shard {
    /// Whether point `index` belongs to this slice.
    pub fn contains(&self, index: usize) -> bool {
        index % self.n as usize == self.k as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_values_parse_lists_ranges_and_steps() {
        let e = |t: &str| Values::text(t).expand("x", 0, 100);
        assert_eq!(e("8,12,16").unwrap(), vec![8, 12, 16]);
        assert_eq!(e("8..=16:4").unwrap(), vec![8, 12, 16]);
        assert_eq!(e("3..=5").unwrap(), vec![3, 4, 5]);
        assert_eq!(e("7").unwrap(), vec![7]);
        assert_eq!(e("16..=8").unwrap_err().message, "empty range 16..=8");
        assert!(e("8..=16:0").is_err());
        assert!(e("a,b")
            .unwrap_err()
            .message
            .contains("`a` is not an integer"));
        assert!(e("8..16").is_err());
        assert!(e("").is_err());
        assert!(e("200").unwrap_err().message.contains("out of range"));
    }

    #[test]
    fn shard_parses_and_rejects() {
        assert_eq!("1/3".parse::<Shard>().unwrap(), Shard { k: 1, n: 3 });
        assert!("3/3".parse::<Shard>().is_err());
        assert!("0/0".parse::<Shard>().is_err());
        assert!("x".parse::<Shard>().is_err());
    }

    #[test]
    fn a_range_whose_width_overflows_is_refused_by_its_count() {
        let e = Values::text("-5000000000000000000..=5000000000000000000")
            .expand("glitch_cycles", 0, 255)
            .unwrap_err();
        assert!(e.message.contains("10000000000000000001 values"), "{e}");
        let e = Values::text("0..=9223372036854775807:1")
            .expand("i_def", 0, 1023)
            .unwrap_err();
        assert!(e.message.contains("more than the 100000"), "{e}");
    }

    #[test]
    fn a_sweep_over_the_cap_is_refused_before_its_points_are_made() {
        let mut s = SweepSpec::default();
        s.apply(&Overrides {
            values: vec![
                ("i_def".into(), "0..=1023".into()),
                ("glitch_cycles".into(), "0..=255".into()),
            ],
            ..Default::default()
        })
        .unwrap();
        let e = s.points().unwrap_err();
        assert!(
            e.parameter.contains("i_def") && e.message.contains("more than the 1000000"),
            "{e}"
        );
        // The product overflows u128 without a panic.
        let factors = [("a", usize::MAX); 3];
        let e = check_sweep_size("sweep", &factors).unwrap_err();
        assert!(e.message.contains("more than 10^38"), "{e}");
    }

    #[test]
    fn default_sweep_is_valid() {
        let p = SweepSpec::default().points().unwrap();
        assert_eq!(p.len(), 3 * 2 * 3 * 3 * 3 * 2);
    }
}
