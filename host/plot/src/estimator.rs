//! The force estimator against the dynamometer (docs/estimator.md): the depth step and the
//! run-up of [`tooltouch_plant::drive::estimator_report`], each estimate and the dynamometer per
//! control period, in one SVG of two panels.

use super::{draw_legend, err, with_legend_panel, LegendEntry, PlotError, Swatch, CATEGORY};
use plotters::prelude::*;
use std::path::Path;
use tooltouch_plant::drive::estimator_report::{EstimateKind, EstimatorReport};
use tooltouch_plant::drive::scenario::Trace;

/// Time span of the depth-step panel, s.
pub const DEPTH_SPAN: (f64, f64) = (7.0, 11.0);
/// Time span of the run-up panel, s.
pub const RUN_UP_SPAN: (f64, f64) = (0.0, 4.0);

fn panel<DB: DrawingBackend>(
    path: &Path,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    tr: &Trace,
    span: (f64, f64),
) -> Result<(), PlotError> {
    let within = |t: f64| t >= span.0 && t <= span.1;
    let mut series: Vec<(&str, RGBColor, &[f64])> =
        vec![("dynamometer", RGBColor(0, 0, 0), &tr.force_meas)];
    for (i, kind) in EstimateKind::ALL.into_iter().enumerate() {
        series.push((kind.name(), CATEGORY[i + 1], kind.series(tr)));
    }
    let values = series.iter().flat_map(|(_, _, x)| {
        tr.t.iter()
            .zip(x.iter())
            .filter(|(t, _)| within(**t))
            .map(|(_, v)| *v)
    });
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (0.0, 1.0) };
    let pad = 0.05 * (hi - lo).max(1.0);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(span.0..span.1, (lo - pad)..(hi + pad))
        .map_err(|e| err(path, e))?;
    chart
        .configure_mesh()
        .x_desc("t, s")
        .y_desc("force, N")
        .draw()
        .map_err(|e| err(path, e))?;
    for (_, c, x) in series {
        let pts: Vec<(f64, f64)> =
            tr.t.iter()
                .zip(x.iter())
                .filter(|(t, _)| within(**t))
                .map(|(t, v)| (*t, *v))
                .collect();
        chart
            .draw_series(LineSeries::new(pts, c.stroke_width(2)))
            .map_err(|e| err(path, e))?;
    }
    // periods on the fast estimate, as dots on the synthesized line
    let fast: Vec<(f64, f64)> =
        tr.t.iter()
            .zip(&tr.force_est)
            .zip(&tr.fast)
            .filter(|((t, _), f)| **f && within(**t))
            .map(|((t, v), _)| (*t, *v))
            .collect();
    let c = CATEGORY[3];
    chart
        .draw_series(fast.into_iter().map(|p| Circle::new(p, 3, c.filled())))
        .map_err(|e| err(path, e))?;
    Ok(())
}

/// The legend of both panels: the dynamometer, each estimate, F9's fast periods.
fn legend_entries() -> Vec<LegendEntry> {
    let mut entries = vec![LegendEntry::new(
        "dynamometer",
        Swatch::Line(RGBColor(0, 0, 0)),
    )];
    for (i, kind) in EstimateKind::ALL.into_iter().enumerate() {
        entries.push(LegendEntry::new(kind.name(), Swatch::Line(CATEGORY[i + 1])));
    }
    entries.push(LegendEntry::new(
        "F9 on the fast estimate",
        Swatch::Dot(CATEGORY[3]),
    ));
    entries
}

/// Draws the report's two runs into `path`.
pub fn estimator(path: &Path, report: &EstimatorReport) -> Result<(), PlotError> {
    let root = SVGBackend::new(path, (1200, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let (charts, legend) = with_legend_panel(&root);
    draw_legend(&legend, 60, &legend_entries()).map_err(|e| err(path, e))?;
    let (top, bottom) = charts.split_vertically(450);
    panel(
        path,
        &top,
        "Depth step 1 -> 1.5 mm at 8 s, force control off: estimates vs dynamometer",
        &report.depth_step,
        DEPTH_SPAN,
    )?;
    panel(
        path,
        &bottom,
        "Run-up 600 -> 800 rpm without cutting (identification 0.1-2.5 s)",
        &report.run_up,
        RUN_UP_SPAN,
    )?;
    root.present().map_err(|e| err(path, e))
}
