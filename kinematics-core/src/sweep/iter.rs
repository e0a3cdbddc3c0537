//! The stepping iterator behind every sweep and simulation: the grid
//! walked sample by sample, each pose predicted from the last ones and
//! solved, the common path kept to one comparison per sample.

use alloc::collections::VecDeque;
use alloc::vec::Vec;
use core::fmt;

use super::drive::{Drive, Grid};
use super::engine::Engine;
use super::handles::{ChangePoints, Wrap};
use super::sample::{Sample, Solved, Stop, StopReason};
use crate::error::Error;
use crate::mechanism::Kind;
use crate::options::Options;

/// A branch tried past a change point: its distance from the extrapolated
/// pose, its sample and its step state.
pub(super) type Candidate<E, S> = (f64, S, <E as Engine>::State);

/// What the sweep keeps of an accepted sample: for the predictor, the
/// change-point tests and the extrapolation past a change point.
#[derive(Clone)]
pub(super) struct Head<C> {
    /// NaN when the entry holds no sample.
    pub(super) at: f64,
    pub(super) q: C,
    qd: C,
    pub(super) conditioning: f64,
    pub(super) det_sign: f64,
}

impl<C: Clone> Head<C> {
    /// An entry holding no sample, its poses `q` and `qd` (to be written
    /// over).
    fn empty(q: C, qd: C) -> Self {
        Self {
            at: f64::NAN,
            q,
            qd,
            conditioning: f64::NAN,
            det_sign: f64::NAN,
        }
    }

    /// Empties the entry (its poses kept, to be written over).
    pub(super) fn clear(&mut self) {
        self.at = f64::NAN;
        self.conditioning = f64::NAN;
        self.det_sign = f64::NAN;
    }
}

/// A sweep or simulation in progress: an iterator over its samples (each
/// `Ok`), ending with the stop (an `Err`) if it stops early. Made by
/// iterating a [`SweepBuilder`](super::SweepBuilder) or a [`Simulation`](super::Simulation); allocates nothing per
/// sample.
///
/// It is the one sweep driver: generated mechanisms and run-time models
/// (`runtime::Model::sweep`, which reads its samples from its stepper) go
/// through it, so that both predict, bisect limit positions, test for
/// change points and choose the branch past one by the same code.
///
/// A sample that may lie past a change point (Φ_u's conditioning falling
/// fast towards zero) is held back until the next one is solved, so that a
/// sample on the wrong side of a change point is never handed out.
pub struct SweepIter<'m, M: Engine, D, S = Sample<M>> {
    pub(super) m: &'m M,
    pub(super) drive: D,
    pub(super) options: Options,
    pub(super) grid: Grid,
    /// 1 / the rate of the sweep variable (0 when it is 0), for the
    /// predictor.
    per_rate: f64,
    wrap: Wrap,
    pub(super) change_points: ChangePoints,
    pub(super) variable: &'static str,
    pub(super) state: Option<M::State>,
    /// The next grid index to solve.
    pub(super) k: usize,
    /// The drivers' rates and accelerations (their entries only).
    pub(super) rates: M::Pose,
    pub(super) accels: M::Pose,
    /// The guess of the next sample (its drivers set by the drive).
    guess: M::Pose,
    /// The last accepted samples, a ring: `history[newest]` the newest,
    /// the one before it at `newest − 1` (mod 4), and so on; an entry
    /// whose value `at` is NaN holds none (before the first sample, and
    /// after a change point).
    pub(super) history: [Head<M::Pose>; 4],
    pub(super) newest: usize,
    /// Whether the conditioning falls so fast at the newest sample that it
    /// could reach zero before the next: the line through it and the one
    /// before meets zero less than two steps on (and it is below 0.5,
    /// where a regular pose is of order one).
    pub(super) falling: bool,
    /// The sign of det Φ_u at the newest sample when the next sample may
    /// be handed out as soon as it keeps that sign (no sample held back,
    /// the conditioning not falling fast); 0 when the slow path decides.
    gate: f64,
    /// The newest sample, when it is held back.
    pub(super) held: Option<S>,
    /// Items ready to hand out before anything else.
    pub(super) out: VecDeque<Result<S, Stop>>,
    /// The change points passed.
    pub(super) passed: Vec<f64>,
    pub(super) done: bool,
    /// The grid indices below which the next sample is solved on the
    /// fast path: 0 while items wait in `out` or the sweep is done, the
    /// grid's [`Grid::inner_end`] otherwise.
    open: usize,
}

impl<M: Engine, D, S> Drop for SweepIter<'_, M, D, S> {
    /// Gives the poses' storage back to the engine, for its next sweep.
    fn drop(&mut self) {
        let [a, b, c, d] = &mut self.history;
        self.m.recycle(&mut [
            &mut self.rates,
            &mut self.accels,
            &mut self.guess,
            &mut a.q,
            &mut a.qd,
            &mut b.q,
            &mut b.qd,
            &mut c.q,
            &mut c.qd,
            &mut d.q,
            &mut d.qd,
        ]);
    }
}

impl<M: Engine, D: fmt::Debug, S> fmt::Debug for SweepIter<'_, M, D, S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SweepIter")
            .field("variable", &self.variable)
            .field("next", &self.k)
            .field("of", &self.grid.count)
            .field("drive", &self.drive)
            .finish_non_exhaustive()
    }
}

impl<'m, M: Engine, D: Drive<M>, S: Solved<M>> SweepIter<'m, M, D, S> {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        m: &'m M,
        start: &M::Pose,
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
            rates: m.zero_pose(),
            accels: m.zero_pose(),
            guess: m.zero_pose(),
            history: core::array::from_fn(|_| Head::empty(m.zero_pose(), m.zero_pose())),
            newest: 0,
            falling: false,
            gate: 0.0,
            held: None,
            out: VecDeque::new(),
            passed: Vec::new(),
            done: false,
            open: 0,
        };
        it.drive.start(&mut it.rates, &mut it.accels);
        let checked = grid.and_then(|g| Ok((g, m.state(options)?)));
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

    /// The state the newest step was taken with (for a run-time model,
    /// its stepper, which holds the sample just handed out).
    #[cfg(feature = "runtime")]
    pub(crate) fn state_mut(&mut self) -> Option<&mut M::State> {
        self.state.as_mut()
    }

    /// The change points passed so far.
    #[must_use]
    pub fn change_points(&self) -> &[f64] {
        &self.passed
    }

    pub(super) fn finish(&mut self, at: f64, reason: StopReason) {
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
    pub(super) fn solve(
        &mut self,
        k: usize,
        guess: &M::Pose,
        state: &mut M::State,
    ) -> Result<S, Error> {
        let at = self.grid.at(k);
        let mut pose = guess.clone();
        self.drive
            .drive(at, &mut pose, &mut self.rates, &mut self.accels);
        S::solve(self.m, at, &pose, &self.rates, &self.accels, state)
    }

    /// The first sample, from `start`: handed out as it is.
    fn first(&mut self, start: &M::Pose) {
        let Some(mut state) = self.state.take() else {
            return;
        };
        let solved = self.solve(0, start, &mut state);
        self.state = Some(state);
        match solved {
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
    }

    /// The newest accepted sample.
    #[inline(always)]
    pub(super) fn head(&self) -> Option<&Head<M::Pose>> {
        self.back(0)
    }

    /// The accepted sample `n` (at most 2) before the newest (0: the
    /// newest).
    #[inline(always)]
    pub(super) fn back(&self, n: usize) -> Option<&Head<M::Pose>> {
        debug_assert!(n <= 2, "the sweep keeps three samples");
        let h = &self.history[self.newest.wrapping_sub(n) & 3];
        (!h.at.is_nan()).then_some(h)
    }

    /// Makes `s` the newest accepted sample.
    #[inline(always)]
    pub(super) fn push_head(&mut self, s: &S) {
        // NaN with no sample before (then the test is false).
        let previous = self.history[self.newest & 3].conditioning;
        let conditioning = s.conditioning();
        let det_sign = s.det_sign();
        self.falling = conditioning < 0.5 && 1.5 * conditioning < previous;
        self.gate = if self.falling { 0.0 } else { det_sign };
        self.newest = (self.newest + 1) & 3;
        let h = &mut self.history[self.newest];
        h.at = s.at();
        // The rates only where the predictor uses them.
        let qd = (S::RATES && self.m.newton_guess()).then_some(&mut h.qd);
        if !s.record(self.state.as_ref(), &mut h.q, qd) {
            h.at = f64::NAN;
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
    pub(super) fn forget(&mut self) {
        for h in &mut self.history {
            h.clear();
        }
        self.falling = false;
    }

    /// Sets `guess` to the guess at `at` ([`predict`]).
    #[inline(always)]
    fn predict(&self, at: f64, guess: &mut M::Pose) {
        let h = &self.history[self.newest & 3];
        let before = &self.history[self.newest.wrapping_sub(1) & 3];
        predict::<M, S>(self.m, (h, before), (at, self.per_rate), guess);
    }

    /// A sample as handed out: its angles wrapped as asked.
    #[inline(always)]
    pub(super) fn wrapped(&self, mut s: S) -> S {
        self.wrap_angles(&mut s);
        s
    }

    /// Wraps the angles of `s` as asked.
    #[inline(always)]
    fn wrap_angles(&self, s: &mut S) {
        if self.wrap != Wrap::Continuous {
            let Some(q) = s.q_mut() else {
                return;
            };
            for (j, c) in self.m.coordinates().iter().enumerate() {
                if c.kind == Kind::Angle {
                    let v = M::get(q, j);
                    M::set(q, j, self.wrap.apply(v));
                }
            }
        }
    }

    /// Queues the held sample to be handed out.
    pub(super) fn release(&mut self) {
        if let Some(s) = self.held.take() {
            let s = self.wrapped(s);
            self.out.push_back(Ok(s));
        }
    }

    /// Solves grid sample `k` = `self.k`, of value `at`: the sample to hand
    /// out, if one is ready.
    #[inline(always)]
    fn advance(&mut self, k: usize, at: f64) -> Option<Result<S, Stop>> {
        self.advance_to(k, at, |s| s).map(Ok)
    }

    /// [`Self::advance`], with the sample of the common path recorded as
    /// the newest, its angles wrapped, and handed to `place`, which puts
    /// it where it is kept (returned, or pushed onto a vector).
    #[inline(always)]
    fn advance_to<R>(&mut self, k: usize, at: f64, place: impl FnOnce(S) -> R) -> Option<R> {
        // The guess a local of the step (kept in registers where a pose
        // is a few values), its storage lent by `self.guess`.
        let mut guess = M::lend(&mut self.guess);
        self.prepare(at, &mut guess);
        let Some(state) = self.state.as_mut() else {
            M::give_back(&mut self.guess, guess);
            return None;
        };
        let step = S::step(self.m, &guess, &self.rates, &self.accels, state);
        M::give_back(&mut self.guess, guess);
        self.conclude(k, at, step, place)
    }

    /// The guess of the sample at `at` (predicted from the last ones) and
    /// the drivers' values, rates and accelerations there (the drive's).
    #[inline(always)]
    fn prepare(&mut self, at: f64, guess: &mut M::Pose) {
        self.predict(at, guess);
        self.drive
            .drive(at, guess, &mut self.rates, &mut self.accels);
    }

    /// Takes the outcome `step` of grid sample `k`, of value `at`: a
    /// sample of the common path recorded as the newest, its angles
    /// wrapped, and handed to `place`; otherwise left to the slow path.
    #[inline(always)]
    fn conclude<R>(
        &mut self,
        k: usize,
        at: f64,
        step: Result<S::Step, Error>,
        place: impl FnOnce(S) -> R,
    ) -> Option<R> {
        match step {
            // The common case, handed out at once: det Φ_u keeps its sign,
            // the conditioning was not falling so fast that it could reach
            // zero before this sample, and nothing is held back (`gate`).
            Ok(step) if self.passes(S::step_det_sign(&step)) => {
                self.k += 1;
                let mut s = S::sample(at, step);
                self.push_head(&s);
                self.wrap_angles(&mut s);
                Some(place(s))
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

    /// Whether a step whose det Φ_u has the sign `det_sign` is a sample of
    /// the common path, handed out at once: it keeps the newest sample's
    /// sign, that sample's conditioning was not falling fast, and nothing
    /// is held back.
    #[inline(always)]
    pub(crate) fn passes(&self, det_sign: f64) -> bool {
        self.gate * det_sign > 0.0
    }

    /// Pushes onto `out` the samples of the common path, solved one after
    /// the other, until the first that is not (a change point, a failure,
    /// the end), which is left to [`Iterator::next`]: the collected sweep's
    /// loop, each sample written once, where it is kept.
    #[inline(always)]
    pub(super) fn push_common(&mut self, out: &mut Vec<S>) {
        while self.k < self.open {
            let k = self.k;
            let at = self.grid.inner(k);
            if self.advance_to(k, at, |s| out.push(s)).is_none() {
                return;
            }
        }
    }
}

impl<M: Engine, D: Drive<M>, S: Solved<M>> SweepIter<'_, M, D, S> {
    /// The next sample's grid index and value where it is solved on the
    /// common path (`None` where the slow path takes it: items wait, or
    /// the sweep is done or at its last value).
    #[cfg(feature = "runtime")]
    #[inline(always)]
    pub(crate) fn next_common(&self) -> Option<(usize, f64)> {
        (self.k < self.open).then(|| (self.k, self.grid.inner(self.k)))
    }

    /// The inputs of the step of the sample at `at` on the common path:
    /// the guess predicted from the last samples, with the drivers'
    /// values, rates and accelerations set by the drive. The step itself
    /// is taken elsewhere ([`Self::conclude_common`] takes its outcome,
    /// [`Self::step_prepared`] takes it here).
    #[cfg(feature = "runtime")]
    #[inline(always)]
    pub(crate) fn step_inputs(&mut self, at: f64) -> [&M::Pose; 3] {
        let mut guess = M::lend(&mut self.guess);
        self.prepare(at, &mut guess);
        M::give_back(&mut self.guess, guess);
        [&self.guess, &self.rates, &self.accels]
    }

    /// Takes the outcome of the step of sample `k` at `at` taken from
    /// [`Self::step_inputs`] elsewhere (the state holding it), as the
    /// sweep takes its own: the sample where it is on the common path,
    /// else `None` and the slow path has it ([`Iterator::next`]).
    #[cfg(feature = "runtime")]
    #[inline(always)]
    pub(crate) fn conclude_common(
        &mut self,
        k: usize,
        at: f64,
        step: Result<S::Step, Error>,
    ) -> Option<S> {
        self.conclude(k, at, step, |s| s)
    }

    /// Takes the step of sample `k` at `at` from [`Self::step_inputs`]
    /// with the sweep's state, then [`Self::conclude_common`].
    #[cfg(feature = "runtime")]
    #[inline(always)]
    pub(crate) fn step_prepared(&mut self, k: usize, at: f64) -> Option<S> {
        let state = self.state.as_mut()?;
        let step = S::step(self.m, &self.guess, &self.rates, &self.accels, state);
        self.conclude(k, at, step, |s| s)
    }

    /// Hands `f` the samples of the common path with the state that
    /// solved them, one after the other, until the first that is not (a
    /// change point, a failure, the end), which is left to
    /// [`Iterator::next`], or until `f` returns `false`: a streamed
    /// sweep's loop without an item made per sample.
    #[cfg(feature = "runtime")]
    #[inline(always)]
    pub(crate) fn each_common(&mut self, mut f: impl FnMut(S, &mut M::State) -> bool) {
        while self.k < self.open {
            let k = self.k;
            let at = self.grid.inner(k);
            let Some(s) = self.advance_to(k, at, |s| s) else {
                return;
            };
            if let Some(state) = self.state.as_mut()
                && !f(s, state)
            {
                return;
            }
        }
    }
}

impl<M: Engine, D: Drive<M>, S: Solved<M>> Iterator for SweepIter<'_, M, D, S> {
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

impl<M: Engine, D: Drive<M>, S: Solved<M>> SweepIter<'_, M, D, S> {
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

/// Writes into `guess` the guess at `at`, where Newton–Raphson starts
/// from it: the newest pose `h` advanced along its rates,
/// u + (du/dt)·Δt (Δt the change of the sweep variable times
/// `per_rate`), or without rates along the secant from the pose `before`
/// it; the newest pose where the guess only names the branch; zeros
/// before the first sample. (Its arguments apart, so that the guess is
/// known not to alias the history.)
#[inline(always)]
fn predict<M: Engine, S: Solved<M>>(
    m: &M,
    (h, before): (&Head<M::Pose>, &Head<M::Pose>),
    (at, per_rate): (f64, f64),
    guess: &mut M::Pose,
) {
    let n = m.coordinates().len();
    if h.at.is_nan() {
        for j in 0..n {
            M::set(guess, j, 0.0);
        }
        return;
    }
    M::copy_pose(guess, &h.q);
    if !m.newton_guess() {
        return;
    }
    let (rate, from) = if S::RATES {
        (&h.qd, None)
    } else {
        if before.at.is_nan() || before.at == h.at {
            return;
        }
        (&h.q, Some((before, 1.0 / (h.at - before.at))))
    };
    let dt = (at - h.at) * if S::RATES { per_rate } else { 1.0 };
    for j in m.drivers()..n {
        let (u, r) = (M::get(guess, j), M::get(rate, j));
        // The secant's slope (u − u_prev) / (at_h − at_prev).
        let slope = match from {
            Some((p, inv)) => (r - M::get(&p.q, j)) * inv,
            None => r,
        };
        M::set(guess, j, u + slope * dt);
    }
}
