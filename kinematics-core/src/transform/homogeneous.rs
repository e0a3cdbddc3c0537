//! 4×4 homogeneous transforms: rotations with translations, screw
//! displacements and their parameters.

use alloc::format;
use nalgebra::{Matrix3, Matrix4, Unit, Vector3};

use crate::error::Error;

use super::rotation::{axis_angle, finite, rotation_matrix, unit_axis};

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
