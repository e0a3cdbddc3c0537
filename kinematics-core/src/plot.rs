//! SVG plots of sweeps and drawings of the mechanism (feature `plot`).
//!
//! Every axis has a title with its unit: angles in degrees, angular rates
//! in rad/s and rad/s², lengths in metres (the unit of the mechanism's
//! parameters: see [`Units`] for another); the swept driver in degrees when
//! it is an angle, the time in seconds. Curves and links are drawn 2 px
//! wide, grid lines 1 px.
//!
//! | function | what it draws |
//! |---|---|
//! | [`plot_motion`] | q, q', q'' of every unknown against the driver, a panel per quantity and kind (angles, lengths) |
//! | [`plot_points`] | position, velocity and acceleration of named points (components and magnitude) against the driver |
//! | [`plot_path`] | the path of a point (a coupler curve), equal scales |
//! | [`plot_skeleton`] | the linkage at chosen poses, with a legend of their driver values, ground pivots and sliders marked |

use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::sweep::{Sample, Sweep};
use crate::{Coordinates, Error, Kind, Mechanism, MotionState, PointState, Role};

pub use crate::view::Projection;
use crate::view::{point_index, point_roles, PointRole};

/// The length unit written on the axes (the values are plotted as
/// computed, in the unit of the mechanism's parameters).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Units {
    /// The name of the length unit, `"m"` by default.
    pub length: &'static str,
}

impl Units {
    /// Metres.
    pub const METRES: Self = Self { length: "m" };
}

impl Default for Units {
    fn default() -> Self {
        Self::METRES
    }
}

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

const FONT: &str = "sans-serif";

fn output(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output {
        path: path.display().to_string(),
        detail: e.to_string(),
    }
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
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
fn tick(v: f64, span: f64) -> String {
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
fn x_axis<M: Mechanism>(sweep: &Sweep<M>, units: Units) -> (String, f64) {
    if sweep.variable == "t" {
        ("t (s)".to_owned(), 1.0)
    } else if sweep.kind == Kind::Angle {
        (
            format!("{} (deg)", sweep.variable),
            180.0 / std::f64::consts::PI,
        )
    } else {
        (format!("{} ({})", sweep.variable, units.length), 1.0)
    }
}

/// One curve of a panel.
struct Curve {
    label: String,
    points: Vec<(f64, f64)>,
    color: RGBColor,
    width: u32,
}

/// Draws `curves` in `area` with the axis titles `x` and `y`, a caption and
/// a legend.
fn panel(
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

/// A chart of the plane `projection` over equal ranges, axes in metres.
fn plane_chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: &str,
    ranges: ((f64, f64), (f64, f64)),
    projection: Projection,
    path: &Path,
) -> Result<Chart<'a, 'b>, Error> {
    let (xn, yn) = projection.names();
    titled_chart(
        area,
        caption,
        ranges.0,
        ranges.1,
        &format!("{xn} (m)"),
        &format!("{yn} (m)"),
        path,
    )
}

/// The legend of the labelled series, upper right.
fn legend<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, path: &Path) -> Result<(), Error> {
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

/// Plots q, q' and q'' of every unknown against the swept variable into an
/// SVG file at `path`: a row per quantity, a column per kind (angles in
/// degrees with their rates in rad/s and rad/s²; lengths in m, m/s,
/// m/s²), one curve per unknown. The driver is in degrees when it is an
/// angle.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = m.sweep(SliderCrank::PHI, &start).turn().steps(72).rate(6.0).run();
/// let file = std::env::temp_dir().join("slider-crank-motion.svg");
/// kinematics_core::plot::plot_motion(&s, &file)?;
/// let svg = std::fs::read_to_string(&file).expect("written");
/// assert!(svg.contains("phi (deg)") && svg.contains("angular velocity (rad/s)"));
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::Output`] when the file cannot be written.
pub fn plot_motion<M: Mechanism>(sweep: &Sweep<M>, path: &Path) -> Result<(), Error> {
    plot_motion_in(sweep, Units::METRES, path)
}

/// [`plot_motion`] with lengths labelled in `units`.
///
/// # Errors
/// [`Error::Output`] when the file cannot be written.
pub fn plot_motion_in<M: Mechanism>(
    sweep: &Sweep<M>,
    units: Units,
    path: &Path,
) -> Result<(), Error> {
    let (x_title, x_scale) = x_axis(sweep, units);
    let kinds: Vec<Kind> = [Kind::Angle, Kind::Length]
        .into_iter()
        .filter(|k| {
            M::COORDINATES
                .iter()
                .any(|c| c.role == Role::Unknown && c.kind == *k)
        })
        .collect();
    let columns = kinds.len().max(1);
    let width = u32::try_from(560 * columns).unwrap_or(1120);
    let root = SVGBackend::new(path, (width, 960)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let areas = root.split_evenly((3, columns));
    let len = units.length;
    for (col, kind) in kinds.iter().enumerate() {
        let titles: [(&str, String, f64); 3] = match kind {
            Kind::Angle => [
                (
                    "angles",
                    "angle (deg)".to_owned(),
                    180.0 / std::f64::consts::PI,
                ),
                (
                    "angular velocities",
                    "angular velocity (rad/s)".to_owned(),
                    1.0,
                ),
                (
                    "angular accelerations",
                    "angular acceleration (rad/s²)".to_owned(),
                    1.0,
                ),
            ],
            Kind::Length => [
                ("lengths", format!("length ({len})"), 1.0),
                ("linear velocities", format!("velocity ({len}/s)"), 1.0),
                (
                    "linear accelerations",
                    format!("acceleration ({len}/s²)"),
                    1.0,
                ),
            ],
        };
        for (order, (caption, y_title, scale)) in titles.iter().enumerate() {
            let value = |s: &Sample<M>, j: usize| {
                let c = match order {
                    0 => s.motion.q(),
                    1 => s.motion.qd(),
                    _ => s.motion.qdd(),
                };
                c.get(j).unwrap_or(f64::NAN) * scale
            };
            let curves: Vec<Curve> = M::COORDINATES
                .iter()
                .enumerate()
                .filter(|(_, c)| c.role == Role::Unknown && c.kind == *kind)
                .enumerate()
                .map(|(n, (j, c))| Curve {
                    label: c.name.to_owned(),
                    points: sweep
                        .samples
                        .iter()
                        .map(|s| (s.at * x_scale, value(s, j)))
                        .collect(),
                    color: PALETTE[n % PALETTE.len()],
                    width: 2,
                })
                .collect();
            let Some(area) = areas.get(order * columns + col) else {
                continue;
            };
            panel(area, caption, &x_title, y_title, &curves, path)?;
        }
    }
    root.present().map_err(|e| output(path, e))
}

/// Plots the position, velocity and acceleration of each point of `points`
/// (by name) against the swept variable into an SVG file at `path`: a
/// column per point, a row per quantity, each with its components (x, y
/// and for spatial mechanisms z) and, for velocity and acceleration, the
/// magnitude (speed |v| and |a|, drawn thicker).
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = m.sweep(SliderCrank::PHI, &start).turn().steps(72).rpm(600.0).run();
/// let file = std::env::temp_dir().join("slider-crank-points.svg");
/// kinematics_core::plot::plot_points(&s, &["B", "C"], &file)?;
/// let svg = std::fs::read_to_string(&file).expect("written");
/// assert!(svg.contains("velocity (m/s)") && svg.contains("|v|"));
/// // An unknown point is an error, not a panic.
/// assert!(kinematics_core::plot::plot_points(&s, &["Q"], &file).is_err());
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::InvalidGeometry`] for an unknown point, [`Error::Output`] when
/// the file cannot be written.
pub fn plot_points<M: Mechanism>(
    sweep: &Sweep<M>,
    points: &[&str],
    path: &Path,
) -> Result<(), Error> {
    plot_points_in(sweep, points, Units::METRES, path)
}

/// [`plot_points`] with lengths labelled in `units`.
///
/// # Errors
/// As [`plot_points`].
pub fn plot_points_in<M: Mechanism>(
    sweep: &Sweep<M>,
    points: &[&str],
    units: Units,
    path: &Path,
) -> Result<(), Error> {
    let indices: Vec<usize> = points
        .iter()
        .map(|p| point_index::<M>(p, "plot"))
        .collect::<Result<_, _>>()?;
    let (x_title, x_scale) = x_axis(sweep, units);
    let columns = indices.len().max(1);
    let width = u32::try_from(560 * columns).unwrap_or(1120);
    let root = SVGBackend::new(path, (width, 960)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let areas = root.split_evenly((3, columns));
    let len = units.length;
    let axes = ["x", "y", "z"];
    for (col, (&k, name)) in indices.iter().zip(points).enumerate() {
        let rows = [
            ("position", format!("position ({len})"), ""),
            ("velocity", format!("velocity ({len}/s)"), "v"),
            ("acceleration", format!("acceleration ({len}/s²)"), "a"),
        ];
        for (order, (what, y_title, prefix)) in rows.iter().enumerate() {
            let vector = |s: &Sample<M>| -> Vec<f64> {
                s.motion.points().get(k).map_or_else(Vec::new, |p| {
                    match order {
                        0 => p.position(),
                        1 => p.velocity(),
                        _ => p.acceleration(),
                    }
                    .to_vec()
                })
            };
            let mut curves: Vec<Curve> = (0..M::POINT_DIM)
                .map(|c| Curve {
                    label: format!("{prefix}{}", axes.get(c).copied().unwrap_or("?")),
                    points: sweep
                        .samples
                        .iter()
                        .map(|s| {
                            (
                                s.at * x_scale,
                                vector(s).get(c).copied().unwrap_or(f64::NAN),
                            )
                        })
                        .collect(),
                    color: PALETTE[c % PALETTE.len()],
                    width: 2,
                })
                .collect();
            if order > 0 {
                curves.push(Curve {
                    label: format!("|{prefix}|"),
                    points: sweep
                        .samples
                        .iter()
                        .map(|s| {
                            (
                                s.at * x_scale,
                                vector(s).iter().map(|v| v * v).sum::<f64>().sqrt(),
                            )
                        })
                        .collect(),
                    color: BLACK,
                    width: 3,
                });
            }
            let Some(area) = areas.get(order * columns + col) else {
                continue;
            };
            panel(
                area,
                &format!("{what} of {name}"),
                &x_title,
                y_title,
                &curves,
                path,
            )?;
        }
    }
    root.present().map_err(|e| output(path, e))
}

/// Plots the path of point `point` over the sweep (projected for spatial
/// mechanisms) into an SVG file at `path`, with equal scales on both axes
/// and the first sample marked.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = m.sweep(SliderCrank::PHI, &start).turn().steps(72).rate(6.0).run();
/// let dir = std::env::temp_dir();
/// use kinematics_core::plot::{plot_path, Projection};
/// plot_path(&s, "C", Projection::XY, &dir.join("slider-crank-slider.svg"))?;
/// // An unknown point is an error, not a panic.
/// assert!(plot_path(&s, "Q", Projection::XY, &dir.join("none.svg")).is_err());
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::InvalidGeometry`] for an unknown point, [`Error::Output`] when
/// the file cannot be written.
pub fn plot_path<M: Mechanism>(
    sweep: &Sweep<M>,
    point: &str,
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    let xy = path_xy(sweep, point, projection)?;
    let ((x0, x1), (y0, y1)) = square(range(xy.iter().map(|p| p.0)), range(xy.iter().map(|p| p.1)));
    let root = SVGBackend::new(path, (720, 720)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let mut chart = plane_chart(
        &root,
        &format!("path of {point}"),
        ((x0, x1), (y0, y1)),
        projection,
        path,
    )?;
    chart
        .draw_series(LineSeries::new(
            xy.iter().copied(),
            PALETTE[0].stroke_width(2),
        ))
        .map_err(|e| output(path, e))?
        .label(format!("{point} over the sweep"))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], PALETTE[0].stroke_width(2)));
    if let (Some(first), Some(s)) = (xy.first(), sweep.samples.first()) {
        let label = if sweep.variable == "t" {
            format!("start, t = {} s", tick(s.at, 1.0))
        } else if sweep.kind == Kind::Angle {
            format!(
                "start, {} = {}°",
                sweep.variable,
                tick(s.at.to_degrees(), 100.0)
            )
        } else {
            format!("start, {} = {}", sweep.variable, tick(s.at, 0.01))
        };
        chart
            .draw_series(std::iter::once(Circle::new(*first, 5, PALETTE[1].filled())))
            .map_err(|e| output(path, e))?
            .label(label)
            .legend(|(x, y)| Circle::new((x + 8, y), 5, PALETTE[1].filled()));
    }
    legend(&mut chart, path)?;
    root.present().map_err(|e| output(path, e))
}

/// The positions of point `point` over `sweep` in the plane of
/// `projection`.
fn path_xy<M: Mechanism>(
    sweep: &Sweep<M>,
    point: &str,
    projection: Projection,
) -> Result<Vec<(f64, f64)>, Error> {
    let k = point_index::<M>(point, "plot")?;
    let (a, b) = projection.axes();
    Ok(sweep
        .samples
        .iter()
        .filter_map(|s| s.motion.points().get(k))
        .map(|p| {
            let r = p.position();
            (
                r.get(a).copied().unwrap_or(0.0),
                r.get(b).copied().unwrap_or(0.0),
            )
        })
        .collect())
}

/// Plots the path of point `point` over the sweep with its worst-case
/// tolerance band (from [`point_deviations`](crate::tolerance::point_deviations)):
/// at each sample, the nominal position ± the worst-case distance along the
/// path's normal, magnified `magnify` times (tolerance bands are often too
/// thin to see at the scale of the path; the legend says the factor).
///
/// ```
/// use kinematics_core::{mechanism, plot::{plot_band, Projection}, tolerance::point_deviations};
/// mechanism! {
///     /// A crank.
///     pub struct Crank {
///         params { a }
///         drivers { phi }
///         unknowns { }
///         points { B = polar(a, phi); }
///         sensitivities { a }
///     }
/// }
/// let m = Crank { a: 0.1 };
/// let s = m.sweep(Crank::PHI, &CrankCoords { phi: 0.0 }).turn().steps(72).run();
/// let d = point_deviations(&m, &s, "B", &[("a", 0.0005)])?;
/// let file = std::env::temp_dir().join("crank-band.svg");
/// plot_band(&s, "B", &d, 10.0, Projection::XY, &file)?;
/// let svg = std::fs::read_to_string(&file).expect("written");
/// assert!(svg.contains("worst-case band ×10"));
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::InvalidGeometry`] for an unknown point or deviations not of
/// this sweep, [`Error::Output`] when the file cannot be written.
pub fn plot_band<M: Mechanism>(
    sweep: &Sweep<M>,
    point: &str,
    deviations: &[crate::tolerance::Deviation],
    magnify: f64,
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    let k = point_index::<M>(point, "plot")?;
    if deviations.len() != sweep.samples.len() {
        return Err(Error::InvalidGeometry {
            what: "plot",
            detail: format!(
                "{} deviations for {} samples: compute them from this sweep",
                deviations.len(),
                sweep.samples.len()
            ),
        });
    }
    let (a, b) = projection.axes();
    let at = |v: &[f64]| {
        (
            v.get(a).copied().unwrap_or(0.0),
            v.get(b).copied().unwrap_or(0.0),
        )
    };
    let nominal: Vec<(f64, f64)> = sweep
        .samples
        .iter()
        .filter_map(|s| s.motion.points().get(k))
        .map(|p| at(p.position()))
        .collect();
    // The unit normal of the path at each sample, from the velocity.
    let edges: Vec<((f64, f64), (f64, f64))> = sweep
        .samples
        .iter()
        .zip(deviations)
        .filter_map(|(s, d)| {
            let p = s.motion.points().get(k)?;
            let (x, y) = at(p.position());
            let (vx, vy) = at(p.velocity());
            let n = (vx * vx + vy * vy).sqrt();
            let (nx, ny) = if n > 0.0 {
                (-vy / n, vx / n)
            } else {
                (0.0, 0.0)
            };
            let w = magnify * d.position_worst;
            Some(((x + nx * w, y + ny * w), (x - nx * w, y - ny * w)))
        })
        .collect();
    let all = || {
        edges
            .iter()
            .flat_map(|(o, i)| [*o, *i])
            .chain(nominal.iter().copied())
    };
    let ((x0, x1), (y0, y1)) = square(range(all().map(|p| p.0)), range(all().map(|p| p.1)));
    let root = SVGBackend::new(path, (720, 720)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let mut chart = plane_chart(
        &root,
        &format!("path of {point} and its tolerance band"),
        ((x0, x1), (y0, y1)),
        projection,
        path,
    )?;
    // A closed path (a whole turn, its end left out) closes its band too.
    let distance =
        |p: (f64, f64), q: (f64, f64)| ((q.0 - p.0).powi(2) + (q.1 - p.1).powi(2)).sqrt();
    let longest = nominal
        .windows(2)
        .map(|w| distance(w[0], w[1]))
        .fold(0.0f64, f64::max);
    let mut edges = edges;
    let mut nominal = nominal;
    if let (Some(&first), Some(&last), true) = (nominal.first(), nominal.last(), nominal.len() > 2)
    {
        if distance(first, last) <= 1.5 * longest {
            edges.push(edges[0]);
            nominal.push(first);
        }
    }
    let band = RGBColor(214, 39, 40);
    chart
        .draw_series(
            edges.windows(2).map(|w| {
                Polygon::new(vec![w[0].0, w[1].0, w[1].1, w[0].1], band.mix(0.3).filled())
            }),
        )
        .map_err(|e| output(path, e))?
        .label(format!("worst-case band ×{}", tick(magnify, 10.0)))
        .legend(move |(x, y)| {
            Rectangle::new([(x, y - 5), (x + 16, y + 5)], band.mix(0.3).filled())
        });
    chart
        .draw_series(LineSeries::new(
            nominal.iter().copied(),
            PALETTE[0].stroke_width(2),
        ))
        .map_err(|e| output(path, e))?
        .label(format!("nominal path of {point}"))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], PALETTE[0].stroke_width(2)));
    legend(&mut chart, path)?;
    root.present().map_err(|e| output(path, e))
}

/// Equal scales: widens the smaller range to the larger one's span.
fn square(x: (f64, f64), y: (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let span = (x.1 - x.0).max(y.1 - y.0);
    let cx = (x.0 + x.1) / 2.0;
    let cy = (y.0 + y.1) / 2.0;
    (
        (cx - span / 2.0, cx + span / 2.0),
        (cy - span / 2.0, cy + span / 2.0),
    )
}

/// Draws the mechanism's skeleton at each pose of `poses` (one colour per
/// pose, with a legend of each pose's driver values): each link of `links`
/// (pairs of point names) as a line between its points, ground pivots
/// (points whose position depends on no coordinate) as hatched triangles,
/// sliders on a ground guide (points that move along one fixed line) as
/// blocks on a dashed guide, and the points' names beside them. Spatial
/// mechanisms are projected orthographically.
///
/// ```
/// # use kinematics_core::{mechanism, plot::{plot_skeleton, Projection}};
/// # mechanism! {
/// #     /// A four-bar.
/// #     pub struct FourBar {
/// #         params { a, b, c, d }
/// #         drivers { phi }
/// #         unknowns { th3, th4 }
/// #         points { A = vec2(0.0, 0.0); B = polar(a, phi); D = vec2(d, 0.0); C = D + polar(c, th4); }
/// #         loops { B + polar(b, th3) == C; }
/// #     }
/// # }
/// # let m = FourBar { a: 0.04, b: 0.12, c: 0.1, d: 0.11 };
/// let pose = m.assemble(&FourBarCoords { phi: 0.0, th3: 1.0, th4: 1.6 })?;
/// let links = [("A", "B"), ("B", "C"), ("C", "D")];
/// let file = std::env::temp_dir().join("four-bar-skeleton.svg");
/// plot_skeleton(&m, &[pose], &links, Projection::XY, &file)?;
/// let svg = std::fs::read_to_string(&file).expect("written");
/// assert!(svg.contains("phi = 0°"));
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::InvalidGeometry`] for an unknown point, [`Error::Output`] when
/// the file cannot be written.
pub fn plot_skeleton<M: Mechanism>(
    m: &M,
    poses: &[M::Coords],
    links: &[(&str, &str)],
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    plot_skeleton_with(m, poses, links, &Overlay::default(), projection, path)
}

/// Curves and marked points drawn with a skeleton by
/// [`plot_skeleton_with`]: a synthesised coupler curve and its target
/// points, a desired path. Coordinates are in the plane of the projection.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Overlay {
    /// Curves, each with its legend label.
    pub curves: Vec<(String, Vec<(f64, f64)>)>,
    /// Marked points (open circles), each set with its legend label.
    pub marks: Vec<(String, Vec<(f64, f64)>)>,
}

impl Overlay {
    /// The path of point `point` over `sweep`, in the plane of
    /// `projection`, as a curve labelled `label`.
    ///
    /// # Errors
    /// [`Error::InvalidGeometry`] for an unknown point.
    pub fn path<M: Mechanism>(
        mut self,
        sweep: &Sweep<M>,
        point: &str,
        projection: Projection,
        label: &str,
    ) -> Result<Self, Error> {
        self.curves
            .push((label.to_owned(), path_xy(sweep, point, projection)?));
        Ok(self)
    }

    /// Marks `points` (in the plane of the projection), labelled `label`.
    #[must_use]
    pub fn marks(mut self, points: &[(f64, f64)], label: &str) -> Self {
        self.marks.push((label.to_owned(), points.to_vec()));
        self
    }
}

/// [`plot_skeleton`] with the curves and marks of `overlay` drawn under
/// and over the mechanism.
///
/// # Errors
/// As [`plot_skeleton`].
pub fn plot_skeleton_with<M: Mechanism>(
    m: &M,
    poses: &[M::Coords],
    links: &[(&str, &str)],
    overlay: &Overlay,
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    let ends: Vec<(usize, usize)> = links
        .iter()
        .map(|(p, q)| Ok((point_index::<M>(p, "plot")?, point_index::<M>(q, "plot")?)))
        .collect::<Result<_, Error>>()?;
    let (a, b) = projection.axes();
    let dim = M::POINT_DIM;
    let positions: Vec<Vec<(f64, f64)>> = poses
        .iter()
        .map(|pose| {
            let mut flat = vec![0.0; M::POINTS * dim];
            m.point_positions_into(pose, &mut flat);
            flat.chunks(dim)
                .map(|c| {
                    (
                        c.get(a).copied().unwrap_or(0.0),
                        c.get(b).copied().unwrap_or(0.0),
                    )
                })
                .collect()
        })
        .collect();
    let roles = poses.first().map_or_else(Vec::new, |p| point_roles(m, p));
    let extra = || {
        overlay
            .curves
            .iter()
            .chain(&overlay.marks)
            .flat_map(|(_, pts)| pts.iter())
    };
    let all = || positions.iter().flatten().chain(extra());
    let ((x0, x1), (y0, y1)) = square(range(all().map(|p| p.0)), range(all().map(|p| p.1)));
    // Room for the ground symbols and labels.
    let pad = 0.08 * (x1 - x0);
    let ((x0, x1), (y0, y1)) = ((x0 - pad, x1 + pad), (y0 - pad, y1 + pad));
    let root = SVGBackend::new(path, (820, 820)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let mut chart = plane_chart(
        &root,
        "the mechanism at each pose",
        ((x0, x1), (y0, y1)),
        projection,
        path,
    )?;
    let span = x1 - x0;
    // Slider guides: dashed grey lines through each slider's positions.
    for (k, role) in roles.iter().enumerate() {
        if *role != PointRole::Slider {
            continue;
        }
        let pts: Vec<(f64, f64)> = positions.iter().map(|ps| ps[k]).collect();
        let (lo, hi) = extreme_along(&pts);
        let (dx, dy) = (hi.0 - lo.0, hi.1 - lo.1);
        let n = (dx * dx + dy * dy).sqrt();
        let (ux, uy) = if n > 0.0 {
            (dx / n, dy / n)
        } else {
            (1.0, 0.0)
        };
        let ext = 0.06 * span;
        let guide = [
            (lo.0 - ux * ext, lo.1 - uy * ext),
            (hi.0 + ux * ext, hi.1 + uy * ext),
        ];
        chart
            .draw_series(
                dashes(guide[0], guide[1], span / 80.0)
                    .into_iter()
                    .map(|seg| PathElement::new(seg, RGBColor(150, 150, 150).stroke_width(1))),
            )
            .map_err(|e| output(path, e))?;
    }
    for (i, (label, curve)) in overlay.curves.iter().enumerate() {
        let color = RGBColor(120, 120, 120).mix(if i == 0 { 1.0 } else { 0.6 });
        chart
            .draw_series(LineSeries::new(
                curve.iter().copied(),
                color.stroke_width(2),
            ))
            .map_err(|e| output(path, e))?
            .label(label.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2))
            });
    }
    let driver_label = |pose: &M::Coords| -> String {
        M::COORDINATES
            .iter()
            .enumerate()
            .filter(|(_, c)| c.role == Role::Driver)
            .map(|(j, c)| {
                let v = pose.get(j).unwrap_or(f64::NAN);
                match c.kind {
                    Kind::Angle => format!("{} = {}°", c.name, tick(v.to_degrees(), 100.0)),
                    Kind::Length => format!("{} = {} m", c.name, tick(v, 0.01)),
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    for (i, (ps, pose)) in positions.iter().zip(poses).enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        chart
            .draw_series(
                ends.iter()
                    .map(|&(p, q)| PathElement::new(vec![ps[p], ps[q]], color.stroke_width(2))),
            )
            .map_err(|e| output(path, e))?
            .label(driver_label(pose))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2))
            });
        // Joints as small open circles; sliders as blocks.
        chart
            .draw_series(
                roles
                    .iter()
                    .enumerate()
                    .filter(|(_, r)| **r == PointRole::Moving)
                    .map(|(k, _)| Circle::new(ps[k], 3, color.stroke_width(1))),
            )
            .map_err(|e| output(path, e))?;
        chart
            .draw_series(
                roles
                    .iter()
                    .enumerate()
                    .filter(|(_, r)| **r == PointRole::Slider)
                    .map(|(k, _)| {
                        EmptyElement::at(ps[k])
                            + Rectangle::new([(-9, -6), (9, 6)], color.mix(0.25).filled())
                            + Rectangle::new([(-9, -6), (9, 6)], color.stroke_width(2))
                    }),
            )
            .map_err(|e| output(path, e))?;
    }
    for (i, (label, pts)) in overlay.marks.iter().enumerate() {
        let color = PALETTE[(poses.len() + i) % PALETTE.len()];
        chart
            .draw_series(
                pts.iter()
                    .map(|&p| Circle::new(p, 6, color.stroke_width(2))),
            )
            .map_err(|e| output(path, e))?
            .label(label.clone())
            .legend(move |(x, y)| Circle::new((x + 8, y), 6, color.stroke_width(2)));
    }
    let first = positions.first().cloned().unwrap_or_default();
    // Ground pivots: a triangle under the pivot, hatched ground below it.
    chart
        .draw_series(
            roles
                .iter()
                .enumerate()
                .filter(|(_, r)| **r == PointRole::Fixed)
                .map(|(k, _)| {
                    EmptyElement::at(first[k])
                        + Polygon::new(
                            vec![(0, 0), (-9, 14), (9, 14)],
                            RGBColor(90, 90, 90).filled(),
                        )
                        + PathElement::new(vec![(-13, 15), (13, 15)], BLACK.stroke_width(2))
                        + Circle::new((0, 0), 3, WHITE.filled())
                        + Circle::new((0, 0), 3, BLACK.stroke_width(1))
                }),
        )
        .map_err(|e| output(path, e))?;
    chart
        .draw_series(
            roles
                .iter()
                .enumerate()
                .filter(|(_, r)| **r == PointRole::Fixed)
                .flat_map(|(k, _)| {
                    let at = first[k];
                    (0..5).map(move |h| {
                        let x = -12 + 6 * h;
                        EmptyElement::at(at)
                            + PathElement::new(vec![(x, 15), (x - 5, 21)], BLACK.stroke_width(1))
                    })
                }),
        )
        .map_err(|e| output(path, e))?;
    // Names, offset up and to the right of the first pose's points.
    chart
        .draw_series(M::POINT_NAMES.iter().zip(&first).map(|(name, p)| {
            EmptyElement::at(*p) + Text::new((*name).to_owned(), (7, -17), (FONT, 14).into_font())
        }))
        .map_err(|e| output(path, e))?;
    legend(&mut chart, path)?;
    root.present().map_err(|e| output(path, e))
}

/// The two points of `pts` farthest apart along their common line.
fn extreme_along(pts: &[(f64, f64)]) -> ((f64, f64), (f64, f64)) {
    let Some(&first) = pts.first() else {
        return ((0.0, 0.0), (0.0, 0.0));
    };
    let far = pts.iter().copied().fold(first, |best, p| {
        let d = |q: (f64, f64)| (q.0 - first.0).powi(2) + (q.1 - first.1).powi(2);
        if d(p) > d(best) {
            p
        } else {
            best
        }
    });
    let other = pts.iter().copied().fold(far, |best, p| {
        let d = |q: (f64, f64)| (q.0 - far.0).powi(2) + (q.1 - far.1).powi(2);
        if d(p) > d(best) {
            p
        } else {
            best
        }
    });
    (other, far)
}

/// A dashed line from `a` to `b`: segments of length `dash` with equal
/// gaps.
fn dashes(a: (f64, f64), b: (f64, f64), dash: f64) -> Vec<Vec<(f64, f64)>> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = (dx * dx + dy * dy).sqrt();
    if !(len > 0.0 && dash > 0.0) {
        return vec![vec![a, b]];
    }
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let n = ((len / dash) as usize).min(400);
    (0..n)
        .step_by(2)
        .map(|i| {
            #[allow(clippy::cast_precision_loss)]
            let (t0, t1) = (
                i as f64 * dash / len,
                ((i + 1) as f64 * dash / len).min(1.0),
            );
            vec![
                (a.0 + dx * t0, a.1 + dy * t0),
                (a.0 + dx * t1, a.1 + dy * t1),
            ]
        })
        .collect()
}
