//! Force designs: each controller of the force path (docs/domain.md §3: PI, adaptive F11,
//! fuzzy PI) with its gains as percent of the Ziegler–Nichols design on the nominal process
//! F10 (`tooltouch_plant::reference::design`). A settings file's `[force]` table names one
//! design ([`crate::firmware_config::ForceDesign`]); a tuning spec's `[force]` table names
//! many ([`ForceSpec`]); both are built into the model's force settings here, alike.

use crate::values::{check_sweep_size, Names, SpecError, Values};
use anyhow::bail;
use serde::{Deserialize, Serialize};
use tooltouch_model::force::config::{ForceSettings, ForceSource};
use tooltouch_model::force::control::ControllerSettings;
use tooltouch_plant::reference::design::{
    adaptive_settings, fuzzy_from_pi, pi_settings, NominalProcess,
};

/// The force sweep's parameters (`[force]` in a spec file).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ForceSpec {
    /// Controllers: `pi`, `adaptive`, `fuzzy`; an empty list (or the text `none`) skips
    /// the force sweep.
    pub controller: Names,
    /// Proportional gain (adaptive: open-loop gain), percent of the design, `1..=1000`.
    pub kp_percent: Values,
    /// Integral gain, percent of the design, `1..=1000` (not used by the adaptive law).
    pub ki_percent: Values,
    /// Force feedback: `estimated`, `measured`.
    pub force_source: Names,
}

impl Default for ForceSpec {
    /// All three controllers, gains at 50/100/200 % of the design, estimated force.
    fn default() -> Self {
        ForceSpec {
            controller: Names::List(vec!["pi".into(), "adaptive".into(), "fuzzy".into()]),
            kp_percent: Values::List(vec![50, 100, 200]),
            ki_percent: Values::List(vec![50, 100, 200]),
            force_source: Names::List(vec!["estimated".into()]),
        }
    }
}

/// One force sweep point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForcePoint {
    /// `pi`, `adaptive` or `fuzzy`.
    pub controller: &'static str,
    /// Proportional gain, percent of the design.
    pub kp_percent: u32,
    /// Integral gain, percent of the design (0 for adaptive).
    pub ki_percent: u32,
    /// Force feedback.
    pub source: ForceSource,
    /// The force-path settings.
    pub settings: ForceSettings,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Pi,
    Adaptive,
    Fuzzy,
}

const CONTROLLERS: [(&str, Kind); 3] = [
    ("pi", Kind::Pi),
    ("adaptive", Kind::Adaptive),
    ("fuzzy", Kind::Fuzzy),
];
const SOURCES: [(&str, ForceSource); 2] = [
    ("estimated", ForceSource::Estimated),
    ("measured", ForceSource::Measured),
];

/// The name of a force source, as specs and settings files spell it.
pub fn source_name(s: ForceSource) -> &'static str {
    match s {
        ForceSource::Estimated => "estimated",
        ForceSource::Measured => "measured",
    }
}

impl ForceSpec {
    /// Every force point, validated (an invalid gain is an error naming `force.*`).
    pub fn points(&self) -> Result<Vec<ForcePoint>, SpecError> {
        let controllers = match &self.controller {
            Names::List(v) if v.is_empty() => return Ok(Vec::new()),
            Names::Text(t) if t.trim() == "none" => return Ok(Vec::new()),
            n => n.expand("force.controller", &CONTROLLERS)?,
        };
        let kps = self.kp_percent.expand("force.kp_percent", 1, 1000)?;
        let kis = self.ki_percent.expand("force.ki_percent", 1, 1000)?;
        let sources = self.force_source.expand("force.force_source", &SOURCES)?;
        let per_source: usize = CONTROLLERS
            .iter()
            .filter(|(_, k)| controllers.contains(k))
            .map(|(_, k)| {
                let kis = if matches!(k, Kind::Adaptive) {
                    1
                } else {
                    kis.len()
                };
                kps.len().saturating_mul(kis)
            })
            .fold(0usize, usize::saturating_add);
        check_sweep_size(
            "force sweep",
            &[
                ("force.force_source", sources.len()),
                (
                    "force.controller × force.kp_percent × force.ki_percent",
                    per_source,
                ),
            ],
        )?;
        let nominal = NominalProcess::default();
        let (kp, ki) = nominal.ziegler_nichols_pi();
        let mut out = Vec::new();
        for &source in &sources {
            for &(name, kind) in CONTROLLERS.iter().filter(|(_, k)| controllers.contains(k)) {
                for &a in &kps {
                    let ki_list: &[u32] = if matches!(kind, Kind::Adaptive) {
                        &[0]
                    } else {
                        &kis
                    };
                    for &b in ki_list {
                        let (kp_s, ki_s) = (kp * f64::from(a) / 100.0, ki * f64::from(b) / 100.0);
                        let controller = match kind {
                            Kind::Pi => ControllerSettings::Pi(pi_settings(kp_s, ki_s)),
                            Kind::Adaptive => ControllerSettings::Adaptive(adaptive_settings(
                                4.0 * f64::from(a) / 100.0,
                                nominal.gain(),
                            )),
                            Kind::Fuzzy => ControllerSettings::Fuzzy(fuzzy_from_pi(
                                kp_s,
                                ki_s,
                                nominal.period,
                                300.0,
                            )),
                        };
                        let settings = ForceSettings {
                            controller,
                            force_source: source,
                            ..Default::default()
                        };
                        settings.validate().map_err(|e| SpecError {
                            parameter: "force.kp_percent / force.ki_percent".into(),
                            message: format!("{name} at {a} % / {b} %: {e}"),
                        })?;
                        out.push(ForcePoint {
                            controller: name,
                            kp_percent: a,
                            ki_percent: b,
                            source,
                            settings,
                        });
                    }
                }
            }
        }
        Ok(out)
    }
}

/// The `[force]` table: a force design as `tooltouch tune` sweeps it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ForceDesign {
    /// `pi`, `adaptive` or `fuzzy`.
    pub controller: String,
    /// Proportional gain (adaptive: open-loop gain), percent of the design.
    pub kp_percent: u32,
    /// Integral gain, percent of the design (not used by the adaptive law).
    pub ki_percent: u32,
    /// `estimated` or `measured`.
    pub force_source: String,
}

impl Default for ForceDesign {
    fn default() -> Self {
        ForceDesign {
            controller: "pi".into(),
            kp_percent: 100,
            ki_percent: 100,
            force_source: "estimated".into(),
        }
    }
}

impl ForceDesign {
    /// Reads a `[force]` table and checks it: the design and its force settings.
    pub fn from_table(table: &toml::Value) -> anyhow::Result<(ForceDesign, ForceSettings)> {
        let design: ForceDesign = table.clone().try_into()?;
        let settings = design.settings()?;
        settings.validate().map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok((design, settings))
    }

    /// The force settings of this design, built as the tune sweep builds its points.
    pub fn settings(&self) -> anyhow::Result<ForceSettings> {
        let spec = ForceSpec {
            controller: Names::List(vec![self.controller.clone()]),
            kp_percent: Values::One(i64::from(self.kp_percent)),
            ki_percent: Values::One(i64::from(self.ki_percent)),
            force_source: Names::List(vec![self.force_source.clone()]),
        };
        let points = spec.points().map_err(|e| {
            anyhow::anyhow!("{}", e.to_string().replace("sweep parameter `force.", "`"))
        })?;
        match points.as_slice() {
            [p] => Ok(p.settings),
            _ => bail!("a [force] table names one controller and one force source"),
        }
    }
}
