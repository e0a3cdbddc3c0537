//! The stepper of a run-time model: the options and parameters checked
//! once, and every array of a step kept from one step to the next, so
//! that a step allocates nothing.

use alloc::vec::Vec;

use super::fused::{PoseFn, StepFn};
use super::solve::{Arrays, Work};
use super::{Flat, Model, Motion};
use crate::closed::Mode;
use crate::error::Error;
use crate::math::copy_small;
use crate::options::{Branch, Options};
use crate::solve::{CLOSED, POLISH};

mod arrays;
mod motion;

/// Steps of one run-time model with its arrays kept: made by
/// [`Model::stepper`], which checks the options and the parameters once
/// (the model is borrowed, so they cannot change while it steps). Each
/// [`Stepper::step`] assembles at the drivers of its start and analyses
/// the motion there, as [`Model::step`] does, into a motion the stepper
/// owns: no allocation per step. Blocks with a closed form are solved in
/// the assembly modes of the first step's start, carried from step to
/// step ([`Stepper::modes`]); the other blocks by Newton–Raphson from the
/// start's unknowns.
///
/// ```
/// use kinematics_core::runtime::Model;
/// use kinematics_core::Options;
/// let mut m = Model::compile(
///     "struct SliderCrank {
///          params   { a, b }
///          drivers  { phi }
///          unknowns { th, x }
///          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
///      }",
/// )?;
/// m.set_values(&[0.1, 0.3])?;
/// let mut stepper = m.stepper(&Options::DEFAULT)?;
/// let mut q = vec![0.0, 0.0, 0.4];
/// for k in 1..=360 {
///     q[0] = f64::from(k).to_radians();
///     let s = stepper.step(&q, &[10.0], &[0.0])?;
///     // x = a cos φ + √(b² − a² sin² φ)
///     let x = 0.1 * q[0].cos() + (0.09 - 0.01 * q[0].sin().powi(2)).sqrt();
///     assert!((s.q[2] - x).abs() < 1e-14);
///     q.copy_from_slice(&s.q);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Stepper<'m> {
    m: &'m Model,
    options: Options,
    work: super::solve::Pooled<'m>,
    motion: Motion,
    pub(super) q: Vec<f64>,
    /// The assembly modes followed (NaN: from the next start).
    pub(super) modes: Vec<f64>,
    /// Whether the last step or pose assembled: then the work holds the
    /// cosines and sines of `q`, as the assembly left them.
    assembled: bool,
    /// The fused step's buffer and factors, where the model has one.
    pub(super) fused: Option<FusedRun<'m>>,
    /// Whether the last step was fused and its motion is still in the
    /// buffer only (written into `motion` when asked for).
    pending: bool,
    /// Whether the last step was [`Stepper::advance_motion`]'s, whose
    /// points' outputs are not evaluated until [`Stepper::complete`].
    stale: bool,
}

/// What a stepper keeps for the fused step: the model's plan and its step
/// and pose functions, looked up once; its buffer (with the values
/// carried from step to step), the steps taken (the carried cosines and
/// sines are refreshed every 16 steps for the drivers and every 64 for
/// the unknowns, as a generated stepper does), whether the buffer holds a
/// scaling that every pose shares, and whether it holds the points'
/// positions at the stepper's pose.
pub(super) struct FusedRun<'m> {
    plan: &'m super::fused::Plan,
    /// The step and pose functions of the plan's code.
    step: StepFn<'m>,
    pose: PoseFn<'m>,
    /// The step with the equations of motion after it (without the
    /// points' outputs) and the outputs alone, once a forward simulation
    /// asked for them ([`Stepper::with_motion`]).
    dynamics: Option<(StepFn<'m>, StepFn<'m>)>,
    pub(super) f: Vec<f64>,
    pub(super) steps: u32,
    pub(super) scaled: bool,
    pub(super) positions: bool,
    /// Whether the buffer holds the equations of motion at the last
    /// step's motion.
    motion: bool,
    io: Io,
}

impl FusedRun<'_> {
    /// Writes the motion of the last fused step into `out`.
    #[inline(always)]
    fn write_motion(&self, m: &Model, out: &mut Motion) {
        let flat = self.flat();
        copy_small(&mut out.q, flat.q);
        copy_small(&mut out.qd, flat.qd);
        copy_small(&mut out.qdd, flat.qdd);
        m.write_outputs(flat.outputs, out);
        out.conditioning = flat.conditioning;
        out.det_sign = flat.det_sign;
        out.residual = flat.residual;
    }

    /// The motion of the last fused step, in the buffer.
    #[inline(always)]
    fn flat(&self) -> Flat<'_> {
        let at = &self.io.flat;
        let f = &self.f[..];
        Flat {
            q: &f[at.q..at.qd],
            qd: &f[at.qd..at.qdd],
            qdd: &f[at.qdd..at.end],
            outputs: &f[at.out..at.out_end],
            conditioning: f[at.conditioning],
            det_sign: f[at.conditioning + 1],
            residual: f[at.residual],
        }
    }
}

/// Where the arrays and values of a [`Flat`] lie in the fused buffer:
/// q, q' and q'' one after another (`q..qd`, `qd..qdd`, `qdd..end`), the
/// outputs (`out..out_end`), the conditioning followed by the sign, and
/// the residual; every range within the buffer (checked when the stepper
/// is made).
#[derive(Clone, Copy)]
pub(super) struct FlatAt {
    pub(super) q: usize,
    pub(super) qd: usize,
    pub(super) qdd: usize,
    end: usize,
    pub(super) out: usize,
    out_end: usize,
    pub(super) conditioning: usize,
    residual: usize,
}

/// What a step checks its inputs against and where its results lie in
/// the fused buffer (from the plan's layout, read once per stepper).
#[derive(Clone, Copy)]
struct Io {
    /// The coordinates and the drivers.
    n: usize,
    nd: usize,
    /// Where a [`Flat`] reads the results.
    flat: FlatAt,
}

impl core::fmt::Debug for Stepper<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Stepper")
            .field("model", &self.m.name)
            .field("options", &self.options)
            .finish_non_exhaustive()
    }
}

impl Model {
    /// A stepper with `options`, which keeps its arrays from step to step.
    ///
    /// # Errors
    /// Invalid options, or parameters not set or invalid.
    pub fn stepper(&self, options: &Options) -> Result<Stepper<'_>, Error> {
        options.validate()?;
        self.validate()?;
        let mut work = self.work();
        work.closing = true;
        let mut kept = self.spare.arrays();
        let buffer = core::mem::take(&mut kept.f);
        let fused = self.fused.as_deref().and_then(|plan| {
            let (step, pose) = plan.functions()?;
            let mut f = buffer;
            plan.buffer_into(&mut f, &work.params);
            if !plan.prepare(&mut f) {
                return None;
            }
            let limit = options.tolerance.min(1e-12);
            let bound = (POLISH * options.tolerance).max(CLOSED).min(limit);
            let branch = match options.branch {
                Branch::Any => 0.0,
                Branch::Positive => 1.0,
                Branch::Negative => -1.0,
            };
            plan.set_options(&mut f, bound, options.singularity_threshold, branch);
            let at = plan.layout();
            let (modes, k) = plan.modes_at();
            let (out, outputs) = plan.outputs_at();
            let n = self.coordinates.len();
            let [c, s, r] = plan.results_at();
            let flat = FlatAt {
                q: at.q,
                qd: at.q + n,
                qdd: at.q + 2 * n,
                end: at.q + 3 * n,
                out,
                out_end: out + outputs,
                conditioning: c,
                residual: r,
            };
            // q, q' and q'' lie one after another, as do the conditioning
            // and the sign, and the outputs after them; every region lies
            // in the buffer (the steps rely on it).
            if at.qd != at.q + n
                || at.qdd != at.qd + n
                || s != c + 1
                || out < flat.end
                || [flat.end, modes + k, flat.out_end, c + 2]
                    .iter()
                    .any(|&e| e > f.len())
                || [c, s, r].iter().any(|&i| i >= f.len())
            {
                return None;
            }
            let io = Io {
                n,
                nd: self.drivers,
                flat,
            };
            Some(FusedRun {
                plan,
                step,
                pose,
                dynamics: None,
                f,
                steps: 0,
                scaled: false,
                positions: false,
                motion: false,
                io,
            })
        });
        let Arrays {
            mut motion,
            mut q,
            mut modes,
            ..
        } = kept;
        self.shape_motion(&mut motion);
        q.clear();
        q.resize(self.coordinates.len(), 0.0);
        modes.clear();
        modes.resize(self.mode_count(), f64::NAN);
        Ok(Stepper {
            m: self,
            options: *options,
            work,
            motion,
            q,
            modes,
            assembled: false,
            fused,
            pending: false,
            stale: false,
        })
    }
}

impl Stepper<'_> {
    /// The modes followed, as signs (NaN: from the next start), for the
    /// sweeps, which choose them past a change point.
    pub(super) fn signs_mut(&mut self) -> &mut [f64] {
        &mut self.modes
    }

    /// Whether the steps and poses take the model's fused machine code:
    /// one function that assembles block by block in closed form and
    /// analyses the motion (compiled at the first stepper of the model),
    /// where the model's every block has a closed form of at most four
    /// unknowns. A step off its common path (past a limit position, at a
    /// singular pose, a value not finite) takes the general path either
    /// way, with the same results to round-off.
    #[must_use]
    pub fn is_fused(&self) -> bool {
        self.fused.is_some()
    }

    /// The assembly modes the steps follow, one per block with two
    /// closed-form solutions (see [`Model::blocks`]): those of the first
    /// step's start until [`Stepper::set_modes`]; `None` before the first
    /// step.
    #[must_use]
    pub fn modes(&self) -> Option<Vec<Mode>> {
        (!self.modes.iter().any(|m| m.is_nan()))
            .then(|| self.modes.iter().map(|&s| Mode::from_sign(s)).collect())
    }

    /// Follows the assembly modes `modes` from the next step on.
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless there is one mode per block with
    /// two ([`Model::mode_count`]).
    pub fn set_modes(&mut self, modes: &[Mode]) -> Result<(), Error> {
        self.m.length("modes", self.modes.len(), modes.len())?;
        for (s, m) in self.modes.iter_mut().zip(modes) {
            *s = m.sign();
        }
        Ok(())
    }

    /// Assembles at the drivers of `start` from its unknowns and analyses
    /// the motion there with the drivers' `rates` and `accelerations`: the
    /// same numbers as [`Model::step`]. The motion is the stepper's, until
    /// the next step.
    ///
    /// # Errors
    /// As [`Model::step`], but for the options and the parameters, which
    /// [`Model::stepper`] checked.
    #[inline]
    pub fn step(
        &mut self,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<&Motion, Error> {
        self.forget();
        if self.fused_step(start, rates, accelerations) {
            // The buffer keeps the motion too (for `flat`).
            self.pending = true;
            if let Some(run) = self.fused.as_ref() {
                run.write_motion(self.m, &mut self.motion);
            }
        } else {
            self.general_step(start, rates, accelerations)?;
        }
        Ok(&self.motion)
    }

    /// [`Stepper::step`] with the motion as flat arrays borrowed from the
    /// stepper ([`Flat`]: q, q', q'', then every point's position,
    /// velocity and acceleration and every frame's 24 values), without
    /// copying them into a [`Motion`]: the same numbers, for a loop that
    /// reads a few of them or copies them into arrays of its own.
    ///
    /// ```
    /// use kinematics_core::runtime::Model;
    /// use kinematics_core::Options;
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
    /// let mut stepper = m.stepper(&Options::DEFAULT)?;
    /// let mut q = vec![0.0, 0.0, 0.4];
    /// let omega = 10.0;
    /// for k in 1..=360 {
    ///     q[0] = f64::from(k).to_radians();
    ///     let s = stepper.step_flat(&q, &[omega], &[0.0])?;
    ///     // The slider C: the second point, after B's six values
    ///     // (position, velocity, acceleration of a planar point).
    ///     let c = &s.outputs[6..12];
    ///     let (sin, cos) = q[0].sin_cos();
    ///     let root = (0.09 - 0.01 * sin * sin).sqrt();
    ///     // x = a cos φ + √(b² − a² sin² φ), ẋ = −a ω sin φ (1 + a cos φ / √…).
    ///     assert!((c[0] - (0.1 * cos + root)).abs() < 1e-14);
    ///     let xd = -0.1 * omega * sin * (1.0 + 0.1 * cos / root);
    ///     assert!((c[2] - xd).abs() < 1e-12);
    ///     q.copy_from_slice(s.q);
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`Stepper::step`].
    #[inline]
    pub fn step_flat(
        &mut self,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<Flat<'_>, Error> {
        self.forget();
        if self.fused_step(start, rates, accelerations) {
            self.pending = true;
        } else {
            self.general_step(start, rates, accelerations)?;
        }
        Ok(match (self.pending, self.fused.as_ref()) {
            (true, Some(run)) => run.flat(),
            _ => self.general_flat(),
        })
    }

    /// [`Stepper::step`] without writing the fused step's results into
    /// the stepper's motion ([`Stepper::motion_now`] and
    /// [`Stepper::flat`] read them).
    #[inline]
    pub(super) fn advance(
        &mut self,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<(), Error> {
        self.advance_with(start, rates, accelerations, false)
    }

    /// [`Stepper::advance`], through the step with the equations of motion
    /// where `equations` ([`Stepper::advance_motion`]).
    #[inline(always)]
    fn advance_with(
        &mut self,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
        equations: bool,
    ) -> Result<(), Error> {
        self.forget();
        // The fused step checks the inputs as it copies them into its
        // buffer (lengths, every value finite) and leaves the errors to
        // the general path's checks.
        if self.fused_go(start, Some((rates, accelerations)), equations) {
            self.pending = true;
            return Ok(());
        }
        self.general_step(start, rates, accelerations)
    }

    /// The step by the library's general code: the inputs checked, the
    /// assembly block by block, the analysis into the stepper's motion.
    #[inline(never)]
    fn general_step(
        &mut self,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<(), Error> {
        let m = self.m;
        m.check_inputs(start, rates, accelerations)?;
        self.assemble(start)?;
        m.analyze_into(
            &self.q,
            rates,
            accelerations,
            &mut self.work,
            &self.options,
            true,
            &mut self.motion,
        )
    }

    /// The motion of the last step, written from the fused buffer if it
    /// is still there only.
    #[inline]
    pub(super) fn motion_now(&mut self) -> &Motion {
        debug_assert!(
            !self.stale,
            "a motion read before `complete` evaluated its points"
        );
        if self.pending {
            self.pending = false;
            if let Some(run) = self.fused.as_ref() {
                run.write_motion(self.m, &mut self.motion);
            }
        }
        &self.motion
    }

    /// The motion of the last step as flat arrays, from the fused buffer
    /// or from the general path's arrays (after
    /// [`Stepper::advance_motion`], the points' outputs only once
    /// [`Stepper::complete`] evaluated them).
    #[inline]
    pub(super) fn flat(&self) -> Flat<'_> {
        if let (true, Some(run)) = (self.pending, self.fused.as_ref()) {
            return run.flat();
        }
        self.general_flat()
    }

    /// The cosines and sines of the last step's pose where it was fused
    /// ([`super::fused::Plan::trig_of`]: cos q_j and sin q_j at 2j and
    /// 2j + 1, and which coordinates' the step wrote); `None` after a
    /// general step.
    #[inline]
    pub(super) fn fused_trig(&self) -> Option<(&[f64], &[bool])> {
        match (self.pending, self.fused.as_ref()) {
            (true, Some(run)) => Some(run.plan.trig_of(&run.f)),
            _ => None,
        }
    }

    /// The conditioning of Φ_u and the sign of its determinant at the
    /// last step: what the sweep judges every sample by, read without
    /// the rest of [`Stepper::flat`].
    #[inline(always)]
    pub(super) fn judged(&self) -> (f64, f64) {
        if let (true, Some(run)) = (self.pending, self.fused.as_ref()) {
            let at = &run.io.flat;
            if let Some(&[c, s]) = run.f.get(at.conditioning..at.conditioning + 2) {
                return (c, s);
            }
        }
        (self.motion.conditioning, self.motion.det_sign)
    }

    /// The fused buffer and where the last step's results lie in it,
    /// while they are there only (else `None`: read [`Stepper::flat`]).
    #[inline(always)]
    pub(super) fn fused_results(&self) -> Option<(&[f64], &FlatAt)> {
        debug_assert!(!self.stale, "outputs read before `complete` evaluated them");
        match (self.pending, self.fused.as_ref()) {
            (true, Some(run)) => Some((&run.f, &run.io.flat)),
            _ => None,
        }
    }

    /// q and q' of the last step, as [`Stepper::flat`] gives them.
    #[inline(always)]
    pub(super) fn pose_rates(&self) -> (&[f64], &[f64]) {
        if let (true, Some(run)) = (self.pending, self.fused.as_ref()) {
            let at = &run.io.flat;
            if let Some(both) = run.f.get(at.q..at.qdd)
                && let Some(split) = both.split_at_checked(at.qd - at.q)
            {
                return split;
            }
        }
        (&self.motion.q, &self.motion.qd)
    }

    /// The motion of the last step of the general path as flat arrays.
    fn general_flat(&self) -> Flat<'_> {
        let m = &self.motion;
        Flat {
            q: &m.q,
            qd: &m.qd,
            qdd: &m.qdd,
            outputs: self.work.outputs(),
            conditioning: m.conditioning,
            det_sign: m.det_sign,
            residual: m.residual,
        }
    }

    /// Assembles at the drivers of `start` from its unknowns, as
    /// [`Stepper::step`] does, without the analysis: the pose (drivers
    /// first), the stepper's until the next step. Cheaper than a step: no
    /// factorisation of Φ_u, so no judgement of its conditioning (a pose
    /// at a singular position is returned as any other, unless a
    /// Newton–Raphson step towards it meets a pivot of the scaled Φ_u at
    /// or below the singularity threshold; a sweep of poses stops only
    /// where the mechanism does not assemble).
    ///
    /// # Errors
    /// As [`Model::assemble`], but for the options and the parameters,
    /// which [`Model::stepper`] checked; [`Error::Singular`] only from such
    /// a Newton–Raphson step.
    pub fn pose(&mut self, start: &[f64]) -> Result<&[f64], Error> {
        self.forget();
        // The fused code checks the pose's length and values itself, and
        // leaves a wrong one to the general path, which says what it is.
        if !self.fused_pose(start) {
            self.m.check_pose(start)?;
            self.assemble(start)?;
        }
        Ok(&self.q)
    }

    /// The pose of the last [`Stepper::pose`] or step, drivers first.
    #[inline]
    pub(super) fn pose_now(&self) -> &[f64] {
        if let (true, Some(run)) = (self.pending, self.fused.as_ref()) {
            return run.flat().q;
        }
        &self.q
    }

    /// The positions of every point at the last pose of
    /// [`Stepper::pose`] or [`Stepper::step`], into `out`
    /// ([`Model::point_dimension`] components per point, in declaration
    /// order).
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `out` has room for every point;
    /// [`Error::NonFinite`] when a position is not finite.
    pub fn positions(&mut self, out: &mut [f64]) -> Result<(), Error> {
        let m = self.m;
        let d = m.point_dim;
        m.length("point positions", m.points.len() * d, out.len())?;
        if let Some(fused) = self.fused_positions() {
            copy_small(out, fused);
            return Ok(());
        }
        m.positions_into(&self.q, &mut self.work, !self.assembled, out)
    }

    /// The positions of every point at the last pose, as
    /// [`Stepper::positions`] writes them, where the fused code left them
    /// in its buffer (read in place); `None` otherwise.
    #[inline]
    pub(super) fn fused_positions(&self) -> Option<&[f64]> {
        match (self.fused.as_ref(), self.m.fused.as_deref()) {
            (Some(run), Some(plan)) if run.positions => {
                let (at, len) = plan.positions_at();
                (len == self.m.points.len() * self.m.point_dim)
                    .then(|| run.f.get(at..at + len))
                    .flatten()
            }
            _ => None,
        }
    }

    /// The step through the model's fused code: `true` when it took the
    /// step, the motion and pose written; `false` when the model has
    /// none, an input has the wrong length or a value not finite (which
    /// the general path reports), or the step left its common path, the
    /// stepper's state (its modes) then as before.
    #[inline(always)]
    fn fused_step(&mut self, start: &[f64], rates: &[f64], accelerations: &[f64]) -> bool {
        self.fused_go(start, Some((rates, accelerations)), false)
    }

    /// The assembly through the model's fused code, with the points'
    /// positions (as [`Stepper::fused_step`]; a bad `start` is refused).
    #[inline]
    fn fused_pose(&mut self, start: &[f64]) -> bool {
        self.fused_go(start, None, false)
    }

    /// Runs the fused step on `start` (and for a step the drivers' rates
    /// and accelerations) in the stepper's modes, refreshing the carried
    /// values when due; without rates, the pose, which also writes the
    /// points' positions. The machine code copies the inputs into its
    /// buffer and checks them, and writes the pose and the modes into the
    /// stepper's once it has succeeded. `true` when it succeeded; `false`
    /// without fused code, for an input of the wrong length or a value
    /// not finite, or when the step left its common path (the pose and
    /// modes then as before).
    #[inline(always)]
    fn fused_go(
        &mut self,
        start: &[f64],
        motion: Option<(&[f64], &[f64])>,
        equations: bool,
    ) -> bool {
        let Some(run) = self.fused.as_mut() else {
            return false;
        };
        let io = run.io;
        if start.len() != io.n {
            return false;
        }
        if !run.scaled {
            rescale(self.m, run, start, &mut self.work, &self.options);
        }
        run.steps = run.steps.wrapping_add(1);
        if run.steps % 16 == 0 {
            run.plan.refresh(&mut run.f, run.steps % 64 == 0);
        }
        let status = match motion {
            Some((rates, accelerations)) => {
                if rates.len() != io.nd || accelerations.len() != io.nd {
                    return false;
                }
                let step = match (&run.dynamics, equations) {
                    (Some((dynamics, _)), true) => dynamics,
                    _ => &run.step,
                };
                run.plan.step(
                    step,
                    &mut run.f,
                    [start, rates, accelerations],
                    &mut self.modes,
                    &mut self.q,
                )
            }
            None => run
                .plan
                .pose(&run.pose, &mut run.f, start, &mut self.modes, &mut self.q),
        };
        if status != 0 {
            return false;
        }
        let (positions, motion) = (
            motion.is_none(),
            motion.is_some() && equations && run.dynamics.is_some(),
        );
        self.fused_done(positions, motion);
        true
    }

    /// Forgets what the last step or pose left (until this one succeeds).
    fn forget(&mut self) {
        self.assembled = false;
        self.pending = false;
        self.stale = false;
        if let Some(run) = self.fused.as_mut() {
            run.positions = false;
            run.motion = false;
        }
    }

    /// Assembles `start` (already checked) into the stepper's pose, in its
    /// modes; records whether it assembled.
    fn assemble(&mut self, start: &[f64]) -> Result<(), Error> {
        self.q.copy_from_slice(start);
        self.m.assemble_into(
            &mut self.q,
            &mut self.work,
            &mut self.modes,
            &self.options,
            false,
        )?;
        self.assembled = true;
        Ok(())
    }
}

/// Writes the scaling of `start` into the fused buffer (once for a
/// model whose scaling every pose shares; at every step otherwise).
#[cold]
fn rescale(m: &Model, run: &mut FusedRun<'_>, start: &[f64], work: &mut Work, options: &Options) {
    let length = m.scaling(start, work, options);
    run.plan
        .set_scaling(&mut run.f, length, &work.rows, &work.weights);
    run.scaled = m.fixed_scaling;
}

#[cfg(test)]
impl Stepper<'_> {
    /// Whether the fused code took `start`, its bound (and branch: any) set.
    pub(super) fn fused_pose_within(&mut self, start: &[f64], bound: Option<f64>) -> bool {
        if let (Some(run), Some(bound)) = (self.fused.as_mut(), bound) {
            let threshold = self.options.singularity_threshold;
            run.plan.set_options(&mut run.f, bound, threshold, 0.0);
        }
        self.fused_pose(start)
    }
}
