//! The plan's machine code: the fused functions compiled when first
//! needed, and the calls into them.

use kinematics_jit::{Function, Fused};

use super::helper::Context;
use super::{DYNAMICS, OUTPUTS, POSE, PRELUDE, Plan, PoseFn, STEP, StepFn};

impl Plan {
    /// The compiled functions, compiled at the first call.
    pub(super) fn code(&self) -> Option<&Fused> {
        self.code
            .get_or_init(|| {
                let s = &self.source;
                let functions: Vec<Function<'_>> = s
                    .functions
                    .iter()
                    .map(|(ops, preset)| Function { ops, preset })
                    .collect();
                Fused::new(&s.graph, self.np, s.coords, self.layout, &functions).ok()
            })
            .as_ref()
    }

    /// The step with the equations of motion after it
    /// ([`kinematics_compiler::motion::EquationsOfMotion`], in the
    /// buffer at [`Plan::motion_at`]) but without the points' outputs, and
    /// the function that evaluates those outputs from the buffer that step
    /// left (checked: status 0 where every output is finite), compiled at
    /// the first call; `None` where the model has none or they did not
    /// compile.
    pub(in crate::runtime) fn dynamics_function(&self) -> Option<(StepFn<'_>, StepFn<'_>)> {
        let code = self
            .dynamics
            .get_or_init(|| {
                let s = &self.source;
                let [(ops, preset), (outputs, outputs_preset)] = s.dynamics.as_ref()?;
                let functions = [
                    Function {
                        ops: &s.functions[PRELUDE].0,
                        preset: &[],
                    },
                    Function { ops, preset },
                    Function {
                        ops: outputs,
                        preset: outputs_preset,
                    },
                ];
                Fused::new(&s.graph, self.np, s.coords, self.layout, &functions).ok()
            })
            .as_ref()?;
        Some((code.function(DYNAMICS)?, code.function(OUTPUTS)?))
    }

    /// Where the roots of the equations of motion lie in the buffer after
    /// [`Plan::dynamics_function`], and how many values they are.
    #[inline]
    pub(in crate::runtime) fn motion_at(&self) -> (usize, usize) {
        self.motion
    }

    /// The step and pose functions, looked up once for a stepper (`None`
    /// where the code did not compile).
    pub(in crate::runtime) fn functions(&self) -> Option<(StepFn<'_>, PoseFn<'_>)> {
        let code = self.code()?;
        Some((code.function(STEP)?, code.function(POSE)?))
    }

    /// One step in the buffer through `step` (of [`Plan::functions`]), its
    /// inputs read from `start`, `rates` and `accelerations` and the modes
    /// from `modes`: 0 when it is done (`modes` and `q` then hold the
    /// modes followed and the pose, the buffer the motion); otherwise the
    /// status that sends it to the general path, `modes` and `q` as they
    /// were. A port shorter than the model's is a status too (−1).
    #[inline]
    pub(in crate::runtime) fn step(
        &self,
        step: &StepFn<'_>,
        f: &mut [f64],
        inputs: [&[f64]; 3],
        modes: &mut [f64],
        q: &mut [f64],
    ) -> i64 {
        step.call(f, &mut Context { plan: self }, inputs, [modes, q])
    }

    /// One assembly in the buffer through `pose` (as [`Plan::step`],
    /// without the rates), with the points' positions: 0 when it is done.
    #[inline]
    pub(in crate::runtime) fn pose(
        &self,
        pose: &PoseFn<'_>,
        f: &mut [f64],
        start: &[f64],
        modes: &mut [f64],
        q: &mut [f64],
    ) -> i64 {
        pose.call(f, &mut Context { plan: self }, [start], [modes, q])
    }
}
