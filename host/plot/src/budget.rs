//! `tooltouch budget --out`: the predicted bias and scatter of each method against the
//! simulated ones, over a sweep of one setting.

use crate::{draw_legend, err, with_legend_panel, Drawn, LegendEntry, PlotError, Swatch, CATEGORY};
use plotters::prelude::*;
use serde::Serialize;
use std::path::Path;
use tooltouch_metrology::budget::{Outcome, Variant};
use tooltouch_metrology::simulate::Simulated;

/// One value of the sweep: each variant's prediction and (if simulated) simulation.
#[derive(Clone, Debug, Serialize)]
pub struct SweepPoint {
    /// The swept setting's value.
    pub value: f64,
    /// One outcome per variant of [`Variant::ALL`].
    pub predicted: Vec<Outcome>,
    /// The simulation of each predicted variant (`None`: refused or not simulated).
    pub simulated: Vec<Option<Simulated>>,
}

/// (swept value, µm) pairs of one variant.
type Series = Vec<(f64, f64)>;

/// Two panels, bias (top) and 1σ (bottom), µm on the diameter, against the swept value:
/// predictions as lines, simulations as dots, one colour per variant.
pub fn budget_sweep(path: &Path, x_label: &str, points: &[SweepPoint]) -> Result<(), PlotError> {
    let n = Variant::ALL.len();
    let series = |i: usize, bias: bool| -> (Series, Series) {
        let mut pred = Vec::new();
        let mut sim = Vec::new();
        for p in points {
            if let Some(pr) = p.predicted.get(i).and_then(Outcome::prediction) {
                pred.push((p.value, if bias { pr.bias_um } else { pr.sigma_um }));
            }
            if let Some(Some(s)) = p.simulated.get(i) {
                sim.push((p.value, if bias { s.bias_um } else { s.sigma_um }));
            }
        }
        (pred, sim)
    };
    let range = |bias: bool| {
        let mut lo = f64::MAX;
        let mut hi = f64::MIN;
        for i in 0..n {
            let (a, b) = series(i, bias);
            for (_, y) in a.iter().chain(&b) {
                lo = lo.min(*y);
                hi = hi.max(*y);
            }
        }
        if lo > hi {
            (-1.0, 1.0)
        } else {
            let pad = ((hi - lo) * 0.1).max(0.1);
            (lo - pad, hi + pad)
        }
    };
    let xs: Vec<f64> = points.iter().map(|p| p.value).collect();
    let x_lo = xs.iter().copied().fold(f64::MAX, f64::min);
    let x_hi = xs.iter().copied().fold(f64::MIN, f64::max);
    let pad = ((x_hi - x_lo) * 0.05).max(0.05);
    let root = SVGBackend::new(path, (1000, 760)).into_drawing_area();
    let draw = || -> Drawn {
        root.fill(&WHITE)?;
        let (left, legend) = with_legend_panel(&root);
        let panels = left.split_evenly((2, 1));
        for (panel, bias) in panels.iter().zip([true, false]) {
            let (lo, hi) = range(bias);
            let mut chart = ChartBuilder::on(panel)
                .caption(
                    if bias {
                        "Bias against the method's reference, µm on the diameter"
                    } else {
                        "Scatter of the decided diameter, µm (1σ)"
                    },
                    ("sans-serif", 18),
                )
                .margin(10)
                .x_label_area_size(36)
                .y_label_area_size(50)
                .build_cartesian_2d(x_lo - pad..x_hi + pad, lo..hi)?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(if bias { "bias, µm" } else { "1σ, µm" })
                .draw()?;
            for (i, &c) in CATEGORY.iter().enumerate().take(n) {
                let (pred, sim) = series(i, bias);
                chart.draw_series(LineSeries::new(pred, c.stroke_width(2)))?;
                chart.draw_series(sim.iter().map(|&p| Circle::new(p, 4, c.filled())))?;
            }
        }
        let mut entries = Vec::new();
        for (i, v) in Variant::ALL.iter().enumerate() {
            entries.push(LegendEntry::new(
                format!("{} predicted", v.name()),
                Swatch::Line(CATEGORY[i]),
            ));
            entries.push(LegendEntry::new(
                format!("{} simulated", v.name()),
                Swatch::Dot(CATEGORY[i]),
            ));
        }
        draw_legend(&legend, 50, &entries)?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| err(path, e))
}
