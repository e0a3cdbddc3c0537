//! The `bodies` and `loads` sections of a run-time model compiled to
//! machine code: the constants, each load's value, their partials and the
//! equations of motion, one stage each of one program.

use alloc::format;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// The `bodies` and `loads` sections of a run-time model's definition,
/// compiled: stage 0 gives the constants
/// ([`kinematics_compiler::dynamics::Dynamics::constants`]), stage 1 + k
/// the value of load k; with a `sensitivities` section, stage 1 + L (L
/// loads) the constants' partials, stage 2 + L + k load k's and stage
/// 2 + 2L + f those of the frame f of the partials' list
/// ([`kinematics_compiler::dynamics::Partials`]).
pub(crate) struct SectionCode {
    sections: kinematics_compiler::dynamics::Dynamics,
    program: kinematics_jit::Program,
    coordinates: usize,
    /// The equations of motion in the coordinates, where the compiler
    /// formed them, and their stage (the last).
    motion: Option<(usize, kinematics_compiler::motion::EquationsOfMotion)>,
    /// What marks a description as these sections' own: a number no
    /// other compiled sections of this process share.
    owner: String,
}

/// The number of the next compiled sections.
static NEXT_SECTIONS: core::sync::atomic::AtomicU64 = core::sync::atomic::AtomicU64::new(0);

impl SectionCode {
    /// The sections as the compiler describes them.
    pub(crate) fn sections(&self) -> &kinematics_compiler::dynamics::Dynamics {
        &self.sections
    }

    /// The sections of `c`, compiled, or `None` where it has none.
    pub(crate) fn new(
        c: &kinematics_compiler::Compiled,
    ) -> Result<Option<Self>, kinematics_jit::JitError> {
        let Some(sections) = c.dynamics() else {
            return Ok(None);
        };
        let constants = sections.constants();
        let mut stages: Vec<&[kinematics_compiler::ir::Id]> = vec![&constants];
        stages.extend(sections.loads.iter().map(|l| l.value.as_slice()));
        // With a `sensitivities` section: the constants' partials, then
        // each load's.
        if let Some(p) = &sections.partials {
            stages.push(&p.constants);
            stages.extend(p.loads.iter().map(Vec::as_slice));
            stages.extend(p.frames.iter().map(|(_, f)| f.as_slice()));
        }
        let motion = c.equations_of_motion().cloned();
        let roots = motion
            .as_ref()
            .map(kinematics_compiler::motion::EquationsOfMotion::roots);
        let motion = match (motion, &roots) {
            (Some(m), Some(r)) => {
                stages.push(r);
                Some((stages.len() - 1, m))
            }
            _ => None,
        };
        let coordinates = c.coordinates().len();
        let program = kinematics_jit::Program::new(
            c.graph(),
            c.parameters().len() + 1,
            coordinates,
            &stages,
        )?;
        let number = NEXT_SECTIONS.fetch_add(1, core::sync::atomic::Ordering::Relaxed);
        Ok(Some(Self {
            sections: sections.clone(),
            program,
            coordinates,
            motion,
            owner: format!("run-time model's sections #{number}"),
        }))
    }

    /// What [`Dynamics::mark_sections`] marks these sections' own
    /// descriptions with.
    pub(crate) fn owner(&self) -> &str {
        &self.owner
    }

    /// The equations of motion in the coordinates and their stage, where
    /// the compiler formed them.
    pub(crate) fn motion(
        &self,
    ) -> Option<(usize, &kinematics_compiler::motion::EquationsOfMotion)> {
        self.motion.as_ref().map(|(s, m)| (*s, m))
    }

    /// Whether a load's value reads the time.
    pub(crate) fn reads_time(&self) -> bool {
        self.program.reads_time()
    }

    /// The number of values stage `stage` writes.
    pub(crate) fn outputs(&self, stage: usize) -> usize {
        self.program.outputs(stage)
    }

    /// Stage `stage` at the parameters `values` (the characteristic length
    /// last), the coordinates, rates and accelerations `coords` and the
    /// time `time`, into `out`; `false` where the lengths do not fit the
    /// program. The cosines and sines of the coordinates marked in
    /// `given` are taken from it (cos q_j, sin q_j at 2j and 2j + 1: those
    /// a fused step already holds), the others computed. Nothing is
    /// allocated for a mechanism of up to ten coordinates and thirty
    /// parameters.
    pub(crate) fn eval_at(
        &self,
        stage: usize,
        values: &[f64],
        coords: [&[f64]; 3],
        time: f64,
        given: Option<(&[f64], &[bool])>,
        out: &mut [f64],
    ) -> bool {
        let mut trig = crate::dynamics::evaluate::Buffer::zeros(2 * self.coordinates);
        self.eval_into(stage, values, coords, time, given, trig.as_mut_slice(), out)
    }

    /// [`SectionCode::eval_at`] with the cosines and sines written into
    /// `trig` (2 per coordinate: room kept by the caller).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn eval_into(
        &self,
        stage: usize,
        values: &[f64],
        coords: [&[f64]; 3],
        time: f64,
        given: Option<(&[f64], &[bool])>,
        trig: &mut [f64],
        out: &mut [f64],
    ) -> bool {
        use crate::dynamics::evaluate::Buffer;
        let n = self.coordinates;
        if coords[0].len() != n || trig.len() != 2 * n {
            return false;
        }
        match given {
            Some((known, fresh)) => {
                for &j in self.program.trig_coordinates() {
                    let (Some(&x), Some(pair)) = (coords[0].get(j), trig.get_mut(2 * j..2 * j + 2))
                    else {
                        continue;
                    };
                    match (fresh.get(j), known.get(2 * j..2 * j + 2)) {
                        (Some(true), Some(k)) => pair.copy_from_slice(k),
                        _ => {
                            let (s, c) = x.sin_cos();
                            pair[0] = c;
                            pair[1] = s;
                        }
                    }
                }
            }
            None => self.program.trig(coords[0], trig, 0),
        }
        // The time, where a load reads it, after the parameters.
        let timed;
        let params = if self.program.reads_time() {
            let mut with_time = Buffer::zeros(values.len() + 1);
            let slice = with_time.as_mut_slice();
            slice[..values.len()].copy_from_slice(values);
            slice[values.len()] = time;
            timed = with_time;
            &*timed
        } else {
            values
        };
        let inputs = kinematics_jit::Inputs {
            params,
            q: coords[0],
            qd: coords[1],
            qdd: coords[2],
            trig,
        };
        self.program.eval(stage, &inputs, out).is_ok()
    }

    /// Stage `stage` at the parameters `values` (with the characteristic
    /// length last) and the coordinates, rates and time of `instant` (zero,
    /// and a time of NaN, without one: the constants' stage reads none),
    /// into `out`. Nothing is allocated for a mechanism of up to ten
    /// coordinates and thirty parameters.
    pub(super) fn eval(
        &self,
        stage: usize,
        values: &[f64],
        instant: Option<&crate::dynamics::Instant<'_>>,
        out: &mut [f64],
    ) {
        use crate::dynamics::evaluate::Buffer;
        let n = self.coordinates;
        let mut q = Buffer::zeros(3 * n);
        let q = q.as_mut_slice();
        if let Some(i) = instant {
            for j in 0..n {
                q[j] = i.q(j);
                q[n + j] = i.qd(j);
                q[2 * n + j] = i.qdd(j);
            }
        }
        // Read from the instant only by a stage that reads it: the instant
        // notes the reading, for the message of a load that is not finite
        // for want of a time.
        let time = match instant {
            Some(i) if self.program.stage_reads_time(stage) => i.time(),
            _ => f64::NAN,
        };
        let coords = [&q[..n], &q[n..2 * n], &q[2 * n..]];
        if !self.eval_at(stage, values, coords, time, None, out) {
            // Lengths are the program's own; a mismatch cannot happen, and
            // would show as NaN, which the sums report.
            out.fill(f64::NAN);
        }
    }
}
