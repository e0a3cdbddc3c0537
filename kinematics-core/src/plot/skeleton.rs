//! Drawings of the linkage itself at chosen poses ([`plot_skeleton`]),
//! with overlays.

use std::path::Path;

use plotters::prelude::*;

use crate::error::Error;
use crate::mechanism::{Coordinate, Coordinates, Kind, Mechanism, Role};
use crate::sweep::Table;
use crate::view::Projection;

use crate::view::{PointRole, point_index, point_roles};

use super::chart::{FONT, PALETTE, Units, legend, output, plane_chart, range, tick};
use super::path::{path_xy, square};

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
    pub fn path<T: Table + ?Sized>(
        mut self,
        sweep: &T,
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
    let dim = M::POINT_DIM;
    let positions: Vec<Vec<(f64, f64)>> = poses
        .iter()
        .map(|pose| {
            let mut flat = vec![0.0; M::POINTS * dim];
            m.point_positions_into(pose, &mut flat);
            flat.chunks(dim).map(|c| projection.of(c)).collect()
        })
        .collect();
    let roles = poses.first().map_or_else(Vec::new, |p| point_roles(m, p));
    let labels: Vec<String> = poses
        .iter()
        .map(|pose| {
            let q: Vec<f64> = (0..M::COORDINATES.len())
                .map(|j| pose.get(j).unwrap_or(f64::NAN))
                .collect();
            driver_label(M::COORDINATES, &q, "m")
        })
        .collect();
    let drawing = Drawing {
        positions: &positions,
        labels: &labels,
        names: M::POINT_NAMES,
        roles: &roles,
        ends: &ends,
        length: "m",
    };
    draw(&drawing, overlay, projection, path)
}

/// [`plot_skeleton`] for any sweep read as a [`Table`] (of a model
/// compiled at run time, say): the mechanism at each of the samples
/// `rows` in the plane of the projection, lengths on the axes and in the
/// legend in the unit of `units`, with `roles` the role of every point (from
/// [`point_roles_by`](crate::view::point_roles_by)), which marks the
/// ground pivots and the sliders.
///
/// # Errors
/// [`Error::InvalidGeometry`] for an unknown point, a row past the end of
/// the sweep or `roles` without a role per point; [`Error::Output`] when
/// the file cannot be written.
pub fn plot_table_skeleton<T: Table + ?Sized>(
    sweep: &T,
    rows: &[usize],
    roles: &[PointRole],
    links: &[(&str, &str)],
    (projection, units): (Projection, Units),
    path: &Path,
) -> Result<(), Error> {
    let ends: Vec<(usize, usize)> = links
        .iter()
        .map(|(p, q)| Ok((sweep.point_index(p, "plot")?, sweep.point_index(q, "plot")?)))
        .collect::<Result<_, Error>>()?;
    let points = sweep.point_names().len();
    if roles.len() != points {
        return Err(Error::InvalidGeometry {
            what: "plot",
            detail: format!("{} point roles for {points} points", roles.len()),
        });
    }
    if let Some(&i) = rows.iter().find(|&&i| i >= sweep.rows()) {
        return Err(Error::InvalidGeometry {
            what: "plot",
            detail: format!("sample {i} asked of a sweep of {} samples", sweep.rows()),
        });
    }
    let positions: Vec<Vec<(f64, f64)>> = rows
        .iter()
        .map(|&i| {
            (0..points)
                .map(|k| projection.of(sweep.point(i, k)[0]))
                .collect()
        })
        .collect();
    let coordinates = sweep.coordinates();
    let labels: Vec<String> = rows
        .iter()
        .map(|&i| {
            let q: Vec<f64> = (0..coordinates.len())
                .map(|j| sweep.coordinate(i, j, 0))
                .collect();
            driver_label(coordinates, &q, units.length)
        })
        .collect();
    let names: Vec<&str> = sweep.point_names().iter().map(|n| n.as_ref()).collect();
    let drawing = Drawing {
        positions: &positions,
        labels: &labels,
        names: &names,
        roles,
        ends: &ends,
        length: units.length,
    };
    draw(&drawing, &Overlay::default(), projection, path)
}

/// The skeleton at poses given as every point's position (each point's
/// components one after the other, as `runtime::Model::point_positions`
/// returns them), each pose with its legend, with the curves and marks
/// of `overlay`: a synthesised design at its targets over its path, say.
/// `names` and `roles` are the points' (of a sweep, a model).
///
/// # Errors
/// [`Error::InvalidGeometry`] for a link's unknown point or positions of
/// the wrong length; [`Error::Output`] when the file cannot be written.
pub fn plot_posed(
    (names, roles): (&[&str], &[PointRole]),
    links: &[(&str, &str)],
    poses: &[(String, Vec<f64>)],
    overlay: &Overlay,
    (projection, units): (Projection, Units),
    path: &Path,
) -> Result<(), Error> {
    let index = |p: &str| {
        names
            .iter()
            .position(|n| *n == p)
            .ok_or_else(|| Error::InvalidGeometry {
                what: "plot",
                detail: format!("no point `{p}`; the points are {}", names.join(", ")),
            })
    };
    let ends: Vec<(usize, usize)> = links
        .iter()
        .map(|(p, q)| Ok((index(p)?, index(q)?)))
        .collect::<Result<_, Error>>()?;
    let n = names.len();
    let mut positions = Vec::with_capacity(poses.len());
    for (_, r) in poses {
        if n == 0 || r.len() % n != 0 || roles.len() != n {
            return Err(Error::InvalidGeometry {
                what: "plot",
                detail: format!(
                    "{} positions and {} roles for {n} points",
                    r.len(),
                    roles.len()
                ),
            });
        }
        let dim = r.len() / n;
        positions.push(r.chunks(dim).map(|c| projection.of(c)).collect());
    }
    let labels: Vec<String> = poses.iter().map(|p| p.0.clone()).collect();
    let drawing = Drawing {
        positions: &positions,
        labels: &labels,
        names,
        roles,
        ends: &ends,
        length: units.length,
    };
    draw(&drawing, overlay, projection, path)
}

/// A pose's legend: its drivers' values, angles in degrees, lengths in
/// the unit named `length`.
fn driver_label(coordinates: &[Coordinate], q: &[f64], length: &str) -> String {
    coordinates
        .iter()
        .zip(q)
        .filter(|(c, _)| c.role == Role::Driver)
        .map(|(c, &v)| match c.kind {
            Kind::Angle => format!("{} = {}°", c.name, tick(v.to_degrees(), 100.0)),
            Kind::Length => format!("{} = {} {length}", c.name, tick(v, 0.01)),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// What a skeleton drawing shows, in the plane of its projection: the
/// points' positions at each pose, each pose's legend, the points' names
/// and roles, and the links as pairs of point indices.
struct Drawing<'a> {
    positions: &'a [Vec<(f64, f64)>],
    labels: &'a [String],
    names: &'a [&'a str],
    roles: &'a [PointRole],
    ends: &'a [(usize, usize)],
    /// The length unit's name on the axes.
    length: &'a str,
}

/// Draws `d` with `overlay` into the SVG file `path`.
fn draw(
    d: &Drawing<'_>,
    overlay: &Overlay,
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    let Drawing {
        positions,
        labels,
        names,
        roles,
        ends,
        length,
    } = *d;
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
        (projection, length),
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
    for (i, (ps, label)) in positions.iter().zip(labels).enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        chart
            .draw_series(
                ends.iter()
                    .map(|&(p, q)| PathElement::new(vec![ps[p], ps[q]], color.stroke_width(2))),
            )
            .map_err(|e| output(path, e))?
            .label(label.clone())
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
        let color = PALETTE[(positions.len() + i) % PALETTE.len()];
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
        .draw_series(names.iter().zip(&first).map(|(name, p)| {
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
        if d(p) > d(best) { p } else { best }
    });
    let other = pts.iter().copied().fold(far, |best, p| {
        let d = |q: (f64, f64)| (q.0 - far.0).powi(2) + (q.1 - far.1).powi(2);
        if d(p) > d(best) { p } else { best }
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
