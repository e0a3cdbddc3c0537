//! The seven elementary 4×4 matrices T1–T7 and the joint transforms of
//! revolute, prismatic, cylindrical, screw and spherical joints.

use nalgebra::{Matrix4, Vector3};

use super::axis::Axis;
use super::homogeneous::{homogeneous, translation};
use super::rotation::{rot_about, rot_x, rot_y, rot_z};

/// Elementary matrix case 1: translation (a, b, c), then rotation θ about
/// the translated x axis: [[1, 0, 0, a], [0, c, −s, b], [0, s, c, c], [0, 0, 0, 1]].
///
/// ```
/// use kinematics_core::transform::{t1, homogeneous, rot_x};
/// use kinematics_core::nalgebra::Vector3;
/// assert_eq!(t1(1.0, 2.0, 3.0, 0.5), homogeneous(&rot_x(0.5), &Vector3::new(1.0, 2.0, 3.0)));
/// ```
#[must_use]
pub fn t1(a: f64, b: f64, c: f64, theta_x: f64) -> Matrix4<f64> {
    homogeneous(&rot_x(theta_x), &Vector3::new(a, b, c))
}

/// Elementary matrix case 2: translation (a, b, c), then rotation θ about
/// the translated y axis.
///
/// ```
/// use kinematics_core::transform::{t2, homogeneous, rot_y};
/// use kinematics_core::nalgebra::Vector3;
/// assert_eq!(t2(1.0, 2.0, 3.0, 0.5), homogeneous(&rot_y(0.5), &Vector3::new(1.0, 2.0, 3.0)));
/// ```
#[must_use]
pub fn t2(a: f64, b: f64, c: f64, theta_y: f64) -> Matrix4<f64> {
    homogeneous(&rot_y(theta_y), &Vector3::new(a, b, c))
}

/// Elementary matrix case 3: translation (a, b, c), then rotation θ about
/// the translated z axis.
///
/// ```
/// use kinematics_core::transform::{t3, homogeneous, rot_z};
/// use kinematics_core::nalgebra::Vector3;
/// assert_eq!(t3(1.0, 2.0, 3.0, 0.5), homogeneous(&rot_z(0.5), &Vector3::new(1.0, 2.0, 3.0)));
/// ```
#[must_use]
pub fn t3(a: f64, b: f64, c: f64, theta_z: f64) -> Matrix4<f64> {
    homogeneous(&rot_z(theta_z), &Vector3::new(a, b, c))
}

/// Elementary matrix case 4: translation (a, b, c), then a screw motion
/// about x with lead k: rotation θ and advance kθ/2π along x.
///
/// ```
/// use kinematics_core::transform::{t4, transform_point};
/// use kinematics_core::nalgebra::Vector3;
/// // Half a turn of lead 2 advances by 1 along x.
/// let p = transform_point(&t4(0.0, 0.0, 0.0, std::f64::consts::PI, 2.0), &Vector3::y());
/// assert!((p - Vector3::new(1.0, -1.0, 0.0)).norm() < 1e-15);
/// ```
#[must_use]
pub fn t4(a: f64, b: f64, c: f64, theta_x: f64, lead: f64) -> Matrix4<f64> {
    t1(a + lead * theta_x / core::f64::consts::TAU, b, c, theta_x)
}

/// Elementary matrix case 5: translation (a, b, c), then a screw motion
/// about y with lead k: rotation θ and advance kθ/2π along y.
///
/// ```
/// use kinematics_core::transform::{t5, transform_point};
/// use kinematics_core::nalgebra::Vector3;
/// // A quarter turn of lead 4 advances by 1 along y.
/// let p = transform_point(&t5(0.0, 0.0, 0.0, std::f64::consts::FRAC_PI_2, 4.0), &Vector3::z());
/// assert!((p - Vector3::new(1.0, 1.0, 0.0)).norm() < 1e-15);
/// ```
#[must_use]
pub fn t5(a: f64, b: f64, c: f64, theta_y: f64, lead: f64) -> Matrix4<f64> {
    t2(a, b + lead * theta_y / core::f64::consts::TAU, c, theta_y)
}

/// Elementary matrix case 6: translation (a, b, c), then a screw motion
/// about z with lead k: rotation θ and advance kθ/2π along z.
///
/// ```
/// use kinematics_core::transform::{t6, transform_point};
/// use kinematics_core::nalgebra::Vector3;
/// // One full turn of a screw of lead 0.125 advances it by 0.125.
/// let p = transform_point(&t6(0.0, 0.0, 0.0, std::f64::consts::TAU, 0.125), &Vector3::x());
/// assert!((p - Vector3::new(1.0, 0.0, 0.125)).norm() < 1e-15);
/// ```
#[must_use]
pub fn t6(a: f64, b: f64, c: f64, theta_z: f64, lead: f64) -> Matrix4<f64> {
    t3(a, b, c + lead * theta_z / core::f64::consts::TAU, theta_z)
}

/// Elementary matrix case 7: translation (a, b, c) only.
///
/// ```
/// use kinematics_core::transform::{t7, translation};
/// use kinematics_core::nalgebra::Vector3;
/// assert_eq!(t7(1.0, 2.0, 3.0), translation(&Vector3::new(1.0, 2.0, 3.0)));
/// ```
#[must_use]
pub fn t7(a: f64, b: f64, c: f64) -> Matrix4<f64> {
    translation(&Vector3::new(a, b, c))
}

// ───────────────────────────── joints ─────────────────────────────

/// Revolute joint: the link offset `offset`, then rotation θ about the
/// joint axis (elementary case 1, 2 or 3).
///
/// ```
/// use kinematics_core::transform::{revolute, t3, Axis};
/// use kinematics_core::nalgebra::Vector3;
/// assert_eq!(revolute(Axis::Z, &Vector3::new(0.0, 2.0, 0.0), 0.3), t3(0.0, 2.0, 0.0, 0.3));
/// ```
#[must_use]
pub fn revolute(axis: Axis, offset: &Vector3<f64>, theta: f64) -> Matrix4<f64> {
    homogeneous(&rot_about(axis, theta), offset)
}

/// Prismatic joint: the link offset, then a slide s along the joint axis
/// (elementary case 7 with the slide added).
///
/// ```
/// use kinematics_core::transform::{prismatic, t7, Axis};
/// use kinematics_core::nalgebra::Vector3;
/// assert_eq!(prismatic(Axis::X, &Vector3::new(0.0, 1.0, 0.0), 0.5), t7(0.5, 1.0, 0.0));
/// ```
#[must_use]
pub fn prismatic(axis: Axis, offset: &Vector3<f64>, s: f64) -> Matrix4<f64> {
    translation(&(offset + axis.unit() * s))
}

/// Cylindrical joint (two freedoms): the link offset, a slide s along the
/// joint axis and a rotation θ about it: T₇(offset + s ê) · T_axis(0, θ).
///
/// ```
/// use kinematics_core::transform::{cylindrical, t2, t7, Axis};
/// use kinematics_core::nalgebra::Vector3;
/// // The notes' s_jl(B, ψ_y) = T₇(A, B, 0) T₂(0, 0, 0, ψ_y).
/// let (a, b, psi) = (0.5, 1.5, 0.7);
/// let m = cylindrical(Axis::Y, &Vector3::new(a, 0.0, 0.0), b, psi);
/// assert!((m - t7(a, b, 0.0) * t2(0.0, 0.0, 0.0, psi)).norm() < 1e-15);
/// ```
#[must_use]
pub fn cylindrical(axis: Axis, offset: &Vector3<f64>, s: f64, theta: f64) -> Matrix4<f64> {
    homogeneous(&rot_about(axis, theta), &(offset + axis.unit() * s))
}

/// Screw joint: the link offset, then rotation θ about the joint axis with
/// the advance kθ/2π along it, k being the lead (positive for a right-hand
/// screw): elementary case 4, 5 or 6.
///
/// ```
/// use kinematics_core::transform::{screw_joint, t6, Axis};
/// use kinematics_core::nalgebra::Vector3;
/// let m = screw_joint(Axis::Z, &Vector3::new(2.0, -3.0, 2.0), 1.0, 0.125);
/// assert!((m - t6(2.0, -3.0, 2.0, 1.0, 0.125)).norm() < 1e-15);
/// ```
#[must_use]
pub fn screw_joint(axis: Axis, offset: &Vector3<f64>, theta: f64, lead: f64) -> Matrix4<f64> {
    cylindrical(axis, offset, lead * theta / core::f64::consts::TAU, theta)
}

/// Spherical joint as three rotations about intersecting axes (z–x–z Euler
/// angles): S = T₃(offset, θ_z) · T₁(0, ψ_x) · T₃(0, φ_z).
///
/// ```
/// use kinematics_core::transform::{spherical, rot_z, rot_x};
/// use kinematics_core::nalgebra::Vector3;
/// let s = spherical(&Vector3::new(0.0, 1.0, 0.0), 0.1, 0.2, 0.3);
/// let r = rot_z(0.1) * rot_x(0.2) * rot_z(0.3);
/// assert!((s.fixed_view::<3, 3>(0, 0) - r).norm() < 1e-15);
/// assert_eq!(s[(1, 3)], 1.0);
/// ```
#[must_use]
pub fn spherical(offset: &Vector3<f64>, theta_z: f64, psi_x: f64, phi_z: f64) -> Matrix4<f64> {
    homogeneous(&(rot_z(theta_z) * rot_x(psi_x) * rot_z(phi_z)), offset)
}
