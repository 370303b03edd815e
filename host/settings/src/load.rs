//! A settings file as `tooltouch vectors`, `tooltouch hdl`, the firmware images and the
//! Python package read it: the golden model's `[measure]` table, the `[lathe]` table (its
//! `clock_hz` states the clock), and the firmware's `[force]` design, checked; and the golden
//! set of a stimulus file under those settings.

use crate::force_design::ForceDesign;
use anyhow::Context;
use std::path::Path;
use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_plant::lathe::LatheScenario;
use tooltouch_vectors::golden_set::GoldenSet;
use tooltouch_vectors::stimulus_file::{self, StatedClock, StimulusFile};

/// A settings file as `vectors` and `hdl` read it.
#[derive(Clone, Debug)]
pub struct LoadedSettings {
    /// The golden model's configuration (default without a file).
    pub config: MeasureConfig,
    /// The `[lathe]` table (default without one).
    pub lathe: LatheScenario,
    /// The clock stated by `--clock-hz` or the file's `[lathe] clock_hz`.
    pub clock: Option<StatedClock>,
}

/// Reads the settings file `path`: the `[measure]` table (or, when the file has neither a
/// `[measure]` nor a `[lathe]` nor a `[force]` table, the measurement fields at top level),
/// the `[lathe]` table, and the firmware's `[force]` design (checked here, used by the
/// firmware's configuration, [`crate::firmware_config`]); any other table or key is
/// an error. `clock_flag` is `--clock-hz`, which wins over the
/// file's `[lathe] clock_hz`.
pub fn load_settings(
    path: Option<&Path>,
    clock_flag: Option<u32>,
) -> anyhow::Result<LoadedSettings> {
    let mut loaded = LoadedSettings {
        config: MeasureConfig::default(),
        lathe: LatheScenario::default(),
        clock: clock_flag.map(|hz| StatedClock {
            hz,
            source: "--clock-hz".into(),
        }),
    };
    let Some(path) = path else {
        return Ok(loaded);
    };
    let text = crate::read_text_file(path, "settings file").map_err(anyhow::Error::msg)?;
    let table: toml::Table = toml::from_str(&text).map_err(|e| {
        anyhow::anyhow!(
            "settings file {}: not valid TOML: {}",
            path.display(),
            crate::toml_error(&text, &e)
        )
    })?;
    let file = format!("settings file {}", path.display());
    for warning in crate::old_spellings_in_toml(&text, &file) {
        eprintln!("{warning}");
    }
    let tables = ["measure", "lathe", "force", "wear"];
    if tables.iter().any(|t| table.contains_key(*t)) {
        if let Some(unknown) = table.keys().find(|k| !tables.contains(&k.as_str())) {
            anyhow::bail!(
                "settings file {}: unknown table or key `{unknown}`: allowed `[measure]`, `[lathe]`, `[force]` and `[wear]`",
                path.display()
            );
        }
    }
    if let Some(force) = table.get("force") {
        ForceDesign::from_table(force)
            .map_err(|e| anyhow::anyhow!("settings file {}: [force] {e:#}", path.display()))?;
    }
    if let Some(wear) = table.get("wear") {
        crate::wear::WearPlan::from_table(wear)
            .map_err(|e| anyhow::anyhow!("settings file {}: {e}", path.display()))?;
    }
    // A `[force]` or `[wear]` table alone marks a file of tables too.
    let other_tables = table
        .get("lathe")
        .or_else(|| table.get("force"))
        .or_else(|| table.get("wear"));
    let settings: MeasureSettings = match (table.get("measure"), other_tables) {
        (Some(measure), _) => measure
            .clone()
            .try_into()
            .with_context(|| format!("{}: [measure]", path.display()))?,
        (None, Some(_)) => MeasureSettings::default(),
        (None, None) => toml::from_str(&text).map_err(|e| {
            anyhow::anyhow!(
                "settings file {}: {}",
                path.display(),
                crate::toml_error(&text, &e)
            )
        })?,
    };
    loaded.config = settings
        .validate()
        .map_err(|e| anyhow::anyhow!("{}: [measure] {e}", path.display()))?;
    if let Some(lathe) = table.get("lathe") {
        loaded.lathe = lathe
            .clone()
            .try_into()
            .with_context(|| format!("{}: [lathe]", path.display()))?;
        if loaded.clock.is_none() && lathe.get("clock_hz").is_some() {
            loaded.clock = Some(StatedClock {
                hz: loaded.lathe.clock_hz,
                source: format!("[lathe] clock_hz of {}", path.display()),
            });
        }
    }
    Ok(loaded)
}

/// The golden set of the stimulus file `path` under `settings` (see the module
/// documentation of [`stimulus_file`]). An event stream's measurement configuration must
/// be the settings' when a settings file was given.
pub fn golden_set_of(
    path: &Path,
    settings: &LoadedSettings,
    config_given: bool,
) -> anyhow::Result<(GoldenSet, &'static str)> {
    let file = path.display().to_string();
    Ok(match stimulus_file::read(path, settings.clock.as_ref())? {
        StimulusFile::Pins { stimulus, format } => {
            (GoldenSet::from_pins(&settings.config, stimulus), format)
        }
        StimulusFile::Events(stream) => {
            if let Some(c) = &stream.measure {
                if config_given && c.hash() != settings.config.hash() {
                    anyhow::bail!(
                        "{file}: made with configuration {:016x}, the settings give {:016x}",
                        c.hash(),
                        settings.config.hash()
                    );
                }
            }
            (GoldenSet::from_events(*stream, &file), "events")
        }
    })
}
