//! `tooltouch budget`: the error budget of the decided diameter predicted from the same
//! settings as `measure` (docs/accuracy.md), term by term for each method and contact rule;
//! `--simulate N` puts the simulated figures beside it; `--out DIR` writes a sweep of
//! predicted against simulated as JSON and a plot. Parsing and printing only: the budget
//! is `tooltouch_metrology`.

use anyhow::Context;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use tooltouch_metrology::budget::{Outcome, Prediction, TermKind};
use tooltouch_metrology::simulate::Simulated;
use tooltouch_metrology::sweep::{predict_variants, simulate_variants, Sweep};
use tooltouch_plant::lathe::LatheScenario;
use tooltouch_settings::Settings;
use tooltouch_vectors::output::OutputFolder;

/// Files `budget --out` writes.
pub const OUTPUTS: [&str; 2] = ["budget.json", "budget.svg"];

/// Arguments of `tooltouch budget`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Settings file (the same TOML as `measure --config`).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Also simulate N measurements per method and contact rule (the golden model on the
    /// simulated lathe) and print them beside the prediction.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(2..=1000))]
    pub simulate: Option<u32>,
    /// Also predict the 1σ of the mean of M measurements at one Z, σ/√M of what changes
    /// between them (the law of S8; default: the
    /// settings' cycle.averages_per_z when above 1, else 4).
    #[arg(long, value_name = "M", value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub averages: Option<u32>,
    /// Write budget.json and budget.svg (predicted, and with --simulate simulated, over
    /// the sweep) into this folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The setting the --out sweep varies: slow-gain, feed-um, mismatch or random.
    #[arg(long, default_value = "slow-gain")]
    pub sweep: Sweep,
    /// The sweep's values, comma-separated (default: per sweep, e.g. slow gain 0,0.5,1,1.5,2,3).
    #[arg(long, value_delimiter = ',')]
    pub sweep_values: Option<Vec<f64>>,
    /// The settings' flags (as `measure`; `--seed` seeds the simulation).
    #[command(flatten)]
    pub flags: super::setting_flags::SettingFlags,
}

fn fmt_outcome(o: &Outcome, sim: Option<&Simulated>, m: u32) -> String {
    let mut s = String::new();
    let name = o.variant().name();
    match o {
        Outcome::Refused { reason, .. } => {
            s.push_str(&format!("{name}: not predicted — {reason}\n"));
        }
        Outcome::Predicted(p) => {
            s.push_str(&format!("{name}: reads {}\n", p.reads));
            s.push_str("  term                               formula         µm (Ø)\n");
            for t in &p.terms {
                let v = match t.kind {
                    TermKind::Bias => format!("{:+8.3}", t.value_um),
                    TermKind::Sigma => format!("±{:7.3}", t.value_um),
                };
                s.push_str(&format!(
                    "  {:<34} {:<13} {v}   {}\n",
                    t.name, t.formula, t.detail
                ));
            }
            s.push_str(&total_line(p, m));
            if let Some(sim) = sim {
                s.push_str(&format!(
                    "  simulated ({} of {} decided): bias {:+.2} µm (± {:.2} standard error), σ {:.2} µm; \
                     vs mean {:+.2}, vs largest {:+.2}\n",
                    sim.decided,
                    sim.repeats,
                    sim.bias_um,
                    sim.bias_standard_error_um,
                    sim.sigma_um,
                    sim.bias_vs_mean_um,
                    sim.bias_vs_largest_um
                ));
            }
        }
    }
    s
}

fn total_line(p: &Prediction, m: u32) -> String {
    let reference = match p.reference {
        tooltouch_metrology::Reference::Mean => "true mean",
        tooltouch_metrology::Reference::Largest => "true largest",
    };
    format!(
        "  predicted: bias {:+.2} ± {:.2} µm (1σ) vs {reference}; 2σ repeatability {:.2} µm; \
         lag {:.2} rev; mean of {m} at one Z: ± {:.2} µm\n",
        p.bias_um,
        p.sigma_um,
        p.repeatability_2sigma_um(),
        p.lag_revs,
        p.sigma_of_mean_um(m)
    )
}

/// Runs `tooltouch budget`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let started = Instant::now();
    let settings: Settings = args.flags.settings(args.config.as_deref())?;
    let (config, scenario) = settings
        .resolve()
        .map_err(|e| args.flags.explain(e, args.config.as_deref()))?;
    let m = args
        .averages
        .unwrap_or(if scenario.cycle.averages_per_z > 1 {
            scenario.cycle.averages_per_z
        } else {
            4
        });
    // The sweep's values checked before any work or output.
    let values = args
        .sweep_values
        .clone()
        .unwrap_or_else(|| args.sweep.default_values());
    if args.out.is_some() {
        for &v in &values {
            args.sweep
                .apply(&scenario, v)
                .validate(&config)
                .with_context(|| format!("--sweep-values {v} (--sweep {:?})", args.sweep))?;
        }
    }
    let outcomes = predict_variants(&settings.measure, &config, &scenario);
    let predicted_s = started.elapsed().as_secs_f64();
    let sims = match args.simulate {
        Some(n) => {
            tooltouch_plant::measurement_cycle::check_run_size(
                &LatheScenario {
                    cycle: tooltouch_plant::lathe::CycleSettings {
                        repeats: n,
                        ..scenario.cycle
                    },
                    ..scenario.clone()
                },
                &config,
            )?;
            simulate_variants(&settings.measure, &scenario, &outcomes, n)?
        }
        None => vec![None; outcomes.len()],
    };
    outln!(
        "error budget of the decided diameter (D = {} mm, {} rpm, f_r = {} mm/rev, {} pulses/rev, \
         window {} rev, i_def {})",
        scenario.diameter_mm,
        scenario.rpm,
        scenario.feed_mm_per_rev,
        config.pulses_per_rev(),
        config.settings().window_revs,
        config.settings().i_def
    );
    for (o, sim) in outcomes.iter().zip(&sims) {
        out!("{}", fmt_outcome(o, sim.as_ref(), m));
    }
    if let Some(dir) = &args.out {
        let out = OutputFolder::create(dir, OUTPUTS)?;
        let mut points = Vec::new();
        for &v in &values {
            let s = args.sweep.apply(&scenario, v);
            let predicted = predict_variants(&settings.measure, &config, &s);
            let simulated = match args.simulate {
                Some(n) => simulate_variants(&settings.measure, &s, &predicted, n)?,
                None => vec![None; predicted.len()],
            };
            points.push(tooltouch_plot::budget::SweepPoint {
                value: v,
                predicted,
                simulated,
            });
        }
        tooltouch_plot::budget::budget_sweep(&out.path("budget.svg"), args.sweep.label(), &points)?;
        let json = serde_json::json!({
            "measure_hash": format!("{:016x}", config.hash()),
            "settings": settings,
            "predicted": outcomes,
            "simulated": sims,
            "sweep": { "setting": args.sweep, "points": points },
        });
        out.write(
            "budget.json",
            serde_json::to_vec_pretty(&json).context("encoding budget.json")?,
        )?;
        out.commit()?;
        outln!("wrote {}", dir.display());
    }
    outln!(
        "predicted in {:.2} s; total {:.2} s",
        predicted_s,
        started.elapsed().as_secs_f64()
    );
    Ok(ExitCode::SUCCESS)
}
