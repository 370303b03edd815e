//! The plots of `tooltouch measure`: the contact density per revolution (the burst pattern
//! growing denser, docs/domain.md §1) and the measured diameters against the true ones.

use super::{
    colour_scale, draw_legend, err, integer_label, with_legend_panel, Drawn, LegendEntry,
    PlotError, Swatch, CATEGORY, DECISION, NAMED_SERIES,
};
use plotters::prelude::*;
use std::path::Path;
use tooltouch_plant::measurement_cycle::MeasurementReport;

/// Contact density per revolution of each approach: the model's contact-pulse count of
/// each window divided by the window's pulses (a line per measurement, each its own
/// colour, named in the legend up to ten and on a colour scale past that), and the
/// fraction of the revolution the contact line was high (dots); the decision level
/// `i_def / window_pulses` as a dashed black line.
pub fn contact_density(
    path: &Path,
    measurements: &[MeasurementReport],
    window_pulses: u32,
    i_def: u32,
) -> Result<(), PlotError> {
    let revs = measurements
        .iter()
        .map(|m| m.window_counts.len().max(m.contact_fraction.len()))
        .max()
        .unwrap_or(1)
        .max(1);
    let n = measurements.len();
    let root = SVGBackend::new(path, (1000, 540)).into_drawing_area();
    let draw = || -> Drawn {
        root.fill(&WHITE)?;
        let (left, legend) = with_legend_panel(&root);
        let mut chart = ChartBuilder::on(&left)
            .caption(
                "Contact density per revolution of each approach",
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0f64..revs as f64, 0f64..1.05f64)?;
        chart
            .configure_mesh()
            .x_desc("revolution since arm")
            .y_desc("contact density")
            .x_label_formatter(&integer_label)
            .draw()?;
        for (i, m) in measurements.iter().enumerate() {
            let c = colour_scale(i, n);
            let model: Vec<(f64, f64)> = m
                .window_counts
                .iter()
                .enumerate()
                .map(|(r, &k)| (r as f64, f64::from(k) / f64::from(window_pulses.max(1))))
                .collect();
            chart.draw_series(LineSeries::new(model, c.stroke_width(2)))?;
            chart.draw_series(
                m.contact_fraction
                    .iter()
                    .enumerate()
                    .map(|(r, &f)| Circle::new((r as f64 + 1.0, f), 2, c.filled())),
            )?;
        }
        // Drawn last, over the data, so no measurement's line hides it.
        let level = f64::from(i_def) / f64::from(window_pulses.max(1));
        chart.draw_series(DashedLineSeries::new(
            [(0.0, level), (revs as f64, level)],
            8,
            5,
            DECISION.stroke_width(2),
        ))?;
        let mut entries = vec![
            LegendEntry::new(
                format!("decision level i_def / window = {level:.3}"),
                Swatch::Dashed(DECISION),
            ),
            LegendEntry::new(
                "line: model count / window pulses",
                Swatch::Line(CATEGORY[7]),
            ),
            LegendEntry::new(
                "dot: time in contact / revolution",
                Swatch::Dot(CATEGORY[7]),
            ),
        ];
        if n <= NAMED_SERIES {
            entries.extend(measurements.iter().enumerate().map(|(i, m)| {
                LegendEntry::new(
                    format!("measurement {}", m.index + 1),
                    Swatch::Line(colour_scale(i, n)),
                )
            }));
        } else {
            let first = measurements.first().map_or(1, |m| m.index + 1);
            let last = measurements.last().map_or(n, |m| m.index + 1);
            entries.push(LegendEntry::new(
                format!("measurements {first} (left) … {last} (right)"),
                Swatch::Scale(n),
            ));
        }
        draw_legend(&legend, 50, &entries)?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| err(path, e))
}

/// Measured diameters per measurement (the method's decision and the first-contact
/// reading) against the true mean and largest diameters, µm from the nominal diameter;
/// the measurement axis ticks whole measurement numbers.
pub fn diameters(
    path: &Path,
    measurements: &[MeasurementReport],
    nominal_mm: f64,
) -> Result<(), PlotError> {
    let um = |mm: f64| (mm - nominal_mm) * 1000.0;
    let mut values: Vec<f64> = Vec::new();
    for m in measurements {
        values.extend(m.diameter_mm.map(um));
        values.extend(m.first_contact_diameter_mm.map(um));
        values.push(um(m.true_mean_diameter_mm));
        values.push(um(m.true_largest_diameter_mm));
    }
    let lo = values.iter().copied().fold(f64::MAX, f64::min).min(0.0) - 1.0;
    let hi = values.iter().copied().fold(f64::MIN, f64::max).max(0.0) + 1.0;
    let n = measurements.len().max(1) as f64;
    type Reading = Box<dyn Fn(&MeasurementReport) -> Option<f64>>;
    let series: [(&str, RGBColor, Reading); 4] = [
        (
            "true largest diameter",
            CATEGORY[3],
            Box::new(|m| Some(m.true_largest_diameter_mm)),
        ),
        (
            "true mean diameter",
            CATEGORY[2],
            Box::new(|m| Some(m.true_mean_diameter_mm)),
        ),
        (
            "first contact",
            CATEGORY[1],
            Box::new(|m| m.first_contact_diameter_mm),
        ),
        (
            "decision (the method's)",
            CATEGORY[0],
            Box::new(|m| m.diameter_mm),
        ),
    ];
    let root = SVGBackend::new(path, (1000, 540)).into_drawing_area();
    let draw = || -> Drawn {
        root.fill(&WHITE)?;
        let (left, legend) = with_legend_panel(&root);
        let mut chart = ChartBuilder::on(&left)
            .caption(
                format!("Measured diameters, µm from D = {nominal_mm} mm"),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.5f64..n + 0.5, lo..hi)?;
        chart
            .configure_mesh()
            .x_desc("measurement")
            .y_desc("diameter − nominal, µm")
            .x_labels((n as usize).min(20))
            .x_label_formatter(&integer_label)
            .draw()?;
        for (_, c, f) in &series {
            let pts: Vec<(f64, f64)> = measurements
                .iter()
                .filter_map(|m| f(m).map(|d| (m.index as f64 + 1.0, um(d))))
                .collect();
            chart.draw_series(LineSeries::new(pts.clone(), c.stroke_width(1)))?;
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))?;
        }
        let entries: Vec<LegendEntry> = series
            .iter()
            .map(|(label, c, _)| LegendEntry::new(*label, Swatch::LineDot(*c)))
            .collect();
        draw_legend(&legend, 50, &entries)?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| err(path, e))
}
