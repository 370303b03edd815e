//! The settings files of `tooltouch control` and `tooltouch wear` (`--config`, examples/
//! control.toml and wear.toml): a `[control]` or `[wear]` table holding the subcommand's
//! flags under their own names (`_` for `-`) and values, spelled as on the command line
//! (the values are parsed by the flags' own `ValueEnum`s). A flag wins over the file; a
//! key left out keeps the flag's default. Unknown tables and keys are errors.

use anyhow::{Context, Result};
use serde::Deserialize;
use std::path::Path;
use tooltouch_settings::wear::WearPlan;

/// Which controller(s).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Which {
    /// PI, Ziegler–Nichols on F10.
    Pi,
    /// Variable-gain adaptive F11.
    Adaptive,
    /// Fuzzy PI.
    Fuzzy,
    /// All three.
    All,
}

/// Which force feedback.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Estimated from the spindle drive (F1–F9).
    Estimated,
    /// Dynamometer.
    Measured,
    /// Both.
    Both,
}

/// Which implementation closes the loop.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum EngineArg {
    /// The fixed-point golden model.
    Model,
    /// The float reference.
    Reference,
}

/// Which cutting process the plant runs.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProcessArg {
    /// Kienzle-type `F ∝ K_s·a^x·f^y` (x = 1, y = 0.75), K_s and τ_p drifting (the default).
    Kienzle,
    /// The linear F10 the controllers are designed on (the table before the nonlinear process).
    Linear,
}

/// `control`'s flags as given (`None`: not on the command line).
#[derive(Clone, Copy, Debug)]
pub struct ControlFlags<'a> {
    /// `--config`.
    pub config: Option<&'a Path>,
    /// `--controller`.
    pub controller: Option<Which>,
    /// `--force`.
    pub force: Option<Source>,
    /// `--engine`.
    pub engine: Option<EngineArg>,
    /// `--seed`.
    pub seed: Option<u64>,
    /// `--process`.
    pub process: Option<ProcessArg>,
}

/// The `[control]` table.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ControlTable {
    controller: Option<String>,
    force: Option<String>,
    engine: Option<String>,
    seed: Option<u64>,
    process: Option<String>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    control: Option<ControlTable>,
    wear: Option<toml::Value>,
}

/// What `control` runs: its flags, else the settings file's keys, else the defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ControlChoice {
    /// `--controller` / `controller` (default `pi`).
    pub controller: Which,
    /// `--force` / `force` (default `estimated`).
    pub force: Source,
    /// `--engine` / `engine` (default `model`).
    pub engine: EngineArg,
    /// `--seed` / `seed` (default 1).
    pub seed: u64,
    /// `--process` / `process` (default `kienzle`).
    pub process: ProcessArg,
}

fn read(path: &Path, table: &str) -> Result<File> {
    let text =
        tooltouch_settings::read_text_file(path, "settings file").map_err(anyhow::Error::msg)?;
    let file: File = toml::from_str(&text).map_err(|e| {
        anyhow::anyhow!(
            "settings file {}: {}",
            path.display(),
            tooltouch_settings::toml_error(&text, &e)
        )
    })?;
    let other = if table == "control" {
        file.wear.is_some()
    } else {
        file.control.is_some()
    };
    if other {
        anyhow::bail!(
            "settings file {}: `tooltouch {table}` reads a `[{table}]` table only",
            path.display()
        );
    }
    Ok(file)
}

/// A value of the file's key `key` parsed as the flag's `ValueEnum` `T`.
fn value<T: clap::ValueEnum>(path: &Path, table: &str, key: &str, text: &str) -> Result<T> {
    T::from_str(text, false).map_err(|_| {
        let allowed: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .filter(|v| !v.is_hide_set())
            .map(|v| v.get_name().to_string())
            .collect();
        anyhow::anyhow!(
            "settings file {}: [{table}] {key} = \"{text}\": allowed {}",
            path.display(),
            allowed.join(", ")
        )
    })
}

/// Resolves `control`'s choices from its flags and its `--config` file.
pub fn control(args: &ControlFlags) -> Result<ControlChoice> {
    let table = match args.config {
        Some(p) => read(p, "control")
            .with_context(|| "reading the control settings")?
            .control
            .unwrap_or_default(),
        None => ControlTable::default(),
    };
    let path = args.config.unwrap_or(Path::new(""));
    Ok(ControlChoice {
        controller: match (args.controller, &table.controller) {
            (Some(v), _) => v,
            (None, Some(t)) => value(path, "control", "controller", t)?,
            (None, None) => Which::Pi,
        },
        force: match (args.force, &table.force) {
            (Some(v), _) => v,
            (None, Some(t)) => value(path, "control", "force", t)?,
            (None, None) => Source::Estimated,
        },
        engine: match (args.engine, &table.engine) {
            (Some(v), _) => v,
            (None, Some(t)) => value(path, "control", "engine", t)?,
            (None, None) => EngineArg::Model,
        },
        seed: args.seed.or(table.seed).unwrap_or(1),
        process: match (args.process, &table.process) {
            (Some(p), _) => p,
            (None, Some(t)) => value(path, "control", "process", t)?,
            (None, None) => ProcessArg::Kienzle,
        },
    })
}

/// Resolves `wear`'s plan from its `--config` file's `[wear]` table
/// (`tooltouch_settings::wear`) and its `--seed` flag (which wins).
pub fn wear_plan(config: Option<&Path>, flag: Option<u64>) -> Result<WearPlan> {
    let mut plan = match config {
        Some(p) => match read(p, "wear")?.wear {
            Some(t) => WearPlan::from_table(&t)
                .map_err(|e| anyhow::anyhow!("settings file {}: {e}", p.display()))?,
            None => WearPlan::default(),
        },
        None => WearPlan::default(),
    };
    if let Some(seed) = flag {
        plan.scenario.seed = seed;
    }
    Ok(plan)
}
