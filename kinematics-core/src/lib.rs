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
pub mod closed;
mod error;
pub mod math;
mod mechanism;
pub mod mobility;
mod names;
mod options;
#[cfg(feature = "plot")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "plot")))]
pub mod plot;
pub mod rigid;
pub mod solve;
pub mod sweep;
#[cfg(feature = "synthesis")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "synthesis")))]
pub mod synthesis;
pub mod tolerance;
pub mod transform;
pub mod view;

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
}
pub use mechanism::{
    Coordinate, Coordinates, DriverValues, FrameState, Kind, Mechanism, MotionState, PointMotion,
    PointState, Pose, Role,
};
pub use nalgebra;
pub use options::{Branch, Convergence, Options};

/// Evaluates `f` for every item of `items` (parameter sets, starting poses)
/// on all cores, returning each item's result or error in order; one failing
/// item never aborts the others (feature `parallel`).
///
/// ```
/// use kinematics_core::{batch, mechanism};
/// mechanism! {
///     /// A slider-crank.
///     pub struct SliderCrank {
///         params { a, b }
///         drivers { phi }
///         unknowns { th, x }
///         loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
///     }
/// }
/// let designs: Vec<SliderCrank> = (1..=4).map(|k| SliderCrank { a: 0.1, b: 0.05 * f64::from(k) }).collect();
/// let start = SliderCrankCoords { phi: 1.2, th: 0.0, x: 0.2 };
/// let results = batch(&designs, |m| m.assemble(&start));
/// // b = 0.05 < a sin φ cannot reach the slider line; the others assemble.
/// assert!(results[0].is_err() && results[3].is_ok());
/// ```
#[cfg(feature = "parallel")]
#[cfg_attr(docsrs_nightly, doc(cfg(feature = "parallel")))]
pub fn batch<T, R, F>(items: &[T], f: F) -> Vec<Result<R, Error>>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> Result<R, Error> + Sync + Send,
{
    use rayon::prelude::*;
    items.par_iter().map(f).collect()
}

/// The README's examples, compiled and run as doctests (one of them
/// derives serde's traits: with the `serde` feature, which the workspace's
/// tests turn on).
#[doc = include_str!("../../README.md")]
#[cfg(all(doctest, feature = "serde"))]
pub struct ReadmeDoctests;

/// Applies the serde derives of a mechanism's definition to one of its
/// generated types (the coordinates, the motion, the modes): with the
/// `serde` feature, as `#[derive(…)]`; without it, a compile error saying
/// to enable it (the generated types hold this crate's types, whose serde
/// implementations come with the feature).
#[cfg(feature = "serde")]
#[doc(hidden)]
#[macro_export]
macro_rules! __with_serde {
    ([$($path:path),+] $item:item) => {
        #[derive($($path),+)]
        $item
    };
}

/// See the `serde` version.
#[cfg(not(feature = "serde"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __with_serde {
    ([$($path:path),+] $item:item) => {
        ::core::compile_error!(
            "deriving Serialize or Deserialize on a mechanism needs the `serde` feature of \
             kinematics-core: `kinematics-core = { version = \"0.1\", features = [\"serde\"] }`"
        );
        $item
    };
}

/// Items used by the code that `mechanism!` generates. Not a stable API:
/// anything here may change in any release.
#[doc(hidden)]
pub mod __private {
    pub use crate::closed;
    pub use crate::math;
    pub use crate::solve::{
        branch_check, characteristic_length, dense_solve, describe, newton, sin_cos_after, Failure,
        FastNewton, Lu, Names, Next, Scaling,
    };
    pub use crate::sweep;
    pub use crate::MotionState;
    pub use crate::{Coordinate, Coordinates, DriverValues, Error, Input, Kind, Mechanism};
    pub use crate::{FrameState, Options, PointMotion, PointState, Pose, Role};
    pub use core::result::Result;
    pub use nalgebra::{Matrix3, Vector2, Vector3};

    /// `rates` and `accelerations` as arrays of one value per driver, or
    /// [`Error::InvalidOption`] when a slice has another length.
    #[inline]
    pub fn driver_arrays<const N: usize>(
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<([f64; N], [f64; N]), Error> {
        match (
            <[f64; N]>::try_from(rates),
            <[f64; N]>::try_from(accelerations),
        ) {
            (Ok(r), Ok(a)) => Ok((r, a)),
            _ => Err(Error::InvalidOption {
                name: "rates and accelerations",
                #[allow(clippy::cast_precision_loss)]
                value: rates.len().max(accelerations.len()) as f64,
                requirement: "must have one value per driver",
            }),
        }
    }

    /// Fails with [`Error::InvalidParameter`] unless `value` > 0 (a
    /// parameter declared `name: length`).
    #[inline]
    pub fn positive(name: &'static str, value: f64) -> Result<(), Error> {
        positive_because(name, value, "must be positive: it is declared a length")
    }

    /// Fails with [`Error::InvalidParameter`] unless `value` > 0: the
    /// distance b of a constraint `norm(v) == b`, which the generated code
    /// solves as v·v = b² (the same solutions only for b > 0).
    #[inline]
    pub fn positive_distance(name: &'static str, value: f64) -> Result<(), Error> {
        positive_because(
            name,
            value,
            "must be positive: it is the distance in a `norm(…) == …` constraint",
        )
    }

    /// Fails with [`Error::InvalidParameter`] and `requirement` unless
    /// `value` > 0 (a NaN fails too).
    #[inline]
    fn positive_because(
        name: &'static str,
        value: f64,
        requirement: &'static str,
    ) -> Result<(), Error> {
        if value > 0.0 {
            Ok(())
        } else {
            Err(Error::InvalidParameter {
                name,
                value,
                requirement,
            })
        }
    }

    /// Fails with [`Error::NonFinite`] when `value` is NaN or infinite.
    #[inline]
    pub fn finite(input: Input, name: &'static str, value: f64) -> Result<(), Error> {
        if value.is_finite() {
            Ok(())
        } else {
            Err(Error::NonFinite { input, name, value })
        }
    }

    /// Fails with [`Error::NonFinite`] naming the first point or frame whose
    /// position, velocity, acceleration, rotation or angular rates hold a NaN
    /// or an infinity. Generated code calls it only after a cheap sum of all
    /// outputs has come out non-finite, so it stays off the hot path.
    #[cold]
    #[inline(never)]
    pub fn finite_outputs<const D: usize>(
        points: &[PointMotion<D>],
        point_names: &[&'static str],
        frames: &[FrameState],
        frame_names: &[&'static str],
    ) -> Result<(), Error> {
        for (name, p) in point_names.iter().zip(points) {
            for v in p.position.iter().chain(&p.velocity).chain(&p.acceleration) {
                finite(Input::Computed, name, *v)?;
            }
        }
        for (name, f) in frame_names.iter().zip(frames) {
            let vectors = [
                f.origin,
                f.velocity,
                f.acceleration,
                f.angular_velocity,
                f.angular_acceleration,
            ];
            for v in f
                .rotation
                .iter()
                .chain(vectors.iter().flat_map(|v| v.iter()))
            {
                finite(Input::Computed, name, *v)?;
            }
        }
        Ok(())
    }
}
