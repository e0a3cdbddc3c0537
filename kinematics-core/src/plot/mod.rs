//! SVG plots of sweeps and drawings of the mechanism (feature `plot`).
//!
//! Every axis has a title with its unit: angles in degrees, angular rates
//! in rad/s and rad/s² (or deg/s, deg/s²: [`Units::angle`]), lengths in metres (the unit of the mechanism's
//! parameters: see [`Units`] for another); the swept driver in degrees when
//! it is an angle, the time in seconds. Curves and links are drawn 2 px
//! wide, grid lines 1 px.
//!
//! | function | what it draws |
//! |---|---|
//! | [`plot_motion`] | q, q', q'' of every unknown against the driver, a panel per quantity and kind (angles, lengths) |
//! | [`plot_points`] | position, velocity and acceleration of named points (components and magnitude) against the driver |
//! | [`plot_path`] | the path of a point (a coupler curve), equal scales |
//! | [`plot_transmission`] | the transmission angle of each dyad against the driver, with the band [40°, 140°] |
//! | [`plot_forces`] | each driver's effort against the driver beside its mean, the shaking force's polar diagram and the joint reactions' ([`crate::dynamics`]) |
//! | [`plot_simulation`] | a forward simulation: each driver's speed against time, and the energies and works with their balance |
//! | [`plot_skeleton`] | the linkage at chosen poses, with a legend of their driver values, ground pivots and sliders marked |
//! | [`plot_table_skeleton`] | the same from the samples of any sweep (a run-time model's) |

pub use crate::view::Projection;

mod chart;
mod forces;
mod merit;
mod motion;
mod path;
mod simulation;
mod skeleton;

pub use chart::Units;
pub use forces::plot_forces;
pub use merit::plot_transmission;
pub use motion::{plot_motion, plot_motion_in, plot_points, plot_points_in};
pub use path::{plot_band, plot_path, plot_path_in};
pub use simulation::plot_simulation;
pub use skeleton::{Overlay, plot_posed, plot_skeleton, plot_skeleton_with, plot_table_skeleton};
