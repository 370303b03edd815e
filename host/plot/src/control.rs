//! The plot of one `tooltouch control` run (`<controller>_<force>.svg`): the cutting
//! force (reference, true, estimated) above and the feed override below, sharing the
//! time axis, with the depth step marked on both.

use super::{draw_legend, err, with_legend_panel, Drawn, LegendEntry, PlotError, Swatch, DECISION};
use plotters::prelude::*;
use std::path::Path;
use tooltouch_plant::drive::scenario::Run;

/// Colour of the true force.
const TRUE_FORCE: RGBColor = RGBColor(31, 119, 180);
/// Colour of the estimated force.
const ESTIMATED_FORCE: RGBColor = RGBColor(214, 39, 40);
/// Colour of the feed override.
const OVERRIDE: RGBColor = RGBColor(44, 160, 44);

/// Draws run `r` titled `title` into `path`; `reference_n` is the force reference, N,
/// and `step_s` the time of the depth step, s.
pub fn control_run(
    path: &Path,
    r: &Run,
    title: &str,
    reference_n: f64,
    step_s: f64,
) -> Result<(), PlotError> {
    let tr = &r.trace;
    let t_end = tr.t.last().copied().unwrap_or(1.0);
    let fmax = tr
        .force_true
        .iter()
        .chain(&tr.force_est)
        .fold(reference_n * 1.2, |a, &b| a.max(b))
        * 1.1;
    let root = SVGBackend::new(path, (1100, 700)).into_drawing_area();
    let draw = || -> Drawn {
        root.fill(&WHITE)?;
        let (left, legend) = with_legend_panel(&root);
        let (top, bottom) = left.split_vertically(450);
        let mut c = ChartBuilder::on(&top)
            .caption(format!("{title}: cutting force"), ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..t_end, 0.0..fmax)?;
        c.configure_mesh()
            .x_desc("t, s")
            .y_desc("force, N")
            .draw()?;
        c.draw_series(LineSeries::new(
            tr.t.iter().zip(&tr.force_true).map(|(&t, &f)| (t, f)),
            TRUE_FORCE.stroke_width(2),
        ))?;
        c.draw_series(LineSeries::new(
            tr.t.iter().zip(&tr.force_est).map(|(&t, &f)| (t, f)),
            ESTIMATED_FORCE.stroke_width(1),
        ))?;
        c.draw_series(DashedLineSeries::new(
            [(0.0, reference_n), (t_end, reference_n)],
            8,
            5,
            DECISION.stroke_width(2),
        ))?;
        c.draw_series(DashedLineSeries::new(
            [(step_s, 0.0), (step_s, fmax)],
            3,
            4,
            RGBColor(90, 90, 90).stroke_width(1),
        ))?;
        let mut c = ChartBuilder::on(&bottom)
            .caption("feed override", ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..t_end, 0.0..160.0)?;
        c.configure_mesh()
            .x_desc("t, s")
            .y_desc("override, %")
            .draw()?;
        c.draw_series(LineSeries::new(
            tr.t.iter()
                .zip(&tr.override_pct)
                .map(|(&t, &o)| (t, f64::from(o))),
            OVERRIDE.stroke_width(2),
        ))?;
        c.draw_series(DashedLineSeries::new(
            [(step_s, 0.0), (step_s, 160.0)],
            3,
            4,
            RGBColor(90, 90, 90).stroke_width(1),
        ))?;
        draw_legend(
            &legend,
            50,
            &[
                LegendEntry::new(
                    format!("force reference {reference_n:.0} N"),
                    Swatch::Dashed(DECISION),
                ),
                LegendEntry::new("true force", Swatch::Line(TRUE_FORCE)),
                LegendEntry::new("estimated force", Swatch::Line(ESTIMATED_FORCE)),
                LegendEntry::new("feed override (lower plot)", Swatch::Line(OVERRIDE)),
                LegendEntry::new(
                    format!("depth step at {step_s} s"),
                    Swatch::Dashed(RGBColor(90, 90, 90)),
                ),
            ],
        )?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| err(path, e))
}
