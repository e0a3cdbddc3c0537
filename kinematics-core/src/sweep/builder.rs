//! The sweep builder returned by a mechanism's `sweep(driver, start)`:
//! the range, steps, rates and options, and how it runs (collected or
//! streamed).

use core::f64::consts::TAU;

use super::collected::{Sweep, collect};
use super::drive::{Grid, SweepDrive};
use super::handles::{Angle, ChangePoints, Driver, Wrap};
use super::iter::SweepIter;
use super::sample::{PoseSample, Sample, Solved, Stop};
use crate::error::Error;
use crate::mechanism::{Coordinates, Kind, Mechanism};
use crate::options::Options;

// ───────────────────────── the builders ─────────────────────────

/// The range of a sweep, as given.
#[derive(Debug, Clone, Copy)]
pub(crate) enum End {
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
    pub(super) m: &'m M,
    driver: Driver<M, U>,
    start: M::Coords,
    pub(super) from: Option<f64>,
    end: End,
    steps: usize,
    rate: f64,
    acceleration: f64,
    pub(super) options: Options,
    wrap: Wrap,
    pub(super) change_points: ChangePoints,
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
    pub(super) fn grid(&self) -> Result<Grid, Error> {
        let from = self
            .from
            .or_else(|| self.start.get(self.driver.index))
            .unwrap_or(f64::NAN);
        let kind = M::COORDINATES
            .get(self.driver.index)
            .map_or(Kind::Length, |c| c.kind);
        grid(from, self.end, self.steps, kind)
    }
}

/// The grid from `from` to `end` in `steps` equal steps, for a driver of
/// `kind`: the number of samples and whether the end is left out; an
/// error for a length driver with no end, or a range not finite.
pub(crate) fn grid(from: f64, end: End, steps: usize, kind: Kind) -> Result<Grid, Error> {
    let steps = steps.max(1);
    let (to, count) = match end {
        End::To(to) => (to, steps + 1),
        End::Turns(n) => (from + TAU * n, steps),
        End::Default if kind == Kind::Angle => (from + TAU, steps),
        End::Default => {
            return Err(Error::InvalidOption {
                name: "to",
                value: f64::NAN,
                requirement: "must be given for a length driver: `.to(value)`",
            });
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
