//! `tooltouch wear`: tool-wear monitoring from spindle power (docs/domain.md §4) — face milling
//! through a sequence of cuts (default: depth 2 mm then 3 mm; `--config`: a `[wear]` table),
//! with a new and a worn tool, each watched with the constant and with the updating
//! threshold, through the fixed-point model's wear monitor; and the mean cutting power
//! P̄(VB) of each condition set (W7).

use anyhow::{Context, Result};
use std::path::PathBuf;
use std::process::ExitCode;
use tooltouch_vectors::output::OutputFolder;

/// Arguments of `tooltouch wear`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Directory for the plots and tables (`wear_<tool>.{svg,csv,json}`,
    /// `wear.{csv,json}`; docs/wear.md). A run replaces this command's files in
    /// the folder; other files are left alone; a failed run leaves the folder as it was.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Noise seed (default 7).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Settings file: a `[wear]` table — the seed, the cutter, the cuts, [VB], idle powers,
    /// efficiency, the tools (examples/wear.toml, docs/wear.md); `--seed` wins over it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Also print the mean cutting power P̄(VB) of every condition set (the table
    /// `wear_vb.{csv,json}` holds).
    #[arg(long)]
    pub vb_table: bool,
}

/// Runs `tooltouch wear`.
pub fn run(args: Args) -> Result<ExitCode> {
    let plan = super::run_settings::wear_plan(args.config.as_deref(), args.seed)?;
    let sc = &plan.scenario;
    let tools = [plan.new_tool, plan.worn_tool];
    let out = match &args.out {
        Some(dir) => {
            let mut known = super::run_tables::table_files("wear").to_vec();
            known.extend(super::run_tables::table_files("wear_vb"));
            for t in &tools {
                known.push(format!("wear_{}.svg", t.name));
                known.extend(super::run_tables::table_files(&format!("wear_{}", t.name)));
            }
            Some(OutputFolder::create(dir, known)?)
        }
        None => None,
    };
    let m = &sc.milling;
    let first = sc.cuts[0].conditions;
    outln!(
        "face milling D = {} mm, Z = {}, t = {} mm, s_z = {} mm, {} rpm, [VB] = {} mm, eta = {}",
        m.diameter_mm,
        m.teeth,
        m.width_mm,
        first.feed_per_tooth_mm,
        (first.rpm * 10.0).round() / 10.0,
        sc.vb_limit_mm,
        m.efficiency
    );
    for (i, cut) in sc.cuts.iter().enumerate() {
        let c = cut.conditions;
        let limit = m.mean_power(sc.vb_limit_mm, &c);
        outln!(
            "  cut {} (depth {} mm, from {:.0} s): [P-bar] = {:.0} W cutting (W7 at [VB]), [P] = {:.0} W motor (W9)",
            i + 1,
            c.depth_mm,
            sc.cut_start(i),
            limit,
            cut.idle_power + limit / m.efficiency
        );
    }
    outln!(
        "{:<6} {:<10} {:>12} {:>12} {:>10}",
        "tool",
        "threshold",
        "alarm at",
        "during cut",
        "verdict"
    );
    let bar = indicatif::ProgressBar::new(4);
    let mut rows = Vec::new();
    let mut verdicts = Vec::new();
    for tool in tools {
        let mut runs = Vec::new();
        for constant in [true, false] {
            let config = sc
                .config(constant)
                .map_err(anyhow::Error::msg)
                .context("configuring the wear monitor")?;
            let r = sc.run(&tool, &config);
            bar.inc(1);
            let name = if constant { "constant" } else { "updating" };
            let worn = tool.vb_start > sc.vb_limit_mm;
            let verdict = match (r.alarm_at.is_some(), worn) {
                (true, true) | (false, false) => "right",
                (true, false) => "FALSE ALARM",
                (false, true) => "MISSED",
            };
            let alarm_cut = r.alarm_at.and_then(|t| sc.cut_at(t));
            let cut =
                alarm_cut.map(|i| format!("{} ({} mm)", i + 1, sc.cuts[i].conditions.depth_mm));
            rows.push(format!(
                "{:<6} {:<10} {:>12} {:>12} {:>10}",
                tool.name,
                name,
                r.alarm_at
                    .map_or("none".to_string(), |t| format!("{t:.2} s")),
                cut.as_deref().unwrap_or("-"),
                verdict
            ));
            verdicts.push(super::run_tables::WearVerdict {
                tool: tool.name,
                threshold: name,
                alarm_at_s: r.alarm_at,
                alarm_power_w: tooltouch_plot::wear::alarm_power(&r).map(|(_, p)| p),
                alarm_cut: alarm_cut.map(|i| i + 1),
                verdict: match verdict {
                    "right" => "right",
                    "FALSE ALARM" => "false-alarm",
                    _ => "missed",
                },
            });
            runs.push((name, r));
        }
        if let Some(out) = &out {
            let name = format!("wear_{}.svg", tool.name);
            tooltouch_plot::wear::wear_runs(&out.path(&name), tool.name, &runs)
                .with_context(|| format!("plotting {}", out.final_path(&name).display()))?;
            if let [(_, constant), (_, updating)] = &runs[..] {
                let series = super::run_tables::wear_series(constant, updating);
                super::run_tables::write_table(
                    out.staging(),
                    &format!("wear_{}", tool.name),
                    &series,
                )?;
            }
        }
    }
    bar.finish_and_clear();
    for r in rows {
        outln!("{r}");
    }
    let vb_rows = super::run_tables::wear_vb_table(sc, plan.worn_tool.vb_start);
    if args.vb_table {
        outln!("mean cutting power P-bar(VB) (W7), W; the motor draws p_i + P-bar/eta");
        let (sets, _) = sc.condition_sets();
        let mut head = format!("{:>8}", "VB mm");
        for (c, _) in &sets {
            let name = format!(
                "b {} s_z {} {:.0} rpm",
                c.depth_mm, c.feed_per_tooth_mm, c.rpm
            );
            head += &format!(" {name:>22}");
        }
        outln!("{head}");
        for chunk in vb_rows.chunks(sets.len().max(1)) {
            let mut line = format!("{:>8.2}", chunk[0].vb_mm);
            for r in chunk {
                line += &format!(" {:>22.0}", r.mean_cutting_power_w);
            }
            outln!("{line}");
        }
    }
    if let Some(out) = out {
        super::run_tables::write_table(out.staging(), "wear_vb", &vb_rows)?;
        super::run_tables::write_table(out.staging(), "wear", &verdicts)?;
        let dir = out.dir().to_path_buf();
        out.commit()?;
        outln!("plots and tables written to {}", dir.display());
    }
    Ok(ExitCode::SUCCESS)
}
