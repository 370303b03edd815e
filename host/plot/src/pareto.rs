//! `pareto.svg` of `tooltouch tune`: each sweep point's latched-diameter error against
//! its FPGA cost, on a log error axis (errors span a scale count's fraction to whole
//! revolutions of feed), one colour per decision method, each method's Pareto front
//! joined by a line.

use super::{
    decades, draw_legend, draw_log_y_axis, err, with_legend_panel, Drawn, LegendEntry, PlotError,
    Swatch, CATEGORY,
};
use plotters::prelude::*;
use std::path::Path;

/// One sweep point as the plot draws it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParetoPoint<'a> {
    /// The decision method, one colour each.
    pub method: &'a str,
    /// FPGA cost, iCE40 logic cells.
    pub logic_cells: u32,
    /// Latched-diameter error against the float reference, µm (> 0: a log axis).
    pub error_um: f64,
    /// Whether the point is on its method's Pareto front.
    pub on_front: bool,
}

/// Draws `points` into `path`.
pub fn pareto(points: &[ParetoPoint], path: &Path) -> Result<(), PlotError> {
    let pts: Vec<(&str, u32, f64, bool)> = points
        .iter()
        .map(|p| (p.method, p.logic_cells, p.error_um, p.on_front))
        .collect();
    let (mut x0, mut x1) = (u32::MAX, 0u32);
    for &(_, x, _, _) in &pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
    }
    if pts.is_empty() {
        (x0, x1) = (0, 1);
    }
    let (lo, hi) = decades(pts.iter().map(|p| p.2));
    let mut methods: Vec<&str> = pts.iter().map(|p| p.0).collect();
    methods.sort_unstable();
    methods.dedup();
    let colour = |i: usize| [CATEGORY[0], CATEGORY[3], CATEGORY[2], CATEGORY[4]][i % 4];
    let root = SVGBackend::new(path, (1000, 600)).into_drawing_area();
    let draw = || -> Drawn {
        root.fill(&WHITE)?;
        let (left, legend) = with_legend_panel(&root);
        let mut chart = ChartBuilder::on(&left)
            .caption(
                "tooltouch tune: latched-diameter error vs FPGA cost",
                ("sans-serif", 20),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(
                x0.saturating_sub(10)..(x1 + 10),
                f64::from(lo)..f64::from(hi),
            )?;
        // The value axis is drawn by hand below (decades, minor ticks); the mesh keeps
        // the logic-cell grid and both axis descriptions.
        chart
            .configure_mesh()
            .y_labels(0)
            .disable_y_mesh()
            .x_desc("logic cells (iCE40 LUT4, estimated)")
            .y_desc("mean |diameter error| vs float reference, µm (log)")
            .draw()?;
        let x_left = x0.saturating_sub(10);
        let x_right = x1 + 10;
        let at = |y: f64| chart.backend_coord(&(x_left, y));
        let grid = |y: f64, style: ShapeStyle| -> Drawn {
            let (a, b) = (at(y), chart.backend_coord(&(x_right, y)));
            root.draw(&PathElement::new([a, b], style))?;
            Ok(())
        };
        draw_log_y_axis(&root, at, lo, hi, grid)?;
        let mut entries = Vec::new();
        for (i, m) in methods.iter().enumerate() {
            let c = colour(i);
            chart.draw_series(
                pts.iter()
                    .filter(|p| p.0 == *m)
                    .map(|&(_, x, y, _)| Circle::new((x, y.log10()), 3, c.mix(0.35).filled())),
            )?;
            let mut front: Vec<(u32, f64)> = pts
                .iter()
                .filter(|p| p.0 == *m && p.3)
                .map(|&(_, x, y, _)| (x, y.log10()))
                .collect();
            front.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
            chart.draw_series(LineSeries::new(front.iter().copied(), c.stroke_width(2)))?;
            chart.draw_series(front.iter().map(|&p| Circle::new(p, 5, c.filled())))?;
            entries.push(LegendEntry::new(
                format!("{m}: every point"),
                Swatch::PaleDot(c),
            ));
            entries.push(LegendEntry::new(
                format!("{m}: Pareto front"),
                Swatch::LineDot(c),
            ));
        }
        draw_legend(&legend, 60, &entries)?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| err(path, e))
}
