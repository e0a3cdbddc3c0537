//! Sweeps over a driver's range and time-driven simulations, and their
//! results as tables.
//!
//! A sweep is built from the mechanism, a driver chosen by its typed handle
//! (generated for every driver, `FourBar::PHI`) and the starting pose; the
//! range, the number of steps, the driver's rate and acceleration and the
//! options are named, with defaults:
//!
//! ```
//! use kinematics_core::mechanism;
//! mechanism! {
//!     /// A slider-crank.
//!     pub struct SliderCrank {
//!         params   { a, b }
//!         drivers  { phi }
//!         unknowns { th, x }
//!         points   { B = polar(a, phi); C = vec2(x, 0.0); }
//!         loops    { B + polar(b, th) == C; }
//!     }
//! }
//! let m = SliderCrank { a: 0.1, b: 0.3 };
//! let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
//! // A full turn in 3600 steps (the end, equal to the start, not repeated)
//! // at 600 rev/min.
//! let cycle = m.sweep(SliderCrank::PHI, &start).turn().steps(3600).rpm(600.0).run();
//! assert!(cycle.stop.is_none());
//! assert_eq!(cycle.samples.len(), 3600);
//! // From 30° to 90° in 60 steps (61 samples, both ends), streamed one
//! // sample at a time instead of collected.
//! let mut fastest = 0.0f64;
//! for sample in m.sweep(SliderCrank::PHI, &start).from_deg(30.0).to_deg(90.0).steps(60) {
//!     let sample = sample.expect("the slider-crank assembles everywhere");
//!     fastest = fastest.max(sample.motion.point_c().speed());
//! }
//! assert!(fastest > 0.0);
//! ```
//!
//! At each step the unknowns are predicted from the previous step's rates
//! and solved from there (in closed form where the macro found one, else by
//! Newton–Raphson), on the assembly branch of the start. A sweep never
//! switches branch silently. It ends early, with the samples it has and a
//! typed [`Stop`], when
//!
//! * the driver reaches a **limit position** (the links cannot close the
//!   loop past it): located by bisection on the exact condition, to the
//!   resolution of `f64`, for blocks solved in closed form;
//! * it reaches a **change point**, where two assembly branches meet (det
//!   Φ_u changes sign, or Φ_u's conditioning falls to zero and rises again
//!   between samples, as at a parallelogram four-bar's folded position):
//!   unless [`ChangePoints::Smooth`] or [`ChangePoints::Switch`] says which
//!   branch to continue on;
//! * Φ_u is singular at a sample, or the mechanism does not assemble.

mod builder;
mod change;
mod collected;
mod drive;
mod engine;
mod handles;
mod iter;
mod sample;
mod table;

pub use builder::SweepBuilder;
#[cfg(feature = "runtime")]
pub(crate) use builder::{End, grid};
pub use collected::Sweep;
#[cfg(feature = "runtime")]
pub(crate) use drive::Grid;
pub use drive::{
    AtRest, Drive, Profile, Simulation, SweepDrive, TimeDrive, constant_acceleration,
    constant_speed,
};
#[doc(hidden)]
pub use engine::Engine;
pub use handles::{Angle, ChangePoints, Driver, Length, Wrap};
pub use iter::SweepIter;
pub use sample::{PoseSample, Sample, Solved, Stop, StopReason};
pub use table::{Layout, Table};

/// For the swept values of a sweep of one turn of an angle driver whose
/// closing sample is left out (as `turn()` sweeps: the last sample one
/// step short of the first plus 2π, to 1e-9 of a turn), the period ±2π
/// that closes its last interval; `None` for another range or fewer than
/// three samples. `at(i)` is sample i's value of `n`. The figures of merit
/// and the mean effort close a cycle by it.
pub(crate) fn closing_period(n: usize, at: impl Fn(usize) -> f64) -> Option<f64> {
    use core::f64::consts::TAU;
    if n < 3 {
        return None;
    }
    let first = at(0);
    let span = at(n - 1) - first + (at(1) - first);
    let period = if span > 0.0 { TAU } else { -TAU };
    ((span - period).abs() <= 1e-9 * TAU).then_some(period)
}
