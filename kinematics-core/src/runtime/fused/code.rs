//! The plan's machine code: the fused functions compiled when first
//! needed, and the calls into them.

use kinematics_jit::{Function, Fused};

use super::helper::Context;
use super::{DYNAMICS, LEFT, OUTPUTS, POSE, PRELUDE, Plan, PoseFn, STEP, StepFn};

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

    /// The pose on two designs per call (`kinematics_jit::Fused::new_in_lanes`):
    /// its buffer and ports hold both designs' values interleaved (value
    /// i of design l at 2i + l); status 0 where both took the common
    /// path, else the first check failed or the status that one left it.
    /// Compiled at the first call; `None` where some block's closed form
    /// is not in the machine code.
    pub(in crate::runtime) fn lanes_pose(&self) -> Option<PoseFn<'_>> {
        self.lanes
            .get_or_init(|| {
                let s = &self.source;
                let (ops, preset) = &s.functions[POSE];
                let function = [Function { ops, preset }];
                Fused::new_in_lanes(&s.graph, self.np, s.coords, self.layout, &function, LEFT).ok()
            })
            .as_ref()?
            .function(0)
    }

    /// The step on two designs per call, as [`Plan::lanes_pose`] the pose:
    /// the buffer and the ports (start, rates, accelerations; modes, pose)
    /// interleaved, status 0 where both designs took the common path, each
    /// lane then the scalar step's computation for its design. Compiled at
    /// the first call; `None` where some part of the step calls the
    /// helper unconditionally.
    pub(in crate::runtime) fn lanes_step(&self) -> Option<StepFn<'_>> {
        self.lanes_step
            .get_or_init(|| {
                let s = &self.source;
                let (ops, preset) = &s.functions[STEP];
                let function = [Function { ops, preset }];
                Fused::new_in_lanes(&s.graph, self.np, s.coords, self.layout, &function, LEFT).ok()
            })
            .as_ref()?
            .function(0)
    }

    /// The drivers' carried values of lane `l` of a buffer in lanes
    /// refreshed, as a stepper's refresh and the helper leave them for a
    /// step or pose from the interleaved inputs `start`: each driver's
    /// carried value forgotten (NaN), then each carried driver's cosine
    /// and sine computed afresh at its value and carried (so that the
    /// code in lanes rotates them by zero, to the same numbers).
    pub(in crate::runtime) fn refresh_drivers_in_lane(
        &self,
        f: &mut [f64],
        start: &[f64],
        l: usize,
    ) {
        let mut put = |at: usize, v: f64| {
            if let Some(slot) = f.get_mut(2 * at + l) {
                *slot = v;
            }
        };
        for j in 0..self.nd {
            put(self.carry + 3 * j + 2, f64::NAN);
        }
        for &j in &self.driver_trig {
            let x = start.get(2 * j + l).copied().unwrap_or(f64::NAN);
            let (s, c) = crate::math::table::sin_cos(x);
            let (carry, trig) = (self.carry + 3 * j, self.layout.trig + 2 * j);
            for (at, v) in [
                (carry, c),
                (carry + 1, s),
                (carry + 2, x),
                (trig, c),
                (trig + 1, s),
            ] {
                put(at, v);
            }
        }
    }

    /// Whether the code in lanes of the pose (`poses`) or of the step is
    /// compiled already ([`Plan::lanes_pose`], [`Plan::lanes_step`]).
    pub(in crate::runtime) fn lanes_compiled(&self, poses: bool) -> bool {
        let code = if poses { &self.lanes } else { &self.lanes_step };
        code.get().is_some_and(Option::is_some)
    }

    /// Counts `positions` more of poses (`poses`) or of steps run by a
    /// batch that could pair its designs in lanes: the total so far, this
    /// batch's included, over the model and its clones.
    pub(in crate::runtime) fn batched(&self, poses: bool, positions: usize) -> usize {
        let counter = &self.batched[usize::from(poses)];
        let before = counter.fetch_add(positions, core::sync::atomic::Ordering::Relaxed);
        before.saturating_add(positions)
    }

    /// Whether `status` of [`Plan::lanes_pose`] says that a design left
    /// the common path there (where its scalar pose calls the helper),
    /// rather than that a check failed.
    pub(in crate::runtime) fn left_lanes(status: i64) -> bool {
        status == LEFT
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
