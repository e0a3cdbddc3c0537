//! The fused step of a run-time model: one machine-code function
//! ([`kinematics_jit::Fused`]) that assembles in closed form and analyses
//! the motion in one straight line, as a generated stepper's `step` does,
//! calling back into this module for what is not an expression (a closed
//! form's branches and the choice of its angle's turn, the block
//! factorisations); the velocity and acceleration solves run in the
//! machine code, from the inverses of the scaled diagonal blocks that the
//! factorisation leaves in the buffer. A second function assembles only
//! (a stepper's `pose`), and writes the points' positions.
//!
//! It is the common path of a [`super::Stepper`] for models whose every
//! block has a closed form (or that have no unknowns) and whose diagonal
//! blocks of Φ_u have at most four unknowns. Anything off the common path
//! (a closed form degenerate or past a limit position, a pose not at
//! round-off, a singular or wrong-branch pose, a value not finite) makes
//! it return a nonzero status and leave the stepper's state as it was:
//! the stepper then takes the general path, which gives the same pose or
//! the error with its message.
//!
//! Its buffer holds, at the offsets of [`Plan`], the parameters (and the
//! characteristic length), q, q', q'', the cosines and sines of q, what
//! each coordinate carries from step to step (cos, sin and the value they
//! belong to), the modes, the row scales and convergence weights, the
//! closing bound and singularity threshold and the branch asked for, the
//! coefficients of the block being solved, the two residuals, Φ_u (dense,
//! row by row), the inverses of the scaled diagonal blocks, the outputs,
//! the points' positions, and the conditioning and sign of det Φ_u found.

use alloc::vec;
use alloc::vec::Vec;

use std::sync::OnceLock;

use kinematics_compiler::Compiled;
use kinematics_compiler::ir::{Graph, Id, Node};
use kinematics_jit::{Callable, Fused, Layout, Op, Port, SmallBlock, SolveBlock, SolveRow};

/// The step function of a plan's code: its inputs read from the start,
/// the drivers' rates and their accelerations; the modes and the pose
/// written back.
pub(super) type StepFn<'a> = Callable<'a, 3, 2>;

/// The pose function of a plan's code: its input read from the start;
/// the modes and the pose written back.
pub(super) type PoseFn<'a> = Callable<'a, 1, 2>;

mod closed;
mod code;
mod helper;
#[cfg(test)]
mod tests;

use super::closed::Form;
use super::invariant::hoist;
use closed::AngleAt;
use helper::Context;

/// The helper's arguments: the closing check and factorisation, driver
/// j's cosine and sine computed afresh at `DRIVER_TRIG + j`, and block
/// i's closed form at `BLOCK + i`.
const FACTOR: u64 = 1;
const DRIVER_TRIG: u64 = 1 << 32;
const BLOCK: u64 = 1 << 48;

/// The statuses that send a step off the common path: a closed form has
/// no solution or is degenerate; the pose is not at round-off (or not
/// finite); Φ_u is singular at the threshold; det Φ_u has the other sign
/// than asked; an output is not finite; the helper was asked for what the
/// plan does not have (never, short of a bug).
const NO_SOLUTION: i64 = 1;
const NOT_CLOSED: i64 = 2;
const SINGULAR: i64 = 3;
const WRONG_BRANCH: i64 = 4;
const NOT_FINITE: i64 = 5;
const INCONSISTENT: i64 = 6;
/// The pose in lanes left the common path in a design (the scalar pose
/// would call the helper there).
const LEFT: i64 = 7;

/// The fused functions: the invariants and offsets of the parameters,
/// the step, the pose.
const PRELUDE: usize = 0;
const STEP: usize = 1;
const POSE: usize = 2;
/// In the second module, compiled for a forward simulation only: the
/// step with the equations of motion's roots after it (the points'
/// outputs left out), and the points' outputs alone, evaluated from the
/// buffer that step left when a motion is read.
const DYNAMICS: usize = 1;
const OUTPUTS: usize = 2;

/// One closed-form block as the fused step solves it.
#[derive(Clone, Debug)]
struct PartPlan {
    form: Form,
    /// The coordinates of its unknowns (drivers first in q), in the
    /// form's order (the first again for a form of one unknown).
    coords: [usize; 2],
    /// The number of its unknowns (1 or 2).
    count: usize,
    /// Its slot among the modes, if it has two.
    mode: Option<usize>,
}

/// One diagonal block of Φ_u, in the order of the substitution.
#[derive(Clone, Debug)]
struct BlockPlan {
    /// Its entries of Φ_u row by row: where each lies in the buffer, where
    /// its row's scale 1/S lies, and whether its column is a length's.
    entries: Vec<(usize, usize, bool)>,
    /// Its number of unknowns.
    n: usize,
    /// Where the inverse of its scaled matrix is written.
    inverse: usize,
}

/// The fused step of one model: its code and the offsets of its buffer.
#[derive(Debug)]
pub(super) struct Plan {
    /// The functions [`PRELUDE`], [`STEP`] and [`POSE`], compiled when a
    /// stepper first needs them (`None` if that failed: the steppers then
    /// take the general path).
    code: OnceLock<Option<Fused>>,
    /// [`PRELUDE`] and [`DYNAMICS`], compiled when a forward simulation
    /// first needs them (`None` without equations of motion, or where the
    /// compiler formed none this code can evaluate: a load that reads the
    /// time).
    dynamics: OnceLock<Option<Fused>>,
    /// [`POSE`] on two designs per call, compiled when a batch of
    /// positions only first needs it (`None` where a block's closed form
    /// goes through the helper: no form in lanes).
    lanes: OnceLock<Option<Fused>>,
    /// [`STEP`] on two designs per call, compiled when a batch of steps
    /// first needs it (`None` as for [`Plan::lanes_pose`]).
    lanes_step: OnceLock<Option<Fused>>,
    /// The positions of steps and of poses that batches which could pair
    /// ran without these ([`Plan::batched`]).
    batched: [core::sync::atomic::AtomicUsize; 2],
    /// Where the equations of motion's roots lie, and how many there are.
    motion: (usize, usize),
    /// What they are compiled from.
    source: Source,
    /// Where the offsets k of sin(q + k) lie, and how many there are.
    offsets: (usize, usize),
    layout: Layout,
    nd: usize,
    /// The drivers whose cosine and sine the step and the pose carry.
    driver_trig: Vec<usize>,
    nu: usize,
    np: usize,
    carry: usize,
    modes: usize,
    rows: usize,
    weights: usize,
    bound: usize,
    threshold: usize,
    branch: usize,
    coef: usize,
    closing: usize,
    residual: usize,
    out: usize,
    outputs: usize,
    positions: usize,
    position_count: usize,
    conditioning: usize,
    sign: usize,
    parts: Vec<PartPlan>,
    blocks: Vec<BlockPlan>,
    /// Whether the blocks' rows and columns, in order, are permutations
    /// of opposite parity (then det Φ_u is minus the product of theirs).
    odd: bool,
    mode_count: usize,
    /// The coordinates whose cosine and sine every successful step writes
    /// into the buffer (the drivers the code reads them of, each block's
    /// angles).
    fresh_trig: Vec<bool>,
}

/// The rewritten graph and the ops of the fused functions, each with the
/// nodes it reads from the buffer.
struct Source {
    graph: Graph,
    coords: usize,
    functions: [Ops; 3],
    /// The step followed by the equations of motion, without the points'
    /// outputs, and the outputs alone, where the model has them.
    dynamics: Option<[Ops; 2]>,
}

/// A fused function's ops, and the nodes it reads from the buffer.
type Ops = (Vec<Op>, Vec<(Id, usize)>);

impl core::fmt::Debug for Source {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Source")
            .field("nodes", &self.graph.len())
            .finish_non_exhaustive()
    }
}

/// Offsets handed out one region after another.
struct Regions(usize);

impl Regions {
    fn take(&mut self, n: usize) -> usize {
        let at = self.0;
        self.0 += n;
        at
    }
}

impl Plan {
    /// The fused step of `c`, or `None` where it does not apply (a block
    /// solved by Newton–Raphson, a diagonal block of more than four
    /// unknowns, or blocks not in the order of a forward substitution).
    pub(super) fn new(c: &Compiled) -> Option<Self> {
        let (nd, nu) = (c.drivers(), c.unknowns());
        let n = nd + nu;
        let np = c.parameters().len() + 1;
        let blocks = c.blocks();
        if blocks
            .iter()
            .any(|b| b.form.is_none() || b.unknowns.len() > 4)
        {
            return None;
        }
        let graph = c.graph();
        let is_zero =
            |id: Id| matches!(graph.node(id), Node::Const(bits) if f64::from_bits(bits) == 0.0);
        let jac = c.jacobian();
        if jac.len() != nu || jac.iter().any(|r| r.len() != nu) {
            return None;
        }
        // Each block's rows may only hold entries in its own columns or
        // in those of the blocks before it.
        let mut block_of = vec![usize::MAX; nu];
        for (b, block) in blocks.iter().enumerate() {
            for &col in &block.unknowns {
                if let Some(slot) = block_of.get_mut(col) {
                    *slot = b;
                }
            }
        }
        for (b, block) in blocks.iter().enumerate() {
            for &r in &block.equations {
                for (col, &e) in jac[r].iter().enumerate() {
                    if !is_zero(e) && block_of[col] > b {
                        return None;
                    }
                }
            }
        }
        let mut parts = Vec::new();
        let mut mode_count = 0;
        for b in &blocks {
            let form = b.form.as_ref()?.places();
            let mode = form.has_modes().then(|| {
                mode_count += 1;
                mode_count - 1
            });
            let first = nd + *b.unknowns.first().unwrap_or(&0);
            let second = b.unknowns.get(1).map_or(first, |&k| nd + k);
            parts.push(PartPlan {
                form,
                coords: [first, second],
                count: b.unknowns.len().min(2),
                mode,
            });
        }
        let lengths = c.length_unknowns();
        let is_length = |col: usize| lengths.get(col).copied().unwrap_or(false);
        let outputs = kinematics_jit::output_roots(c);
        let position_roots: Vec<Id> = c
            .points()
            .iter()
            .flat_map(|p| p.position.iter().copied())
            .collect();
        // Every root the two functions evaluate, for the rewriting.
        let phi: Vec<Id> = c.residuals().iter().map(|(id, _)| *id).collect();
        let jac_entries: Vec<(usize, usize, Id)> = jac
            .iter()
            .enumerate()
            .flat_map(|(r, row)| row.iter().enumerate().map(move |(col, &e)| (r, col, e)))
            .filter(|&(_, _, e)| !is_zero(e))
            .collect();
        let mut all_roots: Vec<Id> = blocks.iter().flat_map(|b| b.coefficients()).collect();
        all_roots.extend(&phi);
        all_roots.extend(jac_entries.iter().map(|&(_, _, e)| e));
        all_roots.extend(c.velocity_rhs());
        all_roots.extend(c.acceleration_rhs());
        all_roots.extend(&outputs);
        all_roots.extend(&position_roots);
        let motion_roots = c
            .equations_of_motion()
            .map(kinematics_compiler::motion::EquationsOfMotion::roots)
            .unwrap_or_default();
        all_roots.extend(&motion_roots);
        let h = hoist(graph, np, n, &all_roots);
        let mut at = Regions(0);
        let params = at.take(np);
        let q = at.take(n);
        let qd = at.take(n);
        let qdd = at.take(n);
        let trig = at.take(2 * n);
        let carry = at.take(3 * n);
        let modes = at.take(mode_count);
        let rows = at.take(nu);
        let weights = at.take(nu);
        let bound = at.take(1);
        let threshold = at.take(1);
        let branch = at.take(1);
        let coef = at.take(12);
        let closing = at.take(1);
        let residual = at.take(1);
        let jac_at = at.take(nu * nu);
        let inverses: Vec<usize> = blocks
            .iter()
            .map(|b| at.take(b.unknowns.len() * b.unknowns.len()))
            .collect();
        let out = at.take(outputs.len());
        let positions = at.take(position_roots.len());
        let motion = at.take(motion_roots.len());
        let conditioning = at.take(1);
        let sign = at.take(1);
        let invariants = at.take(h.invariants.len());
        let offsets = at.take(h.offsets.len());
        let layout = Layout {
            params,
            q,
            qd,
            qdd,
            trig,
            len: at.0,
        };
        let length_at = params + np - 1;
        // The drivers whose cosine and sine the rewritten graph reads (the
        // addition theorem reads some that no stage of the program does).
        let driver_trig = h.trig_read(&all_roots, nd);
        let mut fresh_trig = vec![false; n];
        let angles = parts
            .iter()
            .flat_map(|p| p.coords.into_iter().take(p.count.min(p.form.angles())));
        for j in driver_trig.iter().copied().chain(angles) {
            if let Some(fresh) = fresh_trig.get_mut(j) {
                *fresh = true;
            }
        }

        // The assembly, shared by both functions: the drivers' cosines
        // and sines, each block from its coefficients, the residual.
        let mut assembly: Vec<Op> = driver_trig
            .clone()
            .iter()
            .map(|&j| Op::CarriedTrig {
                value: q + j,
                carried: carry + 3 * j,
                to: trig + 2 * j,
                fresh: DRIVER_TRIG + j as u64,
                series: kinematics_jit::Series {
                    step: crate::closed::CARRIED_STEP,
                    sin: crate::closed::SIN_SERIES,
                    vers: crate::closed::VERS_SERIES,
                },
            })
            .collect();
        // The dyads and the small blocks' factors are written into the
        // machine code for models of up to 16 blocks; beyond, through the
        // helper (each inline dyad and factor adds branches, and the time
        // to compile a function grows faster than its branches).
        let inline = blocks.len() <= 16;
        for (i, (b, part)) in blocks.iter().zip(&parts).enumerate() {
            let roots = h.map_all(&b.coefficients());
            // The RRR dyad and the angle equation in the machine code (the
            // helper where the mode is not set yet or off the common
            // path, the coefficients written into the buffer for it then);
            // the other forms through the helper.
            let angle = |j: usize| AngleAt {
                value: q + j,
                trig: trig + 2 * j,
                carried: carry + 3 * j,
            };
            let inline_op = match (&b.form, part.mode) {
                (Some(form), Some(slot)) if inline => closed::op(
                    &form.map(|id| h.map(id)),
                    [angle(part.coords[0]), angle(part.coords[1])],
                    closed::Slots {
                        mode: modes + slot,
                        store: coef,
                        general: BLOCK + i as u64,
                    },
                ),
                _ => None,
            };
            match inline_op {
                Some(op) => assembly.push(op),
                None => {
                    assembly.push(Op::Store {
                        at: (coef..coef + roots.len()).collect(),
                        roots,
                        finite: None,
                    });
                    assembly.push(Op::Call(BLOCK + i as u64));
                }
            }
        }
        let phi = h.map_all(&phi);
        assembly.push(Op::MaxScaled {
            roots: phi.clone(),
            scales: weights,
            at: closing,
        });

        // The inputs copied into the buffer (and checked: a value not
        // finite takes the general path, which reports it), the modes
        // followed read from the stepper; the pose and the modes written
        // back once the function has succeeded.
        let import = |rates: bool| {
            let mut ops = vec![Op::Import {
                from: Port::Input(0),
                to: q,
                len: n,
                finite: Some(NOT_FINITE),
            }];
            if rates {
                for (i, to) in [(1, qd), (2, qdd)] {
                    ops.push(Op::Import {
                        from: Port::Input(i),
                        to,
                        len: nd,
                        finite: Some(NOT_FINITE),
                    });
                }
            }
            ops.push(Op::Import {
                from: Port::Output(0),
                to: modes,
                len: mode_count,
                finite: None,
            });
            ops
        };
        let export = [
            Op::Export {
                to: 0,
                from: modes,
                len: mode_count,
            },
            Op::Export {
                to: 1,
                from: q,
                len: n,
            },
        ];
        let mut pose = import(false);
        pose.extend(assembly.iter().cloned());
        // The closing check in the machine code (a call of the helper
        // would cost more than the comparison).
        pose.push(Op::AtMost {
            at: closing,
            bound,
            status: NOT_CLOSED,
        });
        pose.push(Op::Store {
            roots: h.map_all(&position_roots),
            at: (positions..positions + position_roots.len()).collect(),
            finite: Some(NOT_FINITE),
        });
        pose.extend(export.iter().cloned());

        let mut step = import(true);
        step.extend(assembly);
        step.push(Op::MaxScaled {
            roots: phi,
            scales: rows,
            at: residual,
        });
        let entries: Vec<Id> = jac_entries.iter().map(|&(_, _, e)| h.map(e)).collect();
        let slots: Vec<usize> = jac_entries
            .iter()
            .map(|&(r, col, _)| jac_at + r * nu + col)
            .collect();
        step.push(Op::Store {
            roots: entries,
            at: slots,
            finite: None,
        });
        if inline && blocks.iter().all(|b| b.unknowns.len() <= 2) {
            // The closing check and the small blocks' factors in the
            // machine code itself.
            step.push(Op::AtMost {
                at: closing,
                bound,
                status: NOT_CLOSED,
            });
            step.push(Op::FactorSmall {
                blocks: blocks
                    .iter()
                    .zip(&inverses)
                    .map(|(b, &inverse)| SmallBlock {
                        entries: b
                            .equations
                            .iter()
                            .flat_map(|&r| b.unknowns.iter().map(move |&col| (r, col)))
                            .map(|(r, col)| {
                                (
                                    h.map(jac[r][col]),
                                    rows + r,
                                    is_length(col).then_some(length_at),
                                )
                            })
                            .collect(),
                        inverse,
                    })
                    .collect(),
                threshold,
                branch,
                odd: c.blocks_flip_determinant(),
                conditioning,
                sign,
                singular: SINGULAR,
                wrong_branch: WRONG_BRANCH,
            });
        } else {
            step.push(Op::Call(FACTOR));
        }
        let solve_blocks: Vec<SolveBlock> = blocks
            .iter()
            .enumerate()
            .map(|(i, b)| SolveBlock {
                rows: b
                    .equations
                    .iter()
                    .map(|&r| SolveRow {
                        rhs: r,
                        scale: rows + r,
                        known: blocks[..i]
                            .iter()
                            .flat_map(|d| d.unknowns.iter().copied())
                            .filter(|&col| !is_zero(jac[r][col]))
                            .map(|col| (jac_at + r * nu + col, col))
                            .collect(),
                    })
                    .collect(),
                inverse: inverses[i],
                cols: b
                    .unknowns
                    .iter()
                    .map(|&col| (col, is_length(col).then_some(length_at)))
                    .collect(),
            })
            .collect();
        step.push(Op::Solve {
            rhs: h.map_all(c.velocity_rhs()),
            blocks: solve_blocks.clone(),
            to: qd + nd,
            finite: Some(NOT_FINITE),
        });
        step.push(Op::Solve {
            rhs: h.map_all(c.acceleration_rhs()),
            blocks: solve_blocks,
            to: qdd + nd,
            finite: Some(NOT_FINITE),
        });
        let outputs_store = Op::Store {
            roots: h.map_all(&outputs),
            at: (out..out + outputs.len()).collect(),
            finite: Some(NOT_FINITE),
        };
        // The equations of motion after the motion, without the points'
        // outputs: an evaluation of the forward dynamics needs none of
        // them (they are evaluated, checked, where a motion is read). (The
        // equations checked by their reduction, which sends a value not
        // finite the general way.) The outputs' own function reads what
        // that step left in the buffer: q, q', q'' (the unknowns' written
        // by the step), the invariants and parameters, and the cosines and
        // sines of the drivers and the blocks' angles, which the shared
        // assembly writes for every coordinate the outputs read
        // (`driver_trig` is taken over all the roots, the outputs' with
        // them); the stepper takes no step between the two.
        let dynamics = (!motion_roots.is_empty()).then(|| {
            let mut ops = step.clone();
            ops.push(Op::Store {
                roots: h.map_all(&motion_roots),
                at: (motion..motion + motion_roots.len()).collect(),
                finite: None,
            });
            ops.extend(export.iter().cloned());
            [ops, vec![outputs_store.clone()]]
        });
        step.push(outputs_store);
        step.extend(export.iter().cloned());
        // The invariants and offsets, computed once per stepper; the two
        // functions read them.
        let prelude = [
            Op::Store {
                roots: h.invariants.clone(),
                at: (invariants..invariants + h.invariants.len()).collect(),
                finite: None,
            },
            Op::Store {
                roots: h.offsets.clone(),
                at: (offsets..offsets + h.offsets.len()).collect(),
                finite: None,
            },
        ];
        let preset: Vec<(Id, usize)> = h
            .invariants
            .iter()
            .enumerate()
            .map(|(i, &id)| (id, invariants + i - params))
            .collect();
        Some(Plan {
            code: OnceLock::new(),
            dynamics: OnceLock::new(),
            lanes: OnceLock::new(),
            lanes_step: OnceLock::new(),
            batched: Default::default(),
            motion: (motion, motion_roots.len()),
            source: Source {
                graph: h.graph,
                coords: n,
                dynamics: dynamics
                    .map(|[ops, outputs]| [(ops, preset.clone()), (outputs, preset.clone())]),
                functions: [
                    (prelude.to_vec(), Vec::new()),
                    (step, preset.clone()),
                    (pose, preset),
                ],
            },
            offsets: (offsets, h.offsets.len()),
            layout,
            nd,
            driver_trig,
            nu,
            np,
            carry,
            modes,
            rows,
            weights,
            bound,
            threshold,
            branch,
            coef,
            closing,
            residual,
            out,
            outputs: outputs.len(),
            positions,
            position_count: position_roots.len(),
            conditioning,
            sign,
            blocks: blocks
                .iter()
                .zip(&inverses)
                .map(|(b, &inverse)| BlockPlan {
                    entries: b
                        .equations
                        .iter()
                        .flat_map(|&r| {
                            b.unknowns
                                .iter()
                                .map(move |&col| (jac_at + r * nu + col, rows + r, is_length(col)))
                        })
                        .collect(),
                    n: b.unknowns.len(),
                    inverse,
                })
                .collect(),
            parts,
            odd: c.blocks_flip_determinant(),
            mode_count,
            fresh_trig,
        })
    }

    /// The cosines and sines of the pose in the buffer `f` (cos q_j and
    /// sin q_j at 2j and 2j + 1) and, for each coordinate, whether a
    /// successful step wrote them (the others are stale or unset).
    pub(super) fn trig_of<'f>(&self, f: &'f [f64]) -> (&'f [f64], &[bool]) {
        let at = self.layout.trig;
        let n = self.fresh_trig.len();
        (f.get(at..at + 2 * n).unwrap_or(&[]), &self.fresh_trig)
    }

    /// A buffer for the code, its parameters `params` (with the
    /// characteristic length last), every carried value NaN (nothing
    /// carried yet), every other value 0; written into `f`, in the
    /// storage it has.
    pub(super) fn buffer_into(&self, f: &mut Vec<f64>, params: &[f64]) {
        f.clear();
        f.resize(self.layout.len, 0.0);
        if let Some(p) = f.get_mut(self.layout.params..self.layout.params + self.np) {
            for (d, s) in p.iter_mut().zip(params) {
                *d = *s;
            }
        }
        if let Some(c) = f.get_mut(self.carry..self.carry + 3 * (self.nd + self.nu)) {
            c.fill(f64::NAN);
        }
    }

    /// Computes, in a buffer of [`Plan::buffer`], what depends on the
    /// parameters alone: `false` when an offset k of sin(q + k) lies
    /// beyond 2²⁰ rad, where q + k rounds away most of q and the addition
    /// theorem would not match the equations as evaluated (the stepper
    /// then takes the general path).
    pub(super) fn prepare(&self, f: &mut [f64]) -> bool {
        if self
            .code()
            .map_or(-1, |c| c.call(PRELUDE, f, &mut Context { plan: self }))
            != 0
        {
            return false;
        }
        let (at, count) = self.offsets;
        f[at..at + count].iter().all(|k| k.abs() <= 1_048_576.0)
    }

    /// Sets the closing bound, the singularity threshold and the sign of
    /// det Φ_u asked for (0: either).
    pub(super) fn set_options(&self, f: &mut [f64], bound: f64, threshold: f64, branch: f64) {
        for (at, v) in [
            (self.bound, bound),
            (self.threshold, threshold),
            (self.branch, branch),
        ] {
            if let Some(x) = f.get_mut(at) {
                *x = v;
            }
        }
    }

    /// Sets the scaling: the characteristic length, the row scales and
    /// the convergence weights.
    pub(super) fn set_scaling(&self, f: &mut [f64], length: f64, rows: &[f64], weights: &[f64]) {
        if let Some(x) = f.get_mut(self.layout.params + self.np - 1) {
            *x = length;
        }
        for (base, v) in [(self.rows, rows), (self.weights, weights)] {
            if let Some(d) = f.get_mut(base..base + self.nu) {
                d.copy_from_slice(&v[..self.nu.min(v.len())]);
            }
        }
    }

    /// Forgets the carried cosines and sines (of the drivers; with
    /// `unknowns`, of the unknowns too), so that the next step computes
    /// them afresh.
    pub(super) fn refresh(&self, f: &mut [f64], unknowns: bool) {
        let to = if unknowns { self.nd + self.nu } else { self.nd };
        for j in 0..to {
            if let Some(x) = f.get_mut(self.carry + 3 * j + 2) {
                *x = f64::NAN;
            }
        }
    }

    /// The layout of the buffer.
    #[inline]
    pub(super) fn layout(&self) -> Layout {
        self.layout
    }

    /// Where the modes, the outputs, the conditioning, the sign and the
    /// reported residual lie, and how many modes and outputs there are.
    #[inline]
    pub(super) fn modes_at(&self) -> (usize, usize) {
        (self.modes, self.mode_count)
    }

    #[inline]
    pub(super) fn outputs_at(&self) -> (usize, usize) {
        (self.out, self.outputs)
    }

    /// Where the points' positions of [`Plan::pose`] lie, and how many
    /// values they are.
    #[inline]
    pub(super) fn positions_at(&self) -> (usize, usize) {
        (self.positions, self.position_count)
    }

    #[inline]
    pub(super) fn results_at(&self) -> [usize; 3] {
        [self.conditioning, self.sign, self.residual]
    }
}
