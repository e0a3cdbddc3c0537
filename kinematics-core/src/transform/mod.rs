//! Finite displacements: planar and spatial rotations, translations, screw
//! displacements, the seven elementary 4×4 matrices and joint transforms.
//!
//! Conventions: column vectors, p' = M p. A positive rotation about a unit
//! axis û follows the right-hand rule (thumb along û). A 4×4 matrix maps a
//! point given in a moving frame j to the frame i it is expressed in,
//! Pⁱ = T_ij Pʲ. These are the same names and conventions as the built-in
//! functions of the spatial `mechanism!` language.

mod axis;
mod homogeneous;
mod joints;
mod planar;
mod rotation;

pub use axis::Axis;
pub use homogeneous::{
    Plane, Screw, homogeneous, screw, screw_about, screw_parameters, transform_point, translation,
};
pub use joints::{
    cylindrical, prismatic, revolute, screw_joint, spherical, t1, t2, t3, t4, t5, t6, t7,
};
pub use planar::{
    apply2, displacement2, rotation_between, rotation_operator, rotation2, rotation2_about,
    translation2,
};
pub(crate) use rotation::finite;
pub use rotation::{AxisAngle, CompositeRotation, axis_angle, rot, rot_about, rot_x, rot_y, rot_z};
