//! `tooltouch faults`: the fault campaign (docs/faults.md) — fault kind × level × decision
//! method × N closed-loop measurements on a faulted lathe, each measurement classified
//! flagged, unconfirmed, silent-wrong, silent-harmless or no-decision-unflagged; a table,
//! `faults.json` and a plot per kind with `--out`; `--shard K/N` runs one slice and
//! `tooltouch faults merge DIR...` joins slices into the unsharded result. Parsing and
//! printing only: the campaign is `tooltouch_metrology::campaign`.

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use tooltouch_metrology::campaign::{
    self, method_name, CampaignResults, CampaignSpec, Class, FaultKind,
};
use tooltouch_model::measure::config::DecisionMethod;
use tooltouch_settings::Settings;
use tooltouch_tune::spec::Shard;
use tooltouch_vectors::output::OutputFolder;

/// The results file of `--out`.
pub const JSON: &str = "faults.json";

/// Arguments of `tooltouch faults`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    command: Option<Command>,
    /// Settings file (the same TOML as `measure --config`: the lathe every cell starts from,
    /// and the measurement settings whose method each cell replaces).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Fault kinds, comma-separated (default: every kind): chips, coolant-bridge,
    /// emi-contact, emi-fes, emi-index, emi-scale, fes-lost, fes-doubled, index-lost,
    /// index-doubled, broken-contact, broken-fes.
    #[arg(long, value_delimiter = ',')]
    kinds: Option<Vec<String>>,
    /// Levels for every kind, comma-separated (default: each kind's own three levels;
    /// probabilities 0–1, rates per second up to 1000).
    #[arg(long, value_delimiter = ',')]
    levels: Option<Vec<f64>>,
    /// Decision methods, comma-separated (default: counter,density,single-pulse).
    #[arg(long, value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// Measurements per cell, 1..=1000.
    #[arg(long, default_value_t = 20)]
    measurements: u32,
    /// Run only slice K of N (cells whose index is K modulo N).
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// Write faults.json and one plot per kind (faults-<kind>.svg) into this folder.
    #[arg(long)]
    out: Option<PathBuf>,
    /// The settings' flags (as `measure`).
    #[command(flatten)]
    flags: super::setting_flags::SettingFlags,
}

#[derive(clap::Subcommand, Debug)]
enum Command {
    /// Join the slices of a sharded campaign (each DIR holds a faults.json written with
    /// `--shard K/N`) into one result, equal to the unsharded run.
    Merge {
        /// The slices' folders.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Where to write the merged result.
        #[arg(long)]
        out: PathBuf,
    },
}

/// The campaign spec of the arguments; an unknown kind or method is named.
fn spec(a: &Args) -> Result<CampaignSpec> {
    let mut spec = CampaignSpec {
        measurements: a.measurements,
        ..CampaignSpec::default()
    };
    if let Some(kinds) = &a.kinds {
        spec.kinds = kinds
            .iter()
            .map(|k| {
                FaultKind::named(k.trim()).with_context(|| {
                    let all: Vec<&str> = FaultKind::ALL.iter().map(|k| k.name()).collect();
                    format!(
                        "--kinds: unknown fault kind `{k}`; the kinds: {}",
                        all.join(", ")
                    )
                })
            })
            .collect::<Result<_>>()?;
    }
    if let Some(levels) = &a.levels {
        spec.levels = levels.clone();
    }
    if let Some(methods) = &a.methods {
        spec.methods = methods
            .iter()
            .map(|m| match m.trim() {
                "counter" => Ok(DecisionMethod::Counter),
                "density" => Ok(DecisionMethod::Density),
                "single-pulse" => Ok(DecisionMethod::SinglePulse),
                other => bail!(
                    "--methods: unknown decision method `{other}`; the methods: counter, density, single-pulse"
                ),
            })
            .collect::<Result<_>>()?;
    }
    spec.validate()?;
    Ok(spec)
}

/// Runs `tooltouch faults`.
pub fn run(a: Args) -> Result<ExitCode> {
    if let Some(Command::Merge { dirs, out }) = &a.command {
        return merge(dirs, out);
    }
    let started = Instant::now();
    let settings: Settings = a.flags.settings(a.config.as_deref())?;
    let (_, scenario) = settings
        .resolve()
        .map_err(|e| a.flags.explain(e, a.config.as_deref()))?;
    let spec = spec(&a)?;
    let shard = a
        .shard
        .as_deref()
        .map(str::parse::<Shard>)
        .transpose()?
        .map(|s| (s.k as usize, s.n as usize));
    let cells = spec.cells().len();
    let mine = (0..cells)
        .filter(|i| shard.is_none_or(|(k, n)| i % n == k))
        .count();
    let bar = ProgressBar::new(mine as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} cells, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    // The output folder is checked before any work.
    let out = a.out.as_deref().map(output_folder).transpose()?;
    let results = campaign::run(&spec, &scenario, &settings.measure, shard, &|| bar.inc(1))?;
    bar.finish_and_clear();
    print_table(&results);
    let measurements =
        (results.cells.len() + results.clean.len()) as f64 * f64::from(spec.measurements);
    let seconds = started.elapsed().as_secs_f64();
    if let (Some(out), Some(dir)) = (out, &a.out) {
        write_into(&results, out)?;
        outln!("wrote {}", dir.display());
    }
    outln!(
        "{} cells, {measurements} measurements in {seconds:.1} s ({:.0} measurements/s)",
        results.cells.len(),
        measurements / seconds.max(1e-9)
    );
    Ok(verdict(&results))
}

/// 0 when no cell let a wrong diameter through unflagged and the clean lathe raised no
/// alarm; 1 otherwise (the campaign's verdict, as `measure`'s for an undecided run).
fn verdict(r: &CampaignResults) -> ExitCode {
    let silent = r
        .cells
        .iter()
        .any(|c| c.counts.silent_wrong + c.counts.no_decision_unflagged > 0);
    let false_alarm = r
        .clean
        .iter()
        .any(|c| c.counts.silent_harmless != c.counts.total());
    if silent || false_alarm {
        ExitCode::from(super::NOT_PASSED)
    } else {
        ExitCode::SUCCESS
    }
}

fn print_table(r: &CampaignResults) {
    let header: Vec<&str> = Class::ALL.iter().map(|c| c.name()).collect();
    outln!(
        "{:<16} {:>9} {:<13} {}   worst accepted error",
        "kind",
        "level",
        "method",
        header
            .iter()
            .map(|h| format!("{h:>9.9}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    let row = |kind: &str,
               level: String,
               method: DecisionMethod,
               counts: &campaign::ClassCounts,
               worst: String| {
        let cols: Vec<String> = Class::ALL
            .iter()
            .map(|&c| format!("{:>9}", counts.of(c)))
            .collect();
        outln!(
            "{kind:<16} {level:>9} {:<13} {}   {worst}",
            method_name(method),
            cols.join(" ")
        );
    };
    for c in &r.clean {
        row(
            "none (clean)",
            "-".into(),
            c.method,
            &c.counts,
            format!(
                "tolerance ±{:.2} µm ({}), bias {:+.2} µm",
                c.tolerance_um, c.tolerance_from, c.bias_um
            ),
        );
    }
    for c in &r.cells {
        row(
            c.key.kind.name(),
            format!("{}", c.key.level),
            c.key.method,
            &c.counts,
            format!("{:.2} µm", c.worst_accepted_error_um),
        );
    }
    let wrong: u32 = r.cells.iter().map(|c| c.counts.silent_wrong).sum();
    let unflagged: u32 = r.cells.iter().map(|c| c.counts.no_decision_unflagged).sum();
    let false_alarms: u32 = r
        .clean
        .iter()
        .map(|c| c.counts.total() - c.counts.silent_harmless)
        .sum();
    outln!(
        "silent-wrong {wrong}, no-decision-unflagged {unflagged}, false alarms on the clean lathe {false_alarms}"
    );
}

/// The kinds present in `r`, in campaign order.
fn kinds_of(r: &CampaignResults) -> Vec<FaultKind> {
    FaultKind::ALL
        .into_iter()
        .filter(|k| r.cells.iter().any(|c| c.key.kind == *k))
        .collect()
}

fn svg_name(kind: FaultKind) -> String {
    format!("faults-{}.svg", kind.name())
}

/// The output folder of a campaign: `faults.json` and a plot per kind.
fn output_folder(dir: &Path) -> Result<OutputFolder> {
    let names: Vec<String> = std::iter::once(JSON.to_string())
        .chain(FaultKind::ALL.iter().map(|&k| svg_name(k)))
        .collect();
    OutputFolder::create(dir, names)
}

/// Writes `r` into `out` and commits it.
fn write_into(r: &CampaignResults, out: OutputFolder) -> Result<()> {
    out.write(
        JSON,
        serde_json::to_vec_pretty(r).context("encoding faults.json")?,
    )?;
    if r.shard.is_none() {
        for k in kinds_of(r) {
            tooltouch_plot::campaign::campaign_kind(&out.path(&svg_name(k)), k, &r.cells)?;
        }
    }
    out.commit()?;
    Ok(())
}

fn merge(dirs: &[PathBuf], out: &Path) -> Result<ExitCode> {
    let folder = output_folder(out)?;
    let parts = dirs
        .iter()
        .map(|d| {
            let path = d.join(JSON);
            let text = tooltouch_settings::read_text_file(&path, "campaign slice")
                .map_err(anyhow::Error::msg)?;
            serde_json::from_str::<CampaignResults>(&text)
                .with_context(|| format!("campaign slice {}: not a faults.json", path.display()))
        })
        .collect::<Result<Vec<_>>>()?;
    let merged = campaign::merge(&parts)?;
    write_into(&merged, folder)?;
    print_table(&merged);
    outln!(
        "faults merge: {} slices, {} cells → {}",
        parts.len(),
        merged.cells.len(),
        out.display()
    );
    Ok(verdict(&merged))
}
