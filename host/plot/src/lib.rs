//! SVG plots of every subcommand, drawn so a person reads them at a glance: the legend in
//! its own panel beside the chart (it never covers data), every series named in it (or,
//! past [`NAMED_SERIES`] series, grouped on a colour scale), decision and threshold lines
//! dashed in a strong colour that the grey grid cannot swallow, integer ticks on count
//! axes and log axes with every decade labelled and minor ticks.
//!
//! One module per subcommand's figures ([`measure`], [`control`], [`wear`], [`pareto`]);
//! this module holds the pieces they share, so the plots look alike.

pub mod budget;
pub mod campaign;
pub mod control;
pub mod estimator;
pub mod measure;
pub mod pareto;
pub mod size_loop;
pub mod wear;

pub use measure::{contact_density, diameters};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
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

pub(crate) fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError {
        file: path.display().to_string(),
        message: e.to_string(),
    }
}

/// What a drawing closure returns: any plotters error, told with the file by [`err`].
pub(crate) type Drawn = Result<(), Box<dyn std::error::Error>>;

/// The SVG drawing area every plot draws on.
pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Ten colours told apart at a glance (the common "category 10" set); series past the
/// tenth go on [`colour_scale`] instead of reusing them.
pub const CATEGORY: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Most series a legend names one by one; more are grouped on a colour scale.
pub const NAMED_SERIES: usize = CATEGORY.len();

/// Colour of decision levels and thresholds: black, dashed and 2 px wide, which neither
/// the light grey grid nor any data colour looks like.
pub const DECISION: RGBColor = RGBColor(0, 0, 0);

/// Width of the legend panel at a plot's right, pixels.
pub const LEGEND_WIDTH: u32 = 280;

/// Colour of series `i` of `n`: [`CATEGORY`] for up to [`NAMED_SERIES`] series, else a
/// dark-blue → green → yellow scale (the perceptually even "viridis" ends) so that
/// neighbouring series have neighbouring colours and no colour repeats.
pub fn colour_scale(i: usize, n: usize) -> RGBColor {
    if n <= NAMED_SERIES {
        return CATEGORY[i % CATEGORY.len()];
    }
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = i as f64 / (n.max(2) - 1) as f64 * (STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// How a legend entry shows its series.
#[derive(Clone, Copy, Debug)]
pub enum Swatch {
    /// A solid line.
    Line(RGBColor),
    /// A dashed line (decision levels, thresholds).
    Dashed(RGBColor),
    /// A filled dot.
    Dot(RGBColor),
    /// A pale dot (many points behind a highlighted few).
    PaleDot(RGBColor),
    /// A line through a dot.
    LineDot(RGBColor),
    /// A colour scale from the first to the last series' colour (`n` series).
    Scale(usize),
}

/// One legend entry.
#[derive(Clone, Debug)]
pub struct LegendEntry {
    /// The series' name, as the SVG's text says it.
    pub label: String,
    /// How it is drawn.
    pub swatch: Swatch,
}

impl LegendEntry {
    /// An entry.
    pub fn new(label: impl Into<String>, swatch: Swatch) -> LegendEntry {
        LegendEntry {
            label: label.into(),
            swatch,
        }
    }
}

/// Splits `root` into the chart's area and a legend panel [`LEGEND_WIDTH`] wide at the
/// right.
pub(crate) fn with_legend_panel<'a>(root: &Area<'a>) -> (Area<'a>, Area<'a>) {
    let (w, _) = root.dim_in_pixel();
    root.split_horizontally(w.saturating_sub(LEGEND_WIDTH))
}

/// Draws `entries` down the legend panel `area`, from `top` pixels.
pub(crate) fn draw_legend(area: &Area, top: i32, entries: &[LegendEntry]) -> Drawn {
    let font = ("sans-serif", 13).into_font().color(&BLACK);
    let mut y = top;
    for e in entries {
        let (x0, x1) = (10, 36);
        match e.swatch {
            Swatch::Line(c) => {
                area.draw(&PathElement::new([(x0, y), (x1, y)], c.stroke_width(2)))?;
            }
            Swatch::Dashed(c) => {
                for k in 0..3 {
                    let a = x0 + k * 10;
                    area.draw(&PathElement::new([(a, y), (a + 6, y)], c.stroke_width(2)))?;
                }
            }
            Swatch::Dot(c) => area.draw(&Circle::new((23, y), 4, c.filled()))?,
            Swatch::PaleDot(c) => area.draw(&Circle::new((23, y), 3, c.mix(0.35).filled()))?,
            Swatch::LineDot(c) => {
                area.draw(&PathElement::new([(x0, y), (x1, y)], c.stroke_width(2)))?;
                area.draw(&Circle::new((23, y), 4, c.filled()))?;
            }
            Swatch::Scale(n) => {
                // A horizontal strip of the scale's colours, first at the left.
                let steps = n.clamp(2, 26);
                for k in 0..steps {
                    let c = colour_scale(k * (n - 1) / (steps - 1), n);
                    let a = x0 + k as i32;
                    area.draw(&Rectangle::new([(a, y - 5), (a + 1, y + 5)], c.filled()))?;
                }
            }
        }
        area.draw(&Text::new(
            e.label.clone(),
            (x1 + 8, y),
            font.clone().pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        y += 20;
    }
    Ok(())
}

/// A tick label for a count axis: the integer at a whole number, nothing between.
pub fn integer_label(x: &f64) -> String {
    if (x - x.round()).abs() < 1e-9 {
        format!("{:.0}", x.round())
    } else {
        String::new()
    }
}

/// The label of the decade `10^k`, in plain decimals (`0.01`, `1`, `100`).
pub fn decade_label(k: i32) -> String {
    if k >= 0 {
        format!("{}", 10u64.pow(k.unsigned_abs().min(18)))
    } else {
        format!("{:.*}", k.unsigned_abs() as usize, 10f64.powi(k))
    }
}

/// The whole decades `(lo, hi)` (`10^lo ..= 10^hi`) that hold every positive value of
/// `values`: at least one decade wide, so a log axis always labels two decades or more.
pub fn decades(values: impl Iterator<Item = f64>) -> (i32, i32) {
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for v in values.filter(|v| *v > 0.0 && v.is_finite()) {
        lo = lo.min(v.log10());
        hi = hi.max(v.log10());
    }
    if lo > hi {
        return (-1, 1);
    }
    let (lo, hi) = (lo.floor() as i32, hi.ceil() as i32);
    (lo, hi.max(lo + 1))
}

/// A log-scaled value axis drawn on a chart whose y coordinate is `log10(value)` over
/// the decades `lo..=hi`: a grid line and a label at every decade, a minor tick (and a
/// fainter grid line) at 2…9 × each decade, and labels at 2 and 5 × too when the axis
/// spans two decades or fewer. `x_left` is the chart's left x coordinate, `at` turns a
/// chart coordinate into the backend's pixel (the chart's `backend_coord`).
pub(crate) fn draw_log_y_axis(
    root: &Area,
    at: impl Fn(f64) -> (i32, i32),
    lo: i32,
    hi: i32,
    grid: impl Fn(f64, ShapeStyle) -> Drawn,
) -> Drawn {
    let font = ("sans-serif", 12).into_font().color(&BLACK);
    let label = |v: f64, text: String| -> Drawn {
        let (px, py) = at(v);
        root.draw(&Text::new(
            text,
            (px - 8, py),
            font.clone().pos(Pos::new(HPos::Right, VPos::Center)),
        ))?;
        Ok(())
    };
    let few = hi - lo <= 2;
    for k in lo..=hi {
        grid(f64::from(k), RGBColor(170, 170, 170).stroke_width(1))?;
        let (px, py) = at(f64::from(k));
        root.draw(&PathElement::new(
            [(px - 6, py), (px, py)],
            BLACK.stroke_width(1),
        ))?;
        label(f64::from(k), decade_label(k))?;
        if k == hi {
            break;
        }
        for m in 2..=9 {
            let y = f64::from(k) + f64::from(m).log10();
            grid(y, RGBColor(228, 228, 228).stroke_width(1))?;
            let (px, py) = at(y);
            root.draw(&PathElement::new(
                [(px - 3, py), (px, py)],
                BLACK.stroke_width(1),
            ))?;
            if few && (m == 2 || m == 5) {
                let digits = (-k).max(0) as usize;
                label(y, format!("{:.*}", digits, f64::from(m) * 10f64.powi(k)))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades_cover_the_values_and_span_at_least_one() {
        assert_eq!(decades([0.04, 7.2].into_iter()), (-2, 1));
        assert_eq!(decades([3.0].into_iter()), (0, 1));
        assert_eq!(decades([0.0, f64::NAN].into_iter()), (-1, 1));
        assert_eq!(decade_label(-2), "0.01");
        assert_eq!(decade_label(0), "1");
        assert_eq!(decade_label(2), "100");
    }

    #[test]
    fn the_colour_scale_never_repeats_a_colour() {
        for n in [1, 6, 10, 11, 40] {
            let mut seen: Vec<RGBColor> = (0..n).map(|i| colour_scale(i, n)).collect();
            seen.dedup();
            assert_eq!(seen.len(), n, "n = {n}");
        }
        assert_eq!(integer_label(&3.0), "3");
        assert_eq!(integer_label(&2.5), "");
    }
}
