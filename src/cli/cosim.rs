//! `tooltouch cosim`: the firmware's co-simulation from the command line.
//!
//! - `cosim firmware` boots a QEMU image (any `--image`, or this repository's, built with
//!   the configuration of `--config` or else the stream's own baked in) on the events of a stimulus (any file `tooltouch vectors`
//!   reads), and checks its trace against the golden outputs, as `tooltouch check` does:
//!   exit 0 when every record matches, 1 on a difference (or a firmware that crashed or
//!   rejected a valid stream), 2 on bad input (an unreadable stimulus or settings file,
//!   a missing tool, an image built with another configuration than the stream's).
//! - `cosim config` writes the configuration file firmware/build.rs bakes into the images
//!   (`TOOLTOUCH_FIRMWARE_CONFIG`; `cargo xtask firmware --config` runs it).

use std::path::PathBuf;
use std::process::ExitCode;
use tooltouch_firmware_runner::{qemu, trace, CosimError};
use tooltouch_settings::firmware_config::{FirmwareConfig, CONFIG_VAR};
use tooltouch_settings::load::{golden_set_of, load_settings};
use tooltouch_vectors::binary;
use tooltouch_vectors::check::{compare_binary, Verdict};

/// Arguments of `tooltouch cosim`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Subcommand, Debug)]
enum Command {
    /// Boot the QEMU firmware image on a stimulus's events and check its trace against the
    /// golden outputs (exit 0 match, 1 mismatch, 2 bad input).
    Firmware(FirmwareArgs),
    /// Validate a settings file and write the configuration file the firmware build bakes
    /// in (set TOOLTOUCH_FIRMWARE_CONFIG to it when building in firmware/).
    Config(ConfigArgs),
}

/// Arguments of `tooltouch cosim firmware`.
#[derive(clap::Args, Debug)]
struct FirmwareArgs {
    /// The stimulus, as `tooltouch vectors --stimulus` reads it: an events stream (.ttv),
    /// a VCD of the six input pins, or run-length pins.
    #[arg(long)]
    stimulus: PathBuf,
    /// The QEMU image (ELF) to boot. Default: build this repository's firmware/ with
    /// the configuration of `--config`, else the stream's own.
    #[arg(long)]
    image: Option<PathBuf>,
    /// Settings TOML (the `[measure]` table `hdl` and `vectors` read, and an optional
    /// `[force]` table): the configuration the image must have been built with, and the
    /// golden model's.
    #[arg(long)]
    config: Option<PathBuf>,
    /// FPGA clock of a pin stimulus, Hz (as `tooltouch vectors --clock-hz`).
    #[arg(long)]
    clock_hz: Option<u32>,
    /// A calibration file (`tooltouch calibrate`): the image is built with its entry for
    /// the configuration baked in (as `cosim config --calibration`), and the decisions it
    /// reports are compared with the golden model's latched positions minus that offset.
    #[arg(long, value_name = "FILE")]
    calibration: Option<PathBuf>,
    /// Also write the firmware's trace here (for `tooltouch check` or a closer look). Its
    /// folder is checked before the image is built; a failed run leaves an existing file
    /// as it was.
    // `FilePath`: a file this command writes (the hostile-input test reads the hint).
    #[arg(long, value_hint = clap::ValueHint::FilePath)]
    trace: Option<PathBuf>,
}

/// Arguments of `tooltouch cosim config`.
#[derive(clap::Args, Debug)]
struct ConfigArgs {
    /// Settings TOML: `[measure]` and `[force]` tables (defaults where absent).
    #[arg(long)]
    config: Option<PathBuf>,
    /// The configuration file to write (whole or not at all: a failed run leaves an
    /// existing file as it was).
    // `FilePath`: a file this command writes (the hostile-input test reads the hint).
    #[arg(long, value_hint = clap::ValueHint::FilePath)]
    out: PathBuf,
    /// A calibration file (`tooltouch calibrate`) to bake: its entry for the settings'
    /// method, contact rule, feed and speed, in scale counts; the firmware reports the
    /// decision position minus that offset. Refused when made with another configuration,
    /// feed or speed (naming both).
    #[arg(long, value_name = "FILE")]
    calibration: Option<PathBuf>,
}

/// Runs `tooltouch cosim`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match args.command {
        Command::Firmware(a) => Ok(firmware(&a)),
        Command::Config(a) => config(&a),
    }
}

fn config(a: &ConfigArgs) -> anyhow::Result<ExitCode> {
    let mut config = FirmwareConfig::load(a.config.as_deref())?;
    if let Some(path) = &a.calibration {
        config = with_calibration(config, a.config.as_deref(), path)?;
    }
    tooltouch_vectors::output::write_file(&a.out, &config.baked_bytes())?;
    outln!(
        "{}: wrote {} (build with {CONFIG_VAR}={})",
        config.hashes(),
        a.out.display(),
        a.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// `config` with the calibration file at `path` baked: its entry for the configuration and
/// the settings file's feed and speed.
pub fn with_calibration(
    config: FirmwareConfig,
    settings: Option<&std::path::Path>,
    path: &std::path::Path,
) -> anyhow::Result<FirmwareConfig> {
    use anyhow::Context;
    let lathe = load_settings(settings, None)?.lathe;
    let text =
        tooltouch_settings::read_text_file(path, "calibration file").map_err(anyhow::Error::msg)?;
    let file: tooltouch_metrology::calibration::Calibration = serde_json::from_str(&text)
        .with_context(|| format!("reading the calibration file {}", path.display()))?;
    let record = file
        .firmware_record(&config.measure, lathe.feed_mm_per_rev, lathe.rpm)
        .with_context(|| format!("--calibration {}", path.display()))?;
    config
        .with_calibration(record)
        .with_context(|| format!("--calibration {}", path.display()))
}

/// Compares the decisions the firmware reported in `trace` with the golden model's
/// ([`tooltouch_firmware_runner::DecisionReporter`] over `set`'s expected outputs) for an image
/// built with `calibration`: the first difference (time, field, both values) as the
/// error; with a calibration, a line saying what was compared.
fn check_decisions(
    set: &tooltouch_vectors::golden_set::GoldenSet,
    calibration: Option<&tooltouch_model::measure::calibration::CalibrationRecord>,
    trace: &[u8],
) -> Result<Option<String>, String> {
    let Some(config) = set.inputs.measure else {
        return Ok(None);
    };
    let mut reporter = tooltouch_firmware_runner::DecisionReporter::new(&config, calibration);
    let want: Vec<(u64, tooltouch_firmware_runner::ReportedDecision)> = set
        .outputs
        .iter()
        .filter_map(|(t, o)| match o {
            binary::Output::Measure(o) => reporter.next(o).map(|d| (*t, d)),
            binary::Output::Force(_) => None,
        })
        .collect();
    let streams = trace::parse(trace).map_err(|e| e.to_string())?;
    let got = streams
        .first()
        .map(|s| s.decisions.clone())
        .unwrap_or_default();
    for (k, (time, w)) in want.iter().enumerate() {
        let Some((t, g)) = got.get(k) else {
            return Err(format!(
                "decision {k} at {time}: the golden model reports position {} (offset {}), \
                 the firmware reports none",
                w.position, w.offset
            ));
        };
        for (field, a, b) in [
            ("time", *time as i64, *t as i64),
            ("corrected position", w.position.into(), g.position.into()),
            ("offset", w.offset.into(), g.offset.into()),
        ] {
            if a != b {
                return Err(format!(
                    "decision {k} at {time}: {field} golden {a}, firmware {b}"
                ));
            }
        }
    }
    if got.len() != want.len() {
        return Err(format!(
            "decisions reported: golden {}, firmware {}",
            want.len(),
            got.len()
        ));
    }
    Ok(calibration.map(|c| {
        format!(
            "{} decisions reported corrected by {} counts (calibration_hash={:016x}), equal \
             to the golden model's",
            want.len(),
            c.offset_for(&config),
            c.hash()
        )
    }))
}

/// How `cosim firmware` ended.
enum Outcome {
    /// Every record matched.
    Match(String),
    /// The firmware differs from the golden model, or failed on a valid stream.
    Mismatch(String),
    /// The inputs could not be used.
    BadInput(String),
}

fn firmware(a: &FirmwareArgs) -> ExitCode {
    let (line, code) = match firmware_outcome(a) {
        Outcome::Match(s) => (s, 0),
        Outcome::Mismatch(s) => (format!("MISMATCH: {s}"), 1),
        Outcome::BadInput(s) => (format!("error: {s}"), 2),
    };
    if code == 2 {
        eprintln!("{line}");
    } else {
        outln!("{line}");
    }
    ExitCode::from(code)
}

fn firmware_outcome(a: &FirmwareArgs) -> Outcome {
    let bad = |e: anyhow::Error| Outcome::BadInput(format!("{e:#}"));
    let settings = match load_settings(a.config.as_deref(), a.clock_hz) {
        Ok(s) => s,
        Err(e) => return bad(e),
    };
    let mut wanted = match FirmwareConfig::load(a.config.as_deref()) {
        Ok(c) => c,
        Err(e) => return bad(e),
    };
    let (mut set, _) = match golden_set_of(&a.stimulus, &settings, a.config.is_some()) {
        Ok(s) => s,
        Err(e) => return bad(e),
    };
    // The firmware configures itself from a measurement configuration record first: a
    // force-only stream gets the settings' (or the default) one, which changes no output.
    if set.inputs.measure.is_none() {
        set.inputs.measure = Some(wanted.measure);
        set.inputs.header.measure_hash = wanted.measure.hash();
    }
    let stream = set.inputs.header;
    if let Some(path) = &a.calibration {
        // The calibration is for the configuration the image runs: the settings', else
        // the stream's own.
        let base = FirmwareConfig {
            measure: set.inputs.measure.unwrap_or(wanted.measure),
            ..wanted
        };
        let base = if a.config.is_some() { wanted } else { base };
        wanted = match with_calibration(base, a.config.as_deref(), path) {
            Ok(c) => c,
            Err(e) => return bad(e),
        };
    }
    if a.config.is_some() && stream.force_hash != 0 && stream.force_hash != wanted.force.hash() {
        return Outcome::BadInput(format!(
            "{}: made with force configuration {:016x}, the settings give {:016x}",
            a.stimulus.display(),
            stream.force_hash,
            wanted.force.hash()
        ));
    }
    // Every input is read and the trace's folder checked before the image is built and
    // booted (minutes on a cold build), so a typo costs no build.
    if let Some(path) = &a.trace {
        if let Err(e) = tooltouch_vectors::output::check_output_file(path) {
            return bad(e);
        }
    }
    let image = match &a.image {
        Some(p) => match std::fs::read(p) {
            Ok(bytes) if bytes.starts_with(b"\x7fELF") => p.clone(),
            Ok(_) => return Outcome::BadInput(format!("{}: not an ELF image", p.display())),
            Err(e) => return Outcome::BadInput(format!("{}: {e}", p.display())),
        },
        None => {
            // Without settings, the image gets the stream's own configuration.
            let config = match &a.config {
                Some(_) => wanted,
                None => FirmwareConfig {
                    measure: set.inputs.measure.unwrap_or(wanted.measure),
                    force: set.inputs.force.unwrap_or(wanted.force),
                    calibration: wanted.calibration,
                },
            };
            let built = qemu::build_configured_firmware(&config);
            match built {
                Ok(p) => p,
                Err(e) => return Outcome::BadInput(e.to_string()),
            }
        }
    };
    let events = binary::encode_event_stream(&set.inputs);
    let expected = binary::encode_output_stream(stream, &set.outputs);
    let (trace_bytes, wall) = match qemu::run_image(&image, &events) {
        Ok(r) => r,
        Err(e @ CosimError::ToolMissing(_)) => return Outcome::BadInput(e.to_string()),
        Err(e) => return Outcome::Mismatch(format!("{}: {e}", image.display())),
    };
    if let Some(path) = &a.trace {
        if let Err(e) = tooltouch_vectors::output::write_file(path, &trace_bytes) {
            return bad(e);
        }
    }
    // The configuration the image was built with, from its status record.
    let image_hashes = trace::parse(&trace_bytes)
        .ok()
        .and_then(|streams| streams.first().and_then(|s| s.profile.image_hashes));
    if let Some((m, f)) = image_hashes {
        outln!(
            "image {}: configuration measure_hash={m:016x} force_hash={f:016x}",
            image.display()
        );
        let differs =
            m != stream.measure_hash || (stream.force_hash != 0 && f != stream.force_hash);
        if differs {
            return Outcome::BadInput(format!(
                "{} was built with configuration measure_hash={m:016x} force_hash={f:016x}, \
                 the stream carries measure_hash={:016x} force_hash={:016x}: build the image \
                 with the stream's settings (`cargo xtask firmware --config SETTINGS`, or \
                 `--config SETTINGS` without `--image`)",
                image.display(),
                stream.measure_hash,
                stream.force_hash
            ));
        }
        if a.config.is_some() && (m, f) != (wanted.measure.hash(), wanted.force.hash()) {
            return Outcome::BadInput(format!(
                "{} was built with configuration measure_hash={m:016x} force_hash={f:016x}, \
                 the settings give {}",
                image.display(),
                wanted.hashes()
            ));
        }
    } else if a.config.is_some() {
        return Outcome::BadInput(format!(
            "{}: its trace does not say which configuration it was built with, so --config \
             cannot be checked against it",
            image.display()
        ));
    }
    let dut_name = a.trace.as_ref().map_or_else(
        || "the firmware's trace".to_string(),
        |p| p.display().to_string(),
    );
    let golden_name = format!("the golden outputs of {}", a.stimulus.display());
    let qemu_line = format!(
        "QEMU ran {} events in {:.2} s",
        set.inputs.events.len(),
        wall.as_secs_f64()
    );
    match compare_binary(&expected, &golden_name, &trace_bytes, &dut_name) {
        Ok(Verdict::Match(s)) => {
            match check_decisions(&set, wanted.calibration.as_ref(), &trace_bytes) {
                Ok(None) => Outcome::Match(format!("{s}; {qemu_line}")),
                Ok(Some(line)) => Outcome::Match(format!("{s}; {line}; {qemu_line}")),
                Err(why) => Outcome::Mismatch(format!("{dut_name}: {why}")),
            }
        }
        Ok(Verdict::Mismatch(s)) => Outcome::Mismatch(s),
        Err(e) => Outcome::Mismatch(format!("{dut_name}: {e}")),
    }
}
