//! `tooltouch tune`: fixed-point tuning sweeps of the measurement front end — every point's
//! error against the float reference and its FPGA cost, the Pareto front, CSV/JSON/SVG in
//! `--out DIR`; `--shard K/N` runs one slice, `tooltouch tune merge DIR...` joins slices.

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use tooltouch_plot::pareto::ParetoPoint;
use tooltouch_tune::{self as tune, output, Overrides, Shard, SweepSpec};
use tooltouch_vectors::output::OutputFolder;

mod optimize;

/// Arguments of `tooltouch tune`.
#[derive(clap::Args, Debug)]
#[command(
    args_conflicts_with_subcommands = true,
    after_help = "Exit codes: 0 success; 2 bad input (a spec or flag value out of range, a sweep \
larger than the limit, an unreadable spec or results.json, slices that do not make one sweep, an \
unwritable output folder)."
)]
pub struct Args {
    #[command(subcommand)]
    command: Option<Command>,
    // Boxed: the flags are many, and `cli::Command` holds every subcommand's `Args`.
    #[command(flatten)]
    sweep: Box<SweepArgs>,
}

#[derive(clap::Subcommand, Debug)]
enum Command {
    /// Find the cheapest point of a space that meets tolerances against the float
    /// references, without running the grid, and write it as a settings file
    /// (docs/tune.md#choosing-a-point-tune-optimize). Exit 1: no point meets the spec.
    Optimize(optimize::Args),
    /// Join the slices of a sharded sweep (each DIR holds a `results.json` written with
    /// `--shard K/N`) into one result, equal to the unsharded run.
    Merge {
        /// Slice directories (or their results.json files).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory (replaced files as for a sweep).
        #[arg(long, default_value = "out/tune")]
        out: PathBuf,
    },
    /// Write one swept point as a settings file for `hdl --config`, `vectors --config`,
    /// `cosim firmware --config` and `cargo xtask firmware --config` (docs/tune.md).
    Point {
        /// The sweep's directory (or its results.json).
        results: PathBuf,
        /// The point's index (the `index` column of results.csv / force.csv).
        index: usize,
        /// The settings file to write (whole or not at all: a failed run leaves an
        /// existing file as it was).
        // `FilePath`: a file this command writes (the hostile-input test reads the hint).
        #[arg(long, value_hint = clap::ValueHint::FilePath)]
        out: PathBuf,
    },
}

/// The sweep's flags. Each parameter flag replaces the spec's values of the parameter of
/// the same name (`-` for `_`); its help shows its syntax: numbers as a list `8,12,16`, one
/// value `16`, or an inclusive range `8..=16` / `8..=16:4`; names as a comma list.
#[derive(clap::Args, Debug)]
struct SweepArgs {
    /// Sweep spec, TOML (parameters not given keep the default sweep's values).
    #[arg(long)]
    spec: Option<PathBuf>,
    /// Output directory for results.json, results.csv, force.csv, pareto.svg. A run
    /// replaces this command's files in the folder (and removes those it did not write
    /// this time); other files are left alone; a failed run leaves the folder as it was.
    #[arg(long, default_value = "out/tune")]
    out: PathBuf,
    /// Run only slice K of N (0-based): points whose index % N == K.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// Scenarios (seeds 1..=N) per point (one number, 1..=1000).
    #[arg(long, value_name = "N")]
    scenarios: Option<u32>,
    /// Revolutions of approach per scenario (one number).
    #[arg(long, value_name = "N")]
    revolutions: Option<u32>,
    /// Decision methods, a comma list of: counter, density, single-pulse.
    #[arg(long, value_name = "NAMES")]
    method: Option<String>,
    /// Contact rules, a comma list of: sticky, sampled.
    #[arg(long, value_name = "NAMES")]
    contact_rule: Option<String>,
    /// Charge laws, a comma list of: linear, exponential.
    #[arg(long, value_name = "NAMES")]
    law: Option<String>,
    /// Capacitor widths, bits (4..=24):
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    charge_bits: Option<String>,
    /// Scale position widths, bits (8..=32):
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    scale_bits: Option<String>,
    /// Glitch filter lengths, clocks (0..=255):
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    glitch_cycles: Option<String>,
    /// Counter thresholds, contact pulses per window:
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    i_def: Option<String>,
    /// Counting windows, revolutions (1..=16):
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    window_revs: Option<String>,
    /// Linear law: pulses from empty to full:
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    charge_pulses: Option<String>,
    /// Linear law: pulses from full to empty:
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    discharge_pulses: Option<String>,
    /// Exponential law: charge shifts:
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    charge_shift: Option<String>,
    /// Exponential law: discharge shifts:
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    discharge_shift: Option<String>,
    /// Fire thresholds, percent of full scale (1..=100):
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    fire_percent: Option<String>,
    /// Re-arm thresholds, percent of full scale (0..=99):
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    rearm_percent: Option<String>,
    /// Force controllers, a comma list of: pi, adaptive, fuzzy; or `none` to skip the force sweep.
    #[arg(long, value_name = "NAMES")]
    force_controller: Option<String>,
    /// Force controllers' proportional gain, percent of the Ziegler–Nichols design:
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    kp_percent: Option<String>,
    /// Force controllers' integral gain, percent of the design:
    /// `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    #[arg(long, value_name = "VALUES")]
    ki_percent: Option<String>,
    /// Force feedback, a comma list of: estimated, measured.
    #[arg(long, value_name = "NAMES")]
    force_source: Option<String>,
}

impl SweepArgs {
    fn overrides(&self) -> Overrides {
        let pairs = [
            ("method", &self.method),
            ("contact_rule", &self.contact_rule),
            ("law", &self.law),
            ("charge_bits", &self.charge_bits),
            ("scale_bits", &self.scale_bits),
            ("glitch_cycles", &self.glitch_cycles),
            ("i_def", &self.i_def),
            ("window_revs", &self.window_revs),
            ("charge_pulses", &self.charge_pulses),
            ("discharge_pulses", &self.discharge_pulses),
            ("charge_shift", &self.charge_shift),
            ("discharge_shift", &self.discharge_shift),
            ("fire_percent", &self.fire_percent),
            ("rearm_percent", &self.rearm_percent),
            ("force.controller", &self.force_controller),
            ("force.kp_percent", &self.kp_percent),
            ("force.ki_percent", &self.ki_percent),
            ("force.force_source", &self.force_source),
        ];
        Overrides {
            scenarios: self.scenarios,
            revolutions: self.revolutions,
            values: pairs
                .iter()
                .filter_map(|(k, v)| v.as_ref().map(|v| (k.to_string(), v.clone())))
                .collect(),
        }
    }
}

/// Runs `tooltouch tune`.
pub fn run(args: Args) -> Result<ExitCode> {
    match args.command {
        Some(Command::Merge { dirs, out }) => merge(&dirs, &out),
        Some(Command::Point {
            results,
            index,
            out,
        }) => point(&results, index, &out),
        Some(Command::Optimize(a)) => optimize::run(&a),
        None => sweep(&args.sweep),
    }
}

fn sweep(a: &SweepArgs) -> Result<ExitCode> {
    let mut spec = match &a.spec {
        Some(p) => {
            let text =
                tooltouch_settings::read_text_file(p, "sweep spec").map_err(anyhow::Error::msg)?;
            let spec = SweepSpec::from_toml(&text)
                .with_context(|| format!("sweep spec {}", p.display()))?;
            let file = format!("sweep spec {}", p.display());
            for warning in tooltouch_settings::old_spellings_in_toml(&text, &file) {
                eprintln!("{warning}");
            }
            spec
        }
        None => SweepSpec::default(),
    };
    let overrides = a.overrides();
    warn_old_spellings(&overrides);
    spec.apply(&overrides)?;
    let shard: Option<Shard> = a.shard.as_deref().map(str::parse).transpose()?;
    let n = tune::points_in(&spec, shard)
        .map_err(|e| name_the_flag(e, &overrides, a.spec.as_deref()))?;
    let bar = ProgressBar::new(n as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} points, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let t = Instant::now();
    let results = tune::run(&spec, shard, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let wall = t.elapsed().as_secs_f64();
    write_folder(&results, &a.out)?;
    let scenarios = spec.scenarios;
    match shard {
        Some(s) => outln!(
            "tune: slice {}/{}: {} of {} points × {scenarios} scenarios in {wall:.1} s → {}",
            s.k,
            s.n,
            results.rows.len(),
            results.points,
            a.out.display()
        ),
        None => {
            outln!(
                "tune: {} measurement points × {scenarios} scenarios of {} revolutions and {} \
                 force-control points × 2 engines in {wall:.1} s ({} threads)",
                results.points,
                spec.approach.revolutions,
                results.force_points,
                rayon::current_num_threads()
            );
            summary(&results);
            outln!("wrote {}", a.out.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Warns on standard error about each old spelling in a flag's names (`--method
/// counter,single_pulse`); the sweep reads it as the new one.
fn warn_old_spellings(overrides: &Overrides) {
    for (key, text) in &overrides.values {
        for piece in text.split(',').map(str::trim) {
            if let Some(new) = tooltouch_settings::renamed_value(piece) {
                let flag = match key.as_str() {
                    "force.controller" => "--force-controller".to_string(),
                    k => format!("--{}", k.rsplit('.').next().unwrap_or(k).replace('_', "-")),
                };
                eprintln!(
                    "{}",
                    tooltouch_settings::old_spelling_warning(&flag, piece, new)
                );
            }
        }
    }
}

/// A sweep error told with the flag that set its parameter (`--force-controller x:`),
/// when a flag did, else with the spec file `spec_file` (when one was given).
fn name_the_flag(
    e: tune::TuneError,
    overrides: &Overrides,
    spec_file: Option<&std::path::Path>,
) -> anyhow::Error {
    if let tune::TuneError::Spec(spec) = &e {
        let flag_value = |key: &str| {
            overrides
                .values
                .iter()
                .find(|(k, _)| k == key)
                .map(|(k, v)| (k.rsplit('.').next().unwrap_or(k).to_string(), v.clone()))
        };
        let set = match spec.parameter.as_str() {
            "scenarios" => overrides
                .scenarios
                .map(|n| ("scenarios".into(), n.to_string())),
            "approach.revolutions" => overrides
                .revolutions
                .map(|n| ("revolutions".into(), n.to_string())),
            "force.controller" => {
                flag_value("force.controller").map(|(_, v)| ("force_controller".into(), v))
            }
            p => flag_value(p),
        };
        if let Some((key, value)) = set {
            return anyhow::anyhow!("--{} {value}: {e}", key.replace('_', "-"));
        }
        if let Some(file) = spec_file {
            return anyhow::anyhow!("sweep spec {}: {e}", file.display());
        }
    }
    e.into()
}

fn summary(r: &tune::Results) {
    let mut front: Vec<&tune::Row> = r.rows.iter().filter(|r| r.pareto).collect();
    front.sort_by_key(|r| r.logic_cells);
    outln!("Pareto front (mean |diameter error| vs float reference against logic cells):");
    outln!(
        "{:>5} {:>12} {:>7} {:>6} {:>6} {:>6} {:>11} {:>9} {:>4} {:>4} {:>10} {:>8}",
        "index",
        "method",
        "rule",
        "chargeb",
        "scaleb",
        "glitch",
        "law",
        "steps",
        "FF",
        "LC",
        "diam_um",
        "revs"
    );
    for x in front {
        outln!(
            "{:>5} {:>12} {:>7} {:>6} {:>6} {:>6} {:>11} {:>9} {:>4} {:>4} {:>10.3} {:>8.2}",
            x.index,
            x.method,
            x.contact_rule,
            x.charge_bits,
            x.scale_bits,
            x.glitch_cycles,
            x.law,
            format!("{}/{}", x.charge, x.discharge),
            x.flip_flops,
            x.logic_cells,
            x.diameter_error_um.unwrap_or(f64::NAN),
            x.revolution_error.unwrap_or(f64::NAN)
        );
    }
    if !r.force.is_empty() {
        outln!("Force control (depth-step scenario, IAE of |F_r − F| in N·s):");
        outln!(
            "{:>5} {:>9} {:>10} {:>5} {:>5} {:>10} {:>10} {:>9} {:>9}",
            "index",
            "ctrl",
            "source",
            "kp%",
            "ki%",
            "IAE model",
            "IAE float",
            "|diff|",
            "overshoot%"
        );
        for x in &r.force {
            outln!(
                "{:>5} {:>9} {:>10} {:>5} {:>5} {:>10.2} {:>10.2} {:>9.3} {:>9.1}",
                x.index,
                x.controller,
                x.force_source,
                x.kp_percent,
                x.ki_percent,
                x.iae_model,
                x.iae_reference,
                x.iae_error,
                x.overshoot_pct
            );
        }
    }
    let misses = r.rows.iter().filter(|r| r.misses > 0).count();
    if misses > 0 {
        outln!("{misses} points missed a decision the reference took (or the reverse)");
    }
}

/// Writes a sweep's files through an [`OutputFolder`]: a run replaces the files of an
/// earlier one (a slice's run removes an earlier whole sweep's pareto.svg), and a failed
/// run leaves the folder as it was.
fn write_folder(results: &tune::Results, dir: &std::path::Path) -> Result<()> {
    let out = OutputFolder::create(
        dir,
        [output::JSON, output::CSV, output::FORCE_CSV, output::SVG],
    )?;
    write_files(results, out.staging())?;
    out.commit()?;
    Ok(())
}

/// Writes a sweep's files into `dir`: the tables ([`output::write`]) and, for a whole
/// sweep, `pareto.svg` ([`tooltouch_plot::pareto`]).
pub fn write_files(results: &tune::Results, dir: &std::path::Path) -> Result<()> {
    output::write(results, dir)?;
    if let Some(rows) = output::pareto_rows(results) {
        let points: Vec<ParetoPoint> = rows
            .iter()
            .map(|&(r, error_um)| ParetoPoint {
                method: r.method.as_str(),
                logic_cells: r.logic_cells,
                // An error below 1 nm is drawn at 1 nm, on the log axis.
                error_um: error_um.max(1e-3),
                on_front: r.pareto,
            })
            .collect();
        tooltouch_plot::pareto::pareto(&points, &dir.join(output::SVG))?;
    }
    Ok(())
}

fn merge(dirs: &[PathBuf], out: &std::path::Path) -> Result<ExitCode> {
    let parts = dirs
        .iter()
        .map(|d| output::read(d))
        .collect::<Result<Vec<_>>>()?;
    let merged = tune::merge(&parts)?;
    write_folder(&merged, out)?;
    outln!(
        "tune merge: {} slices, {} points → {}",
        parts.len(),
        merged.points,
        out.display()
    );
    summary(&merged);
    Ok(ExitCode::SUCCESS)
}

fn point(results: &std::path::Path, index: usize, out: &std::path::Path) -> Result<ExitCode> {
    let r = output::read(results)?;
    let text = tune::point_settings::settings_toml(&r, index)?;
    tooltouch_vectors::output::write_file(out, text.as_bytes())?;
    outln!(
        "{} → {}",
        text.lines().next().unwrap_or("").trim_start_matches("# "),
        out.display()
    );
    Ok(ExitCode::SUCCESS)
}
