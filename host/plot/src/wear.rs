//! The plot of one tool's `tooltouch wear` runs (`wear_<tool>.svg`): the spindle power,
//! the power the monitor watches, each threshold (dashed) and each alarm marked where it
//! happened — at its time, on the watched power that crossed the threshold.

use super::{draw_legend, err, with_legend_panel, Drawn, LegendEntry, PlotError, Swatch};
use plotters::prelude::*;
use std::path::Path;
use tooltouch_plant::milling::WearRun;

/// Colour of the true motor power (the noisy background the monitor filters).
const MOTOR_POWER: RGBColor = RGBColor(170, 170, 170);
/// Colour of the monitored power p̄.
const MONITORED: RGBColor = RGBColor(31, 119, 180);
/// Colours of the thresholds (and their alarms), one per run: saturated and unlike the
/// data's grey and blue; with their dash (length, gap) and width, pixels — the first
/// long and wide, the second short and narrow on top, so both show where they are equal;
/// and the radius of their alarm marker (the second inside the first at the same alarm).
const THRESHOLDS: [(RGBColor, u32, u32, u32, i32); 2] = [
    (RGBColor(214, 39, 40), 14, 6, 4, 10),
    (RGBColor(148, 0, 211), 5, 5, 2, 5),
];

/// The watched power p̄ at the alarm of run `r` (the first sample at or after
/// `alarm_at`), W: where the alarm marker goes.
pub fn alarm_power(r: &WearRun) -> Option<(f64, f64)> {
    let t = r.alarm_at?;
    let i = r.t.iter().position(|&x| x >= t)?;
    Some((t, *r.power.get(i)?))
}

/// Draws the runs of tool `tool` (`(threshold name, run)`) into `path`.
pub fn wear_runs(path: &Path, tool: &str, runs: &[(&str, WearRun)]) -> Result<(), PlotError> {
    let Some((_, first)) = runs.first() else {
        return Err(err(path, "no runs to plot"));
    };
    let t_end = first.t.last().copied().unwrap_or(1.0);
    let pmax = runs
        .iter()
        .flat_map(|(_, r)| r.power_true.iter().chain(&r.allowed))
        .fold(0.0f64, |a, &b| a.max(b))
        * 1.15;
    let root = SVGBackend::new(path, (1100, 500)).into_drawing_area();
    let draw = || -> Drawn {
        root.fill(&WHITE)?;
        let (left, legend) = with_legend_panel(&root);
        let mut c = ChartBuilder::on(&left)
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
            MOTOR_POWER.stroke_width(1),
        ))?;
        c.draw_series(LineSeries::new(
            first.t.iter().zip(&first.power).map(|(&t, &p)| (t, p)),
            MONITORED.stroke_width(2),
        ))?;
        let mut entries = vec![
            LegendEntry::new("motor power (true, period mean)", Swatch::Line(MOTOR_POWER)),
            LegendEntry::new("monitored power p-bar", Swatch::Line(MONITORED)),
        ];
        for ((name, r), (colour, dash, gap, width, radius)) in runs.iter().zip(THRESHOLDS) {
            c.draw_series(DashedLineSeries::new(
                r.t.iter().zip(&r.allowed).map(|(&t, &p)| (t, p)),
                dash,
                gap,
                colour.stroke_width(width),
            ))?;
            entries.push(LegendEntry::new(
                format!("{name} threshold"),
                Swatch::Dashed(colour),
            ));
            match alarm_power(r) {
                Some((t, p)) => {
                    c.draw_series(std::iter::once(Circle::new(
                        (t, p),
                        radius,
                        colour.filled(),
                    )))?;
                    c.draw_series(std::iter::once(Circle::new(
                        (t, p),
                        radius,
                        WHITE.stroke_width(1),
                    )))?;
                    entries.push(LegendEntry::new(
                        format!("{name} alarm: {t:.2} s, {p:.0} W"),
                        Swatch::Dot(colour),
                    ));
                }
                None => entries.push(LegendEntry::new(
                    format!("{name}: no alarm"),
                    Swatch::Dashed(colour),
                )),
            }
        }
        draw_legend(&legend, 50, &entries)?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| err(path, e))
}
