//! Planar displacements: the rotation operator e^{iθ}, and 3×3
//! homogeneous rotations and translations of the plane.

use nalgebra::{Complex, Matrix3, Vector2};

use crate::error::Error;

use super::rotation::finite;

/// Complex rotation operator R = e^{iθ} = cos θ + i sin θ; A₂ = R A₁
/// rotates the complex vector A₁ by θ about the origin.
///
/// ```
/// use kinematics_core::transform::rotation_operator;
/// let a2 = rotation_operator(std::f64::consts::FRAC_PI_2) * kinematics_core::nalgebra::Complex::new(1.0, 0.0);
/// assert!((a2.re).abs() < 1e-15 && (a2.im - 1.0).abs() < 1e-15);
/// ```
#[must_use]
pub fn rotation_operator(theta: f64) -> Complex<f64> {
    Complex::new(crate::math::cos(theta), crate::math::sin(theta))
}

/// The operator that carries A₁ to A₂, R₁₂ = A₂ / A₁ (for |A₁| = |A₂| a pure
/// rotation by θ₁₂ = arg A₂ − arg A₁).
///
/// # Errors
/// [`Error::InvalidGeometry`] when A₁ = 0.
///
/// ```
/// use kinematics_core::{nalgebra::Complex, transform::rotation_between};
/// let r = rotation_between(Complex::new(1.0, 0.0), Complex::new(0.0, 1.0))?;
/// assert!((r.arg() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn rotation_between(a1: Complex<f64>, a2: Complex<f64>) -> Result<Complex<f64>, Error> {
    finite("rotation_between", "the final vector A₂", &[a2.re, a2.im])?;
    // |A₁|, scaled so that it neither overflows nor underflows.
    let m = a1.re.abs().max(a1.im.abs());
    let n1 = m * crate::math::sqrt((a1 / m).norm_sqr());
    if !(n1 > 0.0 && n1.is_finite()) {
        return Err(Error::InvalidGeometry {
            what: "rotation_between",
            detail: "the initial vector A₁ must be finite and non-zero".into(),
        });
    }
    Ok(a2 / a1)
}

/// Planar rotation about the origin in homogeneous coordinates,
/// R(θ) = [[cos θ, −sin θ, 0], [sin θ, cos θ, 0], [0, 0, 1]].
///
/// ```
/// use kinematics_core::transform::{rotation2, apply2};
/// use kinematics_core::nalgebra::Vector2;
/// let p = apply2(&rotation2(std::f64::consts::PI), &Vector2::new(1.0, 2.0));
/// assert!((p - Vector2::new(-1.0, -2.0)).norm() < 1e-15);
/// ```
#[must_use]
pub fn rotation2(theta: f64) -> Matrix3<f64> {
    let (s, c) = crate::math::sin_cos(theta);
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Planar translation by Δ = (Δx, Δy) in homogeneous coordinates,
/// T = [[1, 0, Δx], [0, 1, Δy], [0, 0, 1]].
///
/// ```
/// use kinematics_core::transform::{translation2, apply2};
/// use kinematics_core::nalgebra::Vector2;
/// let p = apply2(&translation2(&Vector2::new(1.0, -1.0)), &Vector2::new(2.0, 2.0));
/// assert_eq!(p, Vector2::new(3.0, 1.0));
/// ```
#[must_use]
pub fn translation2(d: &Vector2<f64>) -> Matrix3<f64> {
    Matrix3::new(1.0, 0.0, d.x, 0.0, 1.0, d.y, 0.0, 0.0, 1.0)
}

/// Rotation by θ followed by translation by Δ, both in the fixed frame:
/// D = T(Δ) R(θ) (the concatenation of finite displacements).
///
/// ```
/// use kinematics_core::transform::{displacement2, rotation2, translation2};
/// use kinematics_core::nalgebra::Vector2;
/// let d = Vector2::new(1.0, 0.5);
/// assert_eq!(displacement2(0.3, &d), translation2(&d) * rotation2(0.3));
/// ```
#[must_use]
pub fn displacement2(theta: f64, d: &Vector2<f64>) -> Matrix3<f64> {
    translation2(d) * rotation2(theta)
}

/// Rotation by θ about the point Q: D = T(+Q) R(θ) T(−Q), whose
/// translation column is Q − R Q.
///
/// ```
/// use kinematics_core::transform::{rotation2_about, apply2};
/// use kinematics_core::nalgebra::Vector2;
/// let q = Vector2::new(1.0, 1.0);
/// // Q itself does not move; (2, 1) turns a quarter about Q to (1, 2).
/// let m = rotation2_about(std::f64::consts::FRAC_PI_2, &q);
/// assert!((apply2(&m, &q) - q).norm() < 1e-15);
/// assert!((apply2(&m, &Vector2::new(2.0, 1.0)) - Vector2::new(1.0, 2.0)).norm() < 1e-15);
/// ```
#[must_use]
pub fn rotation2_about(theta: f64, q: &Vector2<f64>) -> Matrix3<f64> {
    translation2(q) * rotation2(theta) * translation2(&-q)
}

/// Applies a planar homogeneous matrix to a point: (x', y', 1)ᵀ = D (x, y, 1)ᵀ.
///
/// ```
/// use kinematics_core::transform::{apply2, translation2};
/// use kinematics_core::nalgebra::Vector2;
/// assert_eq!(apply2(&translation2(&Vector2::new(1.0, 0.0)), &Vector2::zeros()), Vector2::new(1.0, 0.0));
/// ```
#[must_use]
pub fn apply2(m: &Matrix3<f64>, p: &Vector2<f64>) -> Vector2<f64> {
    let h = m * p.push(1.0);
    Vector2::new(h.x, h.y)
}
