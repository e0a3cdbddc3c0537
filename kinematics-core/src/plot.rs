//! SVG plots of sweeps and drawings of the mechanism (feature `plot`).
//!
//! Curves and links are drawn 2 px wide, grid lines 1 px.

use std::path::Path;

use plotters::prelude::*;

use crate::sweep::Sweep;
use crate::{Coordinates, Error, Mechanism, MotionState, PointState, Role};

/// The plane a spatial mechanism is projected on (planar mechanisms are
/// drawn in their plane).
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
/// plot_path(&s, "B", Projection::XY, &dir.join("slider-crank-path.svg"))?;
/// # Ok::<(), kinematics_core::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Projection {
    /// Looking down z: (x, y).
    XY,
    /// Looking along y: (x, z).
    XZ,
    /// Looking along x: (y, z).
    YZ,
}

impl Projection {
    fn axes(self) -> (usize, usize) {
        match self {
            Projection::XY => (0, 1),
            Projection::XZ => (0, 2),
            Projection::YZ => (1, 2),
        }
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

fn output(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output {
        path: path.display().to_string(),
        detail: e.to_string(),
    }
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9 * (1.0 + hi.abs()));
    (lo - pad, hi + pad)
}

/// Plots q, q' and q'' of every unknown against the swept variable, one
/// panel each, one curve per unknown, into an SVG file at `path`.
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
/// let file = dir.join("slider-crank-motion.svg");
/// kinematics_core::plot::plot_motion(&s, &file)?;
/// assert!(std::fs::read_to_string(&file).is_ok_and(|svg| svg.contains("<svg")));
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::Output`] when the file cannot be written.
pub fn plot_motion<M: Mechanism>(sweep: &Sweep<M>, path: &Path) -> Result<(), Error> {
    let unknowns: Vec<(usize, &str)> = M::COORDINATES
        .iter()
        .enumerate()
        .filter(|(_, c)| c.role == Role::Unknown)
        .map(|(j, c)| (j, c.name))
        .collect();
    let x: Vec<f64> = sweep.samples.iter().map(|s| s.at).collect();
    let (x0, x1) = range(x.iter().copied());
    let root = SVGBackend::new(path, (900, 1000)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let panels = root.split_evenly((3, 1));
    let titles = ["position q", "rate q'", "acceleration q''"];
    for (order, area) in panels.iter().enumerate() {
        let value = |s: &crate::sweep::Sample<M>, j: usize| {
            let c = match order {
                0 => s.motion.q(),
                1 => s.motion.qd(),
                _ => s.motion.qdd(),
            };
            c.get(j).unwrap_or(f64::NAN)
        };
        let (y0, y1) = range(
            sweep
                .samples
                .iter()
                .flat_map(|s| unknowns.iter().map(move |(j, _)| value(s, *j))),
        );
        let mut chart = ChartBuilder::on(area)
            .caption(titles[order], ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(35)
            .y_label_area_size(60)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| output(path, e))?;
        chart
            .configure_mesh()
            .x_desc(sweep.variable)
            .draw()
            .map_err(|e| output(path, e))?;
        for (k, (j, name)) in unknowns.iter().enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            chart
                .draw_series(LineSeries::new(
                    sweep.samples.iter().map(|s| (s.at, value(s, *j))),
                    color.stroke_width(2),
                ))
                .map_err(|e| output(path, e))?
                .label(*name)
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 4), (x + 12, y + 4)], color.filled())
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| output(path, e))?;
    }
    root.present().map_err(|e| output(path, e))
}

fn point_index<M: Mechanism>(name: &str) -> Result<usize, Error> {
    M::POINT_NAMES
        .iter()
        .position(|p| *p == name)
        .ok_or_else(|| Error::InvalidGeometry {
            what: "plot",
            detail: format!(
                "the mechanism has no point `{name}`; its points are {}",
                M::POINT_NAMES.join(", ")
            ),
        })
}

/// Plots the path of point `point` over the sweep (projected for spatial
/// mechanisms) into an SVG file at `path`, with equal scales on both axes.
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
    let k = point_index::<M>(point)?;
    let (a, b) = projection.axes();
    let xy: Vec<(f64, f64)> = sweep
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
        .collect();
    let ((x0, x1), (y0, y1)) = square(range(xy.iter().map(|p| p.0)), range(xy.iter().map(|p| p.1)));
    let root = SVGBackend::new(path, (700, 700)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("path of {point}"), ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| output(path, e))?;
    chart.configure_mesh().draw().map_err(|e| output(path, e))?;
    chart
        .draw_series(LineSeries::new(xy, PALETTE[0].stroke_width(2)))
        .map_err(|e| output(path, e))?;
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
/// pose): each link of `links` (pairs of point names) as a line between its
/// points, and the fixed pivots (points that do not move over the poses) as
/// black triangles; spatial mechanisms are projected orthographically.
///
/// ```no_run
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
/// # let pose = m.assemble(&FourBarCoords { phi: 0.0, th3: 1.0, th4: 1.6 }).unwrap();
/// let links = [("A", "B"), ("B", "C"), ("C", "D")];
/// plot_skeleton(&m, &[pose], &links, Projection::XY, "skeleton.svg".as_ref())?;
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
    let ends: Vec<(usize, usize)> = links
        .iter()
        .map(|(p, q)| Ok((point_index::<M>(p)?, point_index::<M>(q)?)))
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
    let all = || positions.iter().flatten();
    let ((x0, x1), (y0, y1)) = square(range(all().map(|p| p.0)), range(all().map(|p| p.1)));
    let tol = 1e-9 * (x1 - x0).abs().max(1e-300);
    let fixed: Vec<usize> = (0..M::POINTS)
        .filter(|&k| {
            positions.iter().all(|ps| {
                let (p, q) = (ps[k], positions[0][k]);
                (p.0 - q.0).abs() <= tol && (p.1 - q.1).abs() <= tol
            })
        })
        .collect();
    let root = SVGBackend::new(path, (800, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption("mechanism", ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| output(path, e))?;
    chart.configure_mesh().draw().map_err(|e| output(path, e))?;
    for (i, ps) in positions.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        chart
            .draw_series(
                ends.iter()
                    .map(|&(p, q)| PathElement::new(vec![ps[p], ps[q]], color.stroke_width(2))),
            )
            .map_err(|e| output(path, e))?;
    }
    let first = positions.first().cloned().unwrap_or_default();
    chart
        .draw_series(
            fixed
                .iter()
                .map(|&k| TriangleMarker::new(first[k], 9, BLACK.filled())),
        )
        .map_err(|e| output(path, e))?;
    chart
        .draw_series(
            M::POINT_NAMES
                .iter()
                .zip(&first)
                .map(|(name, p)| Text::new((*name).to_owned(), *p, ("sans-serif", 14))),
        )
        .map_err(|e| output(path, e))?;
    root.present().map_err(|e| output(path, e))
}
