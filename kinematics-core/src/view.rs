//! How a drawing sees a mechanism: the plane a spatial mechanism is
//! projected on, and which points are ground pivots or sliders (for the
//! plots and the animation).

use alloc::vec;
use alloc::vec::Vec;

use crate::mechanism::{Coordinate, Coordinates, Kind, Mechanism};

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
/// # #[cfg(feature = "plot")] {
/// let dir = std::env::temp_dir();
/// use kinematics_core::plot::{plot_path, Projection};
/// plot_path(&s, "B", Projection::XY, &dir.join("slider-crank-path.svg"))?;
/// # }
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
    /// The indices of the two coordinates drawn, (horizontal, vertical).
    #[must_use]
    pub fn axes(self) -> (usize, usize) {
        match self {
            Projection::XY => (0, 1),
            Projection::XZ => (0, 2),
            Projection::YZ => (1, 2),
        }
    }

    /// The point `r` (2 or 3 components) in the plane drawn: its two
    /// coordinates of [`Self::axes`], 0 for one it does not have (z of a
    /// planar point).
    #[must_use]
    pub fn of(self, r: &[f64]) -> (f64, f64) {
        let (a, b) = self.axes();
        (
            r.get(a).copied().unwrap_or(0.0),
            r.get(b).copied().unwrap_or(0.0),
        )
    }

    /// The names of the two coordinates drawn.
    #[must_use]
    pub fn names(self) -> (&'static str, &'static str) {
        match self {
            Projection::XY => ("x", "y"),
            Projection::XZ => ("x", "z"),
            Projection::YZ => ("y", "z"),
        }
    }
}

/// How a point moves with the coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointRole {
    /// Its position depends on no coordinate: a ground pivot.
    Fixed,
    /// It moves along one fixed straight line: a slider on a ground guide.
    Slider,
    /// Anything else.
    Moving,
}

/// The role of every point of `m`, from its positions at `pose` and at
/// three poses with every coordinate moved (by 0.3 to 0.9 rad for angles,
/// and 10 to 30 % for lengths): found from the model itself, so that a
/// drawing of a single pose marks its ground pivots too.
///
/// ```
/// use kinematics_core::{mechanism, view::{point_roles, PointRole}};
/// mechanism! {
///     /// A slider-crank.
///     pub struct SliderCrank {
///         params   { a, b }
///         drivers  { phi }
///         unknowns { th, x }
///         points   { A = vec2(0.0, 0.0); B = polar(a, phi); C = vec2(x, 0.0); }
///         loops    { B + polar(b, th) == C; }
///     }
/// }
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let pose = SliderCrankCoords { phi: 0.3, th: -0.1, x: 0.39 };
/// assert_eq!(point_roles(&m, &pose), [PointRole::Fixed, PointRole::Moving, PointRole::Slider]);
/// ```
#[must_use]
pub fn point_roles<M: Mechanism>(m: &M, pose: &M::Coords) -> Vec<PointRole> {
    let q: Vec<f64> = (0..M::COORDINATES.len())
        .map(|j| pose.get(j).unwrap_or(0.0))
        .collect();
    point_roles_by(M::COORDINATES, M::POINT_DIM, &q, |moved, out| {
        let mut c = *pose;
        for (j, &v) in moved.iter().enumerate() {
            c.set(j, v);
        }
        *out = vec![0.0; M::POINTS * M::POINT_DIM];
        m.point_positions_into(&c, out);
    })
}

/// [`point_roles`] for any model: `coordinates` describe the pose `q`
/// (drivers then unknowns), and `positions(q, out)` writes into `out` the
/// positions of every point at `q`, `dim` components each (it sizes `out`).
#[must_use]
pub fn point_roles_by(
    coordinates: &[Coordinate],
    dim: usize,
    q: &[f64],
    positions: impl Fn(&[f64], &mut Vec<f64>),
) -> Vec<PointRole> {
    let dim = dim.max(1);
    let at = |shift: f64| -> Vec<f64> {
        let mut moved = q.to_vec();
        for ((j, c), v) in coordinates.iter().enumerate().zip(&mut moved) {
            // A different shift per coordinate, so that no two move
            // alike.
            #[allow(clippy::cast_precision_loss)]
            let k = 1.0 + 0.37 * j as f64;
            *v = match c.kind {
                Kind::Angle => *v + shift * k,
                Kind::Length => *v + shift * k * (v.abs() + 1.0) / 3.0,
            };
        }
        let mut out = Vec::new();
        positions(&moved, &mut out);
        out
    };
    let (p0, p1, p2, p3) = (at(0.0), at(0.3), at(0.6), at(0.9));
    let size = p0
        .iter()
        .chain(&p1)
        .chain(&p2)
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(1e-300);
    let tol = 1e-9 * size;
    (0..p0.len() / dim)
        .map(|k| {
            let r = |p: &[f64]| -> Vec<f64> {
                p.get(k * dim..(k + 1) * dim)
                    .map_or_else(Vec::new, <[f64]>::to_vec)
            };
            let (a, b, c, d) = (r(&p0), r(&p1), r(&p2), r(&p3));
            let d1: Vec<f64> = b.iter().zip(&a).map(|(x, y)| x - y).collect();
            let d2: Vec<f64> = c.iter().zip(&a).map(|(x, y)| x - y).collect();
            let d3: Vec<f64> = d.iter().zip(&a).map(|(x, y)| x - y).collect();
            let norm = |v: &[f64]| crate::math::sqrt(v.iter().map(|x| x * x).sum::<f64>());
            if norm(&d1) <= tol && norm(&d2) <= tol && norm(&d3) <= tol {
                return PointRole::Fixed;
            }
            // Collinear displacements: |d1 × d| = 0 (in any dimension,
            // |d1|²|d|² − (d1·d)²).
            let collinear = |d: &[f64]| {
                let dot: f64 = d1.iter().zip(d).map(|(x, y)| x * y).sum();
                let (n1, n) = (norm(&d1), norm(d));
                // (the difference cancels to about √ε of its terms)
                crate::math::sqrt((n1 * n1 * n * n - dot * dot).max(0.0)) <= 1e-6 * n1 * n.max(n1)
            };
            if collinear(&d2) && collinear(&d3) {
                PointRole::Slider
            } else {
                PointRole::Moving
            }
        })
        .collect()
}

/// The index of point `name` among the points of `M`, or an error for
/// `what` (the drawing asking) listing the points there are.
#[cfg(feature = "plot")]
pub(crate) fn point_index<M: Mechanism>(
    name: &str,
    what: &'static str,
) -> Result<usize, crate::error::Error> {
    index_of(M::POINT_NAMES, name, what)
}

/// The index of the point `name` among `names`, or an error naming the
/// output `what` and listing the points.
pub(crate) fn index_of(
    names: &[&str],
    name: &str,
    what: &'static str,
) -> Result<usize, crate::error::Error> {
    names
        .iter()
        .position(|p| *p == name)
        .ok_or_else(|| crate::Error::InvalidGeometry {
            what,
            detail: alloc::format!(
                "the mechanism has no point `{name}`; its points are {}",
                names.join(", ")
            ),
        })
}
