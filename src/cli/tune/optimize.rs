//! `tooltouch tune optimize --spec SPEC.toml`: the cheapest point of a search space that
//! meets the spec's tolerances against the float references (docs/tune.md), written as a
//! settings file in `tune point`'s format, with a JSON-lines log of every evaluation.

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tooltouch_tune::optimize::{self, OptimizeSpec};

/// Arguments of `tooltouch tune optimize`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Optimizer spec, TOML: `path`, `cost`, `[space]` (a sweep spec), `[constraints]`,
    /// `[limits]` (docs/tune.md).
    #[arg(long)]
    spec: PathBuf,
    /// The settings file of the answer (whole or not at all; not written when no point
    /// meets the spec).
    #[arg(long, value_hint = clap::ValueHint::FilePath)]
    out: PathBuf,
    /// The evaluation log, JSON lines (default: `--out` with the extension `.jsonl`).
    #[arg(long, value_hint = clap::ValueHint::FilePath)]
    log: Option<PathBuf>,
}

/// Runs `tooltouch tune optimize`: exit 0 with an answer, 1 when no evaluated point meets
/// the spec (naming the constraint and the best value reached), 2 for a bad spec.
pub fn run(a: &Args) -> Result<ExitCode> {
    let text = tooltouch_settings::read_text_file(&a.spec, "optimizer spec")
        .map_err(anyhow::Error::msg)?;
    let spec = OptimizeSpec::from_toml(&text).map_err(|e| {
        anyhow::anyhow!(
            "optimizer spec {}: key `{}`: {}",
            a.spec.display(),
            e.parameter,
            e.message
        )
    })?;
    let log = a
        .log
        .clone()
        .unwrap_or_else(|| a.out.with_extension("jsonl"));
    // The files' folders are checked before the search, not after it.
    for file in [&a.out, &log] {
        if file.is_dir() {
            anyhow::bail!("output file {}: is a folder", file.display());
        }
        let folder = file.parent().filter(|p| !p.as_os_str().is_empty());
        if let Some(folder) = folder.filter(|p| !p.is_dir()) {
            anyhow::bail!(
                "output file {}: its folder {} does not exist (create it first)",
                file.display(),
                folder.display()
            );
        }
    }
    let bar = ProgressBar::new(u64::from(spec.limits.evaluations));
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40} {pos}/{len} evaluations (limit), {elapsed} elapsed, {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let result = optimize::optimize(&spec, &|e| {
        bar.inc(1);
        bar.set_message(format!("last: {} cost {}", e.family, e.cost));
    })
    .with_context(|| format!("optimizer spec {}", a.spec.display()))?;
    bar.finish_and_clear();
    tooltouch_vectors::output::write_file(&log, optimize::log_lines(&result).as_bytes())?;
    let how = result
        .stopped
        .as_deref()
        .map_or_else(String::new, |s| format!(", stopped at the {s}"));
    outln!(
        "tune optimize: {} evaluations of a space of {} points in {:.1} s{how}; log → {}",
        result.evaluations.len(),
        result.grid_points,
        result.seconds,
        log.display()
    );
    match (&result.best, &result.settings_toml) {
        (Some(b), Some(text)) => {
            let e = &result.evaluations[*b];
            write_answer(&a.out, text)?;
            let params: Vec<String> = e
                .parameters
                .iter()
                .map(|(k, v)| format!("{k}={v}"))
                .collect();
            outln!(
                "answer (evaluation {}): {} {}; {} = {}",
                e.evaluation,
                e.family,
                params.join(" "),
                spec.cost_kind().name(),
                e.cost
            );
            outln!(
                "  {}",
                serde_json::to_string(&e.metrics).unwrap_or_default()
            );
            outln!(
                "{} → {}",
                text.lines().next().unwrap_or("").trim_start_matches("# "),
                a.out.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        _ => {
            let why = result.unmet.as_ref().map_or_else(
                || "no point of the space could be evaluated".to_string(),
                ToString::to_string,
            );
            eprintln!("tune optimize: {why} (no settings file written)");
            Ok(ExitCode::from(1))
        }
    }
}

fn write_answer(out: &Path, text: &str) -> Result<()> {
    tooltouch_vectors::output::write_file(out, text.as_bytes())?;
    Ok(())
}
