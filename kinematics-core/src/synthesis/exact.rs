//! Classical exact synthesis of the planar four-bar: three-position
//! motion generation by the circle-point and centre-point construction,
//! and three-precision-point function generation by Freudenstein's
//! equation. Where an exact answer exists, it is found here in closed
//! form, and a [`Search`](super::Search) may start from it.

use std::format;
use std::string::String;

use crate::error::Error;

fn exact(detail: String) -> Error {
    Error::InvalidGeometry {
        what: "exact synthesis",
        detail,
    }
}

/// The centre of the circle through `p` (three points of the plane).
///
/// # Errors
/// [`Error::InvalidGeometry`] when the points are collinear (or two
/// coincide), which no circle passes through.
pub fn circumcentre(p: [[f64; 2]; 3]) -> Result<[f64; 2], Error> {
    // 2 (p_k − p_0) · c = |p_k|² − |p_0|², k = 1, 2.
    let (a, b) = (
        [p[1][0] - p[0][0], p[1][1] - p[0][1]],
        [p[2][0] - p[0][0], p[2][1] - p[0][1]],
    );
    let sq = |q: [f64; 2]| q[0] * q[0] + q[1] * q[1];
    let (ra, rb) = (sq(p[1]) - sq(p[0]), sq(p[2]) - sq(p[0]));
    let det = 2.0 * (a[0] * b[1] - a[1] * b[0]);
    let size = (sq(a) * sq(b)).sqrt();
    if det.is_nan() || det.abs() <= 1e-12 * size {
        return Err(exact(format!(
            "the points {p:?} are collinear: no circle passes through them"
        )));
    }
    Ok([(ra * b[1] - rb * a[1]) / det, (a[0] * rb - b[0] * ra) / det])
}

/// Position `m` of the body frame (coordinates in the body) at the pose
/// `[x, y, θ]`: (x, y) + R(θ) m.
fn in_plane(pose: [f64; 3], m: [f64; 2]) -> [f64; 2] {
    let (s, c) = crate::math::sin_cos(pose[2]);
    [pose[0] + c * m[0] - s * m[1], pose[1] + s * m[0] + c * m[1]]
}

/// Point `r` of the plane in the body frame at the pose `[x, y, θ]`:
/// R(θ)ᵀ (r − (x, y)).
fn in_body(pose: [f64; 3], r: [f64; 2]) -> [f64; 2] {
    let (s, c) = crate::math::sin_cos(pose[2]);
    let (dx, dy) = (r[0] - pose[0], r[1] - pose[1]);
    [c * dx + s * dy, -s * dx + c * dy]
}

/// The centre point of the circle point `circle` (a point of the moving
/// body, in its frame) over three poses of the body, each `[x, y, θ]`:
/// the fixed pivot about which that body point turns through the three
/// positions, the circumcentre of (x_i, y_i) + R(θ_i)·circle.
///
/// # Errors
/// [`Error::InvalidGeometry`] when the three positions of the point are
/// collinear (choose another circle point).
pub fn centre_point(poses: [[f64; 3]; 3], circle: [f64; 2]) -> Result<[f64; 2], Error> {
    circumcentre(poses.map(|p| in_plane(p, circle)))
}

/// The circle point (in the body's frame) of the centre point `centre`
/// (a fixed pivot) over three poses of the body: the body point whose
/// three positions lie on a circle about `centre`, found by inversion
/// (the circumcentre of the centre point seen from the body at each
/// pose, R(θ_i)ᵀ(centre − (x_i, y_i))).
///
/// # Errors
/// [`Error::InvalidGeometry`] when the three images of the centre are
/// collinear.
pub fn circle_point(poses: [[f64; 3]; 3], centre: [f64; 2]) -> Result<[f64; 2], Error> {
    circumcentre(poses.map(|p| in_body(p, centre)))
}

/// A four-bar through three poses of its coupler, from the exact
/// construction ([`three_positions`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MotionFourBar {
    /// The fixed pivots of the two dyads (the input's first).
    pub ground_pivots: [[f64; 2]; 2],
    /// The moving pivots, in the coupler's frame.
    pub moving_pivots: [[f64; 2]; 2],
    /// The crank (input dyad), the coupler, the rocker (output dyad) and
    /// the ground link's lengths.
    pub lengths: [f64; 4],
    /// The input link's angle at each pose, from the x axis (rad).
    pub input_angles: [f64; 3],
    /// The output link's angle at each pose, from the x axis (rad).
    pub output_angles: [f64; 3],
}

/// Three-position motion generation: the four-bar whose coupler passes
/// through three poses `[x, y, θ]`, with the two circle points
/// `circle_points` (the moving pivots, in the coupler's frame, the
/// input dyad's first) chosen by the designer; each fixed pivot is its
/// circle point's centre point ([`centre_point`]). The construction is
/// exact: the coupler frame reaches every pose (the test compares the
/// linkage's lengths and angles with a four-bar solved in closed form).
/// It does not check that the linkage moves from one
/// pose to the next without changing its assembly (a branch defect):
/// the [`Search`](super::Search) checks that over the motion.
///
/// # Errors
/// [`Error::InvalidGeometry`] when a circle point's positions are
/// collinear or the two dyads share a pivot.
pub fn three_positions(
    poses: [[f64; 3]; 3],
    circle_points: [[f64; 2]; 2],
) -> Result<MotionFourBar, Error> {
    let centres = [
        centre_point(poses, circle_points[0])?,
        centre_point(poses, circle_points[1])?,
    ];
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let moving = poses.map(|p| [in_plane(p, circle_points[0]), in_plane(p, circle_points[1])]);
    let lengths = [
        dist(moving[0][0], centres[0]),
        dist(circle_points[0], circle_points[1]),
        dist(moving[0][1], centres[1]),
        dist(centres[0], centres[1]),
    ];
    if lengths[1] == 0.0 || lengths[3] == 0.0 {
        return Err(exact(
            "the two dyads share a pivot: choose circle points apart".into(),
        ));
    }
    let angle = |r: [f64; 2], c: [f64; 2]| crate::math::atan2(r[1] - c[1], r[0] - c[0]);
    Ok(MotionFourBar {
        ground_pivots: centres,
        moving_pivots: circle_points,
        lengths,
        input_angles: moving.map(|m| angle(m[0], centres[0])),
        output_angles: moving.map(|m| angle(m[1], centres[1])),
    })
}

/// A four-bar function generator from Freudenstein's equation
/// ([`freudenstein`]): crank a, coupler b, rocker c, ground d.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FunctionFourBar {
    /// The crank AB (input, at φ from the ground line).
    pub a: f64,
    /// The coupler BC.
    pub b: f64,
    /// The rocker DC (output, at ψ from the ground line, measured at D).
    pub c: f64,
    /// The ground AD.
    pub d: f64,
    /// Freudenstein's constants K1 = d/a, K2 = d/c, K3 = (a² − b² + c² +
    /// d²)/(2ac).
    pub k: [f64; 3],
}

/// Three-precision-point function generation: the four-bar with ground
/// `d` whose output angle ψ equals ψ_j at the input angle φ_j for the
/// three pairs (φ_j, ψ_j). With the crank A→B = a∠φ, the rocker
/// D→C = c∠ψ and D = (d, 0), the loop |C − B| = b gives Freudenstein's
/// equation, linear in its three constants:
///
/// K1 cos ψ − K2 cos φ + K3 = cos(φ − ψ),
/// K1 = d/a, K2 = d/c, K3 = (a² − b² + c² + d²)/(2ac),
///
/// solved for K1, K2, K3 at the three pairs; then a = d/K1, c = d/K2,
/// b² = a² + c² + d² − 2ac·K3.
///
/// # Errors
/// [`Error::InvalidGeometry`] when the three equations are dependent
/// (two pairs the same), when a or c comes out negative (the same
/// linkage with that link turned by 180°: add 180° to its angles) or
/// b² ≤ 0 (no linkage), naming which.
pub fn freudenstein(pairs: [(f64, f64); 3], d: f64) -> Result<FunctionFourBar, Error> {
    if pairs.iter().any(|(x, y)| !(x.is_finite() && y.is_finite())) {
        return Err(exact(format!("the pairs must be finite, not {pairs:?}")));
    }
    if !(d.is_finite() && d > 0.0) {
        return Err(exact(format!(
            "the ground length must be positive, not {d}"
        )));
    }
    let (cos, cos_diff) = (crate::math::cos, |p: f64, q: f64| crate::math::cos(p - q));
    let rows = pairs.map(|(phi, psi)| [cos(psi), -cos(phi), 1.0, cos_diff(phi, psi)]);
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let column = |k: usize| rows.map(|r| r[k]);
    let matrix = |replace: Option<usize>| -> [[f64; 3]; 3] {
        let mut m = rows.map(|r| [r[0], r[1], r[2]]);
        if let Some(k) = replace {
            for (i, row) in m.iter_mut().enumerate() {
                row[k] = column(3)[i];
            }
        }
        m
    };
    let det = det3(matrix(None));
    if det.is_nan() || det.abs() <= 1e-12 {
        return Err(exact(format!(
            "the pairs {pairs:?} give dependent equations (two are the same, or the angles repeat): choose three distinct precision points"
        )));
    }
    let k = [0, 1, 2].map(|i| det3(matrix(Some(i))) / det);
    let (a, c) = (d / k[0], d / k[1]);
    if !(a.is_finite() && c.is_finite() && k[2].is_finite()) {
        return Err(exact(format!(
            "the pairs {pairs:?} give no finite linkage (K = {k:?}): choose other precision points or angle ranges"
        )));
    }
    if a < 0.0 || c < 0.0 {
        let which = match (a < 0.0, c < 0.0) {
            (true, true) => {
                "crank and the rocker come out negative: the same linkage has both turned by 180°; add 180° to every φ_j and ψ_j"
            }
            (true, false) => {
                "crank comes out negative: the same linkage has it turned by 180°; add 180° to every input angle φ_j"
            }
            _ => {
                "rocker comes out negative: the same linkage has it turned by 180°; add 180° to every output angle ψ_j"
            }
        };
        return Err(exact(format!("the {which} and solve again (K = {k:?})")));
    }
    let b2 = a * a + c * c + d * d - 2.0 * a * c * k[2];
    if b2.is_nan() || b2 <= 0.0 {
        return Err(exact(format!(
            "the coupler's length squared comes out {b2}: no four-bar passes the three pairs"
        )));
    }
    Ok(FunctionFourBar {
        a,
        b: crate::math::sqrt(b2),
        c,
        d,
        k,
    })
}

/// The n Chebyshev spacing points of [lo, hi]: x_j = (lo + hi)/2 −
/// (hi − lo)/2 · cos((2j − 1)π / 2n), j = 1 … n, the precision points
/// that minimise the largest structural error of an interpolating
/// function generator.
#[must_use]
pub fn chebyshev(lo: f64, hi: f64, n: usize) -> std::vec::Vec<f64> {
    #[allow(clippy::cast_precision_loss)]
    (1..=n)
        .map(|j| {
            let t = (2.0 * j as f64 - 1.0) * core::f64::consts::PI / (2.0 * n as f64);
            0.5 * (lo + hi) - 0.5 * (hi - lo) * crate::math::cos(t)
        })
        .collect()
}
