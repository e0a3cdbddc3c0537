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

use alloc::borrow::ToOwned;
use alloc::collections::VecDeque;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::f64::consts::{PI, TAU};
use core::fmt;
use core::fmt::Write as _;
use core::marker::PhantomData;

use crate::names::Name;
use crate::{Coordinates, Error, Kind, Mechanism, MotionState, Options, PointState, Pose, Role};

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
    index: usize,
    name: &'static str,
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
                if w >= TAU {
                    0.0
                } else {
                    w
                }
            }
        }
    }
}

/// What a sweep does at a change point, where two assembly branches meet
/// (a parallelogram four-bar folded flat at φ = 0 and 180°).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ChangePoints {
    /// Stop there, with [`StopReason::ChangePoint`].
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

/// One sample of a sweep of positions ([`SweepBuilder::poses`]): the pose,
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
/// positions-only step). The sweep reads the pose, the conditioning and
/// the sign of det Φ_u of each to follow the branch and find change
/// points.
pub trait Solved<M: Mechanism>: Copy + fmt::Debug {
    /// Whether [`Solved::qd`] returns the rates.
    const RATES: bool;
    /// What the mechanism's step returns: the motion, or the pose.
    type Step;
    /// Takes the mechanism's step at the drivers of `start` (the guess of
    /// its unknowns), with the drivers' `rates` and `accelerations`,
    /// carrying `state`.
    ///
    /// # Errors
    /// As the mechanism's step.
    fn step(
        m: &M,
        start: &M::Coords,
        rates: &M::Coords,
        accelerations: &M::Coords,
        state: &mut M::StepState,
    ) -> Result<Self::Step, Error>;
    /// The sign of det Φ_u of a step's result.
    fn step_det_sign(step: &Self::Step) -> f64;
    /// The sample at `at` of a step's result.
    fn sample(at: f64, step: Self::Step) -> Self;
    /// Solves the sample at `at` from `start`, as [`Solved::step`].
    ///
    /// # Errors
    /// As the mechanism's step.
    #[inline(always)]
    fn solve(
        m: &M,
        at: f64,
        start: &M::Coords,
        rates: &M::Coords,
        accelerations: &M::Coords,
        state: &mut M::StepState,
    ) -> Result<Self, Error> {
        Self::step(m, start, rates, accelerations, state).map(|s| Self::sample(at, s))
    }
    /// The value of the sweep variable.
    fn at(&self) -> f64;
    /// The coordinates.
    fn q(&self) -> &M::Coords;
    /// The coordinates, to change (the sweep wraps the angles it reports).
    fn q_mut(&mut self) -> &mut M::Coords;
    /// The rates, where they are computed.
    fn qd(&self) -> Option<&M::Coords>;
    /// See [`MotionState::conditioning`].
    fn conditioning(&self) -> f64;
    /// See [`MotionState::det_sign`].
    fn det_sign(&self) -> f64;
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
    fn q(&self) -> &M::Coords {
        self.motion.q()
    }
    #[inline(always)]
    fn q_mut(&mut self) -> &mut M::Coords {
        self.motion.q_mut()
    }
    #[inline(always)]
    fn qd(&self) -> Option<&M::Coords> {
        Some(self.motion.qd())
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
    fn q(&self) -> &M::Coords {
        &self.pose.q
    }
    #[inline(always)]
    fn q_mut(&mut self) -> &mut M::Coords {
        &mut self.pose.q
    }
    #[inline(always)]
    fn qd(&self) -> Option<&M::Coords> {
        None
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
    /// on (see [`ChangePoints`]). The stop's `at` estimates where.
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
    fn from_error(e: Error) -> Self {
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

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
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
                 meet there; continue with `.change_points(ChangePoints::Smooth)` or `Switch` \
                 to say which branch to follow"
            ),
            StopReason::Singular(e) | StopReason::NotAssembled(e) | StopReason::Invalid(e) => {
                write!(f, "at {v} = {at}: {e}")
            }
        }
    }
}

impl core::error::Error for Stop {}

/// The samples of a sweep, and how it ended.
#[derive(Debug, Clone)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(bound(
        serialize = "M::Motion: serde::Serialize",
        deserialize = "M::Motion: serde::Deserialize<'de>"
    ))
)]
pub struct Sweep<M: Mechanism> {
    /// Name of the swept driver, or "t" for a simulation.
    #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
    pub variable: Name,
    /// The kind of the swept driver (a time is reported as a length-like
    /// plain value).
    pub kind: Kind,
    /// The samples, in order.
    pub samples: Vec<Sample<M>>,
    /// The change points passed on the branch chosen by [`ChangePoints`]
    /// (estimates of the driver value of each).
    pub change_points: Vec<f64>,
    /// `Some` when the sweep stopped early.
    pub stop: Option<Stop>,
}

// ───────────────────────── the builders ─────────────────────────

/// The range of a sweep, as given.
#[derive(Debug, Clone, Copy)]
enum End {
    /// Not given: one turn for an angle, an error for a length.
    Default,
    To(f64),
    /// Whole turns from the start (the end, equal to the start, left out).
    Turns(f64),
}

/// A sweep of one driver, built by the mechanism's `sweep(driver, start)`:
/// the other drivers stay at their values in `start`, at rest.
///
/// | method | meaning | default |
/// |---|---|---|
/// | [`from`](Self::from), [`to`](Self::to) | range, in rad or length units | from the start's value; one turn for an angle |
/// | [`from_deg`](SweepBuilder::from_deg), [`to_deg`](SweepBuilder::to_deg) | range in degrees (angles only) | |
/// | [`turn`](SweepBuilder::turn), [`turns`](SweepBuilder::turns) | whole turns, the end (the start again) left out | |
/// | [`steps`](Self::steps) | equal steps: `n + 1` samples with both ends, `n` for turns | 360 |
/// | [`rate`](Self::rate), [`acceleration`](Self::acceleration) | d' and d'' at every sample | 1 and 0 |
/// | [`rpm`](SweepBuilder::rpm), [`deg_per_s`](SweepBuilder::deg_per_s) | the rate in rev/min or °/s (angles only) | |
/// | [`options`](Self::options) | solver options | [`Options::DEFAULT`] |
/// | [`wrap`](Self::wrap) | how output angles are reported | [`Wrap::Continuous`] |
/// | [`change_points`](Self::change_points) | stop at a change point, or the branch to follow | [`ChangePoints::Stop`] |
///
/// With the default rate of 1 (rad/s or length unit per second), the
/// rates are the derivatives with respect to the driver (velocity
/// coefficients), and the accelerations the second derivatives.
///
/// [`run`](Self::run) collects the samples into a [`Sweep`]; iterating
/// the builder streams them (an item per sample, then the stop as an
/// `Err`), with no allocation per sample.
#[derive(Debug, Clone)]
#[must_use = "a sweep does nothing until it is run or iterated"]
pub struct SweepBuilder<'m, M: Mechanism, U> {
    m: &'m M,
    driver: Driver<M, U>,
    start: M::Coords,
    from: Option<f64>,
    end: End,
    steps: usize,
    rate: f64,
    acceleration: f64,
    options: Options,
    wrap: Wrap,
    change_points: ChangePoints,
}

impl<'m, M: Mechanism, U> SweepBuilder<'m, M, U> {
    /// A sweep of `driver` of `m` from the pose `start` (its drivers, and
    /// the first guess of its unknowns; any unknowns for a mechanism
    /// assembled in closed form, where they only pick the assembly mode).
    pub fn new(m: &'m M, driver: Driver<M, U>, start: &M::Coords) -> Self {
        Self {
            m,
            driver,
            start: *start,
            from: None,
            end: End::Default,
            steps: 360,
            rate: 1.0,
            acceleration: 0.0,
            options: Options::DEFAULT,
            wrap: Wrap::Continuous,
            change_points: ChangePoints::Stop,
        }
    }

    /// The first value of the driver (rad or length unit); by default, its
    /// value in the start pose.
    pub fn from(mut self, value: f64) -> Self {
        self.from = Some(value);
        self
    }

    /// The last value of the driver (rad or length unit), included.
    pub fn to(mut self, value: f64) -> Self {
        self.end = End::To(value);
        self
    }

    /// The number of equal steps (at least 1).
    pub fn steps(mut self, steps: usize) -> Self {
        self.steps = steps;
        self
    }

    /// The driver's rate d' (rad/s or length unit per second) at every
    /// sample.
    pub fn rate(mut self, rate: f64) -> Self {
        self.rate = rate;
        self
    }

    /// The driver's acceleration d'' (rad/s² or length unit per s²) at
    /// every sample.
    pub fn acceleration(mut self, acceleration: f64) -> Self {
        self.acceleration = acceleration;
        self
    }

    /// The solver options.
    pub fn options(mut self, options: &Options) -> Self {
        self.options = *options;
        self
    }

    /// How output angles are reported.
    pub fn wrap(mut self, wrap: Wrap) -> Self {
        self.wrap = wrap;
        self
    }

    /// What to do at a change point.
    pub fn change_points(mut self, change_points: ChangePoints) -> Self {
        self.change_points = change_points;
        self
    }

    /// Runs the sweep, collecting its samples.
    pub fn run(self) -> Sweep<M> {
        let kind = M::COORDINATES
            .get(self.driver.index)
            .map_or(Kind::Length, |c| c.kind);
        collect(self.into_iter(), kind)
    }

    /// The range [from, to], the number of samples and whether the end is
    /// left out; an error for a length driver with no end.
    fn grid(&self) -> Result<Grid, Error> {
        let from = self
            .from
            .or_else(|| self.start.get(self.driver.index))
            .unwrap_or(f64::NAN);
        let steps = self.steps.max(1);
        let kind = M::COORDINATES
            .get(self.driver.index)
            .map_or(Kind::Length, |c| c.kind);
        let (to, count) = match self.end {
            End::To(to) => (to, steps + 1),
            End::Turns(n) => (from + TAU * n, steps),
            End::Default if kind == Kind::Angle => (from + TAU, steps),
            End::Default => {
                return Err(Error::InvalidOption {
                    name: "to",
                    value: f64::NAN,
                    requirement: "must be given for a length driver: `.to(value)`",
                })
            }
        };
        if !(from.is_finite() && to.is_finite()) {
            return Err(Error::InvalidOption {
                name: "from/to",
                value: if from.is_finite() { to } else { from },
                requirement: "must be finite",
            });
        }
        Ok(Grid::even(from, to, steps, count))
    }
}

impl<M: Mechanism> SweepBuilder<'_, M, Angle> {
    /// The first value of the driver, in degrees.
    pub fn from_deg(self, degrees: f64) -> Self {
        self.from(degrees.to_radians())
    }

    /// The last value of the driver, in degrees, included.
    pub fn to_deg(self, degrees: f64) -> Self {
        self.to(degrees.to_radians())
    }

    /// One full turn from the first value; with `steps(n)`, n samples 360°/n
    /// apart (the end, the start again, left out).
    pub fn turn(self) -> Self {
        self.turns(1.0)
    }

    /// `n` full turns (negative: clockwise) from the first value, the end
    /// left out.
    pub fn turns(mut self, n: f64) -> Self {
        self.end = End::Turns(n);
        self
    }

    /// The driver's rate, in revolutions per minute.
    pub fn rpm(self, rpm: f64) -> Self {
        self.rate(rpm * TAU / 60.0)
    }

    /// The driver's rate, in degrees per second.
    pub fn deg_per_s(self, rate: f64) -> Self {
        self.rate(rate.to_radians())
    }

    /// The driver's acceleration, in degrees per second².
    pub fn deg_per_s2(self, acceleration: f64) -> Self {
        self.acceleration(acceleration.to_radians())
    }
}

impl<'m, M: Mechanism, U> IntoIterator for SweepBuilder<'m, M, U> {
    type Item = Result<Sample<M>, Stop>;
    type IntoIter = SweepIter<'m, M, SweepDrive>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<'m, M: Mechanism, U> SweepBuilder<'m, M, U> {
    /// The sweep of positions only: an iterator over [`PoseSample`]s (the
    /// pose with its conditioning, sign of det Φ_u and residual, no
    /// velocities or accelerations), then the stop as an `Err` if it stops
    /// early, as for the full sweep. Each sample is the mechanism's
    /// positions-only step (as a stepper's `pose`); the rates and
    /// accelerations set are not used. Allocates nothing per sample.
    pub fn poses(self) -> SweepIter<'m, M, SweepDrive, PoseSample<M>> {
        self.iter()
    }

    fn iter<S: Solved<M>>(self) -> SweepIter<'m, M, SweepDrive, S> {
        let grid = self.grid();
        let index = self.driver.index;
        let drive = SweepDrive {
            driver: index,
            rate: self.rate,
            acceleration: self.acceleration,
        };
        SweepIter::new(
            self.m,
            &self.start,
            self.driver.name,
            grid,
            drive,
            &self.options,
            self.wrap,
            self.change_points,
        )
    }
}

/// A simulation in time, built by the mechanism's `simulate(start)`: the
/// drivers follow a profile of time (by default they stay at rest at their
/// values in `start`).
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
/// use kinematics_core::sweep::constant_acceleration;
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// // The crank starts from rest with φ'' = 20 rad/s², for one second.
/// let s = m
///     .simulate(&start)
///     .duration(1.0)
///     .steps(100)
///     .profile(constant_acceleration(SliderCrank::PHI, 0.0, 0.0, 20.0))
///     .run();
/// let last = &s.samples[100].motion;
/// assert!((last.qd.phi - 20.0).abs() < 1e-12 && (last.q.phi - 10.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone)]
#[must_use = "a simulation does nothing until it is run or iterated"]
pub struct Simulation<'m, M: Mechanism, P> {
    m: &'m M,
    start: M::Coords,
    duration: f64,
    steps: usize,
    times: Option<Vec<f64>>,
    profile: P,
    options: Options,
    wrap: Wrap,
    change_points: ChangePoints,
}

/// The profile of a simulation whose drivers stay at rest.
#[derive(Debug, Clone, Copy)]
pub struct AtRest;

/// A time profile of the drivers: at time `t`, writes the drivers' values,
/// rates and accelerations into `q`, `qd` and `qdd` (the mechanism's
/// coordinates; only the drivers' fields are read). Implemented by every
/// `FnMut(f64, &mut Coords, &mut Coords, &mut Coords)`.
pub trait Profile<C> {
    /// The drivers at time `t`.
    fn at(&mut self, t: f64, q: &mut C, qd: &mut C, qdd: &mut C);
}

impl<C> Profile<C> for AtRest {
    fn at(&mut self, _t: f64, _q: &mut C, _qd: &mut C, _qdd: &mut C) {}
}

impl<C, F: FnMut(f64, &mut C, &mut C, &mut C)> Profile<C> for F {
    fn at(&mut self, t: f64, q: &mut C, qd: &mut C, qdd: &mut C) {
        self(t, q, qd, qdd);
    }
}

impl<'m, M: Mechanism> Simulation<'m, M, AtRest> {
    /// A simulation of `m` from the pose `start`, the drivers at rest until
    /// a [`profile`](Self::profile) is given; one second in 100 steps by
    /// default.
    pub fn new(m: &'m M, start: &M::Coords) -> Self {
        Self {
            m,
            start: *start,
            duration: 1.0,
            steps: 100,
            times: None,
            profile: AtRest,
            options: Options::DEFAULT,
            wrap: Wrap::Continuous,
            change_points: ChangePoints::Stop,
        }
    }
}

impl<'m, M: Mechanism, P: Profile<M::Coords>> Simulation<'m, M, P> {
    /// The drivers' motion: `profile(t, q, qd, qdd)` writes the drivers'
    /// values, rates and accelerations at time t (see [`constant_speed`]
    /// and [`constant_acceleration`]). A driver it does not write keeps its
    /// start value, at rest.
    pub fn profile<Q: Profile<M::Coords>>(self, profile: Q) -> Simulation<'m, M, Q> {
        Simulation {
            m: self.m,
            start: self.start,
            duration: self.duration,
            steps: self.steps,
            times: self.times,
            profile,
            options: self.options,
            wrap: self.wrap,
            change_points: self.change_points,
        }
    }

    /// The simulated time, from t = 0 (seconds).
    pub fn duration(mut self, seconds: f64) -> Self {
        self.duration = seconds;
        self
    }

    /// The number of equal time steps (`steps + 1` samples).
    pub fn steps(mut self, steps: usize) -> Self {
        self.steps = steps;
        self
    }

    /// The instants to sample instead of equal steps (seconds, increasing;
    /// the first is the start pose's instant).
    pub fn times(mut self, times: &[f64]) -> Self {
        self.times = Some(times.to_vec());
        self
    }

    /// The solver options.
    pub fn options(mut self, options: &Options) -> Self {
        self.options = *options;
        self
    }

    /// How output angles are reported.
    pub fn wrap(mut self, wrap: Wrap) -> Self {
        self.wrap = wrap;
        self
    }

    /// What to do at a change point.
    pub fn change_points(mut self, change_points: ChangePoints) -> Self {
        self.change_points = change_points;
        self
    }

    /// Runs the simulation, collecting its samples.
    pub fn run(self) -> Sweep<M> {
        collect(self.into_iter(), Kind::Length)
    }
}

impl<'m, M: Mechanism, P: Profile<M::Coords>> IntoIterator for Simulation<'m, M, P> {
    type Item = Result<Sample<M>, Stop>;
    type IntoIter = SweepIter<'m, M, TimeDrive<M::Coords, P>>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<'m, M: Mechanism, P: Profile<M::Coords>> Simulation<'m, M, P> {
    /// The simulation of positions only: an iterator over
    /// [`PoseSample`]s, as [`SweepBuilder::poses`] (the profile's rates and
    /// accelerations are not used).
    pub fn poses(self) -> SweepIter<'m, M, TimeDrive<M::Coords, P>, PoseSample<M>> {
        self.iter()
    }

    fn iter<S: Solved<M>>(self) -> SweepIter<'m, M, TimeDrive<M::Coords, P>, S> {
        let grid = if let Some(times) = self.times {
            if times.iter().all(|t| t.is_finite()) && times.windows(2).all(|w| w[0] < w[1]) {
                Ok(Grid::given(times))
            } else {
                Err(Error::InvalidOption {
                    name: "times",
                    value: f64::NAN,
                    requirement: "must be finite and increasing",
                })
            }
        } else if self.duration.is_finite() && self.duration > 0.0 {
            Ok(Grid::even(
                0.0,
                self.duration,
                self.steps.max(1),
                self.steps.max(1) + 1,
            ))
        } else {
            Err(Error::InvalidOption {
                name: "duration",
                value: self.duration,
                requirement: "must be positive and finite (seconds)",
            })
        };
        let drive = TimeDrive {
            start: self.start,
            profile: self.profile,
        };
        SweepIter::new(
            self.m,
            &self.start,
            "t",
            grid,
            drive,
            &self.options,
            self.wrap,
            self.change_points,
        )
    }
}

/// The profile of driver `driver` turning (or sliding) at constant speed
/// from `from`: d = d₀ + ω t, d' = ω, d'' = 0; the other drivers keep their
/// values, at rest.
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
/// use kinematics_core::sweep::constant_speed;
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = m.simulate(&start).duration(0.1).steps(10)
///     .profile(constant_speed(SliderCrank::PHI, 0.0, 6.0))
///     .run();
/// assert!((s.samples[10].motion.q.phi - 0.6).abs() < 1e-15);
/// ```
pub fn constant_speed<M: Mechanism, U>(
    driver: Driver<M, U>,
    from: f64,
    speed: f64,
) -> impl FnMut(f64, &mut M::Coords, &mut M::Coords, &mut M::Coords) {
    constant_acceleration(driver, from, speed, 0.0)
}

/// The profile of driver `driver` with constant acceleration from `from`:
/// d = d₀ + ω₀ t + ½ α t², d' = ω₀ + α t, d'' = α.
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
/// use kinematics_core::sweep::constant_acceleration;
/// let mut profile = constant_acceleration(SliderCrank::PHI, 0.0, 1.0, 2.0);
/// let (mut q, mut qd, mut qdd) = Default::default();
/// profile(3.0, &mut q, &mut qd, &mut qdd);
/// assert_eq!((q.phi, qd.phi, qdd.phi), (12.0, 7.0, 2.0));
/// # let _: (SliderCrankCoords, SliderCrankCoords, SliderCrankCoords) = (q, qd, qdd);
/// ```
pub fn constant_acceleration<M: Mechanism, U>(
    driver: Driver<M, U>,
    from: f64,
    speed: f64,
    acceleration: f64,
) -> impl FnMut(f64, &mut M::Coords, &mut M::Coords, &mut M::Coords) {
    let j = driver.index;
    move |t, q, qd, qdd| {
        q.set(j, from + speed * t + 0.5 * acceleration * t * t);
        qd.set(j, speed + acceleration * t);
        qdd.set(j, acceleration);
    }
}

// ───────────────────────── the engine ─────────────────────────

/// Equally spaced values, `count` of them from `from` by (to − from)/steps;
/// or the given `values`.
#[derive(Debug, Clone)]
struct Grid {
    from: f64,
    to: f64,
    /// (to − from)/steps.
    step: f64,
    steps: usize,
    count: usize,
    values: Option<Vec<f64>>,
}

impl Grid {
    #[allow(clippy::cast_precision_loss)]
    fn even(from: f64, to: f64, steps: usize, count: usize) -> Self {
        Self {
            from,
            to,
            step: (to - from) / steps as f64,
            steps,
            count,
            values: None,
        }
    }

    fn given(values: Vec<f64>) -> Self {
        Self {
            from: values.first().copied().unwrap_or(0.0),
            to: values.last().copied().unwrap_or(0.0),
            step: f64::NAN,
            steps: values.len().saturating_sub(1).max(1),
            count: values.len(),
            values: Some(values),
        }
    }

    /// Value `k`: from + k·step (the last one exactly `to`).
    #[inline]
    fn at(&self, k: usize) -> f64 {
        if k == self.steps && self.values.is_none() {
            self.to
        } else {
            self.inner(k)
        }
    }

    /// Value `k` for k below [`Grid::inner_end`]: the given value, or
    /// from + k·step.
    #[allow(clippy::cast_precision_loss)]
    #[inline(always)]
    fn inner(&self, k: usize) -> f64 {
        if let Some(v) = &self.values {
            return v.get(k).copied().unwrap_or(f64::NAN);
        }
        // Through i64: one conversion instruction (the counts are far
        // below 2⁶³).
        #[allow(clippy::cast_possible_wrap)]
        let k = k as i64 as f64;
        self.from + self.step * k
    }

    /// The indices below which [`Grid::inner`] is the value: all but the
    /// end of an even grid that includes it.
    fn inner_end(&self) -> usize {
        if self.values.is_some() {
            self.count
        } else {
            self.count.min(self.steps)
        }
    }
}

/// How the drivers follow the sweep variable.
pub trait Drive<M: Mechanism> {
    /// Sets, before the first sample, the drivers' rates and accelerations
    /// that are the same at every sample.
    fn start(&self, rates: &mut M::Coords, accels: &mut M::Coords);
    /// Sets the drivers of `pose` for the value `at` of the sweep variable,
    /// and the rates and accelerations that change with it.
    fn drive(
        &mut self,
        at: f64,
        pose: &mut M::Coords,
        rates: &mut M::Coords,
        accels: &mut M::Coords,
    );
    /// The rate of the sweep variable (for the predictor): the swept
    /// driver's d', or 1 for the time.
    fn variable_rate(&self) -> f64;
}

/// One driver swept at a constant rate (see [`SweepBuilder`]).
#[derive(Debug, Clone, Copy)]
pub struct SweepDrive {
    driver: usize,
    rate: f64,
    acceleration: f64,
}

impl<M: Mechanism> Drive<M> for SweepDrive {
    fn start(&self, rates: &mut M::Coords, accels: &mut M::Coords) {
        rates.set(self.driver, self.rate);
        accels.set(self.driver, self.acceleration);
    }

    #[inline(always)]
    fn drive(&mut self, at: f64, pose: &mut M::Coords, _: &mut M::Coords, _: &mut M::Coords) {
        pose.set(self.driver, at);
    }

    fn variable_rate(&self) -> f64 {
        self.rate
    }
}

/// The drivers following a time profile (see [`Simulation`]).
#[derive(Debug, Clone)]
pub struct TimeDrive<C, P> {
    start: C,
    profile: P,
}

impl<M: Mechanism, P: Profile<M::Coords>> Drive<M> for TimeDrive<M::Coords, P> {
    fn start(&self, _: &mut M::Coords, _: &mut M::Coords) {}

    fn drive(
        &mut self,
        t: f64,
        pose: &mut M::Coords,
        rates: &mut M::Coords,
        accels: &mut M::Coords,
    ) {
        let mut q = self.start;
        (*rates, *accels) = (M::Coords::default(), M::Coords::default());
        self.profile.at(t, &mut q, rates, accels);
        for j in 0..M::DRIVERS {
            pose.set(j, q.get(j).unwrap_or(f64::NAN));
        }
    }

    fn variable_rate(&self) -> f64 {
        1.0
    }
}

/// A branch tried past a change point: its distance from the extrapolated
/// pose, its sample and its step state.
type Candidate<M, S> = (f64, S, <M as Mechanism>::StepState);

/// What the sweep keeps of an accepted sample: for the predictor, the
/// change-point tests and the extrapolation past a change point.
struct Head<C> {
    at: f64,
    q: C,
    qd: C,
    conditioning: f64,
    det_sign: f64,
}

impl<C: Copy> Clone for Head<C> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C: Copy> Copy for Head<C> {}

impl<C: Default> Default for Head<C> {
    fn default() -> Self {
        Self {
            at: f64::NAN,
            q: C::default(),
            qd: C::default(),
            conditioning: f64::NAN,
            det_sign: f64::NAN,
        }
    }
}

/// A sweep or simulation in progress: an iterator over its samples (each
/// `Ok`), ending with the stop (an `Err`) if it stops early. Made by
/// iterating a [`SweepBuilder`] or a [`Simulation`]; allocates nothing per
/// sample.
///
/// A sample that may lie past a change point (Φ_u's conditioning falling
/// fast towards zero) is held back until the next one is solved, so that a
/// sample on the wrong side of a change point is never handed out.
pub struct SweepIter<'m, M: Mechanism, D, S = Sample<M>> {
    m: &'m M,
    drive: D,
    options: Options,
    grid: Grid,
    /// 1 / the rate of the sweep variable (0 when it is 0), for the
    /// predictor.
    per_rate: f64,
    wrap: Wrap,
    change_points: ChangePoints,
    variable: &'static str,
    state: Option<M::StepState>,
    /// The next grid index to solve.
    k: usize,
    /// The drivers' rates and accelerations (their entries only).
    rates: M::Coords,
    accels: M::Coords,
    /// The last accepted samples, a ring: `history[newest]` the newest,
    /// the one before it at `newest − 1` (mod 4), and so on; an entry
    /// whose value `at` is NaN holds none (before the first sample, and
    /// after a change point).
    history: [Head<M::Coords>; 4],
    newest: usize,
    /// Whether the conditioning falls so fast at the newest sample that it
    /// could reach zero before the next: the line through it and the one
    /// before meets zero less than two steps on (and it is below 0.5,
    /// where a regular pose is of order one).
    falling: bool,
    /// The sign of det Φ_u at the newest sample when the next sample may
    /// be handed out as soon as it keeps that sign (no sample held back,
    /// the conditioning not falling fast); 0 when the slow path decides.
    gate: f64,
    /// The newest sample, when it is held back.
    held: Option<S>,
    /// Items ready to hand out before anything else.
    out: VecDeque<Result<S, Stop>>,
    /// The change points passed.
    passed: Vec<f64>,
    done: bool,
    /// The grid indices below which the next sample is solved on the
    /// fast path: 0 while items wait in `out` or the sweep is done, the
    /// grid's [`Grid::inner_end`] otherwise.
    open: usize,
}

impl<M: Mechanism, D: fmt::Debug, S> fmt::Debug for SweepIter<'_, M, D, S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SweepIter")
            .field("variable", &self.variable)
            .field("next", &self.k)
            .field("of", &self.grid.count)
            .field("drive", &self.drive)
            .finish_non_exhaustive()
    }
}

impl<'m, M: Mechanism, D: Drive<M>, S: Solved<M>> SweepIter<'m, M, D, S> {
    #[allow(clippy::too_many_arguments)]
    fn new(
        m: &'m M,
        start: &M::Coords,
        variable: &'static str,
        grid: Result<Grid, Error>,
        drive: D,
        options: &Options,
        wrap: Wrap,
        change_points: ChangePoints,
    ) -> Self {
        let rate = drive.variable_rate();
        let per_rate = if rate != 0.0 && rate.is_finite() {
            1.0 / rate
        } else {
            0.0
        };
        let mut it = Self {
            m,
            drive,
            options: *options,
            grid: Grid::even(0.0, 0.0, 1, 0),
            per_rate,
            wrap,
            change_points,
            variable,
            state: None,
            k: 0,
            rates: M::Coords::default(),
            accels: M::Coords::default(),
            history: [Head::default(); 4],
            newest: 0,
            falling: false,
            gate: 0.0,
            held: None,
            out: VecDeque::with_capacity(2),
            passed: Vec::new(),
            done: false,
            open: 0,
        };
        it.drive.start(&mut it.rates, &mut it.accels);
        let checked = grid.and_then(|g| Ok((g, m.step_state(options)?)));
        match checked {
            Ok((grid, state)) => {
                it.grid = grid;
                it.state = Some(state);
                if it.grid.count == 0 {
                    it.done = true;
                } else {
                    it.first(start);
                    it.regate();
                }
            }
            Err(e) => it.finish(f64::NAN, StopReason::from_error(e)),
        }
        it.reopen();
        it
    }

    /// Sets `open` after the slow path.
    fn reopen(&mut self) {
        self.open = if self.out.is_empty() && !self.done {
            self.grid.inner_end()
        } else {
            0
        };
    }

    /// The change points passed so far.
    #[must_use]
    pub fn change_points(&self) -> &[f64] {
        &self.passed
    }

    fn finish(&mut self, at: f64, reason: StopReason) {
        self.out.push_back(Err(Stop {
            variable: self.variable,
            at,
            reason,
        }));
        self.held = None;
        self.done = true;
    }

    /// Solves grid sample `k` from `guess` (its drivers set here) with
    /// `state`, off the hot path.
    fn solve(&mut self, k: usize, guess: &M::Coords, state: &mut M::StepState) -> Result<S, Error> {
        let at = self.grid.at(k);
        let mut pose = *guess;
        self.drive
            .drive(at, &mut pose, &mut self.rates, &mut self.accels);
        S::solve(self.m, at, &pose, &self.rates, &self.accels, state)
    }

    /// The first sample, from `start`: handed out as it is.
    fn first(&mut self, start: &M::Coords) {
        let Some(mut state) = self.state.take() else {
            return;
        };
        match self.solve(0, start, &mut state) {
            Ok(s) => {
                self.push_head(&s);
                let s = self.wrapped(s);
                self.out.push_back(Ok(s));
                self.k = 1;
            }
            Err(e) => {
                let at = self.grid.at(0);
                self.finish(at, StopReason::from_error(e));
            }
        }
        self.state = Some(state);
    }

    /// The newest accepted sample.
    #[inline(always)]
    fn head(&self) -> Option<&Head<M::Coords>> {
        self.back(0)
    }

    /// The accepted sample `n` (at most 2) before the newest (0: the
    /// newest).
    #[inline(always)]
    fn back(&self, n: usize) -> Option<&Head<M::Coords>> {
        debug_assert!(n <= 2, "the sweep keeps three samples");
        let h = &self.history[self.newest.wrapping_sub(n) & 3];
        (!h.at.is_nan()).then_some(h)
    }

    /// Makes `s` the newest accepted sample.
    #[inline(always)]
    fn push_head(&mut self, s: &S) {
        // NaN with no sample before (then the test is false).
        let previous = self.history[self.newest & 3].conditioning;
        let conditioning = s.conditioning();
        let det_sign = s.det_sign();
        self.falling = conditioning < 0.5 && 1.5 * conditioning < previous;
        self.gate = if self.falling { 0.0 } else { det_sign };
        self.newest = (self.newest + 1) & 3;
        let h = &mut self.history[self.newest];
        h.at = s.at();
        h.q = *s.q();
        // The rates only where the predictor uses them.
        if M::NEWTON_GUESS {
            if let Some(qd) = s.qd() {
                h.qd = *qd;
            }
        }
        h.conditioning = conditioning;
        h.det_sign = det_sign;
    }

    /// Sets `gate` after the slow path: open (the newest sample's sign of
    /// det Φ_u) only with a sample accepted, none held back and the
    /// conditioning not falling fast.
    fn regate(&mut self) {
        self.gate = match self.head() {
            Some(h) if !self.falling && self.held.is_none() => h.det_sign,
            _ => 0.0,
        };
    }

    /// Forgets every accepted sample.
    fn forget(&mut self) {
        self.history = [Head::default(); 4];
        self.falling = false;
    }

    /// The guess at `at`, where Newton–Raphson starts from it: the newest
    /// pose advanced along its rates, u + (du/dt)·Δt, or without rates
    /// along the secant from the pose before it; the newest pose where the
    /// guess only names the branch.
    #[inline(always)]
    fn predicted(&self, at: f64) -> M::Coords {
        let Some(h) = self.head() else {
            return M::Coords::default();
        };
        let mut guess = h.q;
        if !M::NEWTON_GUESS {
            return guess;
        }
        let (rate, from) = if S::RATES {
            (&h.qd, None)
        } else {
            match self.back(1) {
                Some(p) if p.at != h.at => (&h.q, Some((p, 1.0 / (h.at - p.at)))),
                _ => return guess,
            }
        };
        let dt = (at - h.at) * if S::RATES { self.per_rate } else { 1.0 };
        for j in M::DRIVERS..M::DRIVERS + M::UNKNOWNS {
            let (Some(u), Some(r)) = (guess.get(j), rate.get(j)) else {
                continue;
            };
            // The secant's slope (u − u_prev) / (at_h − at_prev).
            let slope = match from {
                Some((p, inv)) => (r - p.q.get(j).unwrap_or(r)) * inv,
                None => r,
            };
            guess.set(j, u + slope * dt);
        }
        guess
    }

    /// A sample as handed out: its angles wrapped as asked.
    #[inline(always)]
    fn wrapped(&self, mut s: S) -> S {
        self.wrap_angles(&mut s);
        s
    }

    /// Wraps the angles of `s` as asked.
    #[inline(always)]
    fn wrap_angles(&self, s: &mut S) {
        if self.wrap != Wrap::Continuous {
            let q = s.q_mut();
            for (j, c) in M::COORDINATES.iter().enumerate() {
                if c.kind == Kind::Angle {
                    if let Some(v) = q.get(j) {
                        q.set(j, self.wrap.apply(v));
                    }
                }
            }
        }
    }

    /// Queues the held sample to be handed out.
    fn release(&mut self) {
        if let Some(s) = self.held.take() {
            let s = self.wrapped(s);
            self.out.push_back(Ok(s));
        }
    }

    /// Solves grid sample `k` = `self.k`, of value `at`: the sample to hand
    /// out, if one is ready.
    #[inline(always)]
    fn advance(&mut self, k: usize, at: f64) -> Option<Result<S, Stop>> {
        let mut pose = self.predicted(at);
        self.drive
            .drive(at, &mut pose, &mut self.rates, &mut self.accels);
        let state = self.state.as_mut()?;
        match S::step(self.m, &pose, &self.rates, &self.accels, state) {
            // The common case, handed out at once: det Φ_u keeps its sign,
            // the conditioning was not falling so fast that it could reach
            // zero before this sample, and nothing is held back (`gate`).
            Ok(step) if self.gate * S::step_det_sign(&step) > 0.0 => {
                self.k += 1;
                let mut s = S::sample(at, step);
                self.push_head(&s);
                self.wrap_angles(&mut s);
                Some(Ok(s))
            }
            Ok(step) => {
                self.unusual(S::sample(at, step));
                self.regate();
                self.reopen();
                None
            }
            Err(e) => {
                self.failed(k, e);
                self.regate();
                self.reopen();
                None
            }
        }
    }

    /// A new sample `s` near a possible change point, or after a held one.
    #[cold]
    #[inline(never)]
    fn unusual(&mut self, s: S) {
        let Some(&h) = self.head() else {
            self.k += 1;
            self.push_head(&s);
            self.out.push_back(Ok(s));
            return;
        };
        let (c1, c2) = (h.conditioning, s.conditioning());
        if h.det_sign * s.det_sign() < 0.0 {
            // det Φ_u changed sign between the newest sample and `s`.
            let at = h.at + (s.at() - h.at) * c1 / (c1 + c2);
            self.release();
            return self.change_point(at, h.at, s.at());
        }
        if self.held.is_some() {
            // Does the conditioning dip to zero in a V around the held
            // sample?
            if let Some(&Head {
                at: a,
                conditioning: c0,
                ..
            }) = self.back(1)
            {
                if let Some(t) = v_zero(c0, c1, c2) {
                    let at = if t > 0.0 {
                        h.at + t * (s.at() - h.at)
                    } else {
                        h.at + t * (h.at - a)
                    };
                    // A held sample already at round-off is on the point.
                    let on_it = c1 < 1e-3 * c0.min(c2);
                    if on_it || self.singular_at(at, c1) {
                        if t > 0.0 {
                            self.release();
                            return self.change_point(at, h.at, s.at());
                        }
                        // The held sample is past the point: dropped,
                        // never handed out, and forgotten.
                        self.held = None;
                        self.history[self.newest & 3] = Head::default();
                        self.newest = self.newest.wrapping_sub(1) & 3;
                        return self.change_point(at, a, h.at);
                    }
                }
            }
            self.release();
        }
        // `s` accepted; held back if the conditioning was falling fast.
        self.k += 1;
        let fast = self.falling;
        self.push_head(&s);
        if fast {
            self.held = Some(s);
        } else {
            let s = self.wrapped(s);
            self.out.push_back(Ok(s));
        }
    }

    /// Sample `k` failed with `e`.
    #[cold]
    fn failed(&mut self, k: usize, e: Error) {
        let at = self.grid.at(k);
        match e {
            Error::CannotAssemble { unknowns, .. } => self.no_solution(k, at, unknowns),
            Error::Singular { .. } if self.change_points != ChangePoints::Stop => {
                // Exactly at a change point: this sample is left out, and
                // the branch chosen at the next.
                self.release();
                self.cross(at, k + 1);
            }
            e @ Error::Singular { .. } => {
                // A change point met exactly, if the conditioning rises
                // again past it as it fell before it (a V); else a
                // singular position.
                self.release();
                let before = self.head().map(|h| (h.at, h.conditioning));
                let after = self.probe(k + 1);
                let reason = match (before, after) {
                    (Some((from, c0)), Some((to, c2))) if c2 < 2.0 * c0 && c0 < 2.0 * c2 => {
                        StopReason::ChangePoint { from, to }
                    }
                    _ => StopReason::from_error(e),
                };
                self.finish(at, reason);
            }
            e => {
                self.release();
                self.finish(at, StopReason::from_error(e));
            }
        }
    }

    /// Grid sample `k` solved from the pose extrapolated from the accepted
    /// samples, with a fresh state: its value and conditioning.
    fn probe(&mut self, k: usize) -> Option<(f64, f64)> {
        if k >= self.grid.count {
            return None;
        }
        let target = self.grid.at(k);
        let guess = extrapolated::<M>(&self.known(), target);
        let mut state = self.m.step_state(&self.options).ok()?;
        let s = self.solve(k, &guess, &mut state).ok()?;
        Some((s.at(), s.conditioning()))
    }

    /// A change point at `at`, between the accepted sample at `from` and
    /// the value `next`.
    fn change_point(&mut self, at: f64, from: f64, next: f64) {
        if self.change_points == ChangePoints::Stop {
            self.finish(at, StopReason::ChangePoint { from, to: next });
            return;
        }
        let k = self.grid_index_after(at);
        self.cross(at, k);
    }

    /// The first grid index whose value is past `at` in the direction of
    /// the sweep.
    fn grid_index_after(&self, at: f64) -> usize {
        let forward = self.grid.to >= self.grid.from;
        (0..self.grid.count)
            .find(|&k| {
                let v = self.grid.at(k);
                if forward {
                    v > at
                } else {
                    v < at
                }
            })
            .unwrap_or(self.grid.count)
    }

    /// The accepted poses before a change point, oldest first: (value,
    /// pose).
    fn known(&self) -> Vec<(f64, M::Coords)> {
        (0..=2)
            .rev()
            .filter_map(|n| self.back(n).map(|h| (h.at, h.q)))
            .collect()
    }

    /// Continues past the change point at `at` from grid index `k` (or
    /// the next that assembles) on the branch `self.change_points` names.
    fn cross(&mut self, at: f64, k: usize) {
        let known = self.known();
        let Ok(fresh) = self.m.step_state(&self.options) else {
            self.done = true;
            return;
        };
        let mut probe = fresh.clone();
        let modes = M::step_modes(&mut probe).len();
        for k in k..(k + 3).min(self.grid.count) {
            let target = self.grid.at(k);
            let guess = extrapolated::<M>(&known, target);
            // Every combination of assembly modes (one, from the guess, for
            // Newton–Raphson), each from a fresh state, ranked by distance
            // from the extrapolated pose.
            let mut best: [Option<Candidate<M, S>>; 2] = [None, None];
            for combo in 0..1usize << modes {
                let mut state = fresh.clone();
                for (i, m) in M::step_modes(&mut state).iter_mut().enumerate() {
                    *m = if combo >> i & 1 == 1 { -1.0 } else { 1.0 };
                }
                let Ok(s) = self.solve(k, &guess, &mut state) else {
                    continue;
                };
                let d = distance::<M>(&guess, s.q());
                let entry = Some((d, s, state));
                if best[0].as_ref().is_none_or(|b| d < b.0) {
                    best[1] = best[0].take();
                    best[0] = entry;
                } else if best[1].as_ref().is_none_or(|b| d < b.0) {
                    best[1] = entry;
                }
            }
            if best[0].is_none() {
                // Still at the point: the next grid value.
                continue;
            }
            let chosen = match self.change_points {
                ChangePoints::Switch => best[1].take(),
                _ => best[0].take(),
            };
            let Some((_, s, state)) = chosen else {
                let reason = StopReason::Invalid(Error::InvalidOption {
                    name: "change_points",
                    value: f64::NAN,
                    requirement: "must be `Smooth` or `Stop` here: `Switch` needs the block that \
                                  meets the other branch solved in closed form (see the \
                                  mechanism's BLOCKS), where both branches are at hand",
                });
                self.finish(at, reason);
                return;
            };
            self.passed.push(at);
            self.state = Some(state);
            self.forget();
            self.push_head(&s);
            let s = self.wrapped(s);
            self.out.push_back(Ok(s));
            self.k = k + 1;
            return;
        }
        let from = known.last().map_or(at, |p| p.0);
        let to = self.grid.at(k.min(self.grid.count.saturating_sub(1)));
        self.finish(at, StopReason::ChangePoint { from, to });
    }

    /// No real solution at grid sample `k` (value `at`): a limit position,
    /// or a change point where the two solutions touch and round-off makes
    /// them vanish over a tiny interval.
    fn no_solution(&mut self, k: usize, at: f64, unknowns: &'static str) {
        let Some(&h) = self.head() else {
            self.finish(at, StopReason::LimitPosition { unknowns });
            return;
        };
        let pose = h.q;
        let assembles = |it: &mut Self, v: f64| {
            let mut guess = pose;
            it.drive.drive(v, &mut guess, &mut it.rates, &mut it.accels);
            !matches!(
                it.m.assemble_with(&guess, &it.options),
                Err(Error::CannotAssemble { .. })
            )
        };
        // The last value that assembles, by bisection.
        let (mut good, mut bad) = (h.at, at);
        for _ in 0..200 {
            let mid = good + 0.5 * (bad - good);
            if mid == good || mid == bad {
                break;
            }
            if assembles(self, mid) {
                good = mid;
            } else {
                bad = mid;
            }
        }
        // A change point: the mechanism assembles again within a step, the
        // gap no wider than round-off makes it (1e-6 of the scale).
        if k + 1 < self.grid.count {
            let next = self.grid.at(k + 1);
            if assembles(self, next) {
                let (mut lo, mut hi) = (at, next);
                for _ in 0..200 {
                    let mid = lo + 0.5 * (hi - lo);
                    if mid == lo || mid == hi {
                        break;
                    }
                    if assembles(self, mid) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                let scale = 1.0 + good.abs().max(hi.abs());
                if (hi - good).abs() <= 1e-6 * scale {
                    self.release();
                    return self.change_point(0.5 * (good + hi), h.at, next);
                }
            }
        }
        self.release();
        self.finish(good, StopReason::LimitPosition { unknowns });
    }
}

/// The pose at `target` extrapolated from the `known` poses (up to three:
/// quadratic in the sweep variable), unknowns only.
fn extrapolated<M: Mechanism>(known: &[(f64, M::Coords)], target: f64) -> M::Coords {
    let Some(last) = known.last() else {
        return M::Coords::default();
    };
    let mut guess = last.1;
    for j in M::DRIVERS..M::DRIVERS + M::UNKNOWNS {
        // Lagrange's polynomial through the known poses.
        let mut value = 0.0;
        for (i, (ai, qi)) in known.iter().enumerate() {
            let mut w = 1.0;
            for (l, (al, _)) in known.iter().enumerate() {
                if l != i {
                    w *= (target - al) / (ai - al);
                }
            }
            value += w * qi.get(j).unwrap_or(f64::NAN);
        }
        if value.is_finite() {
            guess.set(j, value);
        }
    }
    guess
}

impl<M: Mechanism, D: Drive<M>, S: Solved<M>> SweepIter<'_, M, D, S> {
    /// Whether Φ_u is singular at `at` (where the conditioning, `c` at the
    /// nearest sample, extrapolates to zero): its conditioning there below
    /// a tenth of `c`, or a singular Jacobian. Tells a change point
    /// from a sharp but regular minimum of the conditioning.
    #[cold]
    fn singular_at(&mut self, at: f64, c: f64) -> bool {
        let known = self.known();
        let mut guess = extrapolated::<M>(&known, at);
        self.drive
            .drive(at, &mut guess, &mut self.rates, &mut self.accels);
        let Ok(mut state) = self.m.step_state(&self.options) else {
            return false;
        };
        match S::solve(self.m, at, &guess, &self.rates, &self.accels, &mut state) {
            Ok(s) => s.conditioning() < 0.1 * c,
            Err(Error::Singular { .. } | Error::CannotAssemble { .. }) => true,
            Err(_) => false,
        }
    }
}

/// Where a V-shaped dip of the conditioning c₀, c₁, c₂ (three equally
/// spaced samples, c₁ the least) reaches zero, as a fraction of a step
/// from the middle sample, if it is V-shaped: the two samples on one side
/// and the line through them meeting zero between the middle sample and
/// the one on the other side, where that line's mirror image passes
/// within 20 % of it. A minimum of a smooth curve sharper than the steps
/// can look so too; the sweep then checks the conditioning at the point.
#[inline]
fn v_zero(c0: f64, c1: f64, c2: f64) -> Option<f64> {
    if !(c1 < c0 && c1 < c2 && c0.min(c2) < 0.5) {
        return None;
    }
    // The point beyond the middle sample (towards c₂), from c₀ and c₁.
    let slope = c0 - c1;
    let t = c1 / slope;
    if t > 0.0 && t < 1.0 {
        let mirrored = slope * (1.0 - t);
        if (mirrored - c2).abs() <= 0.2 * c2 {
            return Some(t);
        }
    }
    // Before it (towards c₀), from c₂ and c₁.
    let slope = c2 - c1;
    let t = c1 / slope;
    if t > 0.0 && t < 1.0 {
        let mirrored = slope * (1.0 - t);
        if (mirrored - c0).abs() <= 0.2 * c0 {
            return Some(-t);
        }
    }
    None
}

/// The distance between two poses: unknown angles compared modulo 2π,
/// lengths as they are.
fn distance<M: Mechanism>(a: &M::Coords, b: &M::Coords) -> f64 {
    let mut d = 0.0;
    for (j, c) in M::COORDINATES.iter().enumerate() {
        if c.role == Role::Driver {
            continue;
        }
        let (Some(x), Some(y)) = (a.get(j), b.get(j)) else {
            continue;
        };
        let e = if c.kind == Kind::Angle {
            Wrap::Signed.apply(y - x)
        } else {
            y - x
        };
        d += e * e;
    }
    d
}

impl<M: Mechanism, D: Drive<M>, S: Solved<M>> Iterator for SweepIter<'_, M, D, S> {
    type Item = Result<S, Stop>;

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        // One comparison on the common path: nothing waiting, not done,
        // and the value is from + k·step.
        let k = self.k;
        if k < self.open {
            let at = self.grid.inner(k);
            if let Some(item) = self.advance(k, at) {
                return Some(item);
            }
        }
        self.next_slow()
    }
}

impl<M: Mechanism, D: Drive<M>, S: Solved<M>> SweepIter<'_, M, D, S> {
    /// [`Iterator::next`] off the fast path: the items waiting, the end,
    /// the last value of an even grid.
    #[inline(never)]
    fn next_slow(&mut self) -> Option<Result<S, Stop>> {
        let item = loop {
            if let Some(item) = self.out.pop_front() {
                break Some(item);
            }
            if self.done {
                break None;
            }
            if self.k >= self.grid.count {
                // The end: the held sample, if any, is before any change
                // point.
                self.done = true;
                break self.held.take().map(|s| Ok(self.wrapped(s)));
            }
            let k = self.k;
            if let Some(item) = self.advance(k, self.grid.at(k)) {
                break Some(item);
            }
        };
        self.reopen();
        item
    }
}

/// Collects a sweep's items.
fn collect<M: Mechanism, D: Drive<M>>(mut it: SweepIter<'_, M, D>, kind: Kind) -> Sweep<M> {
    let mut samples = Vec::with_capacity(it.grid.count + 1);
    let mut stop = None;
    for item in it.by_ref() {
        match item {
            Ok(s) => samples.push(s),
            Err(s) => stop = Some(s),
        }
    }
    Sweep {
        variable: it.variable,
        kind,
        samples,
        change_points: core::mem::take(&mut it.passed),
        stop,
    }
}

impl<M: Mechanism> Sweep<M> {
    /// Whether the last sample returns to the first pose: every unknown
    /// within `tolerance`, angles compared modulo 2π. `None` for a sweep that
    /// stopped early or has fewer than two samples. Meant for a sweep whose
    /// range includes its end (`.to(…)`), one period from its start; a
    /// `.turn()` leaves the end out.
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
    /// let s = m.sweep(SliderCrank::PHI, &start).to(std::f64::consts::TAU).steps(360).run();
    /// assert_eq!(s.is_periodic(1e-9), Some(true));
    /// ```
    #[must_use]
    pub fn is_periodic(&self, tolerance: f64) -> Option<bool> {
        if self.stop.is_some() || self.samples.len() < 2 {
            return None;
        }
        let (first, last) = (self.samples.first()?, self.samples.last()?);
        let ok = M::COORDINATES.iter().enumerate().all(|(j, c)| {
            if c.role == Role::Driver {
                return true;
            }
            let (a, b) = (first.motion.q().get(j), last.motion.q().get(j));
            let (Some(a), Some(b)) = (a, b) else {
                return false;
            };
            let d = if c.kind == Kind::Angle {
                crate::math::rem_euclid(b - a + core::f64::consts::PI, core::f64::consts::TAU)
                    - core::f64::consts::PI
            } else {
                b - a
            };
            d.abs() <= tolerance
        });
        Some(ok)
    }

    /// Largest closure residual over the samples.
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
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(100).run();
    /// assert!(s.max_residual() < 1e-12);
    /// ```
    #[must_use]
    pub fn max_residual(&self) -> f64 {
        self.samples
            .iter()
            .fold(0.0f64, |a, s| a.max(s.motion.residual()))
    }

    /// Column headers, plain identifiers with their units in the name:
    /// the time (`t_s`) for a simulation; each coordinate's value, rate and
    /// acceleration (`th3_rad`, `th3_rad_s`, `th3_rad_s2`; `x_m`, `x_m_s`,
    /// `x_m_s2`); each point's position, velocity and acceleration
    /// components (`B_x_m`, `B_vx_m_s`, `B_ax_m_s2`); each frame's ω and α
    /// (`tool_wx_rad_s`, `tool_alphax_rad_s2`). Lengths are taken to be in
    /// metres: see [`Sweep::headers_in`] for another unit.
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
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).run();
    /// let h = s.headers();
    /// assert_eq!(&h[..4], ["phi_rad", "phi_rad_s", "phi_rad_s2", "th_rad"]);
    /// assert!(h.contains(&"C_vx_m_s".to_owned()));
    /// assert_eq!(h.len(), s.row(&s.samples[0]).len());
    /// ```
    #[must_use]
    pub fn headers(&self) -> Vec<String> {
        self.headers_in("m")
    }

    /// [`Sweep::headers`] with lengths in `unit` (`"mm"`: `x_mm`,
    /// `B_vx_mm_s`); the values are as computed, in the unit of the
    /// mechanism's parameters.
    #[must_use]
    pub fn headers_in(&self, unit: &str) -> Vec<String> {
        let mut h = Vec::new();
        if self.variable == "t" {
            h.push("t_s".to_owned());
        }
        for c in M::COORDINATES {
            let u = match c.kind {
                Kind::Angle => "rad",
                Kind::Length => unit,
            };
            h.push(format!("{}_{u}", c.name));
            h.push(format!("{}_{u}_s", c.name));
            h.push(format!("{}_{u}_s2", c.name));
        }
        let axes = ["x", "y", "z"];
        for p in M::POINT_NAMES {
            for (prefix, suffix) in [("", ""), ("v", "_s"), ("a", "_s2")] {
                for axis in axes.iter().take(M::POINT_DIM) {
                    h.push(format!("{p}_{prefix}{axis}_{unit}{suffix}"));
                }
            }
        }
        for f in M::FRAME_NAMES {
            for (short, suffix) in [("w", "rad_s"), ("alpha", "rad_s2")] {
                for axis in axes {
                    h.push(format!("{f}_{short}{axis}_{suffix}"));
                }
            }
        }
        h
    }

    /// The values of one sample, in the order of [`Sweep::headers`].
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
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).rate(6.0).run();
    /// assert_eq!(s.row(&s.samples[10])[0], 1.0); // φ first
    /// ```
    #[must_use]
    pub fn row(&self, sample: &Sample<M>) -> Vec<f64> {
        let mo = &sample.motion;
        let mut r = Vec::new();
        if self.variable == "t" {
            r.push(sample.at);
        }
        for j in 0..M::COORDINATES.len() {
            for c in [mo.q(), mo.qd(), mo.qdd()] {
                r.push(c.get(j).unwrap_or(f64::NAN));
            }
        }
        for p in mo.points() {
            r.extend_from_slice(p.position());
            r.extend_from_slice(p.velocity());
            r.extend_from_slice(p.acceleration());
        }
        for f in mo.frames() {
            r.extend(
                f.angular_velocity
                    .iter()
                    .chain(f.angular_acceleration.iter()),
            );
        }
        r
    }

    /// The samples as CSV: a header line (see [`Sweep::headers`]), then one
    /// line per sample.
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
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).rate(6.0).run();
    /// assert_eq!(s.to_csv().lines().count(), 1 + 11); // a header, then a line per sample
    /// ```
    #[must_use]
    pub fn to_csv(&self) -> String {
        let mut out = self.headers().join(",");
        out.push('\n');
        for s in &self.samples {
            let row: Vec<String> = self.row(s).iter().map(|v| format!("{v:.12e}")).collect();
            out += &row.join(",");
            out.push('\n');
        }
        out
    }

    /// The samples as an aligned plain-text table, every `every`-th sample
    /// (the last one always included).
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
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).rate(6.0).run();
    /// print!("{}", s.to_text(5)); // every fifth sample, in aligned columns
    /// ```
    #[must_use]
    pub fn to_text(&self, every: usize) -> String {
        let headers = self.headers();
        let width = headers
            .iter()
            .map(|h| h.chars().count())
            .max()
            .unwrap_or(8)
            .max(12);
        let mut out = String::new();
        for h in &headers {
            let _ = write!(out, "{h:>width$} ");
        }
        out.push('\n');
        let n = self.samples.len();
        for (k, s) in self.samples.iter().enumerate() {
            if k % every.max(1) != 0 && k + 1 != n {
                continue;
            }
            for v in self.row(s) {
                let _ = write!(out, "{v:>width$.5} ");
            }
            out.push('\n');
        }
        out
    }
}
