//! Figures against the driver: the coordinates with their rates and
//! accelerations ([`plot_motion`]) and the points' positions, velocities
//! and accelerations ([`plot_points`]).

use std::path::Path;

use plotters::prelude::*;

use crate::error::Error;
use crate::mechanism::{Kind, Role};
use crate::sweep::Table;

use super::chart::{Curve, PALETTE, Units, output, panel, x_axis};

/// Plots q, q' and q'' of every unknown against the swept variable into an
/// SVG file at `path`: a row per quantity, a column per kind (angles in
/// degrees with their rates in rad/s and rad/s² (deg/s and deg/s² with
/// [`Units::angle`] in degrees); lengths in m, m/s,
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
pub fn plot_motion<T: Table + ?Sized>(sweep: &T, path: &Path) -> Result<(), Error> {
    plot_motion_in(sweep, Units::METRES, path)
}

/// [`plot_motion`] with lengths labelled in `units`.
///
/// # Errors
/// [`Error::Output`] when the file cannot be written.
pub fn plot_motion_in<T: Table + ?Sized>(
    sweep: &T,
    units: Units,
    path: &Path,
) -> Result<(), Error> {
    let (x_title, x_scale) = x_axis(sweep, units);
    let kinds: Vec<Kind> = [Kind::Angle, Kind::Length]
        .into_iter()
        .filter(|k| {
            sweep
                .coordinates()
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
                    format!("angular velocity ({}/s)", units.angle.name()),
                    units.angle.factor(),
                ),
                (
                    "angular accelerations",
                    format!("angular acceleration ({}/s²)", units.angle.name()),
                    units.angle.factor(),
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
            let curves: Vec<Curve> = sweep
                .coordinates()
                .iter()
                .enumerate()
                .filter(|(_, c)| c.role == Role::Unknown && c.kind == *kind)
                .enumerate()
                .map(|(n, (j, c))| Curve {
                    label: c.name.to_owned(),
                    points: (0..sweep.rows())
                        .map(|i| (sweep.at(i) * x_scale, sweep.coordinate(i, j, order) * scale))
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
pub fn plot_points<T: Table + ?Sized>(
    sweep: &T,
    points: &[&str],
    path: &Path,
) -> Result<(), Error> {
    plot_points_in(sweep, points, Units::METRES, path)
}

/// [`plot_points`] with lengths labelled in `units`.
///
/// # Errors
/// As [`plot_points`].
pub fn plot_points_in<T: Table + ?Sized>(
    sweep: &T,
    points: &[&str],
    units: Units,
    path: &Path,
) -> Result<(), Error> {
    let indices: Vec<usize> = points
        .iter()
        .map(|p| sweep.point_index(p, "plot"))
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
            let vector = |i: usize| -> &[f64] { sweep.point(i, k)[order] };
            let mut curves: Vec<Curve> = (0..sweep.point_dim())
                .map(|c| Curve {
                    label: format!("{prefix}{}", axes.get(c).copied().unwrap_or("?")),
                    points: (0..sweep.rows())
                        .map(|i| {
                            (
                                sweep.at(i) * x_scale,
                                vector(i).get(c).copied().unwrap_or(f64::NAN),
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
                    points: (0..sweep.rows())
                        .map(|i| {
                            (
                                sweep.at(i) * x_scale,
                                vector(i).iter().map(|v| v * v).sum::<f64>().sqrt(),
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
