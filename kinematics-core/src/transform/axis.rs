//! The coordinate axes, by name.

use nalgebra::Vector3;

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
