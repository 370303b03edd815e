//! SVG plots of a measurement run: the contact density per revolution (the burst pattern
//! growing denser, docs/domain.md §1) and the measured diameters against the true ones.

pub mod estimator;

use crate::measurement_cycle::MeasurementReport;
use plotters::prelude::*;
use std::path::Path;

/// A plot that could not be drawn or written.
#[derive(Debug, thiserror::Error)]
#[error("plot {file}: {message}")]
pub struct PlotError {
    /// The file.
    pub file: String,
    /// What went wrong.
    pub message: String,
}

fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError {
        file: path.display().to_string(),
        message: e.to_string(),
    }
}

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// Contact density per revolution of each approach: the model's contact-pulse count of
/// each window divided by the window's pulses (solid), and the fraction of the revolution
/// the contact line was high (dotted points); the decision level `i_def / window_pulses`
/// as a grey line.
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
    let root = SVGBackend::new(path, (900, 540)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Contact density per revolution of each approach",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0f64..revs as f64, 0f64..1.05f64)
        .map_err(|e| err(path, e))?;
    chart
        .configure_mesh()
        .x_desc("revolution since arm")
        .y_desc("contact density")
        .draw()
        .map_err(|e| err(path, e))?;
    let level = f64::from(i_def) / f64::from(window_pulses.max(1));
    chart
        .draw_series(LineSeries::new(
            [(0.0, level), (revs as f64, level)],
            RGBColor(150, 150, 150),
        ))
        .map_err(|e| err(path, e))?
        .label("decision level i_def / window pulses")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], RGBColor(150, 150, 150)));
    for (i, m) in measurements.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
        let model: Vec<(f64, f64)> = m
            .window_counts
            .iter()
            .enumerate()
            .map(|(r, &n)| (r as f64, f64::from(n) / f64::from(window_pulses.max(1))))
            .collect();
        let s = chart
            .draw_series(LineSeries::new(model, c.stroke_width(2)))
            .map_err(|e| err(path, e))?;
        if i < COLORS.len() {
            s.label(format!("measurement {}", m.index + 1))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c));
        }
        chart
            .draw_series(
                m.contact_fraction
                    .iter()
                    .enumerate()
                    .map(|(r, &f)| Circle::new((r as f64 + 1.0, f), 2, c.filled())),
            )
            .map_err(|e| err(path, e))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))
}

/// Measured diameters per measurement (the method's decision and the first-contact
/// reading) against the true mean and largest diameters, µm from the nominal diameter.
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
    let root = SVGBackend::new(path, (900, 540)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("Measured diameters, µm from D = {nominal_mm} mm"),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.5f64..n + 0.5, lo..hi)
        .map_err(|e| err(path, e))?;
    chart
        .configure_mesh()
        .x_desc("measurement")
        .y_desc("diameter − nominal, µm")
        .draw()
        .map_err(|e| err(path, e))?;
    type Reading = Box<dyn Fn(&MeasurementReport) -> Option<f64>>;
    let series: [(&str, RGBColor, Reading); 4] = [
        (
            "true largest",
            COLORS[3],
            Box::new(|m| Some(m.true_largest_diameter_mm)),
        ),
        (
            "true mean",
            COLORS[2],
            Box::new(|m| Some(m.true_mean_diameter_mm)),
        ),
        (
            "first contact",
            COLORS[1],
            Box::new(|m| m.first_contact_diameter_mm),
        ),
        ("decision (method)", COLORS[0], Box::new(|m| m.diameter_mm)),
    ];
    for (label, c, f) in series {
        let pts: Vec<(f64, f64)> = measurements
            .iter()
            .filter_map(|m| f(m).map(|d| (m.index as f64 + 1.0, um(d))))
            .collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(1)))
            .map_err(|e| err(path, e))?;
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))
            .map_err(|e| err(path, e))?
            .label(label)
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))
}
