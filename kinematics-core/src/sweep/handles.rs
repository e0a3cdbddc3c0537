//! The typed handles of a mechanism's drivers (`FourBar::PHI`), and the
//! options of a sweep that are not numbers: how output angles are
//! wrapped and what happens at a change point.

use core::f64::consts::{PI, TAU};
use core::fmt;
use core::marker::PhantomData;

/// The unit of a driver that is an angle (radians; degrees and rev/min at
/// the API's boundary): the type parameter of [`Driver`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Angle {}

/// The unit of a driver that is a length (a slider's position, in the
/// mechanism's length unit): the type parameter of [`Driver`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Length {}

/// A typed handle of one driver of mechanism `M`, generated for each
/// driver as an associated constant named after it in upper case
/// (`FourBar::PHI` for driver `phi`). `U` is [`Angle`] or [`Length`], so
/// that degree and rev/min helpers exist only for angles, and a handle of
/// one mechanism does not compile with another.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
/// #     }
/// # }
/// assert_eq!((SliderCrank::PHI.index(), SliderCrank::PHI.name()), (0, "phi"));
/// ```
pub struct Driver<M, U> {
    pub(super) index: usize,
    pub(super) name: &'static str,
    marker: PhantomData<fn() -> (M, U)>,
}

impl<M, U> Driver<M, U> {
    /// The handle of driver `index` (in declaration order) named `name`:
    /// for the generated constants.
    #[doc(hidden)]
    #[must_use]
    pub const fn __new(index: usize, name: &'static str) -> Self {
        Self {
            index,
            name,
            marker: PhantomData,
        }
    }

    /// The driver's index among the drivers, in declaration order.
    #[must_use]
    pub const fn index(self) -> usize {
        self.index
    }

    /// The driver's name in the definition.
    #[must_use]
    pub const fn name(self) -> &'static str {
        self.name
    }
}

impl<M, U> Clone for Driver<M, U> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<M, U> Copy for Driver<M, U> {}

impl<M, U> fmt::Debug for Driver<M, U> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Driver({})", self.name)
    }
}

impl<M, U> PartialEq for Driver<M, U> {
    fn eq(&self, other: &Self) -> bool {
        self.index == other.index
    }
}

/// How the angles of the samples' poses are reported (the sweep itself
/// follows them continuously).
///
/// ```
/// use kinematics_core::sweep::Wrap;
/// use std::f64::consts::TAU;
/// assert!((Wrap::Signed.apply(4.0) - (4.0 - TAU)).abs() < 1e-15);
/// assert!((Wrap::Positive.apply(-1.0) - (TAU - 1.0)).abs() < 1e-15);
/// assert_eq!(Wrap::Continuous.apply(7.0), 7.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Wrap {
    /// As followed: continuous through full turns (a crank at 370° reads
    /// 6.46 rad).
    #[default]
    Continuous,
    /// In (−π, π].
    Signed,
    /// In [0, 2π).
    Positive,
}

impl Wrap {
    /// The angle `theta` as this wrapping reports it.
    #[must_use]
    pub fn apply(self, theta: f64) -> f64 {
        match self {
            Self::Continuous => theta,
            // rem_euclid gives [0, 2π), so this is in (−π, π].
            Self::Signed => PI - crate::math::rem_euclid(PI - theta, TAU),
            Self::Positive => {
                let w = crate::math::rem_euclid(theta, TAU);
                // A tiny negative angle rounds to 2π itself.
                if w >= TAU { 0.0 } else { w }
            }
        }
    }
}

/// What a sweep does at a change point, where two assembly branches meet
/// (a parallelogram four-bar folded flat at φ = 0 and 180°).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ChangePoints {
    /// Stop there, with [`StopReason::ChangePoint`](super::StopReason::ChangePoint).
    #[default]
    Stop,
    /// Continue on the branch on which the motion is smooth: the pose past
    /// the point nearest the one extrapolated (to second order) from the
    /// samples before it. A parallelogram four-bar stays a parallelogram.
    Smooth,
    /// Continue on the other branch, where the joint rates jump: a
    /// parallelogram four-bar folds into the crossed (anti-parallelogram)
    /// form. Needs the block that meets the other branch to be solved in
    /// closed form (see the mechanism's `BLOCKS`), where both branches are
    /// at hand.
    Switch,
}
