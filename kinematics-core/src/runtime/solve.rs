//! The numerical core of run-time models: the scaling, Newton–Raphson on
//! the unknowns, Φ_u's factors and conditioning, and the velocity and
//! acceleration solves, all in the arrays of one [`Work`], which a
//! stepper keeps from step to step so that a step allocates nothing.

use alloc::vec;
use alloc::vec::Vec;

use kinematics_jit::{Inputs, Program};
use nalgebra::{Matrix3, Vector3};

use super::{Model, Motion, PointState, Vector};

mod spare;
use crate::error::{Error, Input};
use crate::mechanism::FrameState;
use crate::options::{Convergence, Options};
use crate::solve::dense::{conditioning, lu, lu_above, lu_apply};
use crate::solve::{Failure, Judge, Space, System, describe_by, fast_then_damped, iterate};
pub(super) use spare::{Arrays, Pooled, Spare};

/// The arrays of a solve and an analysis, sized for one model.
#[derive(Default)]
pub(super) struct Work {
    /// The parameters, then the characteristic length L.
    pub(super) params: Vec<f64>,
    pub(super) phi: Vec<f64>,
    jac: Vec<f64>,
    newton: Vec<f64>,
    /// The row scales 1/S_i (S_i with the unknown lengths counted as L).
    pub(super) rows: Vec<f64>,
    /// The convergence weights: `rows` for relative convergence, 1 for
    /// absolute.
    pub(super) weights: Vec<f64>,
    /// Rates and accelerations of zero, for the stages of positions.
    pub(super) zeros: Vec<f64>,
    /// LU factors of Φ_u (Newton's, then the analysis's) and their row
    /// permutation.
    lu: Vec<f64>,
    perm: Vec<usize>,
    /// The arrays of a Newton–Raphson solve of a block.
    space: Part,
    /// Whether the whole system is solved as a step, which must close to
    /// round-off (a stepper's), rather than as an assembly.
    pub(super) closing: bool,
    /// One diagonal block of Φ_u scaled (rows by 1/S_i, length columns by
    /// L) with its permutation; a column of the block's inverse, a unit
    /// vector and the inverse's absolute row sums.
    sub: Vec<f64>,
    sub_perm: Vec<usize>,
    col: Vec<f64>,
    unit: Vec<f64>,
    sums: Vec<f64>,
    /// A right-hand side, and the outputs' stage.
    rhs: Vec<f64>,
    out: Vec<f64>,
    /// cos q_j, sin q_j of the current pose (the stages' `trig` input).
    pub(super) trig: Vec<f64>,
    /// The guess a block-by-block assembly started from.
    pub(super) guess: Vec<f64>,
    /// A closed-form block's coefficients.
    pub(super) coef: Vec<f64>,
    /// Whether `rows`, `weights` and the characteristic length hold the
    /// scaling of every pose (the model's term scales read no coordinate).
    scaling_kept: bool,
}

/// The arrays of a Newton–Raphson solve of a block ([`iterate`]), each of
/// the unknowns' number: the block's unknowns and equations, their row
/// scales and convergence weights, and its scratch.
#[derive(Default)]
struct Part {
    u: Vec<f64>,
    phi: Vec<f64>,
    row: Vec<f64>,
    weights: Vec<f64>,
    start: Vec<f64>,
    step: Vec<f64>,
    origin: Vec<f64>,
}

/// The equations `rows` of a model in the unknowns `cols` (the others
/// held in `q`), as Newton–Raphson iterates on them.
struct Subsystem<'a> {
    m: &'a Model,
    q: &'a mut [f64],
    w: &'a mut Work,
    rows: &'a [usize],
    cols: &'a [usize],
    threshold: f64,
}

impl System for Subsystem<'_> {
    fn eval(&mut self, u: &[f64], phi: &mut [f64]) {
        let nd = self.m.drivers;
        for (x, &c) in u.iter().zip(self.cols) {
            self.q[nd + c] = *x;
        }
        self.m.newton_eval(self.q, self.w);
        for (p, &r) in phi.iter_mut().zip(self.rows) {
            *p = self.w.phi[r];
        }
    }

    fn step(&mut self, phi: &[f64], step: &mut [f64]) -> Result<(), Failure> {
        let (m, nu) = (self.cols.len(), self.m.unknowns());
        let w = &mut *self.w;
        let length = w.params[self.m.params.len()];
        let lengths = &self.m.length_unknowns;
        let unit = |c: usize| if lengths[c] { length } else { 1.0 };
        for (a, &r) in self.rows.iter().enumerate() {
            // Φ̃_u = diag(1/S) Φ_u diag(unit), and diag(1/S) Φ.
            for (b, &c) in self.cols.iter().enumerate() {
                w.lu[a * m + b] = w.jac[r * nu + c] * w.rows[r] * unit(c);
            }
            w.rhs[a] = phi[a] * w.rows[r];
        }
        lu_above(&mut w.lu[..m * m], &mut w.perm[..m], m, self.threshold).map_err(
            |(unknown, pivot)| Failure::Singular {
                unknown,
                conditioning: if pivot.is_finite() { pivot } else { 0.0 },
            },
        )?;
        lu_apply(&w.lu[..m * m], &w.perm[..m], &w.rhs, step, m);
        for (x, &c) in step.iter_mut().zip(self.cols) {
            *x *= unit(c);
        }
        Ok(())
    }
}

impl Work {
    /// The values of the last [`Program::OUTPUTS`] evaluation of an
    /// analysis.
    pub(super) fn outputs(&self) -> &[f64] {
        &self.out
    }
}

impl Model {
    pub(super) fn work(&self) -> Pooled<'_> {
        self.spare.lend(&self.values, || self.fresh_work())
    }

    /// A [`Work`] allocated afresh for this model.
    fn fresh_work(&self) -> Work {
        let nu = self.unknowns();
        let widest = self.blocks.iter().map(|(_, c)| c.len()).max().unwrap_or(0);
        Work {
            params: self.values.clone(),
            phi: vec![0.0; nu],
            jac: vec![0.0; nu * nu],
            newton: vec![0.0; self.program.outputs(Program::NEWTON)],
            rows: vec![1.0; nu],
            weights: vec![1.0; nu],
            zeros: vec![0.0; self.coordinates.len()],
            lu: vec![0.0; nu * nu],
            perm: vec![0; nu],
            space: Part {
                u: vec![0.0; nu],
                phi: vec![0.0; nu],
                row: vec![0.0; nu],
                weights: vec![0.0; nu],
                start: vec![0.0; nu],
                step: vec![0.0; nu],
                origin: vec![0.0; nu],
            },
            closing: false,
            sub: vec![0.0; widest * widest],
            sub_perm: vec![0; widest],
            col: vec![0.0; widest],
            unit: vec![0.0; widest],
            sums: vec![0.0; widest],
            rhs: vec![0.0; nu],
            out: vec![0.0; self.program.outputs(Program::OUTPUTS)],
            trig: vec![0.0; 2 * self.coordinates.len()],
            guess: vec![0.0; self.coordinates.len()],
            coef: vec![0.0; 12],
            scaling_kept: false,
        }
    }

    /// A motion with the model's shape (every value 0), for a stepper to
    /// write its steps into.
    pub(super) fn shaped_motion(&self) -> Motion {
        let mut m = Motion::default();
        self.shape_motion(&mut m);
        m
    }

    /// `m` given the model's shape, every value 0 (the frames at the
    /// origin, unrotated), in the storage it has.
    pub(super) fn shape_motion(&self, m: &mut Motion) {
        let n = self.coordinates.len();
        let d = self.point_dim;
        let zero = FrameState {
            rotation: Matrix3::identity(),
            origin: Vector3::zeros(),
            velocity: Vector3::zeros(),
            acceleration: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
            angular_acceleration: Vector3::zeros(),
        };
        for v in [&mut m.q, &mut m.qd, &mut m.qdd] {
            v.clear();
            v.resize(n, 0.0);
        }
        m.points.clear();
        m.points.resize(self.points.len(), PointState::zeros(d));
        m.frames.clear();
        m.frames.resize(self.frames.len(), zero);
        (m.conditioning, m.det_sign, m.residual) = (0.0, 0.0, 0.0);
    }

    /// Evaluates a stage, whose lengths the model guarantees; `trig`
    /// holds the cosines and sines of q ([`Program::trig`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn eval(
        &self,
        stage: usize,
        params: &[f64],
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        trig: &[f64],
        out: &mut [f64],
    ) {
        let inputs = Inputs {
            params,
            q,
            qd,
            qdd,
            trig,
        };
        // The arrays are the model's own, of its lengths.
        let checked = self.program.eval(stage, &inputs, out);
        debug_assert!(checked.is_ok(), "{checked:?}");
    }

    /// Φ and Φ_u at q into `w.phi`, `w.jac` (row-major).
    /// The cosines and sines of the unknowns are brought up to q first
    /// (the drivers' are those of the last [`Model::scaling`], at the same
    /// drivers).
    pub(super) fn newton_eval(&self, q: &[f64], w: &mut Work) {
        self.program.trig(q, &mut w.trig, self.drivers);
        self.newton_stage(q, w);
    }

    /// [`Model::newton_eval`] with the cosines and sines in `w` already
    /// those of q (as the closed forms leave them).
    pub(super) fn newton_stage(&self, q: &[f64], w: &mut Work) {
        let nu = w.phi.len();
        self.eval(
            Program::NEWTON,
            &w.params,
            q,
            &w.zeros,
            &w.zeros,
            &w.trig,
            &mut w.newton,
        );
        w.phi.copy_from_slice(&w.newton[..nu]);
        w.jac.copy_from_slice(&w.newton[nu..]);
    }

    /// The scaling at the drivers of q, as the generated code forms it:
    /// the characteristic length L, the largest term scale with the
    /// unknown lengths counted as 0 (1 if none is positive), into the
    /// parameters' last slot; the row scales 1/S_i with the unknown
    /// lengths counted as L (1 where S_i = 0); the convergence weights,
    /// those for relative convergence, 1 for absolute. Returns L.
    /// The cosines and sines of every coordinate are brought up to q.
    /// Where the term scales read no coordinate, they are computed once
    /// per `w` (whose options and parameters do not change).
    pub(super) fn scaling(&self, q: &[f64], w: &mut Work, options: &Options) -> f64 {
        let n = self.params.len();
        if w.scaling_kept {
            // The scaling reads no coordinate: only the drivers' cosines
            // and sines are brought up to q (the assembly solves the
            // unknowns', or evaluates them from the guess where it solves
            // by Newton–Raphson).
            self.program.trig_between(q, &mut w.trig, 0, self.drivers);
            return w.params[n];
        }
        self.program.trig(q, &mut w.trig, 0);
        w.params[n] = f64::NAN;
        self.eval(
            Program::SCALES,
            &w.params,
            q,
            &w.zeros,
            &w.zeros,
            &w.trig,
            &mut w.rows,
        );
        let length = w
            .rows
            .iter()
            .copied()
            .fold(0.0f64, |m, v| if v > m { v } else { m });
        let length = if length > 0.0 { length } else { 1.0 };
        w.params[n] = length;
        self.eval(
            Program::FULL_SCALES,
            &w.params,
            q,
            &w.zeros,
            &w.zeros,
            &w.trig,
            &mut w.rows,
        );
        for (r, wt) in w.rows.iter_mut().zip(&mut w.weights) {
            *r = if *r > 0.0 && r.is_finite() {
                1.0 / *r
            } else {
                1.0
            };
            *wt = match options.convergence {
                Convergence::Relative => *r,
                Convergence::Absolute => 1.0,
            };
        }
        w.scaling_kept = self.fixed_scaling;
        length
    }

    /// Newton–Raphson on the equations `rows` for the unknowns `cols`
    /// (0-based among the unknowns; the others fixed), from q, with the
    /// scaling at its drivers (as [`Model::scaling`] leaves it): a
    /// diagonal block of an assembly in closed form and by Newton–Raphson
    /// (`block`), or the whole system. The iteration and its convergence
    /// rule are generated code's: for a block, and for the whole system
    /// in a stepper's step, [`FastNewton`](crate::solve::FastNewton)'s
    /// common path first ([`fast_then_damped`]); for an assembly,
    /// [`iterate`]. The Newton step
    /// is solved through the block's scaled Φ_u, whose pivots at or below
    /// the singularity threshold fail, as generated code solves it. On
    /// return `w` holds Φ and Φ_u at q.
    pub(super) fn solve_part(
        &self,
        q: &mut [f64],
        w: &mut Work,
        options: &Options,
        (rows, cols): (&[usize], &[usize]),
        block: bool,
    ) -> Result<(), Error> {
        let (nd, m) = (self.drivers, cols.len());
        let closing = w.closing;
        let mut space = core::mem::take(&mut w.space);
        let Part {
            u,
            phi,
            row,
            weights,
            start,
            step,
            origin,
        } = &mut space;
        for (x, &c) in u.iter_mut().zip(cols) {
            *x = q[nd + c];
        }
        for ((s, wt), &r) in row.iter_mut().zip(weights.iter_mut()).zip(rows) {
            *s = w.rows[r];
            *wt = w.weights[r];
        }
        let mut system = Subsystem {
            m: self,
            q: &mut *q,
            w: &mut *w,
            rows,
            cols,
            threshold: options.singularity_threshold,
        };
        let scratch = Space {
            row: &row[..m],
            weights: &weights[..m],
            start: &mut start[..m],
            step: &mut step[..m],
        };
        let solved = if block {
            // A block of an assembly in closed form and by Newton–Raphson:
            // its common path to the tolerance, at most 1e-12.
            let fine = Options {
                tolerance: options.tolerance.min(1e-12),
                ..*options
            };
            let judge = (Judge::Assess, &fine);
            fast_then_damped(
                &mut system,
                &mut u[..m],
                &mut phi[..m],
                scratch,
                &mut origin[..m],
                judge,
                options,
            )
        } else if closing {
            let judge = (Judge::Closing, options);
            fast_then_damped(
                &mut system,
                &mut u[..m],
                &mut phi[..m],
                scratch,
                &mut origin[..m],
                judge,
                options,
            )
        } else {
            iterate(&mut system, &mut u[..m], &mut phi[..m], scratch, options)
        };
        w.space = space;
        solved.map(|_| ()).map_err(|f| {
            describe_by(
                f.in_subsystem(rows, cols),
                |u| self.coordinates.get(nd + u).map_or("?", |c| c.name),
                |e| self.equations.get(e).copied().unwrap_or("?"),
                self.configuration(q),
            )
        })
    }

    pub(super) fn configuration(&self, q: &[f64]) -> crate::names::Configuration {
        self.coordinates
            .iter()
            .zip(q)
            .map(|(c, &v)| (c.name, v))
            .collect()
    }

    /// Φ_u at q factored into `w.lu` and `w.perm` (for the velocity and
    /// acceleration solves), its conditioning judged as the generated code
    /// judges it (block by block, the least conditioning of the scaled
    /// diagonal blocks) and the sign of det Φ_u (the positive row and
    /// column scales do not change it); or [`Error::Singular`]. With
    /// `evaluated`, `w` already holds the scaling and Φ, Φ_u at q (as
    /// `solve` leaves them).
    pub(super) fn factor(
        &self,
        q: &[f64],
        w: &mut Work,
        options: &Options,
        evaluated: bool,
    ) -> Result<(f64, f64), Error> {
        let nu = self.unknowns();
        let length = if evaluated {
            w.params[self.params.len()]
        } else {
            let length = self.scaling(q, w, options);
            self.newton_eval(q, w);
            length
        };
        let sign = det_sign(w, nu);
        let (mut conditioning_min, mut at) = (f64::INFINITY, 0);
        for (rows, cols) in &self.blocks {
            let m = cols.len();
            for (a, &r) in rows.iter().enumerate() {
                for (b, &c) in cols.iter().enumerate() {
                    // Φ_u scaled: rows by 1/S_i, length columns by L.
                    let col = if self.length_unknowns[c] { length } else { 1.0 };
                    w.sub[a * m + b] = w.jac[r * nu + c] * w.rows[r] * col;
                }
            }
            let (c, local) = conditioning(
                &mut w.sub[..m * m],
                m,
                &mut w.sub_perm[..m],
                [&mut w.col[..m], &mut w.unit[..m], &mut w.sums[..m]],
            );
            if c < conditioning_min {
                conditioning_min = c;
                at = cols.get(local).copied().unwrap_or(0);
            }
        }
        let conditioning = if nu == 0 { 1.0 } else { conditioning_min };
        if conditioning > options.singularity_threshold && sign != 0.0 {
            Ok((conditioning, sign))
        } else {
            Err(Error::Singular {
                unknown: self.coordinates[self.drivers + at].name,
                conditioning,
                configuration: self.configuration(q),
            })
        }
    }

    /// The motion at the closed pose `q`, into `out` (of the model's
    /// shape, from [`Model::shaped_motion`]): Φ_u factored, q' and q''
    /// solved, every point and frame evaluated, every output checked
    /// finite. `evaluated` as for [`Model::factor`].
    #[allow(clippy::too_many_arguments)]
    pub(super) fn analyze_into(
        &self,
        q: &[f64],
        rates: &[f64],
        accelerations: &[f64],
        w: &mut Work,
        options: &Options,
        evaluated: bool,
        out: &mut Motion,
    ) -> Result<(), Error> {
        let (nd, nu) = (self.drivers, self.unknowns());
        let (conditioning, det_sign) = self.factor(q, w, options, evaluated)?;
        let residual = w
            .phi
            .iter()
            .zip(&w.rows)
            .map(|(p, s)| (p * s).abs())
            .fold(0.0f64, f64::max);
        out.q.copy_from_slice(q);
        out.qd[..nd].copy_from_slice(rates);
        out.qdd[..nd].copy_from_slice(accelerations);
        out.qd[nd..].fill(0.0);
        out.qdd[nd..].fill(0.0);
        // `factor` left the cosines and sines at q.
        self.eval(
            Program::VELOCITY,
            &w.params,
            q,
            &out.qd,
            &out.qdd,
            &w.trig,
            &mut w.rhs,
        );
        lu_apply(&w.lu, &w.perm, &w.rhs, &mut out.qd[nd..], nu);
        self.eval(
            Program::ACCELERATION,
            &w.params,
            q,
            &out.qd,
            &out.qdd,
            &w.trig,
            &mut w.rhs,
        );
        lu_apply(&w.lu, &w.perm, &w.rhs, &mut out.qdd[nd..], nu);
        self.eval(
            Program::OUTPUTS,
            &w.params,
            q,
            &out.qd,
            &out.qdd,
            &w.trig,
            &mut w.out,
        );
        self.write_outputs(&w.out, out);
        out.conditioning = conditioning;
        out.det_sign = det_sign;
        out.residual = residual;
        for (j, c) in self.coordinates.iter().enumerate() {
            let (v, a) = (out.qd[j], out.qdd[j]);
            if !(v.is_finite() && a.is_finite()) {
                return Err(Error::NonFinite {
                    input: Input::Computed,
                    name: c.name,
                    value: if v.is_finite() { a } else { v },
                });
            }
        }
        if let Some(bad) = w.out.iter().position(|v| !v.is_finite()) {
            let d = self.point_dim;
            let point = bad / (3 * d);
            let name = self
                .points
                .get(point)
                .or_else(|| self.frames.get((bad - self.points.len() * 3 * d) / 24))
                .copied()
                .unwrap_or("");
            return Err(Error::NonFinite {
                input: Input::Computed,
                name,
                value: w.out[bad],
            });
        }
        Ok(())
    }

    /// The points and frames of `motion` from the values of the
    /// [`Program::OUTPUTS`] stage, `values`.
    #[inline]
    pub(super) fn write_outputs(&self, values: &[f64], motion: &mut Motion) {
        let d = self.point_dim;
        if d == 2 {
            // Planar points, written element by element.
            for (p, c) in motion.points.iter_mut().zip(values.chunks_exact(6)) {
                if let [r0, r1, v0, v1, a0, a1] = *c {
                    p.position = Vector::from([r0, r1]);
                    p.velocity = Vector::from([v0, v1]);
                    p.acceleration = Vector::from([a0, a1]);
                }
            }
        } else if d == 3 {
            // Spatial points, likewise.
            for (p, c) in motion.points.iter_mut().zip(values.chunks_exact(9)) {
                if let [r0, r1, r2, v0, v1, v2, a0, a1, a2] = *c {
                    p.position = Vector::from([r0, r1, r2]);
                    p.velocity = Vector::from([v0, v1, v2]);
                    p.acceleration = Vector::from([a0, a1, a2]);
                }
            }
        }
        let frames = values.get(self.points.len() * 3 * d..).unwrap_or(&[]);
        for (fr, f) in motion.frames.iter_mut().zip(frames.chunks_exact(24)) {
            if let Ok(values) = <&[f64; 24]>::try_from(f) {
                *fr = FrameState::from_values(values);
            }
        }
    }

    /// The values of the [`Program::OUTPUTS`] stage that `motion` holds,
    /// into `values` (the inverse of [`Model::write_outputs`]).
    pub(super) fn flatten_outputs(&self, motion: &Motion, values: &mut Vec<f64>) {
        values.clear();
        for p in &motion.points {
            values.extend_from_slice(&p.position);
            values.extend_from_slice(&p.velocity);
            values.extend_from_slice(&p.acceleration);
        }
        for f in &motion.frames {
            values.extend(f.rotation.transpose().iter());
            values.extend(f.angular_velocity.iter());
            values.extend(f.angular_acceleration.iter());
            values.extend(f.origin.iter());
            values.extend(f.velocity.iter());
            values.extend(f.acceleration.iter());
        }
    }

    /// The positions of every point at q into `out` (`point_dim` values
    /// per point), each checked finite; with `trig`, the cosines and sines
    /// of q are evaluated first (else `w` holds them, as an assembly
    /// leaves them).
    pub(super) fn positions_into(
        &self,
        q: &[f64],
        w: &mut Work,
        trig: bool,
        out: &mut [f64],
    ) -> Result<(), Error> {
        let d = self.point_dim;
        if trig {
            self.program.trig(q, &mut w.trig, 0);
        }
        self.eval(
            Program::OUTPUTS,
            &w.params,
            q,
            &w.zeros,
            &w.zeros,
            &w.trig,
            &mut w.out,
        );
        for (o, c) in out.chunks_exact_mut(d).zip(w.out.chunks_exact(3 * d)) {
            o.copy_from_slice(&c[..d]);
        }
        match out.iter().position(|v| !v.is_finite()) {
            Some(bad) => Err(Error::NonFinite {
                input: Input::Computed,
                name: self.points[bad / d],
                value: out[bad],
            }),
            None => Ok(()),
        }
    }

    /// [`Model::analyze_into`] into a new motion.
    pub(super) fn analyze_at(
        &self,
        q: &[f64],
        rates: &[f64],
        accelerations: &[f64],
        w: &mut Work,
        options: &Options,
        evaluated: bool,
    ) -> Result<Motion, Error> {
        let mut out = self.shaped_motion();
        self.analyze_into(q, rates, accelerations, w, options, evaluated, &mut out)?;
        Ok(out)
    }
}

/// The sign of det Φ_u (Φ_u as [`Model::newton_eval`] left it in `w`),
/// 0 when it is singular; Φ_u factored into `w`'s LU arrays.
pub(super) fn det_sign(w: &mut Work, nu: usize) -> f64 {
    w.lu.copy_from_slice(&w.jac);
    match lu(&mut w.lu, &mut w.perm, nu) {
        Some(mut sign) => {
            for i in 0..nu {
                if w.lu[i * nu + i] < 0.0 {
                    sign = -sign;
                }
            }
            sign
        }
        None => 0.0,
    }
}

/// Φ_u (as [`Model::newton_eval`] left it in `w`) factored into `w`'s LU
/// arrays; `false` when it is singular.
pub(super) fn factor_jacobian(w: &mut Work, nu: usize) -> bool {
    w.lu.copy_from_slice(&w.jac);
    lu(&mut w.lu, &mut w.perm, nu).is_some()
}

/// x with Φ_u x = b, from the factors of [`factor_jacobian`]; `None`
/// when x is not finite.
pub(super) fn apply_factors(w: &Work, b: &[f64], nu: usize) -> Option<Vec<f64>> {
    let mut x = vec![0.0; nu];
    lu_apply(&w.lu, &w.perm, b, &mut x, nu);
    x.iter().all(|v| v.is_finite()).then_some(x)
}
