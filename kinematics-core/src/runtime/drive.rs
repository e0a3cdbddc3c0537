//! A run-time model as the one sweep driver ([`SweepIter`]) steps it: the
//! model's [`Engine`] (poses as vectors, a [`Stepper`] as the state
//! carried from step to step), the samples the stepper holds, and the
//! loop that hands them to a sink without copying them.
//!
//! The prediction, the bisection of limit positions, the change-point
//! tests and the choice of branch past one are the driver's, the same
//! code as for generated mechanisms.

use alloc::boxed::Box;
use alloc::vec;
use alloc::vec::Vec;

use super::sweep::SweepEnd;
use super::{Flat, Model, Motion, Stepper};
use crate::error::Error;
use crate::mechanism::Coordinate;
use crate::names::Name;
use crate::options::Options;
use crate::sweep::{ChangePoints, Drive, Engine, Grid, Solved, Stop, StopReason, SweepIter, Wrap};

/// A run-time model as a sweep steps it.
pub(super) struct Stepped<'m> {
    m: &'m Model,
    /// Whether some block is solved by Newton–Raphson (then the guess is
    /// predicted from the rates; else the previous pose names the
    /// branch).
    newton: bool,
}

impl<'m> Stepped<'m> {
    pub(super) fn new(m: &'m Model) -> Self {
        Self {
            m,
            newton: m.unknowns() > 0 && !m.all_closed(),
        }
    }
}

impl<'m> Engine for Stepped<'m> {
    type Pose = Vec<f64>;
    type State = Stepper<'m>;

    fn drivers(&self) -> usize {
        self.m.drivers
    }

    fn coordinates(&self) -> &[Coordinate] {
        &self.m.coordinates
    }

    fn newton_guess(&self) -> bool {
        self.newton
    }

    fn zero_pose(&self) -> Vec<f64> {
        self.m.spare.pose(self.m.coordinates.len())
    }

    fn recycle(&self, poses: &mut [&mut Vec<f64>]) {
        self.m
            .spare
            .give_poses(poses.iter_mut().map(|p| core::mem::take(&mut **p)));
    }

    #[inline(always)]
    fn lend(slot: &mut Vec<f64>) -> Vec<f64> {
        core::mem::take(slot)
    }

    #[inline(always)]
    fn give_back(slot: &mut Vec<f64>, pose: Vec<f64>) {
        *slot = pose;
    }

    #[inline(always)]
    fn copy_pose(to: &mut Vec<f64>, from: &Vec<f64>) {
        // A few values, copied by hand (no call of `memcpy`).
        if to.len() == from.len() {
            crate::math::copy_small(to, from);
        } else {
            to.clone_from(from);
        }
    }

    #[inline(always)]
    fn get(pose: &Vec<f64>, j: usize) -> f64 {
        pose.get(j).copied().unwrap_or(f64::NAN)
    }

    #[inline(always)]
    fn set(pose: &mut Vec<f64>, j: usize, value: f64) {
        if let Some(x) = pose.get_mut(j) {
            *x = value;
        }
    }

    fn state(&self, options: &Options) -> Result<Stepper<'m>, Error> {
        self.m.stepper(options)
    }

    fn modes<'s>(state: &'s mut Stepper<'m>) -> &'s mut [f64] {
        state.signs_mut()
    }

    fn assembles(&self, guess: &Vec<f64>, options: &Options) -> bool {
        !matches!(
            self.m.assemble_with(guess, options),
            Err(Error::CannotAssemble { .. })
        )
    }
}

/// A sample of a run-time sweep: the last step of the sweep's stepper,
/// read from it when handed out (no copy), or a motion copied out of it
/// (a sample held back past the next step).
#[derive(Debug)]
pub(super) enum Held {
    /// The stepper's last step, at the value `at`.
    Current {
        at: f64,
        conditioning: f64,
        det_sign: f64,
    },
    /// A motion of its own.
    Kept { at: f64, motion: Box<Motion> },
}

impl<'m> Solved<Stepped<'m>> for Held {
    const RATES: bool = true;
    type Step = (f64, f64);

    #[inline(always)]
    fn step(
        m: &Stepped<'m>,
        start: &Vec<f64>,
        rates: &Vec<f64>,
        accelerations: &Vec<f64>,
        state: &mut Stepper<'m>,
    ) -> Result<(f64, f64), Error> {
        let nd = m.m.drivers;
        state.advance(start, &rates[..nd], &accelerations[..nd])?;
        Ok(state.judged())
    }

    #[inline(always)]
    fn step_det_sign(step: &(f64, f64)) -> f64 {
        step.1
    }

    #[inline(always)]
    fn sample(at: f64, (conditioning, det_sign): (f64, f64)) -> Self {
        Held::Current {
            at,
            conditioning,
            det_sign,
        }
    }

    fn at(&self) -> f64 {
        match self {
            Held::Current { at, .. } | Held::Kept { at, .. } => *at,
        }
    }

    #[inline(always)]
    fn record(
        &self,
        state: Option<&Stepper<'m>>,
        q: &mut Vec<f64>,
        qd: Option<&mut Vec<f64>>,
    ) -> bool {
        let (from_q, from_qd) = match (self, state) {
            (Held::Current { .. }, None) => return false,
            (Held::Current { .. }, Some(state)) => state.pose_rates(),
            (Held::Kept { motion, .. }, _) => (&motion.q[..], &motion.qd[..]),
        };
        crate::math::copy_small(q, from_q);
        if let Some(qd) = qd {
            crate::math::copy_small(qd, from_qd);
        }
        true
    }

    fn q_mut(&mut self) -> Option<&mut Vec<f64>> {
        None
    }

    fn conditioning(&self) -> f64 {
        match self {
            Held::Current { conditioning, .. } => *conditioning,
            Held::Kept { motion, .. } => motion.conditioning,
        }
    }

    fn det_sign(&self) -> f64 {
        match self {
            Held::Current { det_sign, .. } => *det_sign,
            Held::Kept { motion, .. } => motion.det_sign,
        }
    }

    fn keep(self, state: &mut Stepper<'m>) -> Self {
        match self {
            Held::Current { at, .. } => Held::Kept {
                at,
                motion: Box::new(state.motion_now().clone()),
            },
            kept @ Held::Kept { .. } => kept,
        }
    }
}

/// A pose of a run-time sweep of positions: the last pose of the sweep's
/// stepper. Its conditioning is not judged (a sweep of poses looks for
/// no change point): reported as NaN, which no test of a change point
/// passes (a singular Newton step is then a `Singular` stop), the sign of
/// det Φ_u as +1.
#[derive(Debug)]
pub(super) struct PoseOnly {
    at: f64,
}

impl<'m> Solved<Stepped<'m>> for PoseOnly {
    const RATES: bool = false;
    type Step = ();

    #[inline(always)]
    fn step(
        _: &Stepped<'m>,
        start: &Vec<f64>,
        _: &Vec<f64>,
        _: &Vec<f64>,
        state: &mut Stepper<'m>,
    ) -> Result<(), Error> {
        state.pose(start).map(|_| ())
    }

    fn step_det_sign((): &()) -> f64 {
        1.0
    }

    fn sample(at: f64, (): ()) -> Self {
        PoseOnly { at }
    }

    fn at(&self) -> f64 {
        self.at
    }

    #[inline(always)]
    fn record(
        &self,
        state: Option<&Stepper<'m>>,
        q: &mut Vec<f64>,
        _: Option<&mut Vec<f64>>,
    ) -> bool {
        let Some(state) = state else {
            return false;
        };
        crate::math::copy_small(q, state.pose_now());
        true
    }

    fn q_mut(&mut self) -> Option<&mut Vec<f64>> {
        None
    }

    fn conditioning(&self) -> f64 {
        f64::NAN
    }

    fn det_sign(&self) -> f64 {
        1.0
    }
}

/// How a run-time sweep is set up: its variable, the value it starts
/// from (where a stop before the first sample is reported), the options
/// and what to do at a change point.
pub(super) struct Setup<'a> {
    pub(super) variable: Name,
    pub(super) first: f64,
    pub(super) start: &'a [f64],
    pub(super) options: &'a Options,
    pub(super) change_points: ChangePoints,
}

/// The sweep of `m` over `grid`, its drivers following `drive`, each
/// sample assembled and analysed by the model's stepper and handed to
/// `sink` as it is solved; how it ended.
pub(super) fn drive_each<'m, D: Drive<Stepped<'m>>>(
    m: &'m Model,
    setup: &Setup<'_>,
    grid: Result<Grid, Error>,
    drive: D,
    mut sink: impl Sink,
) -> SweepEnd {
    let engine = Stepped::new(m);
    let mut it = match start::<D, Held>(&engine, setup, grid, drive) {
        Ok(it) => it,
        Err(end) => return end,
    };
    let stop = rest(&mut it, &mut sink);
    SweepEnd {
        stop,
        change_points: it.change_points().to_vec(),
    }
}

/// A sweep of `drive_each` to its end from where `it` is: the common
/// path's samples straight to the sink, then one item of the slow path (a
/// change point, a stop, the end), and again; the stop, if it stopped.
pub(super) fn rest<'m, D: Drive<Stepped<'m>>>(
    it: &mut SweepIter<'_, Stepped<'m>, D, Held>,
    sink: &mut impl Sink,
) -> Option<Stop> {
    let mut stop = None;
    loop {
        it.each_common(|s, stepper| {
            match s {
                Held::Current { at, .. } => sink.stepped(at, stepper),
                Held::Kept { at, motion } => sink.motion(at, &motion),
            }
            true
        });
        let Some(item) = it.next() else {
            break;
        };
        match item {
            Ok(Held::Current { at, .. }) => {
                if let Some(stepper) = it.state_mut() {
                    sink.stepped(at, stepper);
                }
            }
            Ok(Held::Kept { at, motion }) => sink.motion(at, &motion),
            Err(s) => stop = Some(s),
        }
    }
    stop
}

/// The sweep of positions of `m` over `grid`: each pose assembled by the
/// model's stepper ([`Stepper::pose`]) and handed to `f` with every
/// point's position; how it ended.
pub(super) fn drive_poses<'m, D: Drive<Stepped<'m>>>(
    m: &'m Model,
    setup: &Setup<'_>,
    grid: Result<Grid, Error>,
    drive: D,
    mut f: impl FnMut(f64, &[f64], &[f64]),
) -> SweepEnd {
    let engine = Stepped::new(m);
    let mut it = match start::<D, PoseOnly>(&engine, setup, grid, drive) {
        Ok(it) => it,
        Err(end) => return end,
    };
    let mut positions = vec![0.0; m.points.len() * m.point_dim];
    let mut stop = None;
    let variable = setup.variable;
    let stopped = |at: f64, e: Error| Stop {
        variable,
        at,
        reason: StopReason::from_error(e),
    };
    loop {
        // The common path's samples straight to `f`, then one item of
        // the slow path (a change point, a stop, the end), and again.
        let mut failed = None;
        it.each_common(|PoseOnly { at }, stepper| {
            match emit_pose(at, stepper, &mut positions, &mut f) {
                Ok(()) => true,
                Err(e) => {
                    failed = Some(stopped(at, e));
                    false
                }
            }
        });
        if failed.is_some() {
            stop = failed;
            break;
        }
        let Some(item) = it.next() else {
            break;
        };
        match item {
            Ok(PoseOnly { at }) => {
                let Some(stepper) = it.state_mut() else {
                    break;
                };
                if let Err(e) = emit_pose(at, stepper, &mut positions, &mut f) {
                    stop = Some(stopped(at, e));
                    break;
                }
            }
            Err(s) => stop = Some(s),
        }
    }
    SweepEnd {
        stop,
        change_points: it.change_points().to_vec(),
    }
}

/// Sample `at`'s pose and positions to `f`: the positions read where the
/// fused code left them, else evaluated into `positions`.
#[inline(always)]
fn emit_pose(
    at: f64,
    stepper: &mut Stepper<'_>,
    positions: &mut [f64],
    f: &mut impl FnMut(f64, &[f64], &[f64]),
) -> Result<(), Error> {
    if let Some(fused) = stepper.fused_positions() {
        f(at, stepper.pose_now(), fused);
        return Ok(());
    }
    stepper.positions(positions)?;
    f(at, stepper.pose_now(), positions);
    Ok(())
}

/// The driver over `engine`, once the inputs are checked; or how the
/// sweep ended before its first sample.
pub(super) fn start<'e, 'm, D: Drive<Stepped<'m>>, S: Solved<Stepped<'m>>>(
    engine: &'e Stepped<'m>,
    setup: &Setup<'_>,
    grid: Result<Grid, Error>,
    drive: D,
) -> Result<SweepIter<'e, Stepped<'m>, D, S>, SweepEnd> {
    let m = engine.m;
    let checked = grid.and_then(|grid| {
        setup.options.validate()?;
        m.validate()?;
        m.check_pose(setup.start)?;
        Ok(grid)
    });
    match checked {
        Ok(grid) => Ok(SweepIter::new(
            engine,
            &setup.start.to_vec(),
            setup.variable,
            Ok(grid),
            drive,
            setup.options,
            Wrap::Continuous,
            setup.change_points,
        )),
        Err(e) => Err(SweepEnd {
            stop: Some(Stop {
                variable: setup.variable,
                at: setup.first,
                reason: StopReason::from_error(e),
            }),
            change_points: Vec::new(),
        }),
    }
}

/// The drivers of a run-time simulation following a profile of time
/// `profile(t, d, d', d'')` (one entry per driver; a driver it does not
/// write keeps its start value, at rest).
pub(super) struct Profiled<P> {
    pub(super) start: Vec<f64>,
    pub(super) drivers: usize,
    pub(super) profile: P,
}

impl<'m, P: FnMut(f64, &mut [f64], &mut [f64], &mut [f64])> Drive<Stepped<'m>> for Profiled<P> {
    fn start(&self, _: &mut Vec<f64>, _: &mut Vec<f64>) {}

    fn drive(&mut self, t: f64, pose: &mut Vec<f64>, rates: &mut Vec<f64>, accels: &mut Vec<f64>) {
        let nd = self.drivers;
        if pose.len() < nd || rates.len() < nd || accels.len() < nd || self.start.len() < nd {
            return;
        }
        pose[..nd].copy_from_slice(&self.start[..nd]);
        rates.fill(0.0);
        accels.fill(0.0);
        (self.profile)(t, &mut pose[..nd], &mut rates[..nd], &mut accels[..nd]);
    }

    fn variable_rate(&self) -> f64 {
        1.0
    }
}

/// What a sweep hands its samples to: a step's (read from the stepper,
/// as a [`Motion`] or flat arrays) or a motion held back past a step.
pub(super) trait Sink {
    fn stepped(&mut self, at: f64, stepper: &mut Stepper<'_>);
    fn motion(&mut self, at: f64, motion: &Motion);
}

/// Hands each sample to a callback as a [`Motion`].
pub(super) struct Motions<F>(pub(super) F);

impl<F: FnMut(f64, &Motion)> Sink for Motions<F> {
    fn stepped(&mut self, at: f64, stepper: &mut Stepper<'_>) {
        (self.0)(at, stepper.motion_now());
    }
    fn motion(&mut self, at: f64, motion: &Motion) {
        (self.0)(at, motion);
    }
}

/// Hands each sample to a callback as flat arrays (a motion held back
/// through arrays of its own).
pub(super) struct Flats<'m, F> {
    f: F,
    m: &'m Model,
    outputs: Vec<f64>,
}

impl<'m, F> Flats<'m, F> {
    pub(super) fn new(m: &'m Model, f: F) -> Self {
        Flats {
            f,
            m,
            outputs: Vec::new(),
        }
    }
}

impl<F: FnMut(f64, &Flat<'_>)> Sink for Flats<'_, F> {
    fn stepped(&mut self, at: f64, stepper: &mut Stepper<'_>) {
        (self.f)(at, &stepper.flat());
    }
    fn motion(&mut self, at: f64, motion: &Motion) {
        self.m.flatten_outputs(motion, &mut self.outputs);
        (self.f)(
            at,
            &Flat {
                q: &motion.q,
                qd: &motion.qd,
                qdd: &motion.qdd,
                outputs: &self.outputs,
                conditioning: motion.conditioning,
                det_sign: motion.det_sign,
                residual: motion.residual,
            },
        );
    }
}
