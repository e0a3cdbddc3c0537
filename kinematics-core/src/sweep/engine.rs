//! What the one sweep driver ([`SweepIter`](super::SweepIter)) needs of a
//! model, so that generated mechanisms and run-time models are swept by
//! the same code: the prediction of the next pose, the limit-position
//! bisection, the change-point tests and the choice of branch past one
//! are written once, over this trait.
//!
//! Every generated mechanism is an [`Engine`] (a blanket implementation
//! over [`Mechanism`], its poses the coordinates struct, its state the
//! step state); a run-time model is one through the adapter in
//! `runtime`, its poses vectors and its state a stepper.

use core::fmt;

use crate::error::Error;
use crate::mechanism::{Coordinate, Coordinates, Mechanism};
use crate::options::Options;

/// A model the sweep driver can step: its coordinates, the poses it is
/// handed and hands back, the state carried from step to step (the
/// assembly modes of its closed forms, its caches), and a full assembly
/// for the bisection of a limit position.
///
/// A pose holds every coordinate, drivers first; the rates and
/// accelerations the driver passes have the same shape (only the
/// drivers' entries are read).
#[doc(hidden)]
pub trait Engine {
    /// A pose: every coordinate, drivers first.
    type Pose: Clone + fmt::Debug;
    /// What a step carries to the next.
    type State: fmt::Debug;
    /// The number of drivers.
    fn drivers(&self) -> usize;
    /// The coordinates, drivers first.
    fn coordinates(&self) -> &[Coordinate];
    /// Whether the unknowns of the guess are where Newton–Raphson starts
    /// (else every block is solved in closed form and the guess only names
    /// the assembly branch, so the previous pose serves).
    fn newton_guess(&self) -> bool;
    /// A pose of the right shape, every value 0.
    fn zero_pose(&self) -> Self::Pose;
    /// Takes back the storage of `poses` (the engine's own, which a sweep
    /// is done with) for its next [`Engine::zero_pose`]s; nothing where a
    /// pose is a few numbers on the stack.
    fn recycle(&self, poses: &mut [&mut Self::Pose]) {
        let _ = poses;
    }
    /// A pose to write a guess into, lent by `slot` (the sweep's storage
    /// for it): a fresh value where a pose is a few numbers on the stack,
    /// `slot`'s own storage where it is on the heap (then no allocation).
    /// Every entry is written before it is read.
    fn lend(slot: &mut Self::Pose) -> Self::Pose;
    /// Gives the storage of `pose` back to `slot` ([`Engine::lend`]).
    fn give_back(slot: &mut Self::Pose, pose: Self::Pose);
    /// `to` = `from` (poses of one engine: the same length).
    #[inline(always)]
    fn copy_pose(to: &mut Self::Pose, from: &Self::Pose) {
        to.clone_from(from);
    }
    /// Coordinate `j` of `pose` (NaN past the last).
    fn get(pose: &Self::Pose, j: usize) -> f64;
    /// Sets coordinate `j` of `pose` (nothing past the last).
    fn set(pose: &mut Self::Pose, j: usize, value: f64);
    /// A fresh state: the assembly modes unset (chosen from the next
    /// guess).
    ///
    /// # Errors
    /// Invalid options or parameters.
    fn state(&self, options: &Options) -> Result<Self::State, Error>;
    /// The assembly modes of the closed-form blocks with two (±1; NaN:
    /// from the next guess), to set.
    fn modes(state: &mut Self::State) -> &mut [f64];
    /// Whether the model assembles at the drivers of `guess` from its
    /// unknowns (a block in closed form with no real solution there is
    /// the one answer that counts as `false`): the test of the bisection
    /// of a limit position.
    fn assembles(&self, guess: &Self::Pose, options: &Options) -> bool;
}

impl<M: Mechanism> Engine for M {
    type Pose = M::Coords;
    type State = M::StepState;

    #[inline(always)]
    fn drivers(&self) -> usize {
        M::DRIVERS
    }

    #[inline(always)]
    fn coordinates(&self) -> &[Coordinate] {
        M::COORDINATES
    }

    #[inline(always)]
    fn newton_guess(&self) -> bool {
        M::NEWTON_GUESS
    }

    #[inline(always)]
    fn zero_pose(&self) -> M::Coords {
        M::Coords::default()
    }

    #[inline(always)]
    fn lend(_: &mut M::Coords) -> M::Coords {
        M::Coords::default()
    }

    #[inline(always)]
    fn give_back(_: &mut M::Coords, _: M::Coords) {}

    #[inline(always)]
    fn get(pose: &M::Coords, j: usize) -> f64 {
        pose.get(j).unwrap_or(f64::NAN)
    }

    #[inline(always)]
    fn set(pose: &mut M::Coords, j: usize, value: f64) {
        pose.set(j, value);
    }

    fn state(&self, options: &Options) -> Result<M::StepState, Error> {
        self.step_state(options)
    }

    fn modes(state: &mut M::StepState) -> &mut [f64] {
        M::step_modes(state)
    }

    fn assembles(&self, guess: &M::Coords, options: &Options) -> bool {
        !matches!(
            self.assemble_with(guess, options),
            Err(Error::CannotAssemble { .. })
        )
    }
}
