//! Sweeps of a run-time model over a driver's range, collected into a
//! [`Sweep`] that the outputs read as a [`Table`]: CSV, text, the plots
//! and the animation, the same as for a generated mechanism.

use core::f64::consts::TAU;

use super::drive::{Flats, Motions, Profiled, Setup, Sink, drive_each, drive_poses};
use super::{Flat, Model, Motion};
use crate::error::Error;
use crate::mechanism::{Coordinate, FrameState, Kind};
use crate::names::{Name, intern};
use crate::options::Options;
use crate::sweep::{ChangePoints, End, Grid, Layout, Stop, SweepDrive, Table, grid};
use crate::view::{PointRole, point_roles_by};

/// One sample of a run-time sweep: the driver's value and the motion
/// there.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// The swept driver's value.
    pub at: f64,
    /// q, q', q'', every point and frame, and the diagnostics.
    pub motion: Motion,
}

/// The samples of a run-time sweep and how it ended; read it as a
/// [`Table`] for its CSV, its text table, its plots and its animation.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The swept driver's name.
    pub variable: Name,
    /// The kind of the swept driver.
    pub kind: Kind,
    /// The samples, in order.
    pub samples: Vec<Sample>,
    /// `Some` when the sweep stopped early.
    pub stop: Option<Stop>,
    /// The change points passed on the branch chosen by
    /// [`SweepBuilder::change_points`] (estimates of the driver value of
    /// each).
    pub change_points: Vec<f64>,
    coordinates: Vec<Coordinate>,
    points: Vec<Name>,
    frames: Vec<Name>,
    point_dim: usize,
}

impl Table for Sweep {
    fn layout(&self) -> Layout<'_> {
        Layout {
            variable: self.variable,
            kind: self.kind,
            coordinates: &self.coordinates,
            points: &self.points,
            frames: &self.frames,
            point_dim: self.point_dim,
        }
    }
    fn rows(&self) -> usize {
        self.samples.len()
    }
    fn at(&self, i: usize) -> f64 {
        self.samples[i].at
    }
    fn coordinate(&self, i: usize, j: usize, order: usize) -> f64 {
        let m = &self.samples[i].motion;
        let c = match order {
            0 => &m.q,
            1 => &m.qd,
            _ => &m.qdd,
        };
        c.get(j).copied().unwrap_or(f64::NAN)
    }
    fn point(&self, i: usize, k: usize) -> [&[f64]; 3] {
        let p = &self.samples[i].motion.points[k];
        [&p.position, &p.velocity, &p.acceleration]
    }
    fn frame(&self, i: usize, f: usize) -> &FrameState {
        &self.samples[i].motion.frames[f]
    }
    fn stop(&self) -> Option<&Stop> {
        self.stop.as_ref()
    }
}

/// A sweep of one driver of a run-time model, built by [`Model::sweep`]:
/// the other drivers stay at their values in the start pose, at rest.
/// The range, steps, rate and options have the defaults of a generated
/// mechanism's sweep: from the start's value, one turn for an angle (the
/// end left out), 360 steps, a rate of 1 and an acceleration of 0.
#[derive(Clone, Debug)]
#[must_use = "a sweep does nothing until it is run"]
pub struct SweepBuilder<'m> {
    m: &'m Model,
    driver: usize,
    start: Vec<f64>,
    from: Option<f64>,
    end: End,
    steps: usize,
    rate: f64,
    acceleration: f64,
    options: Options,
    change_points: ChangePoints,
}

impl Model {
    /// A sweep of the driver named `driver` from the pose `start` (its
    /// drivers, and the first guess of its unknowns, drivers first).
    ///
    /// Each sample is assembled as a [`Stepper`](super::Stepper) steps
    /// (the closed-form blocks in the assembly modes of the start,
    /// carried from sample to sample; the other blocks by Newton–Raphson
    /// from the last pose advanced along its rates), then analysed, by the
    /// one sweep driver that sweeps generated mechanisms
    /// ([`SweepIter`](crate::sweep::SweepIter)): the same prediction,
    /// limit bisection, change-point tests and branch choice. The sweep
    /// never changes assembly branch silently: it stops at a change point
    /// ([`StopReason::ChangePoint`](crate::sweep::StopReason::ChangePoint):
    /// det Φ_u changes sign between two samples, the conditioning dips
    /// to zero around a sample, or falls towards zero while the pose
    /// leaves the branch's extrapolation; unless
    /// [`SweepBuilder::change_points`] says which branch to continue
    /// on), where Φ_u is singular, at a limit position of a closed-form
    /// block ([`StopReason::LimitPosition`](crate::sweep::StopReason::LimitPosition),
    /// its `at` the last value that assembles, by bisection to the
    /// resolution of `f64`) and where the mechanism does not assemble
    /// ([`StopReason::NotAssembled`](crate::sweep::StopReason::NotAssembled)
    /// at the first value that fails: past a limit position of a Newton
    /// block, Newton–Raphson has no root to converge to).
    ///
    /// ```
    /// use kinematics_core::runtime::Model;
    /// use kinematics_core::sweep::Table;
    /// let mut m = Model::compile(
    ///     "struct SliderCrank {
    ///          params   { a, b }
    ///          drivers  { phi }
    ///          unknowns { th, x }
    ///          points   { B = polar(a, phi); C = vec2(x, 0.0); }
    ///          loops    { B + polar(b, th) == C; }
    ///      }",
    /// )?;
    /// m.set_values(&[0.1, 0.3])?;
    /// let s = m.sweep("phi", &[0.0, 0.0, 0.4])?.turn().steps(360).rpm(600.0).run();
    /// assert!(s.stop.is_none());
    /// assert_eq!(s.rows(), 360);
    /// // The slider's stroke is twice the crank.
    /// let x: Vec<f64> = s.samples.iter().map(|s| s.motion.q[2]).collect();
    /// let stroke = x.iter().copied().fold(f64::MIN, f64::max) - x.iter().copied().fold(f64::MAX, f64::min);
    /// assert!((stroke - 0.2).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a name that is not one of the
    /// drivers; the other invalid inputs (the start's length, a
    /// non-finite value, parameters not set) end the sweep with a stop
    /// when it runs.
    pub fn sweep(&self, driver: &str, start: &[f64]) -> Result<SweepBuilder<'_>, Error> {
        let index = self.coordinates[..self.drivers]
            .iter()
            .position(|c| c.name == driver)
            .ok_or_else(|| Error::InvalidOption {
                name: intern(driver),
                value: f64::NAN,
                requirement: "must be one of the model's drivers",
            })?;
        Ok(SweepBuilder {
            m: self,
            driver: index,
            start: start.to_vec(),
            from: None,
            end: End::Default,
            steps: 360,
            rate: 1.0,
            acceleration: 0.0,
            options: Options::DEFAULT,
            change_points: ChangePoints::Stop,
        })
    }

    /// The role of every point at the pose `q` (drivers first): a ground
    /// pivot, a slider on a ground guide, or moving, as
    /// [`point_roles_by`] finds them; for the skeleton of an animation.
    ///
    /// # Errors
    /// [`Error::WrongLength`] for a pose of the wrong length, and invalid
    /// parameters.
    pub fn point_roles(&self, q: &[f64]) -> Result<Vec<PointRole>, Error> {
        self.validate()?;
        self.length("coordinates", self.coordinates.len(), q.len())?;
        Ok(point_roles_by(
            &self.coordinates,
            self.point_dim,
            q,
            |moved, out| *out = self.positions(moved),
        ))
    }
}

impl SweepBuilder<'_> {
    /// The first value of the driver (rad or length unit); by default its
    /// value in the start pose.
    pub fn from(mut self, value: f64) -> Self {
        self.from = Some(value);
        self
    }

    /// The last value of the driver, included.
    pub fn to(mut self, value: f64) -> Self {
        self.end = End::To(value);
        self
    }

    /// One full turn from the first value (an angle driver); with
    /// `steps(n)`, n samples 360°/n apart, the end (the start again) left
    /// out.
    pub fn turn(self) -> Self {
        self.turns(1.0)
    }

    /// `n` full turns (negative: clockwise), the end left out.
    pub fn turns(mut self, n: f64) -> Self {
        self.end = End::Turns(n);
        self
    }

    /// The number of equal steps (at least 1).
    pub fn steps(mut self, steps: usize) -> Self {
        self.steps = steps;
        self
    }

    /// The driver's rate d' at every sample.
    pub fn rate(mut self, rate: f64) -> Self {
        self.rate = rate;
        self
    }

    /// The driver's rate in revolutions per minute (an angle driver).
    pub fn rpm(self, rpm: f64) -> Self {
        self.rate(rpm * TAU / 60.0)
    }

    /// The driver's acceleration d'' at every sample.
    pub fn acceleration(mut self, acceleration: f64) -> Self {
        self.acceleration = acceleration;
        self
    }

    /// The solver options.
    pub fn options(mut self, options: &Options) -> Self {
        self.options = *options;
        self
    }

    /// What to do at a change point, where two assembly branches meet:
    /// stop there (the default), continue on the branch on which the
    /// motion is smooth, or switch to the other (which needs the block
    /// that meets the other branch to be solved in closed form), as for a
    /// generated sweep.
    pub fn change_points(mut self, change_points: ChangePoints) -> Self {
        self.change_points = change_points;
        self
    }

    /// The first value of the swept driver: `from`, else the start's.
    fn first(&self) -> f64 {
        self.from
            .or_else(|| self.start.get(self.driver).copied())
            .unwrap_or(f64::NAN)
    }

    /// Runs the sweep, handing each sample to `f` (the swept value and the
    /// motion there) as it is solved, without collecting them: the same
    /// samples as [`SweepBuilder::run`], with no allocation per sample.
    ///
    /// ```
    /// use kinematics_core::runtime::Model;
    /// let mut m = Model::compile(
    ///     "struct SliderCrank {
    ///          params   { a, b }
    ///          drivers  { phi }
    ///          unknowns { th, x }
    ///          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
    ///      }",
    /// )?;
    /// m.set_values(&[0.1, 0.3])?;
    /// let mut stroke = (f64::INFINITY, f64::NEG_INFINITY);
    /// let end = m.sweep("phi", &[0.0, 0.0, 0.4])?.steps(3600).for_each(|_, s| {
    ///     stroke = (stroke.0.min(s.q[2]), stroke.1.max(s.q[2]));
    /// });
    /// assert!(end.stop.is_none());
    /// // The slider's stroke is twice the crank.
    /// assert!((stroke.1 - stroke.0 - 0.2).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_each(self, f: impl FnMut(f64, &Motion)) -> SweepEnd {
        self.drive(Motions(f))
    }

    /// [`SweepBuilder::for_each`], handing `f` each sample as flat arrays
    /// borrowed from the stepper ([`Flat`]) rather than as a [`Motion`]:
    /// for callers that copy the samples into arrays of their own.
    pub fn for_each_flat(self, f: impl FnMut(f64, &Flat<'_>)) -> SweepEnd {
        let m = self.m;
        self.drive(Flats::new(m, f))
    }

    /// The sweep, its samples handed to `sink`.
    pub(super) fn drive(self, sink: impl Sink) -> SweepEnd {
        let (grid, drive) = self.parts();
        drive_each(self.m, &self.setup(), grid, drive, sink)
    }

    /// The sweep's setup: its variable, first value, start, options and
    /// rule at change points.
    pub(super) fn setup(&self) -> Setup<'_> {
        Setup {
            variable: self.m.coordinates[self.driver].name,
            first: self.first(),
            start: &self.start,
            options: &self.options,
            change_points: self.change_points,
        }
    }

    /// The sweep's values of its driver.
    pub(super) fn grid(&self) -> Result<Grid, Error> {
        self.parts().0
    }

    /// The sweep's grid and the drive of its driver.
    pub(super) fn parts(&self) -> (Result<Grid, Error>, SweepDrive) {
        let kind = self.m.coordinates[self.driver].kind;
        let grid = grid(self.first(), self.end, self.steps, kind);
        let drive = SweepDrive {
            driver: self.driver,
            rate: self.rate,
            acceleration: self.acceleration,
        };
        (grid, drive)
    }

    /// Runs the sweep for positions only, handing `f` the swept value, the
    /// pose (drivers first) and every point's position
    /// ([`Model::point_dimension`] values per point) at each sample: each
    /// pose assembled from the last as a [`Stepper`](super::Stepper)
    /// does ([`Stepper::pose`](super::Stepper::pose)), without the
    /// analysis: no rates, no accelerations, no judgement of the
    /// conditioning, and so no search for change points (the closed forms
    /// stay in the start's modes). It stops where the mechanism does not
    /// assemble: at a limit position, found by bisection as
    /// [`SweepBuilder::run`] finds it, or with the error. No allocation
    /// per sample.
    pub fn for_each_pose(self, f: impl FnMut(f64, &[f64], &[f64])) -> SweepEnd {
        let (grid, drive) = self.parts();
        let mut setup = self.setup();
        setup.change_points = ChangePoints::Stop;
        drive_poses(self.m, &setup, grid, drive, f)
    }

    /// Runs the sweep, collecting its samples.
    pub fn run(self) -> Sweep {
        let m = self.m;
        let coordinate = m.coordinates[self.driver];
        collect(m, (coordinate.name, coordinate.kind), |emit| {
            self.for_each(emit)
        })
    }
}

/// A simulation in time of a run-time model, built by [`Model::simulate`]:
/// the drivers follow a profile of time (by default they stay at rest at
/// their values in the start pose); every sample is assembled and
/// analysed as a sweep's, and the result is a [`Sweep`] whose variable is
/// the time `t`.
///
/// ```
/// use kinematics_core::runtime::Model;
/// let mut m = Model::compile(
///     "struct SliderCrank {
///          params   { a, b }
///          drivers  { phi }
///          unknowns { th, x }
///          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
///      }",
/// )?;
/// m.set_values(&[0.1, 0.3])?;
/// // The crank starts from rest with φ'' = 20 rad/s², for one second.
/// let s = m
///     .simulate(&[0.0, 0.0, 0.4])
///     .duration(1.0)
///     .steps(100)
///     .profile(|t, d, dd, ddd| {
///         d[0] = 10.0 * t * t;
///         dd[0] = 20.0 * t;
///         ddd[0] = 20.0;
///     })
///     .run();
/// let last = &s.samples[100].motion;
/// assert!((last.qd[0] - 20.0).abs() < 1e-12 && (last.q[0] - 10.0).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use = "a simulation does nothing until it is run"]
pub struct Simulation<'m, P> {
    m: &'m Model,
    start: Vec<f64>,
    duration: f64,
    steps: usize,
    profile: P,
    options: Options,
}

impl<P> core::fmt::Debug for Simulation<'_, P> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Simulation")
            .field("duration", &self.duration)
            .field("steps", &self.steps)
            .finish_non_exhaustive()
    }
}

/// The profile of drivers at rest.
fn at_rest(_: f64, _: &mut [f64], _: &mut [f64], _: &mut [f64]) {}

/// The type of a profile given as a function: `(t, d, d', d'')`.
pub type ProfileFn = fn(f64, &mut [f64], &mut [f64], &mut [f64]);

impl Model {
    /// A simulation from the pose `start` (drivers, then guesses of the
    /// unknowns), the drivers at rest until [`Simulation::profile`] says
    /// how they move; one second in 100 steps by default.
    pub fn simulate(&self, start: &[f64]) -> Simulation<'_, ProfileFn> {
        Simulation {
            m: self,
            start: start.to_vec(),
            duration: 1.0,
            steps: 100,
            profile: at_rest as ProfileFn,
            options: Options::DEFAULT,
        }
    }
}

impl<'m, P: FnMut(f64, &mut [f64], &mut [f64], &mut [f64])> Simulation<'m, P> {
    /// The drivers' motion: `profile(t, d, d', d'')` writes the drivers'
    /// values, rates and accelerations at time t (each slice one entry
    /// per driver, in declaration order). A driver it does not write keeps
    /// its start value, at rest.
    pub fn profile<Q: FnMut(f64, &mut [f64], &mut [f64], &mut [f64])>(
        self,
        profile: Q,
    ) -> Simulation<'m, Q> {
        Simulation {
            m: self.m,
            start: self.start,
            duration: self.duration,
            steps: self.steps,
            profile,
            options: self.options,
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

    /// The solver options.
    pub fn options(mut self, options: &Options) -> Self {
        self.options = *options;
        self
    }

    /// Runs the simulation, collecting its samples.
    pub fn run(self) -> Sweep {
        let m = self.m;
        collect(m, ("t", Kind::Length), |emit| self.for_each(emit))
    }

    /// Runs the simulation, handing each sample to `f` (the time and the
    /// motion) as it is solved, without collecting them, as
    /// [`SweepBuilder::for_each`] does for a sweep.
    pub fn for_each(self, f: impl FnMut(f64, &Motion)) -> SweepEnd {
        self.drive(Motions(f))
    }

    /// [`Simulation::for_each`], handing `f` each sample as flat arrays
    /// ([`Flat`]), as [`SweepBuilder::for_each_flat`] does.
    pub fn for_each_flat(self, f: impl FnMut(f64, &Flat<'_>)) -> SweepEnd {
        let m = self.m;
        self.drive(Flats::new(m, f))
    }

    /// The simulation, its samples handed to `sink`.
    fn drive(self, sink: impl Sink) -> SweepEnd {
        let grid = if self.duration.is_finite() && self.duration > 0.0 {
            let steps = self.steps.max(1);
            Ok(Grid::even(0.0, self.duration, steps, steps + 1))
        } else {
            Err(Error::InvalidOption {
                name: "duration",
                value: self.duration,
                requirement: "must be finite and positive",
            })
        };
        let m = self.m;
        let setup = Setup {
            variable: "t",
            first: 0.0,
            start: &self.start,
            options: &self.options,
            change_points: ChangePoints::Stop,
        };
        let drive = Profiled {
            start: self.start.clone(),
            drivers: m.drivers,
            profile: self.profile,
        };
        drive_each(m, &setup, grid, drive, sink)
    }
}

/// The samples that `each` hands to its callback, collected into a
/// [`Sweep`] of the variable `variable` of `kind`.
pub(super) fn collect(
    m: &Model,
    (variable, kind): (Name, Kind),
    each: impl FnOnce(&mut dyn FnMut(f64, &Motion)) -> SweepEnd,
) -> Sweep {
    let mut samples = Vec::new();
    let end = each(&mut |at, motion| {
        samples.push(Sample {
            at,
            motion: motion.clone(),
        });
    });
    sweep_of(m, (variable, kind), samples, end)
}

/// The sweep of `m` in `variable` made of `samples`, owned already (no
/// motion copied), ended by `end`.
pub(super) fn sweep_of(
    m: &Model,
    (variable, kind): (Name, Kind),
    samples: Vec<Sample>,
    end: SweepEnd,
) -> Sweep {
    Sweep {
        variable,
        kind,
        samples,
        stop: end.stop,
        change_points: end.change_points,
        coordinates: m.coordinates.clone(),
        points: m.points.clone(),
        frames: m.frames.clone(),
        point_dim: m.point_dim,
    }
}

/// How a sweep streamed by [`SweepBuilder::for_each`] ended: the stop, if
/// it stopped early, and the change points it passed.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepEnd {
    /// `Some` when the sweep stopped early.
    pub stop: Option<Stop>,
    /// The change points passed (estimates of the swept value at each).
    pub change_points: Vec<f64>,
}
