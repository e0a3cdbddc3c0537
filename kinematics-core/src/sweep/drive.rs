//! What drives a sweep: a grid of a driver's values, or a simulation in
//! time with a motion profile of the drivers (at rest, constant speed,
//! constant acceleration, or any closure).

use alloc::vec::Vec;

use super::collected::{Sweep, collect};
use super::engine::Engine;
use super::handles::{ChangePoints, Driver, Wrap};
use super::iter::SweepIter;
use super::sample::{PoseSample, Sample, Solved, Stop};
use crate::error::Error;
use crate::mechanism::{Coordinates, Kind, Mechanism};
use crate::options::Options;

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
    pub(super) m: &'m M,
    start: M::Coords,
    duration: f64,
    steps: usize,
    times: Option<Vec<f64>>,
    profile: P,
    pub(super) options: Options,
    wrap: Wrap,
    pub(super) change_points: ChangePoints,
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
    /// [`PoseSample`]s, as [`SweepBuilder::poses`](super::SweepBuilder::poses) (the profile's rates and
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
pub(crate) struct Grid {
    pub(super) from: f64,
    pub(super) to: f64,
    /// (to − from)/steps.
    step: f64,
    steps: usize,
    pub(crate) count: usize,
    values: Option<Vec<f64>>,
}

impl Grid {
    #[allow(clippy::cast_precision_loss)]
    pub(crate) fn even(from: f64, to: f64, steps: usize, count: usize) -> Self {
        Self {
            from,
            to,
            step: (to - from) / steps as f64,
            steps,
            count,
            values: None,
        }
    }

    pub(crate) fn given(values: Vec<f64>) -> Self {
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
    pub(crate) fn at(&self, k: usize) -> f64 {
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
    pub(super) fn inner(&self, k: usize) -> f64 {
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
    pub(super) fn inner_end(&self) -> usize {
        if self.values.is_some() {
            self.count
        } else {
            self.count.min(self.steps)
        }
    }
}

/// How the drivers follow the sweep variable.
pub trait Drive<E: Engine> {
    /// Sets, before the first sample, the drivers' rates and accelerations
    /// that are the same at every sample.
    fn start(&self, rates: &mut E::Pose, accels: &mut E::Pose);
    /// Sets the drivers of `pose` for the value `at` of the sweep variable,
    /// and the rates and accelerations that change with it.
    fn drive(&mut self, at: f64, pose: &mut E::Pose, rates: &mut E::Pose, accels: &mut E::Pose);
    /// The rate of the sweep variable (for the predictor): the swept
    /// driver's d', or 1 for the time.
    fn variable_rate(&self) -> f64;
}

/// One driver swept at a constant rate (see [`SweepBuilder`](super::SweepBuilder)).
#[derive(Debug, Clone, Copy)]
pub struct SweepDrive {
    pub(crate) driver: usize,
    pub(crate) rate: f64,
    pub(crate) acceleration: f64,
}

impl<E: Engine> Drive<E> for SweepDrive {
    fn start(&self, rates: &mut E::Pose, accels: &mut E::Pose) {
        E::set(rates, self.driver, self.rate);
        E::set(accels, self.driver, self.acceleration);
    }

    #[inline(always)]
    fn drive(&mut self, at: f64, pose: &mut E::Pose, _: &mut E::Pose, _: &mut E::Pose) {
        E::set(pose, self.driver, at);
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
