//! A stepper's steps with the equations of motion after them (for the
//! forward dynamics), and what a step taken elsewhere (in vector lanes,
//! by a batch) leaves in it.

use crate::error::Error;

use super::Stepper;

impl Stepper<'_> {
    /// Gives this stepper the model's step with the equations of motion
    /// after it ([`Stepper::advance_motion`]; [`Stepper::fused_motion`]
    /// reads them), compiling that code at the first call for the model;
    /// `false` where the model has no fused step or no such code. Its
    /// other steps are as before.
    pub(in crate::runtime) fn with_motion(&mut self) -> bool {
        let Some(run) = self.fused.as_mut() else {
            return false;
        };
        run.dynamics = run.plan.dynamics_function();
        run.dynamics.is_some()
    }

    /// [`Stepper::advance`] through the step with the equations of motion
    /// ([`Stepper::with_motion`]; the plain step without it): the motion
    /// of the coordinates and the equations' roots
    /// ([`Stepper::fused_motion`]), the points' outputs left until
    /// [`Stepper::complete`] (an evaluation of the forward dynamics reads
    /// none of them).
    #[inline]
    pub(in crate::runtime) fn advance_motion(
        &mut self,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<(), Error> {
        self.advance_with(start, rates, accelerations, true)
    }

    /// Evaluates the points' outputs that [`Stepper::advance_motion`] left
    /// out, so that [`Stepper::motion_now`] holds the whole motion: from
    /// the buffer that step left; where an output is not finite, the
    /// step again by the general path, which says why.
    ///
    /// # Errors
    /// The general path's, where it was taken.
    #[inline]
    pub(in crate::runtime) fn complete(&mut self) -> Result<(), Error> {
        if self.stale {
            self.evaluate_outputs()
        } else {
            Ok(())
        }
    }

    /// [`Stepper::complete`] where the outputs are left out.
    #[cold]
    #[inline(never)]
    fn evaluate_outputs(&mut self) -> Result<(), Error> {
        self.stale = false;
        let Some(run) = self.fused.as_mut() else {
            return Ok(());
        };
        let status = match &run.dynamics {
            Some((_, outputs)) => {
                run.plan
                    .step(outputs, &mut run.f, [&[], &[], &[]], &mut [], &mut [])
            }
            None => -1,
        };
        if status == 0 {
            // The motion, whether written already or not, from the buffer
            // again.
            self.pending = true;
            return Ok(());
        }
        let flat = run.flat();
        let nd = self.m.drivers();
        let (q, rates, accelerations) = (
            flat.q.to_vec(),
            flat.qd[..nd].to_vec(),
            flat.qdd[..nd].to_vec(),
        );
        self.forget();
        self.general_step(&q, &rates, &accelerations)
    }

    /// The roots of the equations of motion
    /// ([`kinematics_compiler::motion::EquationsOfMotion::roots`]) at the
    /// last step's motion, where that step was fused with them.
    #[inline]
    pub(in crate::runtime) fn fused_motion(&self) -> Option<&[f64]> {
        let run = self.fused.as_ref().filter(|r| r.motion)?;
        let (at, len) = run.plan.motion_at();
        run.f.get(at..at + len)
    }

    /// Records a fused step or pose that succeeded: the buffer holds its
    /// results (with the points' positions where `positions`, the
    /// equations of motion's roots where `motion`, the points' outputs
    /// then left out).
    #[inline(always)]
    pub(in crate::runtime) fn fused_done(&mut self, positions: bool, motion: bool) {
        if let Some(run) = self.fused.as_mut() {
            run.positions = positions;
            run.motion = motion;
        }
        self.stale = motion;
        // The cosines and sines are in the buffer, not in the work: the
        // positions of a step are evaluated afresh when asked for.
        self.assembled = false;
    }

    /// Where a fused step leaves its results in the buffer (`None`
    /// without fused code).
    pub(in crate::runtime) fn fused_layout(&self) -> Option<super::FlatAt> {
        self.fused.as_ref().map(|run| run.io.flat)
    }

    /// Records a step that the batch took for this stepper in vector
    /// lanes, as the fused step would have taken it: the step counted,
    /// its results in the buffer (as much of it as the batch copied back:
    /// the pose, the judged values and the outputs it reads, or all of
    /// it where the stepper goes on alone).
    #[inline(always)]
    pub(in crate::runtime) fn stepped_in_lanes(&mut self) {
        if let Some(run) = self.fused.as_mut() {
            run.steps = run.steps.wrapping_add(1);
        }
        // What the fused step leaves after `forget`: its results pending
        // in the buffer, no positions, no equations of motion.
        self.fused_done(false, false);
        self.pending = true;
    }
}
