//! Dense linear solves and Newton–Raphson on fixed-size arrays.
//!
//! Generated code works on `[f64; N]` and `[[f64; N]; N]` on the stack, so
//! assembling near a known pose and analysing velocities and accelerations
//! allocate nothing. The Newton–Raphson iteration itself ([`iterate`]) is
//! written once over slices and a [`System`], and serves run-time models
//! too, with one convergence rule.

// The run-time models use all of it, the implicit integrator its LU.
#[cfg_attr(not(feature = "runtime"), allow(dead_code))]
pub(crate) mod dense;
mod failure;
mod linalg;
mod newton;
mod scaling;
#[cfg(test)]
mod tests;

#[cfg(feature = "runtime")]
pub(crate) use failure::describe_by;
pub use failure::{Failure, Names, branch_check, describe};
pub use linalg::{Lu, dense_solve};
pub use newton::{
    CLOSED, FastNewton, Judge, Next, POLISH, ROUND_OFF, Space, System, fast_then_damped, iterate,
    newton, sin_cos_after,
};
pub use scaling::{Scaling, characteristic_length};
