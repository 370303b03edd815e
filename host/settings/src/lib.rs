//! tooltouch's settings files: the one configuration every embodiment is built from.
//!
//! - this page: the settings of `tooltouch measure`;
//! - [`flags`]: their command-line flags, declared once (name, field, help, how each applies);
//! - [`load`]: the same file as `vectors`, `hdl` and the Python package read it;
//! - [`firmware_config`]: the configuration both firmware images are built with;
//! - [`force_design`] and [`values`]: force designs and the value lists specs sweep.
//!
//! Depends on the golden model, the plants and the vector formats; must not depend on the
//! co-simulation runners, tuning, plots or the command line.
//!
//! ## `tooltouch measure`'s settings
//!
//! A TOML file with a `[measure]` table (the golden
//! model's [`MeasureSettings`], integers only) and a `[lathe]` table (the simulated
//! [`LatheScenario`], floats allowed), then command-line flags on top (flags win).
//!
//! ```toml
//! [measure]
//! i_def = 512
//! method = "counter"              # single-pulse | counter | density
//! contact_rule = "sticky"         # sampled | sticky
//! charge_law = { law = "linear", charge_step = 2048, discharge_step = 1024 }
//!
//! [lathe]
//! rpm = 800.0
//! seed = 1
//! [lathe.cycle]
//! repeats = 10
//! [[lathe.slow]]
//! amplitude_um = 0.4
//! period_revs = 2.7
//! ```
//! Every field is optional (defaults: [`MeasureSettings::default`],
//! [`LatheScenario::default`]); unknown tables and fields are errors. [`Settings::resolve`]
//! checks every value and names the first bad field with its allowed range.
//!
//! Every settings-like text file of the command line (this one, a tune spec) is read by
//! [`read_text_file`]: at most [`MAX_TEXT_FILE_BYTES`], checked before it is read (a TOML
//! parse takes about twenty times the file's size), valid UTF-8, each failure one message
//! naming the file.
//!
//! Enum values have one spelling everywhere, kebab-case (`single-pulse`,
//! `permanent-contact`: the command line's convention, docs/cli.md); the old snake_case
//! spellings in [`RENAMED_VALUES`] are still read for one release, each with a warning
//! naming the new one ([`old_spellings_in_toml`]).

pub mod firmware_config;
pub mod flags;
pub mod force_design;
pub mod load;
pub mod values;
pub mod wear;

use serde::{Deserialize, Serialize};
use std::path::Path;
use tooltouch_model::validation::ConfigError;
use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_plant::lathe::{LatheScenario, ScenarioError};

/// The whole settings file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// The golden model's configuration.
    pub measure: MeasureSettings,
    /// The simulated lathe and measurement cycle.
    pub lathe: LatheScenario,
}

/// Largest settings or spec file read, bytes (1 MiB: the largest useful file, every
/// field and a few hundred harmonics, is a few kB).
pub const MAX_TEXT_FILE_BYTES: u64 = 1 << 20;

/// Reads the text file `path` (`what` says what it is, e.g. `settings file`): refuses a
/// directory, a file over [`MAX_TEXT_FILE_BYTES`] before reading it, and bytes that are
/// not UTF-8 (with their offset), and an empty (or blank) file. The error is one line
/// naming the file.
pub fn read_text_file(path: &Path, what: &str) -> Result<String, String> {
    use std::io::Read;
    let name = path.display();
    let file = std::fs::File::open(path).map_err(|e| format!("{what} {name}: {e}"))?;
    let meta = file.metadata().map_err(|e| format!("{what} {name}: {e}"))?;
    if meta.is_dir() {
        return Err(format!("{what} {name}: is a folder, not a file"));
    }
    if meta.len() > MAX_TEXT_FILE_BYTES {
        return Err(format!(
            "{what} {name}: {} bytes, more than the {MAX_TEXT_FILE_BYTES} bytes a settings file may have",
            meta.len()
        ));
    }
    // `take` also bounds a file that grows, or a pipe whose length is unknown.
    let mut bytes = Vec::new();
    file.take(MAX_TEXT_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("{what} {name}: {e}"))?;
    if bytes.len() as u64 > MAX_TEXT_FILE_BYTES {
        return Err(format!(
            "{what} {name}: more than the {MAX_TEXT_FILE_BYTES} bytes a settings file may have"
        ));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        format!(
            "{what} {name}: not a text file (byte {} is not valid UTF-8)",
            e.utf8_error().valid_up_to()
        )
    })?;
    // Every setting has a default, so an empty file would be valid TOML: it is far more
    // likely a mistake (a failed redirect, the wrong file) than a wish for the defaults.
    if text.trim().is_empty() {
        return Err(format!(
            "{what} {name}: empty (leave the flag out to run with the defaults)"
        ));
    }
    Ok(text)
}

/// Enum values whose spelling changed, `(old, new)`: the old one is still accepted for one
/// release, with a warning naming the new one.
pub const RENAMED_VALUES: [(&str, &str); 2] = [
    ("single_pulse", "single-pulse"),
    ("permanent_contact", "permanent-contact"),
];

/// The current spelling of `value` when it is an old one of [`RENAMED_VALUES`].
pub fn renamed_value(value: &str) -> Option<&'static str> {
    RENAMED_VALUES
        .iter()
        .find(|(old, _)| *old == value)
        .map(|&(_, new)| new)
}

/// The warning for an old spelling `old` of `new`, given as `what` (e.g. `--method` or
/// `settings file a.toml: method`).
pub fn old_spelling_warning(what: &str, old: &str, new: &str) -> String {
    format!(
        "warning: {what}: `{old}` is the old spelling of `{new}`; write `{new}` (the old one \
         is accepted until the next release)"
    )
}

/// One warning (see [`old_spelling_warning`]) for every string value of the TOML `text` —
/// a value, an array entry or a piece of comma-separated text — that is an old spelling of
/// [`RENAMED_VALUES`]; `file` names the file. Text that is not TOML gives none (the parse
/// reports it).
pub fn old_spellings_in_toml(text: &str, file: &str) -> Vec<String> {
    fn walk(key: &str, v: &toml::Value, file: &str, out: &mut Vec<String>) {
        match v {
            toml::Value::String(s) => {
                for piece in s.split(',').map(str::trim) {
                    if let Some(new) = renamed_value(piece) {
                        out.push(old_spelling_warning(&format!("{file}: {key}"), piece, new));
                    }
                }
            }
            toml::Value::Array(a) => a.iter().for_each(|v| walk(key, v, file, out)),
            toml::Value::Table(t) => t.iter().for_each(|(k, v)| walk(k, v, file, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    if let Ok(table) = text.parse::<toml::Table>() {
        table.iter().for_each(|(k, v)| walk(k, v, file, &mut out));
    }
    out
}

/// A TOML error as one line: `line N: <the parser's message>` (the parser's own text
/// spans several lines with a drawing of the spot), with the dotted key of the value the
/// error points at when its line is a `key = value` (`line 2: \`measure.checks.revolutions\`:
/// invalid type: integer \`3\`, expected a boolean`).
pub fn toml_error(text: &str, e: &toml::de::Error) -> String {
    let message = e.message().trim().replace('\n', " ");
    match e.span() {
        Some(span) => {
            let start = span.start.min(text.len());
            let line = text[..start].matches('\n').count() + 1;
            match key_at(text, start) {
                Some(key) => format!("line {line}: `{key}`: {message}"),
                None => format!("line {line}: {message}"),
            }
        }
        None => message,
    }
}

/// The dotted key of the `key = value` line holding byte `at` of `text`, under the last
/// `[table]` header above it (`None` when that line has no plain key).
fn key_at(text: &str, at: usize) -> Option<String> {
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..].lines().next().unwrap_or("");
    let (key, _) = line.split_once('=')?;
    let key = key.trim();
    let plain = |k: &str| {
        !k.is_empty()
            && k.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
    };
    if !plain(key) || line_start + line.find('=')? > at {
        return None;
    }
    let table = text[..line_start].lines().rev().find_map(|l| {
        let l = l.trim();
        let inner = l.strip_prefix('[')?.split(']').next()?;
        Some(inner.trim_start_matches('[').trim().to_string())
    });
    Some(match table {
        Some(t) if plain(&t) => format!("{t}.{key}"),
        _ => key.to_string(),
    })
}

/// Bad settings.
#[derive(Debug, thiserror::Error)]
pub enum SettingsError {
    /// The file could not be read (the message names it and says why).
    #[error("{0}")]
    Io(String),
    /// The file is not valid TOML for these settings.
    #[error("settings file {file}: {message}")]
    Parse {
        /// The file.
        file: String,
        /// The parser's message (names the key and line).
        message: String,
    },
    /// A `[measure]` field out of range (a `[measure.checks]` one named in full,
    /// `measure.checks.pulse_tolerance`).
    #[error("{}", measure_error(.0))]
    Measure(ConfigError),
    /// A `[lathe]` field out of range.
    #[error("[lathe] {0}")]
    Lathe(ScenarioError),
    /// A flag that does not fit the other settings.
    #[error("{0}")]
    Conflict(String),
}

/// The message of a `[measure]` field out of range: the model names a `[measure.checks]`
/// field `checks.<field>`, told here by its whole key.
fn measure_error(e: &ConfigError) -> String {
    match e.field.strip_prefix("checks.") {
        Some(leaf) => format!(
            "[measure.checks] configuration field `measure.checks.{leaf}` = {} is out of range: allowed {}..={}",
            e.value, e.min, e.max
        ),
        None => format!("[measure] {e}"),
    }
}

impl Settings {
    /// Reads a settings file; warns on standard error about each old spelling in it
    /// ([`old_spellings_in_toml`]).
    pub fn load(path: &Path) -> Result<Settings, SettingsError> {
        let file = path.display().to_string();
        let text = read_text_file(path, "settings file").map_err(SettingsError::Io)?;
        let settings = Settings::parse(&text, &file)?;
        for warning in old_spellings_in_toml(&text, &format!("settings file {file}")) {
            eprintln!("{warning}");
        }
        Ok(settings)
    }

    /// Parses settings from TOML text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Settings, SettingsError> {
        toml::from_str(text).map_err(|e| SettingsError::Parse {
            file: file.to_string(),
            message: toml_error(text, &e),
        })
    }

    /// Validates both tables: the model's configuration, then the scenario against it.
    pub fn resolve(&self) -> Result<(MeasureConfig, LatheScenario), SettingsError> {
        let config = self.measure.validate().map_err(SettingsError::Measure)?;
        self.lathe.validate(&config).map_err(SettingsError::Lathe)?;
        Ok((config, self.lathe.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::measure::config::{ChargeLaw, DecisionMethod};

    #[test]
    fn a_partial_file_keeps_the_other_defaults() {
        let s = Settings::parse(
            "[measure]\ni_def = 300\nmethod = \"density\"\ncharge_law = { law = \"exponential\", charge_shift = 3, discharge_shift = 4 }\n[lathe]\nrpm = 600.0\n[lathe.cycle]\nrepeats = 3\n",
            "t.toml",
        )
        .unwrap();
        assert_eq!(s.measure.i_def, 300);
        assert_eq!(s.measure.method, DecisionMethod::Density);
        assert!(matches!(
            s.measure.charge_law,
            ChargeLaw::Exponential {
                charge_shift: 3,
                ..
            }
        ));
        assert_eq!(s.lathe.rpm, 600.0);
        assert_eq!(s.lathe.cycle.repeats, 3);
        assert_eq!(s.lathe.diameter_mm, 40.0);
        s.resolve().unwrap();
    }

    #[test]
    fn the_checks_are_read_from_measure_checks() {
        let s = Settings::parse(
            "[measure.checks]\nrevolutions = false\nprobe_revs = 40\nfes_timeout_cycles = 0\nconfirm_windows = 2\n",
            "t.toml",
        )
        .unwrap();
        let c = s.measure.checks;
        assert!(!c.revolutions && c.contact_at_arm);
        assert_eq!(
            (c.probe_revs, c.fes_timeout_cycles, c.confirm_windows),
            (40, 0, 2)
        );
        assert_eq!(
            c.confirm_percent, 25,
            "the other fields keep their defaults"
        );
        let (config, _) = s.resolve().unwrap();
        assert_ne!(
            config.hash(),
            Settings::default().resolve().unwrap().0.hash()
        );
        // Written back and read again, the checks are the same.
        let again = Settings::parse(&toml::to_string(&s).unwrap(), "w.toml").unwrap();
        assert_eq!(again.measure.checks, c);
    }

    #[test]
    fn old_spellings_are_read_with_a_warning_naming_the_new_one() {
        let old = "[measure]\nmethod = \"single_pulse\"\n[lathe.cycle]\nretract_at = \"permanent_contact\"\n";
        let new = old
            .replace("single_pulse", "single-pulse")
            .replace("permanent_contact", "permanent-contact");
        let (a, b) = (
            Settings::parse(old, "o.toml").unwrap(),
            Settings::parse(&new, "n.toml").unwrap(),
        );
        assert_eq!(a, b);
        assert_eq!(a.measure.method, DecisionMethod::SinglePulse);
        let warnings = old_spellings_in_toml(old, "o.toml");
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        let has = |a: &str, b: &str| warnings.iter().any(|w| w.contains(a) && w.contains(b));
        assert!(has("o.toml: method", "`single-pulse`"), "{warnings:?}");
        assert!(
            has("o.toml: retract_at", "`permanent-contact`"),
            "{warnings:?}"
        );
        assert!(old_spellings_in_toml(&new, "n.toml").is_empty());
        // Written back, the settings use the new spelling.
        let written = toml::to_string(&a).unwrap();
        assert!(
            written.contains("\"single-pulse\"") && written.contains("\"permanent-contact\""),
            "{written}"
        );
    }

    #[test]
    fn bad_fields_are_named() {
        let s = Settings::parse("[measure]\ni_def = 5000\n", "t.toml").unwrap();
        let e = s.resolve().unwrap_err().to_string();
        assert!(e.contains("`i_def`") && e.contains("0..=1023"), "{e}");
        let s = Settings::parse("[lathe]\nrpm = 0.0\n", "t.toml").unwrap();
        let e = s.resolve().unwrap_err().to_string();
        assert!(e.contains("`rpm`"), "{e}");
        let s = Settings::parse("[measure.checks]\npulse_tolerance = 300\n", "t.toml").unwrap();
        let e = s.resolve().unwrap_err().to_string();
        assert!(
            e.contains("`measure.checks.pulse_tolerance` = 300") && e.contains("0..=256"),
            "{e}"
        );
        let s = Settings::parse("[measure.checks]\nconfirm_percent = 0\n", "t.toml").unwrap();
        let e = s.resolve().unwrap_err().to_string();
        assert!(e.contains("`measure.checks.confirm_percent`"), "{e}");
        let e = Settings::parse("[measure.checks]\nrevolutions = 3\n", "t.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("t.toml: line 2: `measure.checks.revolutions`: invalid type"),
            "{e}"
        );
        let e = Settings::parse("[measure.checks]\nprobe = 3\n", "t.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.toml") && e.contains("probe"), "{e}");
        let e = Settings::parse("[lathe]\nrmp = 1.0\n", "t.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.toml") && e.contains("rmp"), "{e}");
    }
}
