//! The orientation and motion of a body frame, as a mechanism's motion
//! holds it.

use nalgebra::{Matrix3, Vector3};

use super::PointMotion;
use crate::rigid::FrameMotion;

/// Orientation and motion of a body frame declared in `frames { … }`.
///
/// For a frame given by a rotation R(q) (or a 4×4 transform with rotation R
/// and origin o): Ṙ = Σ ∂R/∂q_j q'_j, the angular velocity ω is the axial
/// vector of the skew part of Ṙ Rᵀ, and α = dω/dt, all in the fixed frame
/// and differentiated exactly at compile time. When R is a product of
/// rotations Rₖ(θₖ) about axes fixed in their bodies (joints `t1`…`t6`,
/// `rot_x`…`rot_z`, `rot` or `screw` about a constant axis), the same ω and
/// α are formed along the chain: ω = Σ zₖ θ̇ₖ and
/// α = Σ (zₖ θ̈ₖ + ωₖ₋₁ × zₖ θ̇ₖ), zₖ being the k-th axis in fixed
/// coordinates and ωₖ₋₁ the sum up to k − 1.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// A crane: the cab turns about z, the boom is raised about its y axis.
/// #     pub struct Crane {
/// #         params   { l }
/// #         drivers  { phi, th }
/// #         unknowns { }
/// #         frames   { boom = rot_z(phi) * rot_y(-th); }
/// #         points   { P = boom * vec3(l, 0.0, 0.0); }
/// #     }
/// # }
/// # fn main() -> Result<(), kinematics_core::Error> {
/// let crane = Crane { l: 12.0 };
/// let pose = crane.assemble(&CraneCoords { phi: 0.0, th: 0.5 })?;
/// let s = crane.analyze(&pose, [0.3, 0.0], [0.0, 0.0])?;
/// let boom = s.frame_boom();
/// // Turning the cab at 0.3 rad/s turns the boom about z.
/// assert!((boom.angular_velocity - kinematics_core::nalgebra::Vector3::new(0.0, 0.0, 0.3)).norm() < 1e-15);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FrameState {
    /// Rotation matrix R (frame axes in fixed coordinates).
    pub rotation: Matrix3<f64>,
    /// Origin o (zero for a pure rotation).
    pub origin: Vector3<f64>,
    /// Velocity of the origin.
    pub velocity: Vector3<f64>,
    /// Acceleration of the origin.
    pub acceleration: Vector3<f64>,
    /// Angular velocity ω.
    pub angular_velocity: Vector3<f64>,
    /// Angular acceleration α = dω/dt.
    pub angular_acceleration: Vector3<f64>,
}

impl FrameState {
    /// A frame's state from its 24 values in the order of the run-time
    /// models' flat outputs (`runtime::Flat::outputs`): R row by
    /// row, ω, α, then the origin's position, velocity and acceleration.
    ///
    /// ```
    /// use kinematics_core::FrameState;
    /// let mut v = [0.0; 24];
    /// (v[0], v[4], v[8], v[11], v[15]) = (1.0, 1.0, 1.0, 2.0, 3.0);
    /// let f = FrameState::from_values(&v);
    /// assert_eq!(f.rotation, nalgebra::Matrix3::identity());
    /// assert_eq!((f.angular_velocity.z, f.origin.x), (2.0, 3.0));
    /// ```
    #[must_use]
    pub fn from_values(v: &[f64; 24]) -> Self {
        FrameState {
            rotation: Matrix3::from_row_slice(&v[..9]),
            angular_velocity: Vector3::new(v[9], v[10], v[11]),
            angular_acceleration: Vector3::new(v[12], v[13], v[14]),
            origin: Vector3::new(v[15], v[16], v[17]),
            velocity: Vector3::new(v[18], v[19], v[20]),
            acceleration: Vector3::new(v[21], v[22], v[23]),
        }
    }

    /// The frame's motion, for the rigid-body helpers of [`crate::rigid`].
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #         /// A crane: the cab turns about z, the boom is raised about its y axis.
    /// #     pub struct Crane {
    /// #         params   { l }
    /// #         drivers  { phi, th }
    /// #         unknowns { }
    /// #         frames   { boom = rot_z(phi) * rot_y(-th); }
    /// #         points   { P = boom * vec3(l, 0.0, 0.0); }
    /// #     }
    /// # }
    /// # fn main() -> Result<(), kinematics_core::Error> {
    /// let crane = Crane { l: 12.0 };
    /// let pose = crane.assemble(&CraneCoords { phi: 0.0, th: 0.5 })?;
    /// let s = crane.analyze(&pose, [0.3, 0.5], [0.0, 0.0])?;
    /// let m = s.frame_boom().motion();
    /// assert_eq!(m.angular_velocity, s.frame_boom().angular_velocity);
    /// # Ok(())
    /// # }
    /// ```
    #[must_use]
    pub fn motion(&self) -> FrameMotion {
        FrameMotion {
            velocity: self.velocity,
            acceleration: self.acceleration,
            angular_velocity: self.angular_velocity,
            angular_acceleration: self.angular_acceleration,
        }
    }

    /// Position, velocity and acceleration of a point fixed in the frame at
    /// local coordinates p: r = o + R p, v = v_o + ω × (R p),
    /// a = a_o + α × (R p) + ω × (ω × (R p)).
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #         /// A crane: the cab turns about z, the boom is raised about its y axis.
    /// #     pub struct Crane {
    /// #         params   { l }
    /// #         drivers  { phi, th }
    /// #         unknowns { }
    /// #         frames   { boom = rot_z(phi) * rot_y(-th); }
    /// #         points   { P = boom * vec3(l, 0.0, 0.0); }
    /// #     }
    /// # }
    /// # fn main() -> Result<(), kinematics_core::Error> {
    /// use kinematics_core::nalgebra::Vector3;
    /// let crane = Crane { l: 12.0 };
    /// let pose = crane.assemble(&CraneCoords { phi: 0.2, th: 0.5 })?;
    /// let s = crane.analyze(&pose, [0.3, 0.5], [0.1, 0.0])?;
    /// // The tip, computed from the frame, is the declared point P.
    /// let tip = s.frame_boom().point(&Vector3::new(12.0, 0.0, 0.0));
    /// assert!((tip.acceleration - s.point_p().acceleration).norm() < 1e-12);
    /// # Ok(())
    /// # }
    /// ```
    #[must_use]
    pub fn point(&self, local: &Vector3<f64>) -> PointMotion<3> {
        let r = self.rotation * local;
        PointMotion {
            position: self.origin + r,
            velocity: crate::rigid::body_point_velocity(&self.velocity, &self.angular_velocity, &r),
            acceleration: crate::rigid::body_point_acceleration(
                &self.acceleration,
                &self.angular_acceleration,
                &self.angular_velocity,
                &r,
            ),
        }
    }
}
