//! Dense linear solves and Newton–Raphson on fixed-size arrays.
//!
//! Everything here works on `[f64; N]` and `[[f64; N]; N]` on the stack, so
//! assembling near a known pose and analysing velocities and accelerations
//! allocate nothing.

mod failure;
mod linalg;
mod newton;
mod scaling;
#[cfg(test)]
mod tests;

pub use failure::{branch_check, describe, Failure, Names};
pub use linalg::{dense_solve, Lu};
pub use newton::{newton, sin_cos_after, FastNewton, Next, CLOSED, POLISH, ROUND_OFF};
pub use scaling::{characteristic_length, Scaling};
