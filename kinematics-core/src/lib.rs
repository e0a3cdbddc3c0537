//! Kinematic analysis of mechanisms declared as vector loop-closure equations.
//!
//! A mechanism is written once in [`mechanism!`]; at compile time the macro
//! checks the model and differentiates it exactly into the velocity Jacobian
//! and the acceleration (convective) terms, and emits straight-line Rust. At
//! run time this crate assembles the mechanism by Newton–Raphson and solves
//! velocities and accelerations of every coordinate and point.
//!
//! Start with the [`guide`]: its [`language`](guide::language) reference
//! lists every section and built-in of `mechanism!` and what it generates,
//! [`failures`](guide::failures) what each bad input gives and what `Ok`
//! guarantees, [`compile_errors`](guide::compile_errors) how a wrong
//! definition is reported.
//!
//! | module | contents |
//! |---|---|
//! | [`sweep`] | full cycles and time-driven simulations, CSV and text tables |
//! | `plot` | SVG figures of a sweep (feature `plot`) |
//! | [`transform`] | planar and spatial transforms, screws, joint matrices |
//! | [`rigid`] | rigid-body velocities and accelerations, relative motion |
//! | [`mobility`] | the Kutzbach–Gruebler count |
//! | [`solve`] | the Newton–Raphson solver and the linear algebra behind it |
//!
//! Features: `std` (on by default; without it the crate is `no_std` with
//! `alloc`, takes its floating-point functions from libm, and the code
//! `mechanism!` generates compiles for embedded targets), `plot` (SVG
//! figures, with plotters) and `parallel` (`batch`, on all cores with
//! rayon), both off by default and both needing `std`.
//!
//! ```
//! use kinematics_core::mechanism;
//!
//! mechanism! {
//!     /// Crank-rocker four-bar: ground pivots A = (0, 0) and D = (d, 0).
//!     pub struct FourBar {
//!         params   { a, b, c, d }
//!         drivers  { phi }
//!         unknowns { th3, th4 }
//!         points {
//!             B = polar(a, phi);
//!             C = vec2(d, 0.0) + polar(c, th4);
//!         }
//!         loops { B + polar(b, th3) == C; }
//!     }
//! }
//!
//! # fn main() -> Result<(), kinematics_core::Error> {
//! let m = FourBar { a: 0.04, b: 0.12, c: 0.10, d: 0.11 };
//! let pose = m.assemble(&FourBarCoords { phi: 0.0, th3: 1.2, th4: 1.9 })?;
//! let s = m.analyze(&pose, 10.0, 0.0)?;            // φ' = 10 rad/s, φ'' = 0
//! // Point C moves on the rocker's circle: v_C ⟂ DC.
//! let dc = s.point_c().position - nalgebra::Vector2::new(m.d, 0.0);
//! assert!(s.point_c().velocity.dot(&dc).abs() < 1e-12);
//! println!("ω3 = {:.4} rad/s, ω4 = {:.4} rad/s", s.qd.th3, s.qd.th4);
//! # Ok(())
//! # }
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
#![forbid(unsafe_code)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
// docs.rs builds with nightly and `--cfg docsrs_nightly` (see Cargo.toml),
// and marks the feature-gated items; a stable `cargo doc`, with or without
// `--cfg docsrs`, does not need the unstable attribute.
#![cfg_attr(docsrs_nightly, feature(doc_cfg))]

extern crate alloc;
// The unit tests use the standard library's harness and constants, also
// when the crate itself is built without it.
#[cfg(all(test, not(feature = "std")))]
extern crate std;

#[cfg(feature = "std")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "std")))]
pub mod animate;
#[cfg(feature = "parallel")]
mod batch;
mod checks;
pub mod closed;
mod derive;
#[cfg(feature = "std")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "std")))]
pub mod dxf;
pub mod dynamics;
mod error;
pub mod links;
pub mod math;
mod mechanism;
pub mod merit;
pub mod mobility;
mod names;
mod options;
#[cfg(feature = "plot")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "plot")))]
pub mod plot;
pub mod rigid;
#[cfg(feature = "runtime")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "runtime")))]
pub mod runtime;
pub mod solve;
pub mod sweep;
#[cfg(feature = "synthesis")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "synthesis")))]
pub mod synthesis;
pub mod tolerance;
pub mod transform;
pub mod units;
pub mod view;

#[cfg(feature = "parallel")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "parallel")))]
pub use batch::batch;
pub use error::{Error, Input};
/// The language is described in [`guide::language`], with every section and
/// built-in and what is generated for a definition.
#[doc(inline)]
pub use kinematics_macros::mechanism;

/// The guide: the `mechanism!` language, the failure modes, the compile
/// errors.
#[doc = include_str!("../docs/guide.md")]
pub mod guide {
    #[doc = include_str!("../docs/language.md")]
    pub mod language {}
    #[doc = include_str!("../docs/failures.md")]
    pub mod failures {}
    #[doc = include_str!("../docs/compile-errors.md")]
    pub mod compile_errors {}
    #[doc = include_str!("../docs/assembly.md")]
    pub mod assembly {}
    // Its example derives serde's traits: compiled as a test with the
    // `serde` feature, which the workspace's tests turn on.
    #[cfg(any(not(doctest), feature = "serde"))]
    #[doc = include_str!("../docs/simulation.md")]
    pub mod simulation {}
    #[doc = include_str!("../docs/forces.md")]
    pub mod forces {}
    #[doc = include_str!("../docs/tolerances.md")]
    pub mod tolerances {}
    #[doc = include_str!("../docs/synthesis.md")]
    pub mod synthesis {}
    #[doc = include_str!("../docs/spatial.md")]
    pub mod spatial {}
    #[doc = include_str!("../docs/toolkit.md")]
    pub mod toolkit {}
    #[cfg(feature = "runtime")]
    #[cfg_attr(docsrs_nightly, doc(cfg(feature = "runtime")))]
    #[doc = include_str!("../docs/runtime.md")]
    #[cfg_attr(feature = "synthesis", doc = include_str!("../docs/runtime-synthesis.md"))]
    #[doc = include_str!("../docs/runtime-models.md")]
    pub mod runtime {}
    #[doc = include_str!("../docs/cli.md")]
    pub mod cli {}
    #[doc = include_str!("../docs/errors.md")]
    pub mod errors {}
    #[doc = include_str!("../docs/verification.md")]
    pub mod verification {}
    #[doc = include_str!("../docs/performance.md")]
    pub mod performance {}
}
pub use mechanism::{
    Coordinate, Coordinates, DriverValues, FrameState, Kind, Mechanism, MotionState, PointMotion,
    PointState, Pose, Role,
};
pub use nalgebra;
pub use options::{Branch, Convergence, Options};

/// The README's examples, compiled and run as doctests (one of them
/// derives serde's traits: with the `serde` feature, which the workspace's
/// tests turn on).
#[doc = include_str!("../../README.md")]
#[cfg(all(doctest, feature = "serde"))]
pub struct ReadmeDoctests;

/// Items used by the code that `mechanism!` generates. Not a stable API:
/// anything here may change in any release.
#[doc(hidden)]
pub mod __private {
    pub use crate::MotionState;
    pub use crate::checks::{
        driver_arrays, finite, finite_outputs, positive, positive_distance, same_bits,
    };
    pub use crate::closed;
    pub use crate::math;
    pub use crate::solve::{
        Failure, FastNewton, Lu, Names, Next, Scaling, branch_check, characteristic_length,
        dense_solve, describe, newton, sin_cos_after,
    };
    pub use crate::sweep;
    pub use crate::{Coordinate, Coordinates, DriverValues, Error, Input, Kind, Mechanism};
    pub use crate::{FrameState, Options, PointMotion, PointState, Pose, Role};
    pub use core::result::Result;
    pub use nalgebra::{Matrix3, Vector2, Vector3};
}
