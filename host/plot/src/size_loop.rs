//! The plot of the measure-then-correct size loop (docs/linuxcnc.md): each part's diameter
//! without and with the tool-offset correction, the in-process measurement, and the
//! tolerance limits (dashed).

use super::{draw_legend, err, with_legend_panel, Drawn, LegendEntry, PlotError, Swatch};
use plotters::prelude::*;
use std::path::Path;

const UNCORRECTED: RGBColor = RGBColor(214, 39, 40);
const CORRECTED: RGBColor = RGBColor(31, 119, 180);
const MEASURED: RGBColor = RGBColor(44, 160, 44);
const LIMITS: RGBColor = RGBColor(90, 90, 90);

/// Draws parts `1..=n` into `path`: `uncorrected`, `corrected` and `measured` diameters,
/// mm (NaN: not measured), against `nominal ± tolerance`, mm.
pub fn size_loop(
    path: &Path,
    nominal: f64,
    tolerance: f64,
    uncorrected: &[f64],
    corrected: &[f64],
    measured: &[f64],
) -> Result<(), PlotError> {
    if uncorrected.is_empty() {
        return Err(err(path, "no parts to plot"));
    }
    let n = uncorrected.len() as f64;
    let finite = uncorrected
        .iter()
        .chain(corrected)
        .chain(measured)
        .filter(|v| v.is_finite());
    let (lo, hi) = finite.fold((nominal - tolerance, nominal + tolerance), |(a, b), &v| {
        (a.min(v), b.max(v))
    });
    let pad = (hi - lo) * 0.1;
    // µm from the nominal on the y axis.
    let um = |v: f64| (v - nominal) * 1e3;
    let root = SVGBackend::new(path, (1000, 500)).into_drawing_area();
    let draw = || -> Drawn {
        root.fill(&WHITE)?;
        let (left, legend) = with_legend_panel(&root);
        let mut c = ChartBuilder::on(&left)
            .caption(
                format!("size loop: Ø{nominal} ± {tolerance} mm"),
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(60)
            .build_cartesian_2d(0.5..n + 0.5, um(lo - pad)..um(hi + pad))?;
        c.configure_mesh()
            .x_desc("part")
            .y_desc("diameter − nominal, µm")
            .draw()?;
        for limit in [tolerance, -tolerance] {
            c.draw_series(DashedLineSeries::new(
                [(0.5, limit * 1e3), (n + 0.5, limit * 1e3)],
                8,
                5,
                LIMITS.stroke_width(2),
            ))?;
        }
        let series = [
            (uncorrected, UNCORRECTED, "without correction"),
            (corrected, CORRECTED, "with correction"),
        ];
        for (values, colour, _) in series {
            c.draw_series(LineSeries::new(
                values
                    .iter()
                    .enumerate()
                    .map(|(i, &v)| (i as f64 + 1.0, um(v))),
                colour.stroke_width(2),
            ))?;
            c.draw_series(
                values
                    .iter()
                    .enumerate()
                    .map(|(i, &v)| Circle::new((i as f64 + 1.0, um(v)), 4, colour.filled())),
            )?;
        }
        c.draw_series(
            measured
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_finite())
                .map(|(i, &v)| Cross::new((i as f64 + 1.0, um(v)), 5, MEASURED.stroke_width(2))),
        )?;
        let entries = vec![
            LegendEntry::new("without correction", Swatch::LineDot(UNCORRECTED)),
            LegendEntry::new("with correction", Swatch::LineDot(CORRECTED)),
            LegendEntry::new("measured in process", Swatch::Dot(MEASURED)),
            LegendEntry::new("tolerance limits", Swatch::Dashed(LIMITS)),
        ];
        draw_legend(&legend, 50, &entries)?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| err(path, e))
}
