//! `tooltouch ranges`: every fixed-point register of the measurement and force paths, the
//! kernels' outputs and their internal registers, over the tuning scenarios — observed
//! min/max, saturation and wrap counts, headroom in bits
//! (docs/tune.md#ranges-and-saturation-tooltouch-ranges) — as a table, `ranges.json`, and a
//! warning naming each register that saturated or wrapped.

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::process::ExitCode;
use tooltouch_settings::firmware_config::FirmwareConfig;
use tooltouch_tune::ranges;
use tooltouch_tune::scenario::ApproachSettings;
use tooltouch_vectors::output::OutputFolder;

/// `ranges.json`.
const JSON: &str = "ranges.json";

/// Arguments of `tooltouch ranges`.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Exit codes: 0 success (saturations are a warning on standard error); \
2 bad input (an unreadable or invalid settings file, a scenario count out of range, an \
unwritable output folder)."
)]
pub struct Args {
    /// Settings file (`[measure]`, `[force]`: `tune point`'s format); default: the defaults.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Tuning scenarios (seeds 1..=N) of the measurement path, 1..=1000.
    #[arg(long, default_value_t = 8)]
    scenarios: u32,
    /// Output directory for ranges.json (a failed run leaves it as it was).
    #[arg(long, default_value = "out/ranges")]
    out: PathBuf,
}

/// Runs `tooltouch ranges`.
pub fn run(a: Args) -> Result<ExitCode> {
    let config = FirmwareConfig::load(a.config.as_deref())?;
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg}, {elapsed} elapsed")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    bar.set_message(format!(
        "{} tuning scenarios and the control scenario",
        a.scenarios
    ));
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    let t = std::time::Instant::now();
    let r = ranges::ranges(
        &config.measure,
        &config.force,
        &ApproachSettings::default(),
        a.scenarios,
    )?;
    bar.finish_and_clear();
    let out = OutputFolder::create(&a.out, [JSON])?;
    let json = serde_json::to_string_pretty(&r).context("encoding ranges")? + "\n";
    std::fs::write(out.staging().join(JSON), json).context("writing ranges.json")?;
    out.commit()?;
    outln!(
        "ranges: {} registers over {} tuning scenarios and the control scenario in {:.1} s",
        r.registers.len(),
        r.scenarios,
        t.elapsed().as_secs_f64()
    );
    print_table(&r);
    for reg in r.saturated() {
        eprintln!(
            "warning: {} {}register `{}` ({}) {}",
            reg.path,
            match reg.kind {
                ranges::Kind::Output => "",
                ranges::Kind::Internal => "internal ",
            },
            reg.name,
            reg.format,
            if reg.wraps > 0 {
                format!("wrapped {} times", reg.wraps)
            } else {
                format!(
                    "saturated at {} of {} samples",
                    reg.saturations, reg.samples
                )
            }
        );
    }
    outln!("wrote {}", a.out.join(JSON).display());
    Ok(ExitCode::SUCCESS)
}

fn print_table(r: &ranges::Ranges) {
    outln!(
        "{:<7} {:<8} {:<26} {:<22} {:>14} {:>14} {:>11} {:>6} {:>8}",
        "path",
        "kind",
        "register",
        "format",
        "min",
        "max",
        "saturated",
        "wraps",
        "headroom"
    );
    for x in &r.registers {
        outln!(
            "{:<7} {:<8} {:<26} {:<22} {:>14} {:>14} {:>11} {:>6} {:>8}",
            x.path,
            match x.kind {
                ranges::Kind::Output => "output",
                ranges::Kind::Internal => "internal",
            },
            x.name,
            x.format,
            trim(x.min),
            trim(x.max),
            x.saturations,
            x.wraps,
            x.headroom_bits
        );
    }
}

fn trim(v: f64) -> String {
    if v.fract() == 0.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.3}")
    }
}
