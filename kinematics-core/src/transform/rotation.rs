//! Spatial rotations: about the coordinate axes and about any axis, the
//! axis and angle of a rotation matrix, and composite rotations.

use alloc::format;
use nalgebra::{Matrix3, Unit, Vector3};

use crate::error::Error;

use super::axis::Axis;

/// Rotation by θ about the x axis: [[1, 0, 0], [0, c, −s], [0, s, c]].
///
/// ```
/// use kinematics_core::transform::rot_x;
/// use kinematics_core::nalgebra::Vector3;
/// let v = rot_x(std::f64::consts::FRAC_PI_2) * Vector3::y();
/// assert!((v - Vector3::z()).norm() < 1e-15);
/// ```
#[must_use]
pub fn rot_x(theta: f64) -> Matrix3<f64> {
    let (s, c) = crate::math::sin_cos(theta);
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

/// Rotation by θ about the y axis: [[c, 0, s], [0, 1, 0], [−s, 0, c]].
///
/// ```
/// use kinematics_core::transform::rot_y;
/// use kinematics_core::nalgebra::Vector3;
/// let v = rot_y(std::f64::consts::FRAC_PI_2) * Vector3::z();
/// assert!((v - Vector3::x()).norm() < 1e-15);
/// ```
#[must_use]
pub fn rot_y(theta: f64) -> Matrix3<f64> {
    let (s, c) = crate::math::sin_cos(theta);
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// Rotation by θ about the z axis: [[c, −s, 0], [s, c, 0], [0, 0, 1]].
///
/// ```
/// use kinematics_core::transform::rot_z;
/// use kinematics_core::nalgebra::Vector3;
/// let v = rot_z(std::f64::consts::FRAC_PI_2) * Vector3::x();
/// assert!((v - Vector3::y()).norm() < 1e-15);
/// ```
#[must_use]
pub fn rot_z(theta: f64) -> Matrix3<f64> {
    let (s, c) = crate::math::sin_cos(theta);
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Rotation about a coordinate axis.
///
/// ```
/// use kinematics_core::transform::{rot_about, rot_y, Axis};
/// assert_eq!(rot_about(Axis::Y, 0.2), rot_y(0.2));
/// ```
#[must_use]
pub fn rot_about(axis: Axis, theta: f64) -> Matrix3<f64> {
    match axis {
        Axis::X => rot_x(theta),
        Axis::Y => rot_y(theta),
        Axis::Z => rot_z(theta),
    }
}

/// Fails with [`Error::InvalidGeometry`] naming `name` in `what` unless
/// every value is finite.
pub(crate) fn finite(what: &'static str, name: &str, values: &[f64]) -> Result<(), Error> {
    match values.iter().find(|v| !v.is_finite()) {
        None => Ok(()),
        Some(v) => Err(Error::InvalidGeometry {
            what,
            detail: format!("{name} holds {v}; every input must be a finite number"),
        }),
    }
}

/// The unit vector along `axis`, scaled by its largest component first so
/// that the norm neither underflows (1e-200) nor overflows (1e200).
pub(super) fn unit_axis(
    axis: &Vector3<f64>,
    what: &'static str,
) -> Result<Unit<Vector3<f64>>, Error> {
    let m = axis.amax();
    if m > 0.0 && axis.iter().all(|v| v.is_finite()) {
        let v = axis / m;
        Ok(Unit::new_unchecked(v / v.norm()))
    } else {
        Err(Error::InvalidGeometry {
            what,
            detail: format!(
                "the axis {:?} must be a finite, non-zero vector",
                axis.as_slice()
            ),
        })
    }
}

/// Rotation by θ about the axis û through the origin (the axis is
/// normalised), with v = 1 − cos θ (the versine):
///
/// R = [[uₓ²v + c, uₓu_y v − u_z s, uₓu_z v + u_y s],
///      [uₓu_y v + u_z s, u_y²v + c, u_y u_z v − uₓ s],
///      [uₓu_z v − u_y s, u_y u_z v + uₓ s, u_z²v + c]],
///
/// that is r₂ = r₁ + sin θ (û × r₁) + vers θ [(r₁·û)û − r₁].
///
/// # Errors
/// [`Error::InvalidGeometry`] for a zero or non-finite axis.
///
/// ```
/// use kinematics_core::transform::{rot, rot_z};
/// use kinematics_core::nalgebra::Vector3;
/// let r = rot(&Vector3::new(0.0, 0.0, 2.0), 0.4)?;
/// assert!((r - rot_z(0.4)).norm() < 1e-15);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn rot(axis: &Vector3<f64>, theta: f64) -> Result<Matrix3<f64>, Error> {
    let u = unit_axis(axis, "rot")?;
    finite("rot", "the angle θ", &[theta])?;
    Ok(rotation_matrix(&u, theta))
}

pub(super) fn rotation_matrix(u: &Unit<Vector3<f64>>, theta: f64) -> Matrix3<f64> {
    let (s, c) = crate::math::sin_cos(theta);
    let v = 1.0 - c;
    let (x, y, z) = (u.x, u.y, u.z);
    Matrix3::new(
        x * x * v + c,
        x * y * v - z * s,
        x * z * v + y * s,
        x * y * v + z * s,
        y * y * v + c,
        y * z * v - x * s,
        x * z * v - y * s,
        y * z * v + x * s,
        z * z * v + c,
    )
}

/// Axis and angle of a rotation.
///
/// ```
/// use kinematics_core::transform::{axis_angle, rot_y};
/// let aa = axis_angle(&rot_y(0.8))?;
/// assert!((aa.angle - 0.8).abs() < 1e-15 && (aa.axis.y - 1.0).abs() < 1e-15);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisAngle {
    /// Unit axis û (right-hand rule).
    pub axis: Unit<Vector3<f64>>,
    /// Angle θ in [0, π].
    pub angle: f64,
}

/// The inverse problem: û and θ ∈ [0, π] with R = R(û, θ).
///
/// cos θ = (r₁₁ + r₂₂ + r₃₃ − 1)/2 and sin θ û = ½(r₃₂ − r₂₃, r₁₃ − r₃₁,
/// r₂₁ − r₁₂), so θ = atan2(|·|, cos θ). Near θ = π the skew part vanishes
/// and the axis is taken from the symmetric part, (R + Rᵀ)/2 − cos θ I =
/// (1 − cos θ) û ûᵀ. At θ = 0 the axis is undefined; ẑ is returned. At θ = π
/// both ±û describe the rotation; the one with its largest component positive
/// is returned.
///
/// Matrices rounded to a few decimals (printed ones) are accepted; a matrix
/// farther than 0.01 from orthonormal, or a reflection, is an error.
///
/// # Errors
/// [`Error::InvalidGeometry`] when `r` is not a rotation.
///
/// ```
/// use kinematics_core::transform::{axis_angle, rot};
/// use kinematics_core::nalgebra::Vector3;
/// let aa = axis_angle(&rot(&Vector3::new(1.0, 2.0, 2.0), 2.0)?)?;
/// assert!((aa.angle - 2.0).abs() < 1e-12);
/// assert!((aa.axis.into_inner() - Vector3::new(1.0, 2.0, 2.0) / 3.0).norm() < 1e-12);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn axis_angle(r: &Matrix3<f64>) -> Result<AxisAngle, Error> {
    finite("rotation matrix", "the matrix R", r.as_slice())?;
    check_rotation(r)?;
    let c = ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0);
    let w = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) / 2.0;
    let s = w.norm();
    let angle = crate::math::atan2(s, c);
    if s < 1e-300 && c > 0.0 {
        return Ok(AxisAngle {
            axis: Vector3::z_axis(),
            angle: 0.0,
        });
    }
    let axis = if c >= 0.0 {
        w / s
    } else {
        // (R + Rᵀ)/2 − cos θ I = (1 − cos θ) û ûᵀ: take its largest column.
        let b = (r + r.transpose()) / 2.0 - Matrix3::identity() * c;
        let k = (0..3)
            .max_by(|&i, &j| b[(i, i)].total_cmp(&b[(j, j)]))
            .unwrap_or(0);
        let col: Vector3<f64> = b.column(k).into();
        let mut u = col / col.norm();
        if u.dot(&w) < 0.0 || (s < 1e-12 && u[u.iamax()] < 0.0) {
            u = -u;
        }
        u
    };
    Ok(AxisAngle {
        axis: Unit::new_normalize(axis),
        angle,
    })
}

fn check_rotation(r: &Matrix3<f64>) -> Result<(), Error> {
    let deviation = (r.transpose() * r - Matrix3::identity()).abs().max();
    let det = r.determinant();
    if !(deviation <= 1e-2 && det > 0.0) {
        return Err(Error::InvalidGeometry {
            what: "rotation matrix",
            detail: format!(
                "it is not a rotation: |RᵀR − I| = {deviation:.3e}, det R = {det:.4} \
                 (a rotation has RᵀR = I and det R = 1)"
            ),
        });
    }
    Ok(())
}

/// A sequence of rotations about the axes of the fixed frame F or of the
/// mobile frame M, composed as the notes' composite-rotation algorithm:
/// start from R = I; a rotation about a fixed axis premultiplies,
/// R ← R_k(φ) R; a rotation about the mobile frame's own axis postmultiplies,
/// R ← R R_k(φ). The result maps M coordinates into F coordinates.
///
/// ```
/// use kinematics_core::transform::{Axis, CompositeRotation, rot_x, rot_y};
/// let r = CompositeRotation::new()
///     .about_fixed(Axis::X, 0.3)
///     .about_mobile(Axis::Y, 0.2)
///     .matrix();
/// assert!((r - rot_x(0.3) * rot_y(0.2)).norm() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompositeRotation(Matrix3<f64>);

impl Default for CompositeRotation {
    fn default() -> Self {
        Self::new()
    }
}

impl CompositeRotation {
    /// R = I: the mobile frame coincides with the fixed one.
    ///
    /// ```
    /// use kinematics_core::transform::CompositeRotation;
    /// assert_eq!(CompositeRotation::new().matrix(), kinematics_core::nalgebra::Matrix3::identity());
    /// ```
    #[must_use]
    pub fn new() -> Self {
        Self(Matrix3::identity())
    }

    /// Rotates by φ about axis k of the fixed frame: R ← R_k(φ) R.
    ///
    /// ```
    /// use kinematics_core::transform::{rot_x, rot_z, Axis, CompositeRotation};
    /// let r = CompositeRotation::new().about_fixed(Axis::Z, 0.1).about_fixed(Axis::X, 0.2);
    /// assert!((r.matrix() - rot_x(0.2) * rot_z(0.1)).norm() < 1e-15);
    /// ```
    #[must_use]
    pub fn about_fixed(self, axis: Axis, phi: f64) -> Self {
        Self(rot_about(axis, phi) * self.0)
    }

    /// Rotates by φ about axis k of the mobile frame: R ← R R_k(φ).
    ///
    /// ```
    /// use kinematics_core::transform::{rot_x, rot_z, Axis, CompositeRotation};
    /// let r = CompositeRotation::new().about_mobile(Axis::Z, 0.1).about_mobile(Axis::X, 0.2);
    /// assert!((r.matrix() - rot_z(0.1) * rot_x(0.2)).norm() < 1e-15);
    /// ```
    #[must_use]
    pub fn about_mobile(self, axis: Axis, phi: f64) -> Self {
        Self(self.0 * rot_about(axis, phi))
    }

    /// The composite rotation matrix.
    ///
    /// ```
    /// use kinematics_core::transform::{rot_y, Axis, CompositeRotation};
    /// assert_eq!(CompositeRotation::new().about_fixed(Axis::Y, 1.0).matrix(), rot_y(1.0));
    /// ```
    #[must_use]
    pub fn matrix(&self) -> Matrix3<f64> {
        self.0
    }
}
