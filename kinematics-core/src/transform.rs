//! Finite displacements: planar and spatial rotations, translations, screw
//! displacements, the seven elementary 4×4 matrices and joint transforms.
//!
//! Conventions: column vectors, p' = M p. A positive rotation about a unit
//! axis û follows the right-hand rule (thumb along û). A 4×4 matrix maps a
//! point given in a moving frame j to the frame i it is expressed in,
//! Pⁱ = T_ij Pʲ. These are the same names and conventions as the built-in
//! functions of the spatial `mechanism!` language.

use alloc::format;
use nalgebra::{Complex, Matrix3, Matrix4, Unit, Vector2, Vector3};

use crate::Error;

/// A coordinate axis of a frame.
///
/// ```
/// use kinematics_core::transform::{rot_z, Axis, CompositeRotation};
/// let r = CompositeRotation::new().about_fixed(Axis::Z, 0.3).matrix();
/// assert!((r - rot_z(0.3)).norm() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// The x axis.
    X,
    /// The y axis.
    Y,
    /// The z axis.
    Z,
}

impl Axis {
    /// The unit vector of the axis.
    ///
    /// ```
    /// use kinematics_core::transform::Axis;
    /// assert_eq!(Axis::Y.unit(), kinematics_core::nalgebra::Vector3::y());
    /// ```
    #[must_use]
    pub fn unit(self) -> Vector3<f64> {
        match self {
            Axis::X => Vector3::x(),
            Axis::Y => Vector3::y(),
            Axis::Z => Vector3::z(),
        }
    }
}

// ───────────────────────────── planar ─────────────────────────────

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

// ───────────────────────────── spatial rotations ─────────────────────────────

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
fn unit_axis(axis: &Vector3<f64>, what: &'static str) -> Result<Unit<Vector3<f64>>, Error> {
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

fn rotation_matrix(u: &Unit<Vector3<f64>>, theta: f64) -> Matrix3<f64> {
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

// ───────────────────────────── 4×4 transforms ─────────────────────────────

/// The 4×4 matrix [[R, d], [0, 1]]: rotation R then translation d.
///
/// ```
/// use kinematics_core::transform::{homogeneous, rot_z, transform_point};
/// use kinematics_core::nalgebra::Vector3;
/// let t = homogeneous(&rot_z(std::f64::consts::FRAC_PI_2), &Vector3::new(1.0, 0.0, 0.0));
/// assert!((transform_point(&t, &Vector3::x()) - Vector3::new(1.0, 1.0, 0.0)).norm() < 1e-15);
/// ```
#[must_use]
pub fn homogeneous(r: &Matrix3<f64>, d: &Vector3<f64>) -> Matrix4<f64> {
    let mut t = r.to_homogeneous();
    t[(0, 3)] = d.x;
    t[(1, 3)] = d.y;
    t[(2, 3)] = d.z;
    t
}

/// Spatial translation by d: [[I, d], [0, 1]].
///
/// ```
/// use kinematics_core::transform::{translation, transform_point};
/// use kinematics_core::nalgebra::Vector3;
/// let p = transform_point(&translation(&Vector3::new(-1.0, -2.0, 2.0)), &Vector3::new(1.0, 4.0, 2.0));
/// assert_eq!(p, Vector3::new(0.0, 2.0, 4.0));
/// ```
#[must_use]
pub fn translation(d: &Vector3<f64>) -> Matrix4<f64> {
    homogeneous(&Matrix3::identity(), d)
}

/// Applies a 4×4 homogeneous matrix to a point: (p', 1)ᵀ = T (p, 1)ᵀ.
///
/// ```
/// use kinematics_core::transform::{t3, transform_point};
/// use kinematics_core::nalgebra::Vector3;
/// let p = transform_point(&t3(1.0, 0.0, 0.0, std::f64::consts::PI), &Vector3::x());
/// assert!(p.norm() < 1e-15);
/// ```
#[must_use]
pub fn transform_point(t: &Matrix4<f64>, p: &Vector3<f64>) -> Vector3<f64> {
    let h = t * p.push(1.0);
    Vector3::new(h.x, h.y, h.z)
}

/// Screw displacement about the axis û through the origin: rotation θ and
/// translation Δ along û, S = T(Δû) R(û, θ) = [[R, Δû], [0, 1]] (eq. 33).
///
/// # Errors
/// [`Error::InvalidGeometry`] for a zero or non-finite axis.
///
/// ```
/// use kinematics_core::transform::{screw, transform_point};
/// use kinematics_core::nalgebra::Vector3;
/// // A quarter turn about z with a lift of 0.5.
/// let s = screw(&Vector3::z(), std::f64::consts::FRAC_PI_2, 0.5)?;
/// let p = transform_point(&s, &Vector3::x());
/// assert!((p - Vector3::new(0.0, 1.0, 0.5)).norm() < 1e-15);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn screw(axis: &Vector3<f64>, theta: f64, delta: f64) -> Result<Matrix4<f64>, Error> {
    let u = unit_axis(axis, "screw")?;
    finite("screw", "the angle θ", &[theta])?;
    finite("screw", "the slide Δ", &[delta])?;
    Ok(homogeneous(
        &rotation_matrix(&u, theta),
        &(u.into_inner() * delta),
    ))
}

/// Screw displacement about the axis û through the point P:
/// S = T(Δû) T(P) R(û, θ) T(−P), whose translation column is
/// Δû + P − R P.
///
/// # Errors
/// [`Error::InvalidGeometry`] for a zero or non-finite axis.
///
/// ```
/// use kinematics_core::transform::{screw_about, transform_point};
/// use kinematics_core::nalgebra::Vector3;
/// // Points of the axis only slide along it.
/// let p = Vector3::new(1.0, 2.0, 3.0);
/// let s = screw_about(&Vector3::new(0.0, 0.0, 1.0), &p, 1.0, 0.25)?;
/// assert!((transform_point(&s, &p) - (p + Vector3::new(0.0, 0.0, 0.25))).norm() < 1e-15);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn screw_about(
    axis: &Vector3<f64>,
    point: &Vector3<f64>,
    theta: f64,
    delta: f64,
) -> Result<Matrix4<f64>, Error> {
    let u = unit_axis(axis, "screw_about")?;
    finite("screw_about", "the point P of the axis", point.as_slice())?;
    finite("screw_about", "the angle θ", &[theta])?;
    finite("screw_about", "the slide Δ", &[delta])?;
    let r = rotation_matrix(&u, theta);
    let d = u.into_inner() * delta + point - r * point;
    Ok(homogeneous(&r, &d))
}

/// Parameters of a screw displacement.
///
/// ```
/// use kinematics_core::transform::{screw, screw_parameters};
/// use kinematics_core::nalgebra::Vector3;
/// let s = screw_parameters(&screw(&Vector3::z(), 0.5, 2.0)?)?;
/// assert!((s.angle - 0.5).abs() < 1e-15 && (s.translation - 2.0).abs() < 1e-15);
/// assert!(s.point.norm() < 1e-15); // the axis passes through the origin
/// # Ok::<(), kinematics_core::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Screw {
    /// Unit direction of the screw axis û.
    pub axis: Unit<Vector3<f64>>,
    /// Rotation θ ∈ [0, π] about û.
    pub angle: f64,
    /// Translation Δ along û.
    pub translation: f64,
    /// The point of the axis nearest the origin.
    pub point: Vector3<f64>,
}

/// A coordinate plane.
///
/// ```
/// use kinematics_core::transform::{screw_about, screw_parameters, Plane};
/// use kinematics_core::nalgebra::Vector3;
/// let t = screw_about(&Vector3::x(), &Vector3::new(0.0, 1.0, 2.0), 1.0, 0.0)?;
/// let p = screw_parameters(&t)?.intersection(Plane::YZ)?;
/// assert!((p - Vector3::new(0.0, 1.0, 2.0)).norm() < 1e-12);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    /// x = 0.
    YZ,
    /// y = 0.
    XZ,
    /// z = 0.
    XY,
}

impl Screw {
    /// Where the screw axis crosses a coordinate plane: P + λû with the
    /// plane's coordinate zero.
    ///
    /// # Errors
    /// [`Error::InvalidGeometry`] when the axis is parallel to the plane.
    ///
    /// ```
    /// use kinematics_core::transform::{screw_about, screw_parameters, Plane};
    /// use kinematics_core::nalgebra::Vector3;
    /// let t = screw_about(&Vector3::new(1.0, 1.0, 0.0), &Vector3::new(0.0, 0.0, 2.0), 1.0, 0.0)?;
    /// let p = screw_parameters(&t)?.intersection(Plane::YZ)?;
    /// assert!((p - Vector3::new(0.0, 0.0, 2.0)).norm() < 1e-12);
    /// # Ok::<(), kinematics_core::Error>(())
    /// ```
    pub fn intersection(&self, plane: Plane) -> Result<Vector3<f64>, Error> {
        finite("screw axis", "the axis point", self.point.as_slice())?;
        finite("screw axis", "the axis direction", self.axis.as_slice())?;
        let k = match plane {
            Plane::YZ => 0,
            Plane::XZ => 1,
            Plane::XY => 2,
        };
        let uk = self.axis[k];
        if uk.abs() < 1e-12 {
            return Err(Error::InvalidGeometry {
                what: "screw axis",
                detail: format!("the axis is parallel to the {plane:?} plane and never crosses it"),
            });
        }
        Ok(self.point - self.axis.into_inner() * (self.point[k] / uk))
    }
}

/// The inverse problem of a screw displacement (Chasles): from
/// T = [[R, d], [0, 1]], the axis û and angle θ of R (see [`axis_angle`]),
/// the slide Δ = û·d, and the point P of the axis nearest the origin,
/// P = ½ (d⊥ + cot(θ/2) û × d⊥) with d⊥ = d − Δû (from d⊥ = (I − R) P).
/// A pure translation (θ = 0) has its axis along d, through the origin.
///
/// # Errors
/// [`Error::InvalidGeometry`] when the rotation part is not a rotation or the
/// bottom row is not (0, 0, 0, 1).
///
/// ```
/// use kinematics_core::transform::{screw_about, screw_parameters};
/// use kinematics_core::nalgebra::Vector3;
/// let t = screw_about(&Vector3::new(1.0, 2.0, 2.0), &Vector3::new(0.0, 6.0, 6.0), 2.0, 3.0)?;
/// let s = screw_parameters(&t)?;
/// assert!((s.angle - 2.0).abs() < 1e-12 && (s.translation - 3.0).abs() < 1e-12);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn screw_parameters(t: &Matrix4<f64>) -> Result<Screw, Error> {
    finite("screw matrix", "the transform T", t.as_slice())?;
    let bottom = [t[(3, 0)], t[(3, 1)], t[(3, 2)], t[(3, 3)] - 1.0];
    if bottom.iter().any(|v| v.is_nan() || v.abs() > 1e-9) {
        return Err(Error::InvalidGeometry {
            what: "screw matrix",
            detail: "the bottom row of a homogeneous transform must be (0, 0, 0, 1)".into(),
        });
    }
    let r: Matrix3<f64> = t.fixed_view::<3, 3>(0, 0).into();
    let d: Vector3<f64> = t.fixed_view::<3, 1>(0, 3).into();
    let aa = axis_angle(&r)?;
    if aa.angle == 0.0 {
        let n = d.norm();
        let axis = if n > 0.0 {
            Unit::new_normalize(d)
        } else {
            Vector3::z_axis()
        };
        return Ok(Screw {
            axis,
            angle: 0.0,
            translation: n,
            point: Vector3::zeros(),
        });
    }
    let u = aa.axis.into_inner();
    let delta = u.dot(&d);
    let perp = d - u * delta;
    let cot_half = 1.0 / crate::math::tan(aa.angle / 2.0);
    let point = (perp + u.cross(&perp) * cot_half) / 2.0;
    // Remove any component along û left by rounding in the data.
    let point = point - u * u.dot(&point);
    Ok(Screw {
        axis: aa.axis,
        angle: aa.angle,
        translation: delta,
        point,
    })
}

// ───────────────────────────── elementary matrices ─────────────────────────────

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
