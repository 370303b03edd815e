//! The fault campaign's plot, one per fault kind (docs/faults.md): the share of the
//! measurements in each class against the fault's level, one line per class and decision
//! method (counter solid, density dashed, single pulse dotted by its marker).

use super::{draw_legend, err, with_legend_panel, Drawn, LegendEntry, PlotError, Swatch, CATEGORY};
use plotters::prelude::*;
use std::path::Path;
use tooltouch_metrology::campaign::{method_name, CellResult, Class, FaultKind};

/// Draws the cells of `kind` in `cells` into `path`: each class's share (%) against the
/// level (a log axis when the levels span a decade or more).
pub fn campaign_kind(path: &Path, kind: FaultKind, cells: &[CellResult]) -> Result<(), PlotError> {
    let mine: Vec<&CellResult> = cells.iter().filter(|c| c.key.kind == kind).collect();
    if mine.is_empty() {
        return Err(err(path, format!("no cell of {} to plot", kind.name())));
    }
    let mut methods: Vec<_> = mine.iter().map(|c| c.key.method).collect();
    methods.dedup();
    methods.sort_by_key(|m| *m as u8);
    methods.dedup();
    let levels: Vec<f64> = mine.iter().map(|c| c.key.level).collect();
    let (lo, hi) = levels
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &l| (a.min(l), b.max(l)));
    let log = hi / lo >= 10.0;
    let x = |l: f64| if log { l.log10() } else { l };
    let (x0, x1) = if (x(hi) - x(lo)).abs() < 1e-12 {
        (x(lo) - 0.5, x(hi) + 0.5)
    } else {
        let pad = (x(hi) - x(lo)) * 0.05;
        (x(lo) - pad, x(hi) + pad)
    };
    let root = SVGBackend::new(path, (1000, 500)).into_drawing_area();
    let draw = || -> Drawn {
        root.fill(&WHITE)?;
        let (left, legend) = with_legend_panel(&root);
        let mut c = ChartBuilder::on(&left)
            .caption(
                format!("fault campaign: {}", kind.name()),
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(x0..x1, -2.0..102.0)?;
        let unit = kind.unit();
        let x_desc = if log {
            format!("log10 level, {unit}")
        } else {
            format!("level, {unit}")
        };
        c.configure_mesh()
            .x_desc(x_desc)
            .y_desc("measurements, %")
            .draw()?;
        let mut entries = Vec::new();
        for (ci, class) in Class::ALL.into_iter().enumerate() {
            let colour = CATEGORY[ci % CATEGORY.len()];
            for (mi, &method) in methods.iter().enumerate() {
                let mut points: Vec<(f64, f64)> = mine
                    .iter()
                    .filter(|c| c.key.method == method)
                    .map(|c| {
                        let share = f64::from(c.counts.of(class))
                            / f64::from(c.counts.total().max(1))
                            * 100.0;
                        (x(c.key.level), share)
                    })
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                if points.iter().all(|p| p.1 == 0.0) {
                    continue;
                }
                let style = colour.stroke_width(2);
                if mi == 1 {
                    c.draw_series(DashedLineSeries::new(points.clone(), 8, 5, style))?;
                } else {
                    c.draw_series(LineSeries::new(points.clone(), style))?;
                }
                c.draw_series(points.iter().map(|&p| -> DynElement<_, _> {
                    match mi {
                        0 => Circle::new(p, 4, colour.filled()).into_dyn(),
                        1 => TriangleMarker::new(p, 5, colour.filled()).into_dyn(),
                        _ => Cross::new(p, 5, colour.stroke_width(2)).into_dyn(),
                    }
                }))?;
                let name = method_name(method);
                let swatch = if mi == 1 {
                    Swatch::Dashed(colour)
                } else {
                    Swatch::Line(colour)
                };
                entries.push(LegendEntry::new(
                    format!("{}, {name}", class.name()),
                    swatch,
                ));
            }
        }
        draw_legend(&legend, 50, &entries)?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| err(path, e))
}
