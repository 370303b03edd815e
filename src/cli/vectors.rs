//! `tooltouch vectors`: the golden response to the user's own stimulus — a VCD of the six
//! input pins (a bench recording, a simulation), an input event stream, or run-length pins
//! — as every file a device under test is checked with ([`GoldenSet`]).
//!
//! The settings file is the one `tooltouch measure` and `tooltouch hdl` take
//! ([`load_settings`]).

use crate::lathe::LatheScenario;
use crate::output::OutputFolder;
use crate::vectors::golden_set::{self, GoldenSet};
use crate::vectors::stimulus_file::{self, StatedClock, StimulusFile};
use anyhow::Context;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tooltouch_model::{MeasureConfig, MeasureSettings};

/// The clock rule, shown in `--help` of `vectors` and `hdl`.
pub const CLOCK_RULE: &str = "\
Clock: the period P = 1e9 / clock_hz ns comes from --clock-hz, else the settings file's \
[lathe] clock_hz, else the stimulus file's own clock (a golden VCD's `clock_hz` comment, an \
event stream's tick rate), else 50 MHz; a stated clock that differs from the file's own is \
an error. A VCD's clock k takes the pins' values at time k*P (the last change at or \
before it); its clocks run from time 0 to its last time.";

/// Arguments of `tooltouch vectors`.
#[derive(clap::Args, Debug)]
#[command(after_help = CLOCK_RULE)]
pub struct Args {
    /// The stimulus: a VCD holding the six input pins (arm contact index fes scale_a
    /// scale_b: in a scope `inputs`, or named `pin_<name>`, or the shallowest outside a
    /// scope `outputs`), an input event stream (.ttv: measurement and/or force events), or
    /// run-length pins (the testbench's stim.hex).
    #[arg(long)]
    pub stimulus: PathBuf,
    /// Settings TOML, as `tooltouch measure` takes it: the golden model's `[measure]`
    /// table (or its fields at top level) and `[lathe] clock_hz`; other tables are errors.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// FPGA clock, Hz (see the clock rule below).
    #[arg(long)]
    pub clock_hz: Option<u32>,
    /// Output folder (created): golden.vcd, stim.hex, expect.hex, events.ttv,
    /// expected_outputs.ttv, summary.json. A run replaces this command's files in the
    /// folder (and removes those it did not write this time, e.g. golden.vcd for a
    /// force-only stream); other files are left alone; a failed run leaves the folder as it
    /// was.
    #[arg(long)]
    pub out: PathBuf,
}

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
/// firmware's configuration, [`crate::cosim::firmware_config`]); any other table or key is
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
    let text =
        crate::settings::read_text_file(path, "settings file").map_err(anyhow::Error::msg)?;
    let table: toml::Table = toml::from_str(&text).map_err(|e| {
        anyhow::anyhow!(
            "settings file {}: not valid TOML: {}",
            path.display(),
            crate::settings::toml_error(&text, &e)
        )
    })?;
    let file = format!("settings file {}", path.display());
    for warning in crate::settings::old_spellings_in_toml(&text, &file) {
        eprintln!("{warning}");
    }
    let tables = ["measure", "lathe", "force"];
    if tables.iter().any(|t| table.contains_key(*t)) {
        if let Some(unknown) = table.keys().find(|k| !tables.contains(&k.as_str())) {
            anyhow::bail!(
                "settings file {}: unknown table or key `{unknown}`: allowed `[measure]`, `[lathe]` and `[force]`",
                path.display()
            );
        }
    }
    if let Some(force) = table.get("force") {
        crate::cosim::firmware_config::ForceDesign::from_table(force)
            .map_err(|e| anyhow::anyhow!("settings file {}: [force] {e:#}", path.display()))?;
    }
    // A `[force]` table alone marks a file of tables too.
    let other_tables = table.get("lathe").or_else(|| table.get("force"));
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
                crate::settings::toml_error(&text, &e)
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

/// Runs `tooltouch vectors`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let settings = load_settings(args.config.as_deref(), args.clock_hz)?;
    let (set, format) = golden_set_of(&args.stimulus, &settings, args.config.is_some())?;
    let out = OutputFolder::create(&args.out, golden_set::FILES)?;
    let source = serde_json::json!({
        "file": args.stimulus.display().to_string(),
        "format": format,
        "settings": args.config.as_ref().map(|p| p.display().to_string()),
    });
    let summary = set.write(&out, source)?;
    let dir = out.dir().to_path_buf();
    let files = out.commit()?;
    let hashes = [
        ("measure_hash", "configuration"),
        ("force_hash", "force configuration"),
    ]
    .iter()
    .filter_map(|(k, what)| summary[k].as_str().map(|h| format!("{what} {h}")))
    .collect::<Vec<_>>()
    .join(", ");
    outln!(
        "{hashes}: {} events, {} force events, decisions: {}; wrote {}",
        summary["events"],
        summary["force_events"],
        summary["decisions"].as_array().map_or(0, Vec::len),
        dir.display()
    );
    if let Some(why) = &set.no_cycle_level {
        outln!("  no golden VCD nor testbench vectors: {why}");
    }
    if let Some(c) = &set.cycle {
        outln!(
            "  {} clocks at {} Hz in {} segments",
            c.stimulus.total_cycles(),
            c.stimulus.clock_hz,
            c.stimulus.segments.len()
        );
        match &c.hex {
            Ok(v) => {
                outln!(
                    "  testbench vectors: {} stim.hex words, {} expect.hex words",
                    v.stim_words,
                    v.expect_words
                );
                if v.stim_words.max(v.expect_words) > crate::hdl::hex::DEFAULT_DEPTH {
                    outln!(
                        "  (more than a default testbench holds: `tooltouch hdl --vectors {}` sizes it, \
                         or give `--stim-depth {} --expect-depth {}`)",
                        args.stimulus.display(),
                        v.stim_words,
                        v.expect_words
                    );
                }
            }
            Err(why) => outln!("  no testbench vectors: {why}"),
        }
    }
    for f in files {
        outln!("  {}", f.display());
    }
    Ok(ExitCode::SUCCESS)
}
