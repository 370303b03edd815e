//! Force-control gain sweep: each controller of the force path (docs/domain.md §3: PI, adaptive
//! F11, fuzzy PI) with its gains scaled around the Ziegler–Nichols design on the nominal process
//! F10 ([`crate::reference::design`]), run on the depth-step scenario
//! ([`crate::drive::scenario`]) twice — with the fixed-point model kernel and with the float
//! reference stack — and compared by the integral of absolute force error (IAE, N·s).
//!
//! The fixed-point error of a gain point is `|IAE_model − IAE_reference|`; the IAE itself
//! says how good the gains are. The force path runs in firmware, so it has no FPGA cost.

use super::values::{Names, SpecError, Values};
use crate::drive::scenario::{run, ControlScenario, Engine};
use crate::reference::design::{adaptive_settings, fuzzy_from_pi, pi_settings, NominalProcess};
use serde::{Deserialize, Serialize};
use tooltouch_model::force::config::{ForceSettings, ForceSource};
use tooltouch_model::force::control::ControllerSettings;

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

/// Results of one force point.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ForceRow {
    /// The point's index in the whole sweep (after the measurement points).
    pub index: usize,
    /// Controller.
    pub controller: String,
    /// Force feedback.
    pub force_source: String,
    /// Proportional gain, percent of the design.
    pub kp_percent: u32,
    /// Integral gain, percent of the design.
    pub ki_percent: u32,
    /// IAE of the fixed-point model kernel, N·s.
    pub iae_model: f64,
    /// IAE of the float reference, N·s.
    pub iae_reference: f64,
    /// `|iae_model − iae_reference|`, N·s.
    pub iae_error: f64,
    /// Overshoot after the depth step, model, % of the reference force.
    pub overshoot_pct: f64,
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

fn source_name(s: ForceSource) -> &'static str {
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
        super::spec::check_sweep_size(
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

/// Runs one force point with both engines.
pub fn row(index: usize, p: &ForcePoint) -> ForceRow {
    let (iae_model, iae_reference, overshoot_pct) = match p.settings.validate() {
        Ok(config) => {
            let sc = ControlScenario::new(config);
            let m = run(&sc, Engine::Model, false).metrics;
            let r = run(&sc, Engine::Reference, false).metrics;
            (m.iae, r.iae, m.overshoot_pct)
        }
        Err(_) => (f64::NAN, f64::NAN, f64::NAN),
    };
    ForceRow {
        index,
        controller: p.controller.into(),
        force_source: source_name(p.source).into(),
        kp_percent: p.kp_percent,
        ki_percent: p.ki_percent,
        iae_model,
        iae_reference,
        iae_error: (iae_model - iae_reference).abs(),
        overshoot_pct,
    }
}
