//! The flags of `tooltouch measure`'s settings, declared once: [`SETTING_FLAGS`] holds each
//! flag's name, the settings field it sets, its value's kind, its help, and how it applies.
//! The command line builds its arguments from the table (it parses; this module applies and
//! explains); `budget` and `calibrate` take the same flags.
//!
//! Flags apply after the settings file, in the table's order ([`GivenFlags::settings`]).
//! A settings error is told as the user spelled its culprit ([`GivenFlags::explain`]): the
//! flag and its value, else the settings file, else a default nobody set.

use crate::{old_spelling_warning, read_text_file, Settings, SettingsError};
use std::path::Path;
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_plant::lathe::RetractAt;

/// The kind of value a flag takes.
#[derive(Clone, Copy, Debug)]
pub enum ValueKind {
    /// An unsigned 8-bit integer.
    U8,
    /// An unsigned 16-bit integer.
    U16,
    /// An unsigned 32-bit integer.
    U32,
    /// An unsigned 64-bit integer.
    U64,
    /// A float.
    F64,
    /// A switch: `true`/`false` (also `on`/`off`, `yes`/`no`, `1`/`0`).
    Bool,
    /// One of named values.
    Choice(&'static [Choice]),
}

/// A named value of a [`ValueKind::Choice`] flag.
#[derive(Clone, Copy, Debug)]
pub struct Choice {
    /// Its spelling.
    pub name: &'static str,
    /// What it means (the help's line).
    pub help: &'static str,
    /// Accepted but not listed (an old spelling).
    pub hidden: bool,
}

/// A flag's value as parsed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FlagValue {
    /// An integer of a `U8`…`U64` flag.
    Int(u64),
    /// A float.
    Float(f64),
    /// A switch.
    Bool(bool),
    /// A [`Choice`]'s name.
    Choice(&'static str),
}

impl std::fmt::Display for FlagValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FlagValue::Int(v) => v.fmt(f),
            FlagValue::Float(v) => v.fmt(f),
            FlagValue::Bool(v) => v.fmt(f),
            FlagValue::Choice(v) => v.fmt(f),
        }
    }
}

fn mismatch(v: &FlagValue) -> SettingsError {
    SettingsError::Conflict(format!("internal: a flag's value {v} is not of its kind"))
}

impl FlagValue {
    fn int<T: TryFrom<u64>>(&self) -> Result<T, SettingsError> {
        match *self {
            FlagValue::Int(v) => T::try_from(v).map_err(|_| mismatch(self)),
            _ => Err(mismatch(self)),
        }
    }

    fn float(&self) -> Result<f64, SettingsError> {
        match *self {
            FlagValue::Float(v) => Ok(v),
            _ => Err(mismatch(self)),
        }
    }

    fn bool(&self) -> Result<bool, SettingsError> {
        match *self {
            FlagValue::Bool(v) => Ok(v),
            _ => Err(mismatch(self)),
        }
    }

    fn choice(&self) -> Result<&'static str, SettingsError> {
        match *self {
            FlagValue::Choice(v) => Ok(v),
            _ => Err(mismatch(self)),
        }
    }
}

/// One flag of the settings.
#[derive(Clone, Copy, Debug)]
pub struct SettingFlag {
    /// The long flag without `--` (`i-def`).
    pub flag: &'static str,
    /// The settings field it sets, dotted from the file's root (`measure.i_def`).
    pub key: &'static str,
    /// The help's section (the table the field is in).
    pub heading: &'static str,
    /// The help line.
    pub help: &'static str,
    /// Its value's kind.
    pub kind: ValueKind,
    /// Whether the flag's value is the field's value (not a factor on it), so that the
    /// field's range error is the flag's.
    pub direct: bool,
    /// Applies a parsed value to the settings.
    pub apply: fn(&mut Settings, &FlagValue) -> Result<(), SettingsError>,
}

impl SettingFlag {
    /// The last part of [`SettingFlag::key`] (`cycle.repeats` → `repeats`).
    pub fn leaf(&self) -> &'static str {
        self.key.rsplit('.').next().unwrap_or(self.key)
    }
}

const MEASURE: &str = "Golden model [measure]";
const CHECKS: &str = "Measurement checks [measure.checks] (docs/measure.md)";
const LATHE: &str = "Lathe [lathe]";
const CYCLE: &str = "Measurement cycle [lathe.cycle]";

/// A direct flag setting the integer field `$($field).+` of [`Settings`].
macro_rules! int {
    ($flag:literal, $key:literal, $heading:expr, $kind:ident, $help:literal, $($field:ident).+) => {
        SettingFlag {
            flag: $flag,
            key: $key,
            heading: $heading,
            help: $help,
            kind: ValueKind::$kind,
            direct: true,
            apply: |s, v| {
                s.$($field).+ = v.int()?;
                Ok(())
            },
        }
    };
}

/// A direct flag setting the float field `$($field).+` of [`Settings`].
macro_rules! float {
    ($flag:literal, $key:literal, $heading:expr, $help:literal, $($field:ident).+) => {
        SettingFlag {
            flag: $flag,
            key: $key,
            heading: $heading,
            help: $help,
            kind: ValueKind::F64,
            direct: true,
            apply: |s, v| {
                s.$($field).+ = v.float()?;
                Ok(())
            },
        }
    };
}

/// A direct flag setting the switch field `$($field).+` of [`Settings`].
macro_rules! switch {
    ($flag:literal, $key:literal, $heading:expr, $help:literal, $($field:ident).+) => {
        SettingFlag {
            flag: $flag,
            key: $key,
            heading: $heading,
            help: $help,
            kind: ValueKind::Bool,
            direct: true,
            apply: |s, v| {
                s.$($field).+ = v.bool()?;
                Ok(())
            },
        }
    };
}

const fn choice(name: &'static str, help: &'static str) -> Choice {
    Choice {
        name,
        help,
        hidden: false,
    }
}

/// Every flag of the settings, in help and application order.
pub static SETTING_FLAGS: [SettingFlag; 46] = [
    SettingFlag {
        flag: "method",
        key: "measure.method",
        heading: MEASURE,
        help: "Decision method",
        kind: ValueKind::Choice(&[
            choice(
                "single-pulse",
                "First contact (measures near the largest diameter)",
            ),
            Choice {
                name: "single",
                help:
                    "The old spelling of `single-pulse`: accepted for one release, with a warning",
                hidden: true,
            },
            choice(
                "counter",
                "Pulse counter: count > i_def (50 % → the mean diameter)",
            ),
            choice("density", "Contact-density detector (digital capacitor)"),
        ]),
        direct: true,
        apply: |s, v| {
            s.measure.method = match v.choice()? {
                "single-pulse" => DecisionMethod::SinglePulse,
                "single" => {
                    eprintln!(
                        "{}",
                        old_spelling_warning("--method", "single", "single-pulse")
                    );
                    DecisionMethod::SinglePulse
                }
                "counter" => DecisionMethod::Counter,
                "density" => DecisionMethod::Density,
                _ => return Err(mismatch(v)),
            };
            Ok(())
        },
    },
    int!(
        "i-def",
        "measure.i_def",
        MEASURE,
        U32,
        "Decide when the window's contact-pulse count exceeds this (50 % of 1024 = 512)",
        measure.i_def
    ),
    int!(
        "pulses-per-rev",
        "measure.pulses_per_rev",
        MEASURE,
        U16,
        "FES pulses per revolution (16..=16384)",
        measure.pulses_per_rev
    ),
    int!(
        "window-revs",
        "measure.window_revs",
        MEASURE,
        U8,
        "Revolutions per counting window (1..=16)",
        measure.window_revs
    ),
    SettingFlag {
        flag: "contact-rule",
        key: "measure.contact_rule",
        heading: MEASURE,
        help: "Contact bit rule",
        kind: ValueKind::Choice(&[
            choice("sampled", "Contact level at the FES edge"),
            choice("sticky", "Contact at any time since the previous FES pulse"),
        ]),
        direct: true,
        apply: |s, v| {
            s.measure.contact_rule = match v.choice()? {
                "sampled" => ContactRule::Sampled,
                "sticky" => ContactRule::Sticky,
                _ => return Err(mismatch(v)),
            };
            Ok(())
        },
    },
    int!(
        "charge-bits",
        "measure.charge_bits",
        MEASURE,
        U8,
        "Capacitor charge register width, bits (4..=24)",
        measure.charge_bits
    ),
    SettingFlag {
        flag: "charge-law",
        key: "measure.charge_law",
        heading: MEASURE,
        help: "Capacitor law. The default configuration is linear with steps 64/64; switching \
               the law from the file's takes 2048/1024 (linear) or shifts 5/6 (exponential) \
               unless the steps or shifts are given",
        kind: ValueKind::Choice(&[
            choice("linear", "Linear steps"),
            choice("exponential", "RC-like, by shifts"),
        ]),
        direct: true,
        apply: |s, v| {
            let law = &mut s.measure.charge_law;
            match (v.choice()?, *law) {
                ("linear", ChargeLaw::Exponential { .. }) => {
                    *law = ChargeLaw::Linear {
                        charge_step: 2048,
                        discharge_step: 1024,
                    }
                }
                ("exponential", ChargeLaw::Linear { .. }) => {
                    *law = ChargeLaw::Exponential {
                        charge_shift: 5,
                        discharge_shift: 6,
                    }
                }
                ("linear" | "exponential", _) => {}
                _ => return Err(mismatch(v)),
            }
            Ok(())
        },
    },
    SettingFlag {
        flag: "charge-step",
        key: "measure.charge_law.charge_step",
        heading: MEASURE,
        help: "Linear law: charge per contact pulse, LSBs",
        kind: ValueKind::U32,
        direct: true,
        apply: |s, v| match &mut s.measure.charge_law {
            ChargeLaw::Linear { charge_step, .. } => {
                *charge_step = v.int()?;
                Ok(())
            }
            ChargeLaw::Exponential { .. } => Err(need_linear()),
        },
    },
    SettingFlag {
        flag: "discharge-step",
        key: "measure.charge_law.discharge_step",
        heading: MEASURE,
        help: "Linear law: discharge per pulse without contact, LSBs",
        kind: ValueKind::U32,
        direct: true,
        apply: |s, v| match &mut s.measure.charge_law {
            ChargeLaw::Linear { discharge_step, .. } => {
                *discharge_step = v.int()?;
                Ok(())
            }
            ChargeLaw::Exponential { .. } => Err(need_linear()),
        },
    },
    SettingFlag {
        flag: "charge-shift",
        key: "measure.charge_law.charge_shift",
        heading: MEASURE,
        help: "Exponential law: charging time constant, pulses, as a power of two",
        kind: ValueKind::U8,
        direct: true,
        apply: |s, v| match &mut s.measure.charge_law {
            ChargeLaw::Exponential { charge_shift, .. } => {
                *charge_shift = v.int()?;
                Ok(())
            }
            ChargeLaw::Linear { .. } => Err(need_exponential()),
        },
    },
    SettingFlag {
        flag: "discharge-shift",
        key: "measure.charge_law.discharge_shift",
        heading: MEASURE,
        help: "Exponential law: discharging time constant, pulses, as a power of two",
        kind: ValueKind::U8,
        direct: true,
        apply: |s, v| match &mut s.measure.charge_law {
            ChargeLaw::Exponential {
                discharge_shift, ..
            } => {
                *discharge_shift = v.int()?;
                Ok(())
            }
            ChargeLaw::Linear { .. } => Err(need_exponential()),
        },
    },
    int!(
        "fire-threshold",
        "measure.fire_threshold",
        MEASURE,
        U32,
        "Density detector fire threshold, LSBs",
        measure.fire_threshold
    ),
    int!(
        "rearm-threshold",
        "measure.rearm_threshold",
        MEASURE,
        U32,
        "Density detector re-arm threshold, LSBs (< fire threshold)",
        measure.rearm_threshold
    ),
    int!(
        "glitch-cycles",
        "measure.glitch_cycles",
        MEASURE,
        U8,
        "Glitch filter length, clocks (0..=255)",
        measure.glitch_cycles
    ),
    int!(
        "scale-bits",
        "measure.scale_bits",
        MEASURE,
        U8,
        "Scale position counter width, bits (8..=32)",
        measure.scale_bits
    ),
    switch!(
        "contact-at-arm",
        "measure.checks.contact_at_arm",
        CHECKS,
        "Fault `contact_at_arm` when the contact is closed as the arm rises (true/false)",
        measure.checks.contact_at_arm
    ),
    switch!(
        "revolutions",
        "measure.checks.revolutions",
        CHECKS,
        "Check each revolution's FES pulses against pulses_per_rev ± pulse_tolerance \
         (faults `pulses_lost`, `index_missing`; true/false)",
        measure.checks.revolutions
    ),
    int!(
        "pulse-tolerance",
        "measure.checks.pulse_tolerance",
        CHECKS,
        U16,
        "FES pulses a revolution may differ from pulses_per_rev (0..=pulses_per_rev/4)",
        measure.checks.pulse_tolerance
    ),
    switch!(
        "scale-errors",
        "measure.checks.scale_errors",
        CHECKS,
        "Fault `scale_error` on an illegal scale transition while armed (true/false)",
        measure.checks.scale_errors
    ),
    int!(
        "probe-revs",
        "measure.checks.probe_revs",
        CHECKS,
        U16,
        "Fault `no_decision` after this many revolutions since arm without a decision (0: off)",
        measure.checks.probe_revs
    ),
    int!(
        "fes-timeout-cycles",
        "measure.checks.fes_timeout_cycles",
        CHECKS,
        U32,
        "Fault `fes_timeout` after this many clocks without an FES pulse while armed (0: off)",
        measure.checks.fes_timeout_cycles
    ),
    int!(
        "confirm-windows",
        "measure.checks.confirm_windows",
        CHECKS,
        U8,
        "Counting windows from the deciding one that must confirm the decision (0..=16; 0: \
         confirmed at the decision)",
        measure.checks.confirm_windows
    ),
    int!(
        "confirm-percent",
        "measure.checks.confirm_percent",
        CHECKS,
        U8,
        "Confirmation level, % of a window's pulses (1..=100; single-pulse: one contact pulse)",
        measure.checks.confirm_percent
    ),
    int!(
        "clock-hz",
        "lathe.clock_hz",
        LATHE,
        U32,
        "FPGA clock, Hz (divides 1e9)",
        lathe.clock_hz
    ),
    float!("rpm", "lathe.rpm", LATHE, "Spindle speed, rpm", lathe.rpm),
    float!(
        "diameter-mm",
        "lathe.diameter_mm",
        LATHE,
        "Nominal diameter, mm",
        lathe.diameter_mm
    ),
    float!(
        "feed-mm-per-rev",
        "lathe.feed_mm_per_rev",
        LATHE,
        "Radial approach feed f_r, mm/rev",
        lathe.feed_mm_per_rev
    ),
    float!(
        "scale-resolution-um",
        "lathe.scale_resolution_um",
        LATHE,
        "Linear scale resolution, µm per count",
        lathe.scale_resolution_um
    ),
    SettingFlag {
        flag: "profile-gain",
        key: "lathe.profile",
        heading: LATHE,
        help: "Multiply every profile (form error) amplitude by this",
        kind: ValueKind::F64,
        direct: false,
        apply: |s, v| {
            let amplitudes = s.lathe.profile.iter_mut().map(|h| &mut h.amplitude_um);
            scale_amplitudes("--profile-gain", v.float()?, "profile", amplitudes)
        },
    },
    SettingFlag {
        flag: "slow-gain",
        key: "lathe.slow",
        heading: LATHE,
        help: "Multiply every slow (period > 1 rev) spindle error amplitude by this (0: none)",
        kind: ValueKind::F64,
        direct: false,
        apply: |s, v| {
            let amplitudes = s.lathe.slow.iter_mut().map(|h| &mut h.amplitude_um);
            scale_amplitudes("--slow-gain", v.float()?, "slow", amplitudes)
        },
    },
    float!(
        "random-um",
        "lathe.random_um",
        LATHE,
        "Random radius error (roughness), µm standard deviation",
        lathe.random_um
    ),
    float!(
        "repeating-mismatch",
        "lathe.repeating_mismatch",
        LATHE,
        "Fraction of the per-revolution spindle errors that does not cancel (0..=1)",
        lathe.repeating_mismatch
    ),
    int!(
        "seed",
        "lathe.seed",
        LATHE,
        U64,
        "Seed of every random stream",
        lathe.seed
    ),
    int!(
        "bounce-pulses",
        "lathe.electrics.bounce_pulses",
        LATHE,
        U32,
        "Bounce pulses at first touch",
        lathe.electrics.bounce_pulses
    ),
    float!(
        "non-conduction-us",
        "lathe.electrics.non_conduction_us",
        LATHE,
        "Non-conduction after first touch, µs",
        lathe.electrics.non_conduction_us
    ),
    float!(
        "spike-rate-hz",
        "lathe.electrics.spike_rate_hz",
        LATHE,
        "Noise spikes on the contact line, per second",
        lathe.electrics.spike_rate_hz
    ),
    int!(
        "spike-max-cycles",
        "lathe.electrics.spike_max_cycles",
        LATHE,
        U32,
        "Longest noise spike, clocks (capped at glitch_cycles)",
        lathe.electrics.spike_max_cycles
    ),
    int!(
        "repeats",
        "lathe.cycle.repeats",
        CYCLE,
        U32,
        "Measurements (each at a new Z)",
        lathe.cycle.repeats
    ),
    float!(
        "clearance-um",
        "lathe.cycle.clearance_um",
        CYCLE,
        "Approach start above the nominal radius, µm",
        lathe.cycle.clearance_um
    ),
    float!(
        "retract-mm-per-s",
        "lathe.cycle.retract_mm_per_s",
        CYCLE,
        "Retract speed, mm/s",
        lathe.cycle.retract_mm_per_s
    ),
    float!(
        "z-step-mm",
        "lathe.cycle.z_step_mm",
        CYCLE,
        "Z step between measurements, mm (> nose radius)",
        lathe.cycle.z_step_mm
    ),
    float!(
        "nose-radius-mm",
        "lathe.cycle.nose_radius_mm",
        CYCLE,
        "Tool nose radius, mm",
        lathe.cycle.nose_radius_mm
    ),
    float!(
        "z-dwell-ms",
        "lathe.cycle.z_dwell_ms",
        CYCLE,
        "Z step time, ms",
        lathe.cycle.z_dwell_ms
    ),
    float!(
        "cnc-reaction-us",
        "lathe.cycle.cnc_reaction_us",
        CYCLE,
        "CNC reaction from \"register now\" to feed stop, µs",
        lathe.cycle.cnc_reaction_us
    ),
    SettingFlag {
        flag: "retract-at",
        key: "lathe.cycle.retract_at",
        heading: CYCLE,
        help: "When to retract",
        kind: ValueKind::Choice(&[
            choice("decision", "CNC reaction time after \"register now\""),
            choice(
                "permanent-contact",
                "After a whole revolution of permanent contact (records the full burst pattern)",
            ),
        ]),
        direct: true,
        apply: |s, v| {
            s.lathe.cycle.retract_at = match v.choice()? {
                "decision" => RetractAt::Decision,
                "permanent-contact" => RetractAt::PermanentContact,
                _ => return Err(mismatch(v)),
            };
            Ok(())
        },
    },
    int!(
        "max-approach-revs",
        "lathe.cycle.max_approach_revs",
        CYCLE,
        U32,
        "Give up an approach after this many revolutions",
        lathe.cycle.max_approach_revs
    ),
];

fn need_linear() -> SettingsError {
    SettingsError::Conflict("--charge-step/--discharge-step need --charge-law linear".into())
}

fn need_exponential() -> SettingsError {
    SettingsError::Conflict("--charge-shift/--discharge-shift need --charge-law exponential".into())
}

/// Multiplies each amplitude of the `[lathe] list` by `gain` (the flag `flag`), naming the
/// flag when the gain or a scaled amplitude is out of range (`0..=1000` µm).
fn scale_amplitudes<'a>(
    flag: &str,
    gain: f64,
    list: &str,
    amplitudes: impl Iterator<Item = &'a mut f64>,
) -> Result<(), SettingsError> {
    if !(gain.is_finite() && gain >= 0.0) {
        return Err(SettingsError::Conflict(format!(
            "{flag} {gain} is out of range: allowed 0 or more (a factor on every [lathe] {list} amplitude)"
        )));
    }
    for (i, a) in amplitudes.enumerate() {
        let scaled = *a * gain;
        if scaled > 1000.0 {
            return Err(SettingsError::Conflict(format!(
                "{flag} {gain} makes [lathe] {list}[{i}].amplitude_um {} × {gain} = {scaled} µm, \
                 out of range: allowed 0..=1000 µm",
                *a
            )));
        }
        *a = scaled;
    }
    Ok(())
}

/// The settings flags given on a command line, each with its parsed value.
#[derive(Clone, Debug, Default)]
pub struct GivenFlags {
    given: Vec<(&'static SettingFlag, FlagValue)>,
}

impl GivenFlags {
    /// Records `flag` given with `value` (flags apply in [`SETTING_FLAGS`]' order).
    pub fn push(&mut self, flag: &'static SettingFlag, value: FlagValue) {
        self.given.push((flag, value));
    }

    /// The settings: defaults, then the file `config`, then these flags.
    pub fn settings(&self, config: Option<&Path>) -> Result<Settings, SettingsError> {
        let mut s = match config {
            Some(path) => Settings::load(path)?,
            None => Settings::default(),
        };
        for f in &SETTING_FLAGS {
            for (_, v) in self.given.iter().filter(|(g, _)| std::ptr::eq(*g, f)) {
                (f.apply)(&mut s, v)?;
            }
        }
        Ok(s)
    }

    /// The flag that set the settings field `field` (as a [`ScenarioError`] or
    /// `ConfigError` names it: `rpm`, `cycle.repeats`, `i_def`) and its value as given.
    ///
    /// [`ScenarioError`]: tooltouch_plant::lathe::ScenarioError
    pub fn flag_of(&self, field: &str) -> Option<(String, String)> {
        let leaf = field.rsplit('.').next().unwrap_or(field);
        self.given
            .iter()
            .find(|(f, _)| f.direct && f.leaf() == leaf)
            .map(|(f, v)| (format!("--{}", f.flag), v.to_string()))
    }

    /// The flag of a settings field whether given or not (`cycle.retract_mm_per_s` →
    /// `--retract-mm-per-s`), or its key for a field without a flag.
    fn flag_of_name(field: &str) -> String {
        let leaf = field.rsplit('.').next().unwrap_or(field);
        let flag = leaf.replace('_', "-");
        if SETTING_FLAGS.iter().any(|f| f.flag == flag) {
            format!("--{flag}")
        } else {
            format!("`{field}` in --config")
        }
    }

    /// A settings error told as the user spelled the culprit: the flag and its value when
    /// a flag set the field, else the settings file (when the field is in it), else a
    /// default the user did not set. `config` is the `--config` file.
    pub fn explain(&self, e: SettingsError, config: Option<&Path>) -> anyhow::Error {
        let field = match &e {
            SettingsError::Measure(c) => c.field.to_string(),
            SettingsError::Lathe(l) => l.field.clone(),
            _ => return e.into(),
        };
        if let Some((flag, value)) = self.flag_of(&field) {
            return anyhow::anyhow!("{flag} {value}: {e}");
        }
        match config {
            Some(path) if file_sets(path, &e, &field) => {
                anyhow::anyhow!("settings file {}: {e}", path.display())
            }
            _ => anyhow::anyhow!(
                "{e}; this value is the default (not set by a flag or the settings file) and does not fit the other settings: set {} or change those",
                Self::flag_of_name(&field)
            ),
        }
    }
}

/// Whether the settings file `path` sets the field of `e` (`field`, dotted, with list
/// indices `profile[0].amplitude_um`).
fn file_sets(path: &Path, e: &SettingsError, field: &str) -> bool {
    let Ok(text) = read_text_file(path, "settings file") else {
        return false;
    };
    let Ok(table) = toml::from_str::<toml::Table>(&text) else {
        return false;
    };
    let (root, alt) = match e {
        SettingsError::Measure(_) => ("measure", Some("charge_law")),
        _ => ("lathe", None),
    };
    let lookup = |prefix: Option<&str>| {
        let mut at = table.get(root);
        for part in prefix.into_iter().chain(field.split('.')) {
            let (key, index) = match part.split_once('[') {
                Some((k, i)) => (k, i.trim_end_matches(']').parse::<usize>().ok()),
                None => (part, None),
            };
            at = at.and_then(|t| t.get(key));
            if let Some(i) = index {
                at = at.and_then(|t| t.get(i));
            }
        }
        at.is_some()
    };
    lookup(None) || alt.is_some_and(|a| lookup(Some(a)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_flag_is_its_keys_leaf_or_a_factor_and_each_is_declared_once() {
        let mut names: Vec<&str> = SETTING_FLAGS.iter().map(|f| f.flag).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), SETTING_FLAGS.len());
        for f in &SETTING_FLAGS {
            let leaf_flag = f.leaf().replace('_', "-");
            assert_eq!(f.direct, leaf_flag == f.flag, "{}", f.flag);
            assert!(f.key.starts_with("measure.") || f.key.starts_with("lathe."));
        }
    }

    #[test]
    fn flags_apply_over_the_defaults_and_name_themselves_in_errors() {
        let by = |name: &str| SETTING_FLAGS.iter().find(|f| f.flag == name).unwrap();
        let mut given = GivenFlags::default();
        given.push(by("i-def"), FlagValue::Int(300));
        given.push(by("rpm"), FlagValue::Float(600.0));
        given.push(by("repeats"), FlagValue::Int(3));
        let s = given.settings(None).unwrap();
        assert_eq!(
            (s.measure.i_def, s.lathe.rpm, s.lathe.cycle.repeats),
            (300, 600.0, 3)
        );
        assert_eq!(
            given.flag_of("cycle.repeats"),
            Some(("--repeats".into(), "3".into()))
        );
        assert_eq!(given.flag_of("seed"), None);
        given.push(by("charge-shift"), FlagValue::Int(3));
        let e = given.settings(None).unwrap_err().to_string();
        assert!(e.contains("--charge-law exponential"), "{e}");
        let mut checks = GivenFlags::default();
        checks.push(by("probe-revs"), FlagValue::Int(7));
        checks.push(by("scale-errors"), FlagValue::Bool(false));
        let s = checks.settings(None).unwrap();
        assert_eq!(s.measure.checks.probe_revs, 7);
        assert!(!s.measure.checks.scale_errors && s.measure.checks.revolutions);
        let mut bad = GivenFlags::default();
        bad.push(by("pulse-tolerance"), FlagValue::Int(600));
        let e = bad.settings(None).unwrap().resolve().unwrap_err();
        let e = bad.explain(e, None).to_string();
        assert!(
            e.starts_with("--pulse-tolerance 600: ")
                && e.contains("`measure.checks.pulse_tolerance`"),
            "{e}"
        );
        assert_eq!(
            GivenFlags::flag_of_name("checks.confirm_windows"),
            "--confirm-windows"
        );
        assert_eq!(
            GivenFlags::flag_of_name("cycle.averages_per_z"),
            "`cycle.averages_per_z` in --config"
        );
    }
}
