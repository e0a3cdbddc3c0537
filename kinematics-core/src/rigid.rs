//! Rigid-body kinematics: velocity and acceleration of points of a body, of
//! points moving relative to a body, angular velocity from body vectors and
//! over chains of frames.
//!
//! All vectors are 3-D and expressed in one frame; a planar problem uses
//! z = 0 for positions and (0, 0, ω) for angular velocities.

use nalgebra::Vector3;

use crate::error::Error;

/// Motion of a reference frame (or body) at an instant: its origin's
/// velocity and acceleration, its angular velocity ω and acceleration α.
///
/// ```
/// use kinematics_core::rigid::{body_point_velocity, FrameMotion};
/// use kinematics_core::nalgebra::Vector3;
/// let disc = FrameMotion { angular_velocity: Vector3::new(0.0, 0.0, 2.0), ..Default::default() };
/// let v = body_point_velocity(&disc.velocity, &disc.angular_velocity, &Vector3::new(0.5, 0.0, 0.0));
/// assert_eq!(v, Vector3::new(0.0, 1.0, 0.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameMotion {
    /// Velocity of the frame's origin O.
    pub velocity: Vector3<f64>,
    /// Acceleration of the frame's origin O.
    pub acceleration: Vector3<f64>,
    /// Angular velocity ω.
    pub angular_velocity: Vector3<f64>,
    /// Angular acceleration α = dω/dt.
    pub angular_acceleration: Vector3<f64>,
}

/// Velocity of a point fixed in a body: v = v_O + ω × r, with r from the
/// body's point O to the point.
///
/// ```
/// use kinematics_core::rigid::body_point_velocity;
/// use kinematics_core::nalgebra::Vector3;
/// // A wheel turning at 2 rad/s about z: the point at (1, 0, 0) moves at (0, 2, 0).
/// let v = body_point_velocity(&Vector3::zeros(), &Vector3::new(0.0, 0.0, 2.0), &Vector3::x());
/// assert_eq!(v, Vector3::new(0.0, 2.0, 0.0));
/// ```
#[must_use]
pub fn body_point_velocity(
    v_o: &Vector3<f64>,
    omega: &Vector3<f64>,
    r: &Vector3<f64>,
) -> Vector3<f64> {
    v_o + omega.cross(r)
}

/// Acceleration of a point fixed in a body:
/// a = a_O + α × r + ω × (ω × r) (tangential plus normal terms).
///
/// ```
/// use kinematics_core::rigid::body_point_acceleration;
/// use kinematics_core::nalgebra::Vector3;
/// // Uniform rotation at 2 rad/s: centripetal −ω² r.
/// let a = body_point_acceleration(&Vector3::zeros(), &Vector3::zeros(), &Vector3::new(0.0, 0.0, 2.0), &Vector3::x());
/// assert_eq!(a, Vector3::new(-4.0, 0.0, 0.0));
/// ```
#[must_use]
pub fn body_point_acceleration(
    a_o: &Vector3<f64>,
    alpha: &Vector3<f64>,
    omega: &Vector3<f64>,
    r: &Vector3<f64>,
) -> Vector3<f64> {
    a_o + alpha.cross(r) + omega.cross(&omega.cross(r))
}

/// Motion of a point that moves relative to a body, term by term.
///
/// ```
/// use kinematics_core::rigid::{relative_motion, FrameMotion};
/// use kinematics_core::nalgebra::Vector3;
/// let rod = FrameMotion { angular_velocity: Vector3::new(0.0, 0.0, 3.0), ..Default::default() };
/// let m = relative_motion(&rod, &Vector3::new(0.5, 0.0, 0.0), &Vector3::new(1.0, 0.0, 0.0), &Vector3::zeros());
/// // The parts add up to the absolute acceleration.
/// assert_eq!(m.transport_acceleration + m.coriolis + m.relative_acceleration, m.acceleration);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RelativeMotion {
    /// Absolute velocity v = v_O + v_rel + ω × r.
    pub velocity: Vector3<f64>,
    /// Absolute acceleration a = a_O + a_rel + 2ω × v_rel + α × r + ω × (ω × r).
    pub acceleration: Vector3<f64>,
    /// Transport velocity v_O + ω × r (of the body point coinciding with it).
    pub transport_velocity: Vector3<f64>,
    /// Transport acceleration a_O + α × r + ω × (ω × r).
    pub transport_acceleration: Vector3<f64>,
    /// Coriolis acceleration 2ω × v_rel.
    pub coriolis: Vector3<f64>,
    /// Velocity relative to the body, v_rel.
    pub relative_velocity: Vector3<f64>,
    /// Acceleration relative to the body, a_rel.
    pub relative_acceleration: Vector3<f64>,
}

/// Velocity and acceleration of a point at r from the origin of a moving
/// frame, moving relative to it with v_rel and a_rel (both measured in the
/// frame, expressed in fixed axes):
/// v = v_O + v_rel + ω × r and a = a_O + a_rel + 2ω × v_rel + α × r + ω × (ω × r).
///
/// ```
/// use kinematics_core::rigid::{relative_motion, FrameMotion};
/// use kinematics_core::nalgebra::Vector3;
/// // A bead sliding outward at 1 m/s on a rod turning at 3 rad/s about z.
/// let rod = FrameMotion { angular_velocity: Vector3::new(0.0, 0.0, 3.0), ..Default::default() };
/// let m = relative_motion(&rod, &Vector3::new(0.5, 0.0, 0.0), &Vector3::new(1.0, 0.0, 0.0), &Vector3::zeros());
/// assert_eq!(m.coriolis, Vector3::new(0.0, 6.0, 0.0));
/// assert_eq!(m.acceleration, Vector3::new(-4.5, 6.0, 0.0));
/// ```
#[must_use]
pub fn relative_motion(
    frame: &FrameMotion,
    r: &Vector3<f64>,
    v_rel: &Vector3<f64>,
    a_rel: &Vector3<f64>,
) -> RelativeMotion {
    let w = &frame.angular_velocity;
    let transport_velocity = body_point_velocity(&frame.velocity, w, r);
    let transport_acceleration =
        body_point_acceleration(&frame.acceleration, &frame.angular_acceleration, w, r);
    let coriolis = 2.0 * w.cross(v_rel);
    RelativeMotion {
        velocity: transport_velocity + v_rel,
        acceleration: transport_acceleration + coriolis + a_rel,
        transport_velocity,
        transport_acceleration,
        coriolis,
        relative_velocity: *v_rel,
        relative_acceleration: *a_rel,
    }
}

/// Angular velocity of a body from two non-parallel vectors a, b fixed in it
/// and their time derivatives (ȧ = ω × a, ḃ = ω × b):
/// ω = ½ [(ȧ × ḃ)/(ȧ · b) + (ḃ × ȧ)/(ḃ · a)] (the chapter's eq. 4.25, the
/// symmetric form of eq. 4.18).
///
/// Both denominators equal ±ω·(a × b), so they vanish together when ω lies
/// in the plane of a and b; there the exact identity
/// a × ȧ + b × ḃ = [(|a|² + |b|²) I − a aᵀ − b bᵀ] ω is solved instead (its
/// matrix is regular whenever a and b are not parallel).
///
/// # Errors
/// [`Error::InvalidGeometry`] when a and b are parallel, or the derivatives
/// are not those of vectors of one rigid body (no ω gives ȧ = ω × a and
/// ḃ = ω × b).
///
/// ```
/// use kinematics_core::rigid::angular_velocity_from_vectors;
/// use kinematics_core::nalgebra::Vector3;
/// let (a, b) = (Vector3::new(1.0, 0.0, 0.5), Vector3::new(0.0, 1.0, 1.0));
/// for w in [Vector3::new(0.3, -1.0, 2.0), a + 2.0 * b] {
///     let got = angular_velocity_from_vectors(&a, &b, &w.cross(&a), &w.cross(&b))?;
///     assert!((got - w).norm() < 1e-12);
/// }
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn angular_velocity_from_vectors(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    a_dot: &Vector3<f64>,
    b_dot: &Vector3<f64>,
) -> Result<Vector3<f64>, Error> {
    for (name, v) in [("ȧ", a_dot), ("ḃ", b_dot), ("a", a), ("b", b)] {
        crate::transform::finite("angular_velocity_from_vectors", name, v.as_slice())?;
    }
    let scale = a.norm() * b.norm();
    // Written so that NaN inputs fail the test.
    let independent = a.cross(b).norm() > 1e-12 * scale;
    if !independent {
        return Err(Error::InvalidGeometry {
            what: "angular_velocity_from_vectors",
            detail: "the two body vectors a and b must not be parallel (or zero)".into(),
        });
    }
    let d1 = a_dot.dot(b);
    let d2 = b_dot.dot(a);
    let rate = a_dot.norm() * b.norm() + b_dot.norm() * a.norm();
    let omega = if d1.abs() > 1e-6 * rate && d2.abs() > 1e-6 * rate {
        (a_dot.cross(b_dot) / d1 + b_dot.cross(a_dot) / d2) / 2.0
    } else {
        let m = nalgebra::Matrix3::identity() * (a.norm_squared() + b.norm_squared())
            - a * a.transpose()
            - b * b.transpose();
        let rhs = a.cross(a_dot) + b.cross(b_dot);
        m.lu().solve(&rhs).unwrap_or_else(Vector3::zeros)
    };
    let residual = (omega.cross(a) - a_dot).norm() + (omega.cross(b) - b_dot).norm();
    let consistent = residual <= 1e-9 * (a_dot.norm() + b_dot.norm()) + f64::MIN_POSITIVE;
    if !consistent {
        return Err(Error::InvalidGeometry {
            what: "angular_velocity_from_vectors",
            detail: "the derivatives are not those of vectors of one rigid body \
                     (no ω gives ȧ = ω × a and ḃ = ω × b)"
                .into(),
        });
    }
    Ok(omega)
}

/// Angular velocity over a chain of frames: ω_rn = ω_r1 + ω_12 + … +
/// ω_(n−1)n, each term the angular velocity of a frame relative to the
/// previous one (eq. 4.26).
///
/// ```
/// use kinematics_core::rigid::angular_velocity_chain;
/// use kinematics_core::nalgebra::Vector3;
/// let w = angular_velocity_chain(&[Vector3::new(0.0, 0.0, 6.0), Vector3::new(2.0, 0.0, 0.0)]);
/// assert_eq!(w, Vector3::new(2.0, 0.0, 6.0));
/// ```
#[must_use]
pub fn angular_velocity_chain(relative: &[Vector3<f64>]) -> Vector3<f64> {
    relative.iter().sum()
}

/// Time derivative in the fixed frame of a vector c known in a frame turning
/// at ω: dc/dt = (dc/dt)_frame + ω × c (eq. 4.31).
///
/// ```
/// use kinematics_core::rigid::derivative_in_moving_frame;
/// use kinematics_core::nalgebra::Vector3;
/// // The notes' satellite dish: ω̇₂ = 1.5i + 6k × 2i = 1.5i + 12j.
/// let d = derivative_in_moving_frame(&Vector3::new(1.5, 0.0, 0.0), &Vector3::new(0.0, 0.0, 6.0), &Vector3::new(2.0, 0.0, 0.0));
/// assert_eq!(d, Vector3::new(1.5, 12.0, 0.0));
/// ```
#[must_use]
pub fn derivative_in_moving_frame(
    rate_in_frame: &Vector3<f64>,
    omega: &Vector3<f64>,
    c: &Vector3<f64>,
) -> Vector3<f64> {
    rate_in_frame + omega.cross(c)
}

/// Angular velocity of a link between two spherical joints with no spin
/// about its own axis: Ω = b × v_BA / |b|², with b = B − A and v_BA = v_B − v_A.
/// Any spin about b is a passive freedom that the joints cannot determine.
///
/// # Errors
/// [`Error::InvalidGeometry`] when b = 0.
///
/// ```
/// use kinematics_core::rigid::no_spin_angular_velocity;
/// use kinematics_core::nalgebra::Vector3;
/// let b = Vector3::new(0.0, 0.0, 2.0);
/// let w = Vector3::new(1.0, -0.5, 0.0); // perpendicular to b
/// let got = no_spin_angular_velocity(&b, &w.cross(&b))?;
/// assert!((got - w).norm() < 1e-15);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn no_spin_angular_velocity(
    b: &Vector3<f64>,
    v_ba: &Vector3<f64>,
) -> Result<Vector3<f64>, Error> {
    crate::transform::finite(
        "no_spin_angular_velocity",
        "the relative motion of B and A",
        v_ba.as_slice(),
    )?;
    let b2 = b.norm_squared();
    if !(b2 > 0.0 && b2.is_finite()) {
        return Err(Error::InvalidGeometry {
            what: "no_spin_angular_velocity",
            detail: "the link vector b = B − A must be finite and non-zero".into(),
        });
    }
    Ok(b.cross(v_ba) / b2)
}

/// Angular acceleration of the same link with no spin about its axis, the
/// derivative of Ω = b × v_BA / |b|²: since ḃ = v_BA and |b| is constant,
/// α = b × a_BA / |b|², with a_BA = a_B − a_A.
///
/// # Errors
/// [`Error::InvalidGeometry`] when b = 0.
///
/// ```
/// use kinematics_core::rigid::no_spin_angular_acceleration;
/// use kinematics_core::nalgebra::Vector3;
/// let a = no_spin_angular_acceleration(&Vector3::new(0.0, 0.0, 1.0), &Vector3::new(0.0, 3.0, 0.0))?;
/// assert_eq!(a, Vector3::new(-3.0, 0.0, 0.0));
/// # Ok::<(), kinematics_core::Error>(())
/// ```
pub fn no_spin_angular_acceleration(
    b: &Vector3<f64>,
    a_ba: &Vector3<f64>,
) -> Result<Vector3<f64>, Error> {
    no_spin_angular_velocity(b, a_ba)
}
