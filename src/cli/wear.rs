//! `tooltouch wear`: tool-wear monitoring from spindle power (docs/domain.md §4) — face milling at
//! depth 2 mm then 3 mm, with a new and a worn tool, each watched with the constant and
//! with the updating threshold, through the fixed-point model's wear monitor.

use crate::milling::{WearRun, WearScenario, NEW_TOOL, WORN_TOOL};
use crate::output::OutputFolder;
use anyhow::{Context, Result};
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `tooltouch wear`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Directory for the plots (`wear_<tool>.svg`). A run replaces this command's files in
    /// the folder; other files are left alone; a failed run leaves the folder as it was.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Noise seed.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
}

/// Runs `tooltouch wear`.
pub fn run(args: Args) -> Result<ExitCode> {
    let sc = WearScenario {
        seed: args.seed,
        ..WearScenario::default()
    };
    let out = match &args.out {
        Some(dir) => Some(OutputFolder::create(
            dir,
            [NEW_TOOL, WORN_TOOL].map(|t| format!("wear_{}.svg", t.name)),
        )?),
        None => None,
    };
    let m = &sc.milling;
    outln!(
        "face milling D = {} mm, Z = {}, t = {} mm, s_z = {} mm, {} rpm, [VB] = {} mm, eta = {}",
        m.diameter_mm,
        m.teeth,
        m.width_mm,
        sc.feed_per_tooth_mm,
        sc.rpm,
        sc.vb_limit_mm,
        m.efficiency
    );
    for (i, d) in sc.depths.iter().enumerate() {
        let c = sc.conditions(i);
        let limit = m.mean_power(sc.vb_limit_mm, &c);
        outln!(
            "  cut {} (depth {d} mm, from {:.0} s): [P-bar] = {:.0} W (W7 at [VB]), [P] = {:.0} W (W9)",
            i + 1,
            sc.idle_s + i as f64 * sc.segment_s,
            limit,
            m.motor_power(limit)
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
    for tool in [NEW_TOOL, WORN_TOOL] {
        let mut runs = Vec::new();
        for constant in [true, false] {
            let config = sc
                .config(constant)
                .map_err(|e| anyhow::anyhow!("{e}"))
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
            let cut = r.alarm_at.map(|t| {
                if t < sc.idle_s + sc.segment_s {
                    "1 (2 mm)"
                } else {
                    "2 (3 mm)"
                }
            });
            rows.push(format!(
                "{:<6} {:<10} {:>12} {:>12} {:>10}",
                tool.name,
                name,
                r.alarm_at
                    .map_or("none".to_string(), |t| format!("{t:.2} s")),
                cut.unwrap_or("-"),
                verdict
            ));
            runs.push((name, r));
        }
        if let Some(out) = &out {
            let name = format!("wear_{}.svg", tool.name);
            plot(&out.path(&name), tool.name, &runs)
                .with_context(|| format!("plotting {}", out.final_path(&name).display()))?;
        }
    }
    bar.finish_and_clear();
    for r in rows {
        outln!("{r}");
    }
    if let Some(out) = out {
        let dir = out.dir().to_path_buf();
        out.commit()?;
        outln!("plots written to {}", dir.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn plot(path: &Path, tool: &str, runs: &[(&str, WearRun)]) -> Result<()> {
    let root = SVGBackend::new(path, (1000, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let Some((_, first)) = runs.first() else {
        return Ok(());
    };
    let t_end = first.t.last().copied().unwrap_or(1.0);
    let pmax = runs
        .iter()
        .flat_map(|(_, r)| r.power_true.iter().chain(&r.allowed))
        .fold(0.0f64, |a, &b| a.max(b))
        * 1.15;
    let mut c = ChartBuilder::on(&root)
        .caption(
            format!("{tool} tool: spindle power and thresholds"),
            ("sans-serif", 20),
        )
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..t_end, 0.0..pmax)?;
    c.configure_mesh()
        .x_desc("t, s")
        .y_desc("power, W")
        .draw()?;
    c.draw_series(LineSeries::new(
        first.t.iter().zip(&first.power_true).map(|(&t, &p)| (t, p)),
        RGBColor(180, 180, 180).stroke_width(1),
    ))?
    .label("motor power (true, period mean)")
    .legend(|(x, y)| PathElement::new([(x, y), (x + 15, y)], RGBColor(180, 180, 180)));
    c.draw_series(LineSeries::new(
        first.t.iter().zip(&first.power).map(|(&t, &p)| (t, p)),
        BLUE.stroke_width(2),
    ))?
    .label("monitored p-bar")
    .legend(|(x, y)| PathElement::new([(x, y), (x + 15, y)], BLUE));
    for ((name, r), color) in runs.iter().zip([RED, GREEN]) {
        c.draw_series(LineSeries::new(
            r.t.iter().zip(&r.allowed).map(|(&t, &p)| (t, p)),
            color.stroke_width(2),
        ))?
        .label(format!("{name} threshold"))
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 15, y)], color));
        if let Some(t) = r.alarm_at {
            c.draw_series(std::iter::once(Circle::new(
                (t, pmax * 0.95),
                6,
                color.filled(),
            )))?
            .label(format!("{name} alarm"))
            .legend(move |(x, y)| Circle::new((x + 7, y), 5, color.filled()));
        }
    }
    c.configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE)
        .draw()?;
    root.present()?;
    Ok(())
}
