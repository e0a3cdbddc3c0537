//! What a sweep hands out: a sample (the motion, or the pose alone) at
//! each driver value, and the typed reason it stopped early.

use core::fmt;

use super::engine::Engine;
use crate::error::Error;
use crate::mechanism::{Mechanism, MotionState, Pose};
use crate::names::Name;

/// One instant of a sweep.
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
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).run();
/// let last = &s.samples[10];
/// assert_eq!((last.at, last.motion.q.phi), (1.0, 1.0));
/// ```
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(bound(
        serialize = "M::Motion: serde::Serialize",
        deserialize = "M::Motion: serde::Deserialize<'de>"
    ))
)]
pub struct Sample<M: Mechanism> {
    /// Value of the swept driver (or the time, for a simulation).
    pub at: f64,
    /// Coordinates, rates, accelerations, points and frames; its
    /// `residual` says how well the loops close.
    pub motion: M::Motion,
}

impl<M: Mechanism> Clone for Sample<M> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<M: Mechanism> Copy for Sample<M> {}

impl<M: Mechanism> fmt::Debug for Sample<M> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Sample")
            .field("at", &self.at)
            .field("motion", &self.motion)
            .finish()
    }
}

/// One sample of a sweep of positions ([`SweepBuilder::poses`](super::SweepBuilder::poses)): the pose,
/// its points' positions and its diagnostics, no velocities or
/// accelerations.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let poses: Vec<_> = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).poses().collect();
/// let last = poses[10].as_ref().unwrap();
/// assert_eq!((last.at, last.pose.q.phi), (1.0, 1.0));
/// assert!(last.pose.residual < 1e-15);
/// // The crank pin B, by name.
/// assert!((last.pose.points.B.x - 0.1 * 1f64.cos()).abs() < 1e-15);
/// ```
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(bound(
        serialize = "M::Coords: serde::Serialize, M::Positions: serde::Serialize",
        deserialize = "M::Coords: serde::Deserialize<'de>, M::Positions: serde::Deserialize<'de>"
    ))
)]
pub struct PoseSample<M: Mechanism> {
    /// Value of the swept driver (or the time, for a simulation).
    pub at: f64,
    /// The coordinates, the points' positions, the conditioning, the sign
    /// of det Φ_u and the residual.
    pub pose: Pose<M::Coords, M::Positions>,
}

impl<M: Mechanism> Clone for PoseSample<M> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<M: Mechanism> Copy for PoseSample<M> {}

impl<M: Mechanism> fmt::Debug for PoseSample<M> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PoseSample")
            .field("at", &self.at)
            .field("pose", &self.pose)
            .finish()
    }
}

/// What a sweep hands out for each sample: a [`Sample`] (the motion, from
/// the mechanism's step) or a [`PoseSample`] (positions only, from its
/// positions-only step), or for a run-time model a sample its stepper
/// holds. The sweep reads the pose, the conditioning and the sign of
/// det Φ_u of each to follow the branch and find change points.
pub trait Solved<E: Engine>: Sized + fmt::Debug {
    /// Whether [`Solved::record`] writes the rates.
    const RATES: bool;
    /// What the model's step returns: the motion, or the pose.
    type Step;
    /// Takes the model's step at the drivers of `start` (the guess of its
    /// unknowns), with the drivers' `rates` and `accelerations`, carrying
    /// `state`.
    ///
    /// # Errors
    /// As the model's step.
    fn step(
        m: &E,
        start: &E::Pose,
        rates: &E::Pose,
        accelerations: &E::Pose,
        state: &mut E::State,
    ) -> Result<Self::Step, Error>;
    /// The sign of det Φ_u of a step's result.
    fn step_det_sign(step: &Self::Step) -> f64;
    /// The sample at `at` of a step's result.
    fn sample(at: f64, step: Self::Step) -> Self;
    /// Solves the sample at `at` from `start`, as [`Solved::step`].
    ///
    /// # Errors
    /// As the model's step.
    #[inline(always)]
    fn solve(
        m: &E,
        at: f64,
        start: &E::Pose,
        rates: &E::Pose,
        accelerations: &E::Pose,
        state: &mut E::State,
    ) -> Result<Self, Error> {
        Self::step(m, start, rates, accelerations, state).map(|s| Self::sample(at, s))
    }
    /// The value of the sweep variable.
    fn at(&self) -> f64;
    /// Writes the pose into `q` and, when asked and [`Solved::RATES`], the
    /// rates into `qd`; `state` is the one whose step made the sample.
    /// `false`, with nothing written, where the sample is read from the
    /// state and there is none.
    fn record(&self, state: Option<&E::State>, q: &mut E::Pose, qd: Option<&mut E::Pose>) -> bool;
    /// The pose, to wrap the angles the sweep reports (`None` where the
    /// state holds it: reported as solved).
    fn q_mut(&mut self) -> Option<&mut E::Pose>;
    /// See [`MotionState::conditioning`].
    fn conditioning(&self) -> f64;
    /// See [`MotionState::det_sign`].
    fn det_sign(&self) -> f64;
    /// The sample, made to outlive the next step of `state` (the one
    /// that made it): a sample the state holds is copied out of it.
    #[inline(always)]
    #[must_use]
    fn keep(self, _state: &mut E::State) -> Self {
        self
    }
}

impl<M: Mechanism> Solved<M> for Sample<M> {
    const RATES: bool = true;
    type Step = M::Motion;
    #[inline(always)]
    fn step(
        m: &M,
        start: &M::Coords,
        rates: &M::Coords,
        accelerations: &M::Coords,
        state: &mut M::StepState,
    ) -> Result<M::Motion, Error> {
        m.step_carried(start, rates, accelerations, state)
    }
    #[inline(always)]
    fn step_det_sign(step: &M::Motion) -> f64 {
        step.det_sign()
    }
    #[inline(always)]
    fn sample(at: f64, motion: M::Motion) -> Self {
        Self { at, motion }
    }
    #[inline(always)]
    fn at(&self) -> f64 {
        self.at
    }
    #[inline(always)]
    fn record(
        &self,
        _: Option<&M::StepState>,
        q: &mut M::Coords,
        qd: Option<&mut M::Coords>,
    ) -> bool {
        *q = *self.motion.q();
        if let Some(qd) = qd {
            *qd = *self.motion.qd();
        }
        true
    }
    #[inline(always)]
    fn q_mut(&mut self) -> Option<&mut M::Coords> {
        Some(self.motion.q_mut())
    }
    #[inline(always)]
    fn conditioning(&self) -> f64 {
        self.motion.conditioning()
    }
    #[inline(always)]
    fn det_sign(&self) -> f64 {
        self.motion.det_sign()
    }
}

impl<M: Mechanism> Solved<M> for PoseSample<M> {
    const RATES: bool = false;
    type Step = Pose<M::Coords, M::Positions>;
    #[inline(always)]
    fn step(
        m: &M,
        start: &M::Coords,
        _: &M::Coords,
        _: &M::Coords,
        state: &mut M::StepState,
    ) -> Result<Pose<M::Coords, M::Positions>, Error> {
        m.pose_carried(start, state)
    }
    #[inline(always)]
    fn step_det_sign(step: &Pose<M::Coords, M::Positions>) -> f64 {
        step.det_sign
    }
    #[inline(always)]
    fn sample(at: f64, pose: Pose<M::Coords, M::Positions>) -> Self {
        Self { at, pose }
    }
    #[inline(always)]
    fn at(&self) -> f64 {
        self.at
    }
    #[inline(always)]
    fn record(
        &self,
        _: Option<&M::StepState>,
        q: &mut M::Coords,
        _: Option<&mut M::Coords>,
    ) -> bool {
        *q = self.pose.q;
        true
    }
    #[inline(always)]
    fn q_mut(&mut self) -> Option<&mut M::Coords> {
        Some(&mut self.pose.q)
    }
    #[inline(always)]
    fn conditioning(&self) -> f64 {
        self.pose.conditioning
    }
    #[inline(always)]
    fn det_sign(&self) -> f64 {
        self.pose.det_sign
    }
}

/// Why a sweep stopped before its end.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum StopReason {
    /// A limit position of the driver: past the stop's `at`, the block of
    /// `unknowns` has no real solution (the links cannot close the loop).
    /// For a block solved in closed form, `at` is the last value that
    /// assembles, by bisection to the resolution of `f64`.
    LimitPosition {
        /// The block's unknowns, joined by ", ".
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        unknowns: Name,
    },
    /// A change point between the samples at `from` and `to`: two assembly
    /// branches meet there, and the sweep was not told which to continue
    /// on (see [`ChangePoints`](super::ChangePoints)). The stop's `at` estimates where.
    ChangePoint {
        /// The last sample before the point.
        from: f64,
        /// The first value past it.
        to: f64,
    },
    /// Φ_u is singular at the stop's `at` ([`Error::Singular`]): a
    /// dead-centre or toggle position met exactly, or a model whose
    /// equations do not fix the unknowns there.
    Singular(Error),
    /// The mechanism does not assemble at `at`: Newton–Raphson did not
    /// converge, or a block has no real solution at the first sample.
    NotAssembled(Error),
    /// An input is invalid: options, parameters, the range, a non-finite
    /// value.
    Invalid(Error),
}

impl StopReason {
    pub(crate) fn from_error(e: Error) -> Self {
        match e {
            Error::Singular { .. } => Self::Singular(e),
            Error::InvalidParameter { .. }
            | Error::InvalidOption { .. }
            | Error::NonFinite { .. } => Self::Invalid(e),
            _ => Self::NotAssembled(e),
        }
    }

    /// The error behind the stop, when there is one.
    #[must_use]
    pub fn error(&self) -> Option<&Error> {
        match self {
            Self::Singular(e) | Self::NotAssembled(e) | Self::Invalid(e) => Some(e),
            Self::LimitPosition { .. } | Self::ChangePoint { .. } => None,
        }
    }
}

/// Where and why a sweep stopped before its end.
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
/// use kinematics_core::sweep::StopReason;
/// // a > b: the rod cannot follow the crank past sin φ = b / a.
/// let m = SliderCrank { a: 0.3, b: 0.2 };
/// let start = m.assemble(&SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.5 })?;
/// let s = m.sweep(SliderCrank::PHI, &start).turn().steps(360).run();
/// let stop = s.stop.expect("stops at the limit position");
/// assert!(matches!(stop.reason, StopReason::LimitPosition { .. }));
/// assert!((stop.at - (0.2f64 / 0.3).asin()).abs() < 1e-10);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stop {
    /// Name of the swept driver, or "t" for a simulation.
    #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
    pub variable: Name,
    /// Value of the swept driver (or the time) at which it stopped.
    pub at: f64,
    /// Why.
    pub reason: StopReason,
}

/// How to continue past a change point, in Rust: the hint of [`Stop`]'s
/// `Display`.
const RUST_CHANGE_POINTS: &str = "`.change_points(ChangePoints::Smooth)` or `Switch`";

impl Stop {
    /// The message of `Display`, with `change_points` (how the caller's
    /// language says to continue past a change point: the command's
    /// `--change-points smooth` or `switch`, Python's
    /// `change_points="smooth"` or `"switch"`) in place of the Rust
    /// builder call.
    #[must_use]
    pub fn message_with(&self, change_points: &str) -> alloc::string::String {
        struct With<'a>(&'a Stop, &'a str);
        impl fmt::Display for With<'_> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                self.0.write(f, self.1)
            }
        }
        alloc::format!("{}", With(self, change_points))
    }

    fn write(&self, f: &mut fmt::Formatter<'_>, change_points: &str) -> fmt::Result {
        let (v, at) = (self.variable, self.at);
        match &self.reason {
            StopReason::LimitPosition { unknowns } => write!(
                f,
                "limit position at {v} = {at}: past it the links of ({unknowns}) cannot close \
                 the loop; sweep a range inside the limits, or choose a linkage whose driver \
                 turns fully"
            ),
            StopReason::ChangePoint { from, to } => write!(
                f,
                "change point near {v} = {at} (between {from} and {to}): two assembly branches \
                 meet there; continue with {change_points} to say which branch to follow"
            ),
            StopReason::Singular(e) | StopReason::NotAssembled(e) | StopReason::Invalid(e) => {
                write!(f, "at {v} = {at}: {e}")
            }
        }
    }
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write(f, RUST_CHANGE_POINTS)
    }
}

impl core::error::Error for Stop {}
