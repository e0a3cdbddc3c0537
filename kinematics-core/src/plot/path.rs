//! Figures in the plane of the mechanism: a point's path
//! ([`plot_path`]) and its tolerance band ([`plot_band`]).

use std::path::Path;

use plotters::prelude::*;

use crate::error::Error;
use crate::mechanism::Kind;
use crate::sweep::Table;
use crate::view::Projection;

use super::chart::{PALETTE, Units, legend, output, plane_chart, range, tick};

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
pub fn plot_path<T: Table + ?Sized>(
    sweep: &T,
    point: &str,
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    plot_path_in(sweep, point, projection, Units::METRES, path)
}

/// [`plot_path`] with the axes in the length unit of `units`.
///
/// # Errors
/// As [`plot_path`].
pub fn plot_path_in<T: Table + ?Sized>(
    sweep: &T,
    point: &str,
    projection: Projection,
    units: Units,
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
        (projection, units.length),
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
    if let (Some(first), true) = (xy.first(), sweep.rows() > 0) {
        let (variable, at) = (sweep.variable(), sweep.at(0));
        let label = if variable == "t" {
            format!("start, t = {} s", tick(at, 1.0))
        } else if sweep.kind() == Kind::Angle {
            format!("start, {variable} = {}°", tick(at.to_degrees(), 100.0))
        } else {
            format!("start, {variable} = {}", tick(at, 0.01))
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
pub(super) fn path_xy<T: Table + ?Sized>(
    sweep: &T,
    point: &str,
    projection: Projection,
) -> Result<Vec<(f64, f64)>, Error> {
    let k = sweep.point_index(point, "plot")?;
    Ok((0..sweep.rows())
        .map(|i| projection.of(sweep.point(i, k)[0]))
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
pub fn plot_band<T: Table + ?Sized>(
    sweep: &T,
    point: &str,
    deviations: &[crate::tolerance::Deviation],
    magnify: f64,
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    let k = sweep.point_index(point, "plot")?;
    if deviations.len() != sweep.rows() {
        return Err(Error::InvalidGeometry {
            what: "plot",
            detail: format!(
                "{} deviations for {} samples: compute them from this sweep",
                deviations.len(),
                sweep.rows()
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
    let nominal: Vec<(f64, f64)> = (0..sweep.rows())
        .map(|i| at(sweep.point(i, k)[0]))
        .collect();
    // The unit normal of the path at each sample, from the velocity.
    let edges: Vec<((f64, f64), (f64, f64))> = deviations
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let [r, v, _] = sweep.point(i, k);
            let (x, y) = at(r);
            let (vx, vy) = at(v);
            let n = (vx * vx + vy * vy).sqrt();
            let (nx, ny) = if n > 0.0 {
                (-vy / n, vx / n)
            } else {
                (0.0, 0.0)
            };
            let w = magnify * d.position_worst;
            ((x + nx * w, y + ny * w), (x - nx * w, y - ny * w))
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
        (projection, "m"),
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
        && distance(first, last) <= 1.5 * longest
    {
        edges.push(edges[0]);
        nominal.push(first);
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
pub(super) fn square(x: (f64, f64), y: (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let span = (x.1 - x.0).max(y.1 - y.0);
    let cx = (x.0 + x.1) / 2.0;
    let cy = (y.0 + y.1) / 2.0;
    (
        (cx - span / 2.0, cx + span / 2.0),
        (cy - span / 2.0, cy + span / 2.0),
    )
}
