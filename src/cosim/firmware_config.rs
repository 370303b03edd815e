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
//! The baked file: `TTFWCFG1`, then the measurement configuration's canonical bytes and
//! the force configuration's (model::wire), each after its length as a little-endian u16.

use crate::cli::vectors::load_settings;
use crate::tune::force::ForceSpec;
use crate::tune::values::{Names, Values};
use anyhow::{bail, Context};
use serde::{Deserialize, Serialize};
use std::path::Path;
use tooltouch_model::force::config::{ForceConfig, ForceSettings};
use tooltouch_model::MeasureConfig;

/// The environment variable firmware/build.rs reads: the path of a baked configuration
/// file ([`FirmwareConfig::baked_bytes`]).
pub const CONFIG_VAR: &str = "TOOLTOUCH_FIRMWARE_CONFIG";
/// The first bytes of a baked configuration file.
pub const MAGIC: &[u8; 8] = b"TTFWCFG1";

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

/// The configuration an image is built with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirmwareConfig {
    /// The measurement configuration.
    pub measure: MeasureConfig,
    /// The force configuration.
    pub force: ForceConfig,
}

impl Default for FirmwareConfig {
    /// What an image built without a configuration runs.
    fn default() -> Self {
        FirmwareConfig {
            measure: MeasureConfig::default(),
            force: ForceSettings::default()
                .validate()
                .unwrap_or_else(|e| unreachable!("the default force settings are valid: {e}")),
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
        Ok(config)
    }

    /// The baked configuration file's bytes (module documentation).
    pub fn baked_bytes(&self) -> Vec<u8> {
        let (m, n) = self.measure.canonical_bytes();
        let (f, k) = self.force.canonical_bytes();
        let mut out = MAGIC.to_vec();
        for part in [&m[..n], &f[..k]] {
            out.extend_from_slice(&(part.len() as u16).to_le_bytes());
            out.extend_from_slice(part);
        }
        out
    }

    /// `measure_hash=… force_hash=…`, as the image reports it.
    pub fn hashes(&self) -> String {
        format!(
            "measure_hash={:016x} force_hash={:016x}",
            self.measure.hash(),
            self.force.hash()
        )
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
        assert_eq!(u16::from_le_bytes([bytes[8], bytes[9]]), 31);

        std::fs::write(&path, "[force]\ncontroller = \"bang-bang\"\n").unwrap();
        let e = format!("{:#}", FirmwareConfig::load(Some(&path)).unwrap_err());
        assert!(e.contains("[force]") && e.contains("bang-bang"), "{e}");
        std::fs::write(&path, "[force]\nkp_percent = 0\n").unwrap();
        let e = format!("{:#}", FirmwareConfig::load(Some(&path)).unwrap_err());
        assert!(e.contains("kp_percent") && e.contains("1..=1000"), "{e}");
    }
}
