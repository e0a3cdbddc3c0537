//! What a synthesis needs of a mechanism, for the mechanisms `mechanism!`
//! generates and (with the `runtime` feature) for the models compiled at
//! run time: its names, its parameters by index, one analysis at a
//! target with the position-level sensitivities, and a path over a turn.

use std::vec;
use std::vec::Vec;

use crate::error::Error;
use crate::mechanism::{Coordinate, Coordinates, MotionState, PointState};
use crate::options::Options;
use crate::sweep::{Driver, SweepBuilder};
use crate::tolerance::Sensitive;

/// The seal of [`Subject`]: implemented here for the generated
/// mechanisms, and by the run-time model's own module for
/// `runtime::Model` (the synthesis knows no run-time model).
pub(crate) mod sealed {
    pub trait Sealed {}
    impl<M: crate::tolerance::Sensitive + Clone> Sealed for M {}
}

/// A mechanism a [`Synthesis`](super::Synthesis) can vary: every
/// mechanism `mechanism!` generates with a `sensitivities` section and,
/// with the `runtime` feature, `runtime::Model`
/// (its parameters those of its `sensitivities` section). Sealed: its
/// methods are the synthesis's own.
pub trait Subject: Clone + sealed::Sealed {
    /// A pose of the mechanism, drivers first: the generated coordinates
    /// struct, or a `Vec<f64>` for a run-time model.
    type Pose: Clone + core::fmt::Debug;
    /// What one analysis carries (the scaling, the assembly modes).
    #[doc(hidden)]
    type State: Clone;

    /// The names the synthesis refers to.
    #[doc(hidden)]
    fn shape(&self) -> Shape;
    /// Parameter `k` of the `sensitivities` section (NaN past the last).
    #[doc(hidden)]
    fn parameter_at(&self, k: usize) -> f64;
    /// Sets parameter `k` of the `sensitivities` section; `false` past
    /// the last.
    #[doc(hidden)]
    fn set_parameter_at(&mut self, k: usize, value: f64) -> bool;
    /// Coordinate `i` of a pose (NaN past the last).
    #[doc(hidden)]
    fn coordinate(pose: &Self::Pose, i: usize) -> f64;
    /// Sets coordinate `i` of a pose.
    #[doc(hidden)]
    fn set_coordinate(pose: &mut Self::Pose, i: usize, value: f64);
    /// A fresh state for analyses of this design, the assembly modes not
    /// chosen (NaN).
    #[doc(hidden)]
    ///
    /// # Errors
    /// Invalid options or parameters.
    fn state(&self, options: &Options) -> Result<Self::State, Error>;
    /// The assembly modes of a state, as signs (NaN: from the next pose).
    #[doc(hidden)]
    fn modes(state: &mut Self::State) -> &mut [f64];
    /// Assembles at the drivers of `pose` from its unknowns in the modes
    /// of `state` (choosing them from the pose where they are NaN), with
    /// a unit rate of `driver`: the pose solved into `pose`, and `out`
    /// filled (the sensitivities only when `sensitivities`).
    #[doc(hidden)]
    ///
    /// # Errors
    /// As the analysis and the sensitivities.
    fn solve(
        &self,
        pose: &mut Self::Pose,
        driver: usize,
        state: &mut Self::State,
        sensitivities: bool,
        out: &mut Solved,
    ) -> Result<(), Error>;
    /// [`Self::solve`] at each of `poses` into the matching `out`, each
    /// from `state` as it is (its modes; not changed), as one
    /// evaluation of a synthesis solves its targets.
    #[doc(hidden)]
    ///
    /// # Errors
    /// As [`Self::solve`], at the first pose that fails.
    fn solve_each(
        &self,
        poses: &mut [Self::Pose],
        driver: usize,
        state: &Self::State,
        sensitivities: bool,
        out: &mut [Solved],
    ) -> Result<(), Error> {
        for (pose, out) in poses.iter_mut().zip(out) {
            let mut state = state.clone();
            self.solve(pose, driver, &mut state, sensitivities, out)?;
        }
        Ok(())
    }
    /// The positions of every point (one after the other, each with its
    /// components) over a sweep of `driver` from `start` to `to` in
    /// `steps` steps, with the driver's value at each, and whether the
    /// sweep stopped before `to`.
    #[doc(hidden)]
    fn path(
        &self,
        driver: usize,
        start: &Self::Pose,
        to: f64,
        steps: usize,
        options: &Options,
    ) -> (Vec<(f64, Vec<f64>)>, bool);
    /// Whether a whole turn of the angle driver `driver` from `start`
    /// sweeps without stopping.
    #[doc(hidden)]
    fn turns(&self, driver: usize, start: &Self::Pose, options: &Options) -> bool;
}

/// The names of a [`Subject`]: its coordinates, its points and the
/// parameters of its `sensitivities` section.
#[doc(hidden)]
#[derive(Clone, Debug)]
pub struct Shape {
    /// Every coordinate, drivers first.
    pub coordinates: Vec<Coordinate>,
    /// Every point, in declaration order.
    pub points: Vec<&'static str>,
    /// The components of a point (2 or 3).
    pub point_dim: usize,
    /// The parameters of the `sensitivities` section, in its order.
    pub parameters: Vec<&'static str>,
}

/// One analysis at a target: the pose's coordinates and rates, every
/// point's position and velocity (for a unit driver rate), and, when
/// asked for, ∂q/∂p as `[parameter][coordinate]` and ∂r/∂p as
/// `[parameter][point][component]`.
#[doc(hidden)]
#[derive(Clone, Debug)]
pub struct Solved {
    /// q.
    pub q: Vec<f64>,
    /// q' for the unit driver rate.
    pub qd: Vec<f64>,
    /// Every point's position, `point_dim` values each.
    pub positions: Vec<f64>,
    /// Every point's velocity, likewise.
    pub velocities: Vec<f64>,
    /// ∂q/∂p.
    pub dq: Vec<f64>,
    /// ∂r/∂p.
    pub dr: Vec<f64>,
}

impl Solved {
    /// The arrays for `shape`, zero.
    pub(super) fn for_shape(shape: &Shape) -> Self {
        let (n, p, d, k) = (
            shape.coordinates.len(),
            shape.points.len(),
            shape.point_dim,
            shape.parameters.len(),
        );
        Solved {
            q: vec![0.0; n],
            qd: vec![0.0; n],
            positions: vec![0.0; p * d],
            velocities: vec![0.0; p * d],
            dq: vec![0.0; k * n],
            dr: vec![0.0; k * p * d],
        }
    }
}

/// The driver of a synthesis: a generated mechanism's driver handle
/// (`FourBar::PHI`), or a driver's name for a run-time model.
pub trait DriverOf<M: Subject> {
    /// The driver's index among the coordinates, or what is wrong.
    #[doc(hidden)]
    ///
    /// # Errors
    /// A name that is not a driver of `m`.
    fn driver_index(&self, m: &M) -> Result<usize, std::string::String>;
}

impl<M: Sensitive + Clone, U> DriverOf<M> for Driver<M, U> {
    fn driver_index(&self, _: &M) -> Result<usize, std::string::String> {
        Ok(self.index())
    }
}

impl<M: Sensitive + Clone> Subject for M {
    type Pose = M::Coords;
    type State = M::StepState;

    fn shape(&self) -> Shape {
        Shape {
            coordinates: M::COORDINATES.to_vec(),
            points: M::POINT_NAMES.to_vec(),
            point_dim: M::POINT_DIM,
            parameters: M::PARAMETERS.to_vec(),
        }
    }

    fn parameter_at(&self, k: usize) -> f64 {
        self.parameter(k)
    }

    fn set_parameter_at(&mut self, k: usize, value: f64) -> bool {
        self.set_parameter(k, value)
    }

    fn coordinate(pose: &M::Coords, i: usize) -> f64 {
        pose.get(i).unwrap_or(f64::NAN)
    }

    fn set_coordinate(pose: &mut M::Coords, i: usize, value: f64) {
        pose.set(i, value);
    }

    fn state(&self, options: &Options) -> Result<M::StepState, Error> {
        self.step_state(options)
    }

    fn modes(state: &mut M::StepState) -> &mut [f64] {
        M::step_modes(state)
    }

    fn solve(
        &self,
        pose: &mut M::Coords,
        driver: usize,
        state: &mut M::StepState,
        sensitivities: bool,
        out: &mut Solved,
    ) -> Result<(), Error> {
        let mut rates = M::Coords::default();
        rates.set(driver, 1.0);
        let zeros = M::Coords::default();
        let motion = self.step_carried(pose, &rates, &zeros, state)?;
        *pose = *motion.q();
        for (i, (q, qd)) in out.q.iter_mut().zip(&mut out.qd).enumerate() {
            *q = motion.q().get(i).unwrap_or(f64::NAN);
            *qd = motion.qd().get(i).unwrap_or(f64::NAN);
        }
        let d = M::POINT_DIM;
        for ((p, r), v) in motion
            .points()
            .iter()
            .zip(out.positions.chunks_exact_mut(d))
            .zip(out.velocities.chunks_exact_mut(d))
        {
            r.copy_from_slice(p.position());
            v.copy_from_slice(p.velocity());
        }
        if sensitivities {
            self.position_sensitivities_into(&motion, &mut out.dq, &mut out.dr)?;
        }
        Ok(())
    }

    fn path(
        &self,
        driver: usize,
        start: &M::Coords,
        to: f64,
        steps: usize,
        options: &Options,
    ) -> (Vec<(f64, Vec<f64>)>, bool) {
        let name = M::COORDINATES.get(driver).map_or("", |c| c.name);
        let handle = Driver::<M, crate::sweep::Angle>::__new(driver, name);
        let sweep = SweepBuilder::new(self, handle, start)
            .to(to)
            .steps(steps)
            .options(options)
            .run();
        let samples = sweep
            .samples
            .iter()
            .map(|x| {
                let r = x
                    .motion
                    .points()
                    .iter()
                    .flat_map(|p| p.position().iter().copied());
                (x.at, r.collect())
            })
            .collect();
        (samples, sweep.stop.is_some())
    }

    fn turns(&self, driver: usize, start: &M::Coords, options: &Options) -> bool {
        let name = M::COORDINATES.get(driver).map_or("", |c| c.name);
        let handle = Driver::<M, crate::sweep::Angle>::__new(driver, name);
        let sweep = SweepBuilder::new(self, handle, start)
            .turn()
            .options(options)
            .run();
        sweep.stop.is_none()
    }
}
