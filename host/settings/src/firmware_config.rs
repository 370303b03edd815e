//! The configuration a firmware image is built with: the settings file that
//! `tooltouch hdl --config` and `tooltouch vectors --config` read (its `[measure]` table,
//! validated by the model) plus an optional `[force]` table, in the file format that
//! firmware/build.rs bakes into both images (`TOOLTOUCH_FIRMWARE_CONFIG`).
//!
//! The `[force]` table names a force design the way `tooltouch tune` sweeps it, so any
//! swept force point can be written as a settings file (`tooltouch tune point`):
//!
//! ```toml
//! [force]
//! controller = "pi"          # pi | adaptive | fuzzy
//! kp_percent = 100           # proportional gain, % of the Ziegler–Nichols design, 1..=1000
//! ki_percent = 100           # integral gain, % of the design, 1..=1000 (adaptive: unused)
//! force_source = "estimated" # estimated | measured
//! ```
//! Every field is optional (the values shown); without a `[force]` table the force path
//! runs `ForceSettings::default()`, the set-up of `tooltouch control`'s default plant.
//!
//! A `[wear]` table (the one `tooltouch wear --config` reads, [`crate::wear`]) sets the
//! wear monitor: its cuts' condition sets, efficiency and settling hold, by the same rule
//! as the command's updating threshold.
//!
//! A reference-part calibration (`tooltouch calibrate`'s file, the entry for the
//! configuration's method and contact rule, converted to scale counts by
//! `tooltouch_metrology::calibration::firmware_record`) is added with
//! [`FirmwareConfig::with_calibration`] (`tooltouch cosim config --calibration`,
//! `cargo xtask firmware --calibration`): the firmware then reports the corrected decision
//! position (model::measure::calibration).
//!
//! The baked file: `TTFWCFG1`, then the measurement configuration's canonical bytes and
//! the force configuration's (model::wire), each after its length as a little-endian u16,
//! then, with a calibration only, the calibration record's canonical bytes after their
//! length (a file without a calibration is the same as before calibrations existed).

pub use crate::force_design::ForceDesign;
use crate::load::load_settings;
use anyhow::Context;
use std::path::Path;
use tooltouch_model::force::config::{ForceConfig, ForceSettings};
use tooltouch_model::measure::calibration::CalibrationRecord;
use tooltouch_model::MeasureConfig;

/// The environment variable firmware/build.rs reads: the path of a baked configuration
/// file ([`FirmwareConfig::baked_bytes`]).
pub const CONFIG_VAR: &str = "TOOLTOUCH_FIRMWARE_CONFIG";
/// The first bytes of a baked configuration file.
pub const MAGIC: &[u8; 8] = b"TTFWCFG1";

/// The configuration an image is built with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirmwareConfig {
    /// The measurement configuration.
    pub measure: MeasureConfig,
    /// The force configuration.
    pub force: ForceConfig,
    /// The reference-part calibration the firmware applies to the decision it reports
    /// (`None`: offset 0, the raw position). Part of the image's identity, not of the
    /// FPGA's configuration hash.
    pub calibration: Option<CalibrationRecord>,
}

impl Default for FirmwareConfig {
    /// What an image built without a configuration runs.
    fn default() -> Self {
        FirmwareConfig {
            measure: MeasureConfig::default(),
            force: ForceSettings::default()
                .validate()
                .unwrap_or_else(|e| unreachable!("the default force settings are valid: {e}")),
            calibration: None,
        }
    }
}

impl FirmwareConfig {
    /// Reads a settings file (see the module documentation); `None` gives the defaults.
    pub fn load(path: Option<&Path>) -> anyhow::Result<FirmwareConfig> {
        let mut config = FirmwareConfig {
            measure: load_settings(path, None)?.config,
            ..FirmwareConfig::default()
        };
        let Some(path) = path else {
            return Ok(config);
        };
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        let table: toml::Table =
            toml::from_str(&text).with_context(|| format!("{}: not valid TOML", path.display()))?;
        if let Some(force) = table.get("force") {
            let (_, settings) = ForceDesign::from_table(force)
                .with_context(|| format!("{}: [force]", path.display()))?;
            config.force = settings
                .validate()
                .map_err(|e| anyhow::anyhow!("{}: [force] {e}", path.display()))?;
        }
        if let Some(wear) = table.get("wear") {
            let plan = crate::wear::WearPlan::from_table(wear)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
            let mut settings = *config.force.settings();
            settings.wear = plan
                .monitor_settings(&settings)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
            config.force = settings
                .validate()
                .map_err(|e| anyhow::anyhow!("{}: [wear] {e}", path.display()))?;
        }
        Ok(config)
    }

    /// This configuration with `calibration` baked: refused, naming both hashes, when it
    /// was made with another measurement configuration, or when its offset does not fit
    /// the scale position.
    pub fn with_calibration(self, calibration: CalibrationRecord) -> anyhow::Result<Self> {
        calibration
            .check_for(&self.measure)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(FirmwareConfig {
            calibration: Some(calibration),
            ..self
        })
    }

    /// The baked configuration file's bytes (module documentation).
    pub fn baked_bytes(&self) -> Vec<u8> {
        let (m, n) = self.measure.canonical_bytes();
        let (f, k) = self.force.canonical_bytes();
        let c = self.calibration.map(|c| c.canonical_bytes());
        let mut out = MAGIC.to_vec();
        for part in [&m[..n], &f[..k]]
            .into_iter()
            .chain(c.as_ref().map(|c| &c[..]))
        {
            out.extend_from_slice(&(part.len() as u16).to_le_bytes());
            out.extend_from_slice(part);
        }
        out
    }

    /// `measure_hash=… force_hash=…`, as the image reports it, and with a calibration
    /// ` calibration_hash=… offset=… counts`.
    pub fn hashes(&self) -> String {
        let mut s = format!(
            "measure_hash={:016x} force_hash={:016x}",
            self.measure.hash(),
            self.force.hash()
        );
        if let Some(c) = &self.calibration {
            s.push_str(&format!(
                " calibration_hash={:016x} offset={} counts",
                c.hash(),
                c.offset_counts
            ));
        }
        s
    }

    /// A name for an image of this configuration: the measure and force hashes, and the
    /// calibration's when one is baked.
    pub fn image_name(&self) -> String {
        let mut name = format!("{:016x}-{:016x}", self.measure.hash(), self.force.hash());
        if let Some(c) = &self.calibration {
            name.push_str(&format!("-{:016x}", c.hash()));
        }
        name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_force_table_is_a_tune_design_and_the_measure_table_is_hdls() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        std::fs::write(
            &path,
            "[measure]\ni_def = 300\n[force]\ncontroller = \"fuzzy\"\nkp_percent = 50\n",
        )
        .unwrap();
        let c = FirmwareConfig::load(Some(&path)).unwrap();
        assert_eq!(c.measure.settings().i_def, 300);
        assert_ne!(c.force.hash(), FirmwareConfig::default().force.hash());
        let bytes = c.baked_bytes();
        assert!(bytes.starts_with(MAGIC));
        assert_eq!(
            usize::from(u16::from_le_bytes([bytes[8], bytes[9]])),
            tooltouch_model::wire::measure_config::CANONICAL_CONFIG_LEN
        );

        std::fs::write(&path, "[force]\ncontroller = \"bang-bang\"\n").unwrap();
        let e = format!("{:#}", FirmwareConfig::load(Some(&path)).unwrap_err());
        assert!(e.contains("[force]") && e.contains("bang-bang"), "{e}");
        std::fs::write(
            &path,
            "[wear]\ncuts = [{ depth_mm = 3, rpm = 300, feed_per_tooth_mm = 0.2, seconds = 5 }, { depth_mm = 2, rpm = 300, feed_per_tooth_mm = 0.2, seconds = 5 }]\n",
        )
        .unwrap();
        let c = FirmwareConfig::load(Some(&path)).unwrap();
        let plan = crate::wear::WearPlan::from_table(
            &toml::from_str::<toml::Table>(&std::fs::read_to_string(&path).unwrap()).unwrap()
                ["wear"],
        )
        .unwrap();
        let expected = plan.scenario.config(false).unwrap();
        assert_eq!(
            c.force.settings().wear,
            expected.settings().wear,
            "one rule"
        );
        assert_eq!(c.force.settings().wear.set_count, 2);
        // A calibration of a non-default configuration.
        let c = FirmwareConfig {
            measure: tooltouch_model::MeasureSettings {
                i_def: 300,
                ..Default::default()
            }
            .validate()
            .unwrap(),
            ..c
        };
        let plain = c.baked_bytes();
        let record = CalibrationRecord {
            measure_hash: c.measure.hash(),
            offset_counts: -21,
            feed_nm_per_rev: 1000,
            speed_milli_rpm: 800_000,
        };
        let calibrated = c.with_calibration(record).unwrap();
        let bytes = calibrated.baked_bytes();
        assert_eq!(
            &bytes[..plain.len()],
            &plain[..],
            "the same file, then the record"
        );
        assert_eq!(
            bytes[plain.len()..],
            [&21u16.to_le_bytes()[..], &record.canonical_bytes()[..]].concat()
        );
        assert_ne!(calibrated.image_name(), c.image_name());
        assert!(calibrated.hashes().contains("offset=-21 counts"));
        let e = FirmwareConfig::default()
            .with_calibration(record)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("{:016x}", c.measure.hash()))
                && e.contains(&format!("{:016x}", MeasureConfig::default().hash())),
            "{e}"
        );
        std::fs::write(&path, "[force]\nkp_percent = 0\n").unwrap();
        let e = format!("{:#}", FirmwareConfig::load(Some(&path)).unwrap_err());
        assert!(e.contains("kp_percent") && e.contains("1..=1000"), "{e}");
    }
}
