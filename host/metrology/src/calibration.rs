//! Calibration on a reference part (docs/accuracy.md "Calibration on a reference part";
//! papers' S1–S3: a second system determines the real position of the size-determining tool
//! point, Δ_P = X_M − X_P,D, and the systematic error is compensated by it).
//!
//! The calibration cycle measures a reference of known diameter `m` times with each method
//! and contact rule, on the machine as set (its spindle errors, its path from the loads, the
//! speed, the feed, the contact electrics); the reference itself is round (no form error)
//! with its own roughness. The offset of a variant is the mean of (decided − known)
//! diameter: what the method adds on that machine at that feed. A later measurement with the
//! same configuration (the model configuration's hash, which names the method and the rule)
//! and feed subtracts it. What stays is the residual: the part of the bias that depends on
//! the workpiece (its form moves the 50 % share level; its largest diameter is what the
//! single pulse reads) and on conditions other than the calibrated ones.
//!
//! Each entry also holds its offset in scale counts, `round(offset_um / (2 · resolution))`
//! (nearest, halves away from zero; one count moves the diameter by twice the scale's
//! resolution), which [`Calibration::firmware_record`] turns into the record the firmware
//! bakes (model::measure::calibration): the firmware subtracts it from the latched position
//! it reports, where a controller applies it. Its corrected diameter
//! ([`firmware_corrected_mm`]) differs from the host's ([`corrected_mm`]) by the rounding
//! only: at most half a count on the radius, the scale's resolution on the diameter.

use crate::budget::Variant;
use crate::simulate::{config_of, simulate, SimulateError};
use serde::{Deserialize, Serialize};
use tooltouch_model::measure::calibration::CalibrationRecord;
use tooltouch_model::measure::config::{ContactRule, DecisionMethod};
use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_plant::lathe::surface::mix;
use tooltouch_plant::lathe::{LatheScenario, SpindlePath};

/// The calibration file's format name.
pub const FORMAT: &str = "tooltouch-calibration/3";

/// The reference part.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReferencePart {
    /// Its known diameter, mm, `0.1..=2000`.
    pub diameter_mm: f64,
    /// Its roughness, µm 1σ, `0..=10` (a ground ring: about 0.05).
    pub roughness_um: f64,
    /// False: a round reference (a ring or a ground cylinder, no form error) mounted on
    /// the spindle. True: a surface cut in this set-up and its diameter measured off the
    /// machine, so it carries the workpiece's form error and roughness (`roughness_um` is
    /// then not used).
    pub as_cut: bool,
}

/// One variant's offset at one feed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CalibrationEntry {
    /// The decision method.
    pub method: DecisionMethod,
    /// The contact rule.
    pub contact_rule: ContactRule,
    /// The model configuration's hash for this method and rule (hex, as `measure_hash` in
    /// `measure`'s summary.json).
    pub measure_hash: String,
    /// The approach feed calibrated at, mm/rev.
    pub feed_mm_per_rev: f64,
    /// The spindle speed calibrated at, rpm.
    pub rpm: f64,
    /// The mean of (decided − known) diameter on the reference, µm.
    pub offset_um: f64,
    /// The scale's resolution, µm per count (on the radius).
    pub scale_resolution_um: f64,
    /// The spindle's supports and loads the calibration was made under (the cutting force
    /// of the pass it serves, the belt load, the unbalance, the play): they set the path
    /// difference, the largest part of the offset (docs/accuracy.md, "The spindle path").
    pub spindle_path: SpindlePath,
    /// The offset in scale counts as the firmware subtracts it from the latched position:
    /// `round(offset_um / (2 · scale_resolution_um))`, halves away from zero.
    pub offset_counts: i32,
    /// Its standard error, µm.
    pub standard_error_um: f64,
    /// The 1σ of one reference measurement, µm.
    pub sigma_um: f64,
    /// Measurements that decided.
    pub decided: usize,
}

/// A calibration file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// [`FORMAT`].
    pub format: String,
    /// The reference part measured.
    pub reference: ReferencePart,
    /// Measurements per variant.
    pub repeats: u32,
    /// One entry per variant.
    pub entries: Vec<CalibrationEntry>,
}

/// A calibration that cannot be made or applied.
#[derive(Debug, thiserror::Error)]
pub enum CalibrationError {
    /// The simulation could not run.
    #[error(transparent)]
    Simulate(#[from] SimulateError),
    /// A reference part's field is out of range.
    #[error("reference part: {field} = {value} is out of range: allowed {range}")]
    Reference {
        /// The field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// The allowed range.
        range: &'static str,
    },
    /// No measurement on the reference decided.
    #[error("{variant}: no measurement of the reference decided")]
    Undecided {
        /// The variant's name.
        variant: String,
    },
    /// The file is not a calibration file of this format.
    #[error("not a {FORMAT} file (format `{0}`)")]
    Format(String),
    /// The file holds no entry for this method and rule.
    #[error(
        "the calibration file holds no entry for method {method:?}, contact rule {rule:?}: \
         calibrate with this configuration (`tooltouch calibrate`)"
    )]
    NoEntry {
        /// The method.
        method: DecisionMethod,
        /// The rule.
        rule: ContactRule,
    },
    /// The file was made with another configuration.
    #[error(
        "the calibration was made with another configuration (measure hash {file}, this run \
         {run}): recalibrate with these settings"
    )]
    OtherConfiguration {
        /// The file's hash.
        file: String,
        /// This run's hash.
        run: String,
    },
    /// The file was made at another feed.
    #[error(
        "the calibration was made at f_r = {file} mm/rev, this run approaches at {run} mm/rev: \
         the offset is mostly the decision lag, proportional to the feed; recalibrate at this feed"
    )]
    OtherFeed {
        /// The file's feed.
        file: f64,
        /// This run's feed.
        run: f64,
    },
    /// The offset in counts does not match the offset in µm, or does not fit a scale
    /// position.
    #[error(
        "the calibration's offset of {offset_um} µm is {counts} scale counts, expected \
         {expected} (a {resolution_um} µm scale): the file is damaged or hand-edited; \
         calibrate again"
    )]
    Counts {
        /// The file's offset, µm.
        offset_um: f64,
        /// The file's offset, counts.
        counts: i32,
        /// The counts the µm figure gives.
        expected: i64,
        /// The scale's resolution, µm.
        resolution_um: f64,
    },
    /// The calibration does not fit the configuration's scale position.
    #[error("{0}")]
    Record(String),
    /// The file was made with another scale resolution.
    #[error(
        "the calibration was made with a {file} µm scale, this run's scale counts {run} µm: \
         its offset_counts are counts of the other scale, and the quantization differs; \
         recalibrate with this scale"
    )]
    OtherResolution {
        /// The file's resolution, µm per count.
        file: f64,
        /// This run's, µm per count.
        run: f64,
    },
    /// The file was made with the spindle in another state of load (another cutting force,
    /// belt load, unbalance, play or none of the loads).
    #[error(
        "the calibration was made with {field} = {file}, this run has {run}: the spindle's \
         path while measuring moves with its loads (its offset from the machining path \
         {file_offset_um:+.2} µm in the file's state, {run_offset_um:+.2} µm in this run's, \
         radius; the budget's path term follows it) and the calibration's offset with it; \
         recalibrate in this state"
    )]
    OtherSpindlePath {
        /// The first field that differs (`spindle_path.cutting_force_n`, …).
        field: &'static str,
        /// Its value in the file (`loads`: 1 or 0).
        file: f64,
        /// Its value in this run.
        run: f64,
        /// The path's offset in the file's state, µm (radius).
        file_offset_um: f64,
        /// The path's offset in this run's state, µm (radius).
        run_offset_um: f64,
    },
    /// The file was made at another spindle speed.
    #[error(
        "the calibration was made at {file} rpm, this run measures at {run} rpm: the speed \
         changes the spindle's path and the time a window takes; recalibrate at this speed"
    )]
    OtherSpeed {
        /// The file's speed, rpm.
        file: f64,
        /// This run's speed, rpm.
        run: f64,
    },
}

/// The hash of `config` as the files write it.
pub fn hash_hex(config: &MeasureConfig) -> String {
    format!("{:016x}", config.hash())
}

/// The machine as set, holding the reference part instead of the workpiece: a round one
/// has no form error and its own roughness; an as-cut one keeps the workpiece's.
pub fn reference_scenario(machine: &LatheScenario, reference: &ReferencePart) -> LatheScenario {
    LatheScenario {
        diameter_mm: reference.diameter_mm,
        profile: if reference.as_cut {
            machine.profile.clone()
        } else {
            Vec::new()
        },
        random_um: if reference.as_cut {
            machine.random_um
        } else {
            reference.roughness_um
        },
        ..machine.clone()
    }
}

/// The variants a calibration covers: every method and rule but the density detector,
/// whose decision the budget does not model either (it can be calibrated the same way; it
/// is left out to keep the cycle short).
pub fn calibrated_variants() -> impl Iterator<Item = Variant> {
    Variant::ALL
        .into_iter()
        .filter(|v| v.method != DecisionMethod::Density)
}

/// Measures `reference` on the machine `machine` `repeats` times per variant and returns
/// the calibration.
pub fn calibrate(
    measure: &MeasureSettings,
    machine: &LatheScenario,
    reference: &ReferencePart,
    repeats: u32,
) -> Result<Calibration, CalibrationError> {
    if !(0.1..=2000.0).contains(&reference.diameter_mm) {
        return Err(CalibrationError::Reference {
            field: "diameter_mm",
            value: reference.diameter_mm,
            range: "0.1..=2000",
        });
    }
    if !(0.0..=10.0).contains(&reference.roughness_um) {
        return Err(CalibrationError::Reference {
            field: "roughness_um",
            value: reference.roughness_um,
            range: "0..=10",
        });
    }
    let scenario = reference_scenario(machine, reference);
    let mut entries = Vec::new();
    for variant in calibrated_variants() {
        let config = config_of(measure, variant).map_err(SimulateError::Measure)?;
        // Other Z positions than the workpiece's runs (the reference is another surface).
        let seed = mix(scenario.seed, 0xca1b_0001, 0);
        let sim = simulate(measure, &scenario, variant, repeats, seed)?;
        if sim.decided == 0 {
            return Err(CalibrationError::Undecided {
                variant: variant.name(),
            });
        }
        // The known diameter is the reference's mean diameter; its roughness is drawn per Z,
        // so the error against each Z's true mean is the offset's estimate.
        entries.push(CalibrationEntry {
            method: variant.method,
            contact_rule: variant.rule,
            measure_hash: hash_hex(&config),
            feed_mm_per_rev: machine.feed_mm_per_rev,
            rpm: machine.rpm,
            offset_um: sim.bias_vs_mean_um,
            scale_resolution_um: machine.scale_resolution_um,
            spindle_path: machine.spindle_path.clone(),
            offset_counts: offset_counts(sim.bias_vs_mean_um, machine.scale_resolution_um).ok_or(
                CalibrationError::Counts {
                    offset_um: sim.bias_vs_mean_um,
                    counts: 0,
                    expected: 0,
                    resolution_um: machine.scale_resolution_um,
                },
            )?,
            standard_error_um: sim.bias_standard_error_um,
            sigma_um: sim.sigma_um,
            decided: sim.decided,
        });
    }
    Ok(Calibration {
        format: FORMAT.into(),
        reference: *reference,
        repeats,
        entries,
    })
}

impl Calibration {
    /// The entry for a run with `config` on the machine `scenario`: refused as
    /// [`Self::entry_for`] refuses (its feed and speed), and when the file was made with
    /// another scale resolution or with the spindle in another state of load.
    pub fn entry_for_machine(
        &self,
        config: &MeasureConfig,
        scenario: &LatheScenario,
    ) -> Result<&CalibrationEntry, CalibrationError> {
        let entry = self.entry_for(config, scenario.feed_mm_per_rev, scenario.rpm)?;
        let run = scenario.scale_resolution_um;
        if (entry.scale_resolution_um - run).abs() > 1e-9 * run.abs() {
            return Err(CalibrationError::OtherResolution {
                file: entry.scale_resolution_um,
                run,
            });
        }
        let fields = |p: &SpindlePath| {
            [
                ("spindle_path.loads", if p.loads { 1.0 } else { 0.0 }),
                ("spindle_path.cutting_force_n", p.cutting_force_n),
                ("spindle_path.belt_load_n", p.belt_load_n),
                ("spindle_path.unbalance_g_mm", p.unbalance_g_mm),
                ("spindle_path.unbalance_phase_rad", p.unbalance_phase_rad),
                ("spindle_path.machining_rpm", p.machining_rpm),
                ("spindle_path.clearance_um", p.clearance_um),
                ("spindle_path.span_mm", p.span_mm),
                ("spindle_path.overhang_mm", p.overhang_mm),
                (
                    "spindle_path.front_stiffness_n_per_um",
                    p.front_stiffness_n_per_um,
                ),
                (
                    "spindle_path.rear_stiffness_n_per_um",
                    p.rear_stiffness_n_per_um,
                ),
            ]
        };
        let differs = fields(&entry.spindle_path)
            .into_iter()
            .zip(fields(&scenario.spindle_path))
            .find(|((_, a), (_, b))| (a - b).abs() > 1e-9 * a.abs().max(b.abs()));
        if let Some(((field, file), (_, run))) = differs {
            return Err(CalibrationError::OtherSpindlePath {
                field,
                file,
                run,
                file_offset_um: entry.spindle_path.difference(scenario.rpm).offset_um,
                run_offset_um: scenario.spindle_path.difference(scenario.rpm).offset_um,
            });
        }
        Ok(entry)
    }

    /// The entry for a run with `config` approaching at `feed_mm_per_rev` with the spindle
    /// at `rpm`: refused when the file is of another format, holds no entry for the method
    /// and rule, was made with another configuration, at another feed or at another speed
    /// (relative difference over 1e-9).
    pub fn entry_for(
        &self,
        config: &MeasureConfig,
        feed_mm_per_rev: f64,
        rpm: f64,
    ) -> Result<&CalibrationEntry, CalibrationError> {
        if self.format != FORMAT {
            return Err(CalibrationError::Format(self.format.clone()));
        }
        let (method, rule) = (config.settings().method, config.settings().contact_rule);
        let entry = self
            .entries
            .iter()
            .find(|e| e.method == method && e.contact_rule == rule)
            .ok_or(CalibrationError::NoEntry { method, rule })?;
        let run = hash_hex(config);
        if entry.measure_hash != run {
            return Err(CalibrationError::OtherConfiguration {
                file: entry.measure_hash.clone(),
                run,
            });
        }
        if (entry.feed_mm_per_rev - feed_mm_per_rev).abs() > 1e-9 * feed_mm_per_rev.abs() {
            return Err(CalibrationError::OtherFeed {
                file: entry.feed_mm_per_rev,
                run: feed_mm_per_rev,
            });
        }
        if (entry.rpm - rpm).abs() > 1e-9 * rpm.abs() {
            return Err(CalibrationError::OtherSpeed {
                file: entry.rpm,
                run: rpm,
            });
        }
        let expected = (entry.offset_um / (2.0 * entry.scale_resolution_um)).round();
        if !expected.is_finite() || expected != f64::from(entry.offset_counts) {
            return Err(CalibrationError::Counts {
                offset_um: entry.offset_um,
                counts: entry.offset_counts,
                expected: expected as i64,
                resolution_um: entry.scale_resolution_um,
            });
        }
        Ok(entry)
    }

    /// The record a firmware image in `config` bakes (model::measure::calibration): the
    /// entry [`Self::entry_for`] finds for a run approaching at `feed_mm_per_rev` with the
    /// spindle at `rpm` (refused as it refuses), its offset in counts, feed and speed;
    /// refused when the offset does not fit the configuration's scale position.
    pub fn firmware_record(
        &self,
        config: &MeasureConfig,
        feed_mm_per_rev: f64,
        rpm: f64,
    ) -> Result<CalibrationRecord, CalibrationError> {
        let entry = self.entry_for(config, feed_mm_per_rev, rpm)?;
        let record = CalibrationRecord {
            measure_hash: config.hash(),
            offset_counts: entry.offset_counts,
            feed_nm_per_rev: (entry.feed_mm_per_rev * 1e6)
                .round()
                .clamp(0.0, u32::MAX.into()) as u32,
            speed_milli_rpm: (entry.rpm * 1e3).round().clamp(0.0, u32::MAX.into()) as u32,
        };
        record
            .check_for(config)
            .map_err(|e| CalibrationError::Record(e.to_string()))?;
        Ok(record)
    }
}

/// A diameter with the calibration's offset removed, mm.
pub fn corrected_mm(diameter_mm: f64, entry: &CalibrationEntry) -> f64 {
    diameter_mm - entry.offset_um / 1000.0
}

/// The diameter the firmware's corrected position gives, mm: `diameter_mm` with the
/// offset in counts removed (2 · resolution per count). Within the scale's resolution of
/// [`corrected_mm`].
pub fn firmware_corrected_mm(diameter_mm: f64, entry: &CalibrationEntry) -> f64 {
    diameter_mm - 2.0 * f64::from(entry.offset_counts) * entry.scale_resolution_um / 1000.0
}

/// `offset_um` (on the diameter) in scale counts of `resolution_um`: to the nearest count,
/// halves away from zero; `None` when it is not finite or does not fit an i32.
pub fn offset_counts(offset_um: f64, resolution_um: f64) -> Option<i32> {
    let counts = (offset_um / (2.0 * resolution_um)).round();
    (counts.is_finite() && counts.abs() < f64::from(i32::MAX)).then_some(counts as i32)
}

/// The residual bias of one variant on the workpiece after the calibration.
#[derive(Clone, Debug, Serialize)]
pub struct Residual {
    /// The variant's name.
    pub variant: String,
    /// The condition, in words (`calibrated`, `f_r 0.0005 mm/rev`, `600 rpm`).
    pub condition: String,
    /// The raw bias against the true mean diameter, µm.
    pub raw_bias_um: f64,
    /// The raw bias against the true largest diameter, µm (what the single pulse reads).
    pub raw_bias_vs_largest_um: f64,
    /// The offset applied, µm.
    pub offset_um: f64,
    /// What stays: raw bias − offset, µm.
    pub residual_um: f64,
    /// The residual's standard error (the two simulations'), µm.
    pub standard_error_um: f64,
}

/// The residual bias on the workpiece `machine` of each variant with `calibration`'s offset
/// applied, at the calibrated conditions and with the feed and speed changed to each of
/// `feeds` and `speeds` (the offset kept: the file is made once).
pub fn residuals(
    measure: &MeasureSettings,
    machine: &LatheScenario,
    calibration: &Calibration,
    repeats: u32,
    feeds: &[f64],
    speeds: &[f64],
) -> Result<Vec<Residual>, CalibrationError> {
    let mut conditions = vec![("calibrated".to_string(), machine.clone())];
    for &f in feeds {
        conditions.push((
            format!("f_r {f} mm/rev"),
            LatheScenario {
                feed_mm_per_rev: f,
                ..machine.clone()
            },
        ));
    }
    for &n in speeds {
        conditions.push((
            format!("{n} rpm"),
            LatheScenario {
                rpm: n,
                ..machine.clone()
            },
        ));
    }
    let mut out = Vec::new();
    for variant in calibrated_variants() {
        let config = config_of(measure, variant).map_err(SimulateError::Measure)?;
        let entry = calibration.entry_for(&config, machine.feed_mm_per_rev, machine.rpm)?;
        for (condition, scenario) in &conditions {
            let sim = simulate(measure, scenario, variant, repeats, scenario.seed)?;
            out.push(Residual {
                variant: variant.name(),
                condition: condition.clone(),
                raw_bias_um: sim.bias_vs_mean_um,
                raw_bias_vs_largest_um: sim.bias_vs_largest_um,
                offset_um: entry.offset_um,
                residual_um: sim.bias_vs_mean_um - entry.offset_um,
                standard_error_um: sim.bias_standard_error_um.hypot(entry.standard_error_um),
            });
        }
    }
    Ok(out)
}
