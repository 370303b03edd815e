//! `tooltouch control`: the depth-step force-control scenario (docs/domain.md §3) — 500 N reference,
//! depth 1 mm stepping to 1.5 mm at 8 s — closed through the fixed-point model (or the
//! float reference), with its metrics, SVG plots and the sample-level vectors.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tooltouch_model::force::config::{ForceConfig, ForceSource};
use tooltouch_plant::drive::scenario::{
    self, scenario_settings, ControlScenario, ControllerKind, Engine, Run,
};
use tooltouch_vectors::output::OutputFolder;

use super::run_settings::ControlFlags;
pub use super::run_settings::{EngineArg, ProcessArg, Source, Which};

/// Arguments of `tooltouch control`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Settings file: a `[control]` table of these flags' keys (examples/control.toml);
    /// a flag wins over it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Controller (default `pi`); `all` prints the table for the three.
    #[arg(long, value_enum)]
    pub controller: Option<Which>,
    /// Force feedback (default `estimated`); `both` runs measured and estimated.
    #[arg(long, value_enum)]
    pub force: Option<Source>,
    /// Fixed-point model or float reference (default `model`).
    #[arg(long, value_enum)]
    pub engine: Option<EngineArg>,
    /// Noise seed (default 1).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Cutting process (default `kienzle`: nonlinear in the feed, K_s and τ_p drifting;
    /// `linear`: F10 as the controllers are designed on; docs/control.md).
    #[arg(long, value_enum)]
    pub process: Option<ProcessArg>,
    /// Directory for plots, vectors and tables (`<controller>_<force>.{svg,csv,json,
    /// events.ttv,outputs.ttv}`, `control.{csv,json}`; docs/control.md).
    /// A run replaces this command's files in the folder (and removes those it did not
    /// write this time, e.g. other controllers'); other files are left alone; a failed run
    /// leaves the folder as it was.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also characterize the force estimator against the dynamometer (force control off:
    /// a depth step and a run-up without cutting; docs/estimator.md): a second table and,
    /// with `--out`, `estimator.csv`, `estimator.json` and `estimator.svg`; then the same
    /// depth step on drives that are not the estimator's model, with its default and with
    /// identified settings (`estimator_mismatch.{csv,json}`).
    #[arg(long)]
    pub estimator_report: bool,
}

/// Runs `tooltouch control`.
pub fn run(args: Args) -> Result<ExitCode> {
    let chosen = super::run_settings::control(&ControlFlags {
        config: args.config.as_deref(),
        controller: args.controller,
        force: args.force,
        engine: args.engine,
        seed: args.seed,
        process: args.process,
    })?;
    let kinds: Vec<ControllerKind> = match chosen.controller {
        Which::Pi => vec![ControllerKind::Pi],
        Which::Adaptive => vec![ControllerKind::Adaptive],
        Which::Fuzzy => vec![ControllerKind::Fuzzy],
        Which::All => ControllerKind::ALL.to_vec(),
    };
    let sources: Vec<ForceSource> = match chosen.force {
        Source::Estimated => vec![ForceSource::Estimated],
        Source::Measured => vec![ForceSource::Measured],
        Source::Both => vec![ForceSource::Measured, ForceSource::Estimated],
    };
    let engine = match chosen.engine {
        EngineArg::Model => Engine::Model,
        EngineArg::Reference => Engine::Reference,
    };
    let out = match &args.out {
        Some(dir) => Some(OutputFolder::create(dir, known_outputs())?),
        None => None,
    };
    let jobs: Vec<(ControllerKind, ForceSource)> = kinds
        .iter()
        .flat_map(|&k| sources.iter().map(move |&s| (k, s)))
        .collect();
    let bar = indicatif::ProgressBar::new(jobs.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} runs {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let process_name = match chosen.process {
        ProcessArg::Kienzle => "kienzle",
        ProcessArg::Linear => "linear",
    };
    outln!(
        "depth step 1.0 -> 1.5 mm at 8 s, reference 500 N, engine {:?}, process {process_name}",
        engine
    );
    outln!(
        "{:<9} {:<10} {:>10} {:>11} {:>12} {:>10} {:>10}",
        "controller",
        "force",
        "overshoot",
        "settling",
        "ss error",
        "IAE",
        "override"
    );
    let mut rows = Vec::new();
    for &(k, source) in &jobs {
        bar.set_message(format!("{} {}", k.name(), source_name(source)));
        let settings = match chosen.process {
            ProcessArg::Kienzle => scenario::kienzle_settings(
                k,
                source,
                &tooltouch_plant::drive::kienzle::KienzleProcess::default(),
            ),
            ProcessArg::Linear => scenario_settings(k, source),
        };
        let config = settings
            .validate()
            .map_err(|e| anyhow::anyhow!("{e}"))
            .with_context(|| format!("configuring the {} controller", k.name()))?;
        let mut sc = ControlScenario::new(config);
        if chosen.process == ProcessArg::Kienzle {
            sc = sc.with_kienzle_process();
        }
        sc.seed = chosen.seed;
        let r = scenario::run(&sc, engine, args.out.is_some() && engine == Engine::Model);
        if let Some(out) = &out {
            let stem = format!("{}_{}", k.name(), source_name(source));
            let reference_n = config.settings().reference.to_num::<f64>();
            tooltouch_plot::control::control_run(
                &out.path(&format!("{stem}.svg")),
                &r,
                &stem,
                reference_n,
                sc.depth.step_at,
            )
            .with_context(|| format!("plotting {stem}"))?;
            let series = super::run_tables::control_series(&r, reference_n);
            super::run_tables::write_table(out.staging(), &stem, &series)?;
            if engine == Engine::Model {
                write_vectors(
                    out.staging(),
                    &stem,
                    &r,
                    &config,
                    u32::from(settings.sample_hz),
                )?;
            }
        }
        rows.push((k, source, r.metrics));
        bar.inc(1);
    }
    bar.finish_and_clear();
    if let Some(out) = &out {
        let engine_name = match engine {
            Engine::Model => "model",
            Engine::Reference => "reference",
        };
        let table: Vec<_> = rows
            .iter()
            .map(|(k, s, m)| {
                super::run_tables::ControlMetrics::new(
                    k.name(),
                    source_name(*s),
                    engine_name,
                    chosen.seed,
                    m,
                )
            })
            .collect();
        super::run_tables::write_table(out.staging(), "control", &table)?;
    }
    for (k, source, m) in rows {
        outln!(
            "{:<9} {:<10} {:>9.1}% {:>10.2}s {:>10.1} N {:>8.1}Ns {:>5}-{:<4}",
            k.name(),
            source_name(source),
            m.overshoot_pct,
            m.settling_s,
            m.steady_error_n,
            m.iae,
            m.override_range.0,
            m.override_range.1
        );
    }
    if args.estimator_report {
        estimator_report(chosen.seed, out.as_ref())?;
    }
    if let Some(out) = out {
        let dir = out.dir().to_path_buf();
        out.commit()?;
        outln!("plots, tables and vectors written to {}", dir.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// `--estimator-report`: the estimator table, and its files into `out`.
fn estimator_report(seed: u64, out: Option<&OutputFolder>) -> Result<()> {
    let report = tooltouch_plant::drive::estimator_report::report(seed);
    outln!();
    for line in report.table() {
        outln!("{line}");
    }
    if let Some(out) = out {
        let write = |name: &str, text: String| {
            let path = out.path(name);
            std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))
        };
        write(ESTIMATOR_FILES[0], report.csv()?)?;
        write(ESTIMATOR_FILES[1], report.json()? + "\n")?;
        tooltouch_plot::estimator::estimator(&out.path(ESTIMATOR_FILES[2]), &report)?;
    }
    let sweep = tooltouch_plant::drive::mismatch_report::report(seed);
    outln!();
    for line in sweep.table() {
        outln!("{line}");
    }
    if let Some(out) = out {
        let write = |name: &str, text: String| {
            let path = out.path(name);
            std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))
        };
        write(ESTIMATOR_FILES[3], sweep.csv()?)?;
        write(ESTIMATOR_FILES[4], sweep.json()? + "\n")?;
    }
    Ok(())
}

/// The files of `--estimator-report --out`: the report on the estimator's own drive and the
/// sweep over mismatched drives.
const ESTIMATOR_FILES: [&str; 5] = [
    "estimator.csv",
    "estimator.json",
    "estimator.svg",
    "estimator_mismatch.csv",
    "estimator_mismatch.json",
];

/// Every file `control --out` can write: plot, series and vectors of each controller and
/// source, the metrics table and the estimator report's files. The vectors' old names
/// (`.events.bin`, `.outputs.bin`, before they took the `.ttv` of every vector file) are
/// listed too, so a run removes the stale copies an older version left.
fn known_outputs() -> Vec<String> {
    let mut names = super::run_tables::table_files("control").to_vec();
    names.extend(ESTIMATOR_FILES.map(String::from));
    for k in ControllerKind::ALL {
        for s in [ForceSource::Estimated, ForceSource::Measured] {
            for suffix in [
                "svg",
                "csv",
                "json",
                "events.ttv",
                "outputs.ttv",
                "events.bin",
                "outputs.bin",
            ] {
                names.push(format!("{}_{}.{suffix}", k.name(), source_name(s)));
            }
        }
    }
    names
}

fn source_name(s: ForceSource) -> &'static str {
    match s {
        ForceSource::Estimated => "estimated",
        ForceSource::Measured => "measured",
    }
}

/// Writes `<stem>.events.ttv` and `<stem>.outputs.ttv` of a run
/// ([`tooltouch_vectors::force_run::streams`]) into `dir`.
pub fn write_vectors(
    dir: &Path,
    stem: &str,
    r: &Run,
    config: &ForceConfig,
    tick_hz: u32,
) -> Result<()> {
    let (events, outputs) =
        tooltouch_vectors::force_run::streams(&r.events, &r.outputs, config, tick_hz);
    for (name, bytes) in [("events", events), ("outputs", outputs)] {
        let path = dir.join(format!("{stem}.{name}.ttv"));
        std::fs::write(&path, bytes).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}
