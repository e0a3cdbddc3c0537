//! What the figures share: units, colours, axis ranges and ticks, the
//! panels and charts they are drawn on, and their legends.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::error::Error;
use crate::mechanism::Kind;
use crate::sweep::Table;
use crate::units::AngleUnit;
use crate::view::Projection;

/// The units written on the axes: the length unit's name (lengths are
/// plotted as computed, in the unit of the mechanism's parameters), and
/// the unit of angular rates and accelerations (angles themselves are
/// plotted in degrees).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Units {
    /// The name of the length unit, `"m"` by default.
    pub length: &'static str,
    /// Angular velocities in rad/s or deg/s, accelerations in rad/s² or
    /// deg/s² (radians by default).
    pub angle: AngleUnit,
}

impl Units {
    /// Metres, and angular rates in radians.
    pub const METRES: Self = Self {
        length: "m",
        angle: AngleUnit::Radians,
    };
}

impl Default for Units {
    fn default() -> Self {
        Self::METRES
    }
}

pub(super) const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

pub(super) const FONT: &str = "sans-serif";

pub(super) fn output(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output {
        path: path.display().to_string(),
        detail: e.to_string(),
    }
}

pub(super) fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9 * (1.0 + hi.abs().max(lo.abs())));
    (lo - pad, hi + pad)
}

/// A tick label: as many decimals as the axis span needs, and never "-0".
pub(super) fn tick(v: f64, span: f64) -> String {
    let decimals = if span > 0.0 && span.is_finite() {
        // Up to about ten ticks: enough decimals for a tenth of the span.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let d = (-(span / 10.0).log10()).ceil().max(0.0) as usize;
        d.min(9)
    } else {
        3
    };
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_owned()
    } else {
        s
    }
}

/// The x axis of a sweep: its title and the factor from the swept value.
pub(super) fn x_axis<T: Table + ?Sized>(sweep: &T, units: Units) -> (String, f64) {
    let variable = sweep.variable();
    if variable == "t" {
        ("t (s)".to_owned(), 1.0)
    } else if sweep.kind() == Kind::Angle {
        (format!("{variable} (deg)"), 180.0 / std::f64::consts::PI)
    } else {
        (format!("{variable} ({})", units.length), 1.0)
    }
}

/// One curve of a panel.
pub(super) struct Curve {
    pub(super) label: String,
    pub(super) points: Vec<(f64, f64)>,
    pub(super) color: RGBColor,
    pub(super) width: u32,
}

/// Draws `curves` in `area` with the axis titles `x` and `y`, a caption and
/// a legend.
pub(super) fn panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    caption: &str,
    x: &str,
    y: &str,
    curves: &[Curve],
    path: &Path,
) -> Result<(), Error> {
    let (x0, x1) = range(curves.iter().flat_map(|c| c.points.iter().map(|p| p.0)));
    let (y0, y1) = range(curves.iter().flat_map(|c| c.points.iter().map(|p| p.1)));
    // Room above the curves for the legend.
    let y1 = y1 + 0.06 * (y1 - y0) * (curves.len() as f64);
    let mut chart = titled_chart(area, caption, (x0, x1), (y0, y1), x, y, path)?;
    for c in curves {
        let color = c.color;
        chart
            .draw_series(LineSeries::new(
                c.points.iter().copied(),
                color.stroke_width(c.width),
            ))
            .map_err(|e| output(path, e))?
            .label(c.label.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2))
            });
    }
    legend(&mut chart, path)
}

/// A chart in `area` over [x0, x1] × [y0, y1] with its caption, the axis
/// titles `x` and `y`, ticks that never read "-0", and a light grid.
#[allow(clippy::too_many_arguments)]
fn titled_chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: &str,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    x: &str,
    y: &str,
    path: &Path,
) -> Result<Chart<'a, 'b>, Error> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, 17))
        .margin(10)
        .x_label_area_size(42)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| output(path, e))?;
    let (xs, ys) = (x1 - x0, y1 - y0);
    chart
        .configure_mesh()
        .x_desc(x)
        .y_desc(y)
        .axis_desc_style((FONT, 14))
        .label_style((FONT, 12))
        .x_label_formatter(&|v| tick(*v, xs))
        .y_label_formatter(&|v| tick(*v, ys))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| output(path, e))?;
    Ok(chart)
}

/// A chart of the plane `projection` over equal ranges, axes in the
/// length unit named `length`.
pub(super) fn plane_chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: &str,
    ranges: ((f64, f64), (f64, f64)),
    (projection, length): (Projection, &str),
    path: &Path,
) -> Result<Chart<'a, 'b>, Error> {
    let (xn, yn) = projection.names();
    titled_chart(
        area,
        caption,
        ranges.0,
        ranges.1,
        &format!("{xn} ({length})"),
        &format!("{yn} ({length})"),
        path,
    )
}

/// The legend of the labelled series, upper right.
pub(super) fn legend<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, path: &Path) -> Result<(), Error> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FONT, 13))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(160, 160, 160))
        .draw()
        .map_err(|e| output(path, e))
}

/// A chart of the SVG backend in plain coordinates.
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;
