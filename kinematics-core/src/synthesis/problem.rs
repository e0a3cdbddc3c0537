//! The least-squares problem handed to Levenberg–Marquardt: the free
//! variables mapped into their bounds, the residuals at the targets, and
//! their exact Jacobian from the mechanism's sensitivities.

use core::cell::{Cell, RefCell};
use core::f64::consts::{PI, TAU};
use std::vec;
use std::vec::Vec;

use levenberg_marquardt::LeastSquaresProblem;
use nalgebra_lm::{DMatrix, DVector, Dyn, storage::Owned};

use crate::error::Error;
use crate::mechanism::Kind;

use super::design::{Output, Synthesis, Timing};
use super::subject::{Solved, Subject};

/// The bounded parameter p for the free variable x.
fn from_free(x: f64, (lo, hi): (f64, f64)) -> (f64, f64) {
    match (lo.is_finite(), hi.is_finite()) {
        (true, true) => (
            lo + (hi - lo) * 0.5 * (1.0 + (x).sin()),
            (hi - lo) * 0.5 * (x).cos(),
        ),
        (true, false) => {
            let r = (x * x + 1.0).sqrt();
            (lo - 1.0 + r, x / r)
        }
        (false, true) => {
            let r = (x * x + 1.0).sqrt();
            (hi + 1.0 - r, -x / r)
        }
        (false, false) => (x, 1.0),
    }
}

/// The free variable x of the bounded parameter p (p clamped into the
/// bounds).
pub(super) fn to_free(p: f64, (lo, hi): (f64, f64)) -> f64 {
    match (lo.is_finite(), hi.is_finite()) {
        (true, true) => {
            let t = (2.0 * (p - lo) / (hi - lo) - 1.0).clamp(-1.0, 1.0);
            (t).asin()
        }
        (true, false) => {
            let r = (p - lo + 1.0).max(1.0);
            (r * r - 1.0).sqrt()
        }
        (false, true) => {
            let r = (hi + 1.0 - p).max(1.0);
            -(r * r - 1.0).sqrt()
        }
        (false, false) => p,
    }
}

pub(super) fn norm(v: &[f64]) -> f64 {
    crate::math::sqrt(v.iter().map(|x| x * x).sum())
}

/// An angle difference in (−π, π].
fn wrapped(d: f64) -> f64 {
    PI - (PI - d).rem_euclid(TAU)
}

/// The least-squares problem handed to the solver.
pub(super) struct Problem<'s, M: Subject> {
    pub(super) s: &'s Synthesis<M>,
    pub(super) n: usize,
    pub(super) x: Vec<f64>,
    /// The weight of the inequality residuals.
    pub(super) weight: f64,
    /// The size of the residual vector returned for a design that cannot
    /// be assembled (larger than any the solver has accepted).
    pub(super) reject: f64,
    /// The last pose of each target (the guess of the next analysis).
    pub(super) poses: RefCell<Vec<M::Pose>>,
    /// The analysis at each target (kept from evaluation to evaluation).
    pub(super) solved: RefCell<Vec<Solved>>,
    /// The assembly modes (as the step state holds them).
    pub(super) modes: Vec<f64>,
    pub(super) evaluations: Cell<usize>,
    pub(super) jacobians: Cell<usize>,
    pub(super) rejected: Cell<usize>,
}

impl<M: Subject> Problem<'_, M> {
    /// The design and driver values at x.
    pub(super) fn design_at(&self, x: &[f64]) -> (M, Vec<f64>) {
        let s = self.s;
        let mut design = s.design.clone();
        for (i, &k) in s.varied.iter().enumerate() {
            design.set_parameter_at(k, from_free(x[i], s.bounds[k]).0);
        }
        let t = &x[s.varied.len()..];
        let values = match &s.timing {
            Timing::Free => t.to_vec(),
            Timing::Prescribed(v) => v.clone(),
            Timing::Relative(v) => v.iter().map(|d| t[0] + d).collect(),
        };
        (design, values)
    }

    /// The largest violation of a linear inequality or of the order of
    /// the driver values.
    pub(super) fn violation(&self) -> f64 {
        let (design, values) = self.design_at(&self.x);
        let linear = self
            .s
            .linear
            .iter()
            .map(|(terms, h)| {
                terms
                    .iter()
                    .map(|&(k, c)| c * design.parameter_at(k))
                    .sum::<f64>()
                    - h
            })
            .fold(0.0f64, f64::max);
        self.order_gaps(&values)
            .into_iter()
            .map(|(g, _, _)| g)
            .fold(linear, f64::max)
    }

    /// With ordered free timing, for each target j the inequality
    /// φ_j − φ_{j+1} ≤ 0 (the last against φ₁ + 2π for an angle driver,
    /// none for a length driver) as (its left side, j, the index of the
    /// other value); empty otherwise.
    fn order_gaps(&self, values: &[f64]) -> Vec<(f64, usize, usize)> {
        let s = self.s;
        if !s.ordered || s.timing != Timing::Free {
            return Vec::new();
        }
        let n = values.len();
        (0..n)
            .filter_map(|j| {
                if j + 1 < n {
                    Some((values[j] - values[j + 1], j, j + 1))
                } else if s.driver_is_angle() && n > 1 {
                    Some((values[j] - values[0] - s.order_span, j, 0))
                } else {
                    None
                }
            })
            .collect()
    }

    /// √w_j of target j.
    fn root_weight(&self, j: usize) -> f64 {
        self.s
            .weights
            .as_ref()
            .map_or(1.0, |w| w.get(j).copied().unwrap_or(1.0).sqrt())
    }

    /// E, the largest error and each target's error (not weighted) from
    /// the residuals (the inequality residuals left out).
    pub(super) fn errors(&self, res: &[f64]) -> (f64, f64, Vec<f64>) {
        let d = self.s.dim;
        let fit = &res[..self.n * d];
        let e = fit.iter().map(|r| r * r).sum();
        let each: Vec<f64> = fit
            .chunks(d)
            .enumerate()
            .map(|(j, r)| {
                let w = self.root_weight(j);
                if w > 0.0 { norm(r) / w } else { f64::NAN }
            })
            .collect();
        let worst = each
            .iter()
            .copied()
            .filter(|e| !e.is_nan())
            .fold(0.0f64, f64::max);
        (e, worst, each)
    }

    /// The residuals at x and, if `jacobian`, the Jacobian (row-major,
    /// residuals × unknowns).
    pub(super) fn evaluate(
        &self,
        x: &[f64],
        jacobian: bool,
    ) -> Result<(Vec<f64>, Vec<f64>), Error> {
        let s = self.s;
        let (n, d, nv) = (self.n, s.dim, s.varied.len());
        let nx = x.len();
        let (design, values) = self.design_at(x);
        let nrows = self.rows();
        let mut res = vec![0.0; nrows];
        let mut jac = if jacobian {
            vec![0.0; nrows * nx]
        } else {
            Vec::new()
        };
        let ncoord = s.shape.coordinates.len();
        let (npoints, dim) = (s.shape.points.len(), s.shape.point_dim);
        let dpdx: Vec<f64> = s
            .varied
            .iter()
            .enumerate()
            .map(|(i, &k)| from_free(x[i], s.bounds[k]).1)
            .collect();
        // A fresh state for the design (its scaling and the sines and
        // cosines of its parameters), in the modes of the synthesis.
        let mut fresh = design.state(&s.options)?;
        M::modes(&mut fresh).copy_from_slice(&self.modes);
        let mut poses = self.poses.borrow_mut();
        for (pose, &v) in poses.iter_mut().zip(&values) {
            M::set_coordinate(pose, s.driver, v);
        }
        let mut all = self.solved.borrow_mut();
        design.solve_each(&mut poses, s.driver, &fresh, jacobian, &mut all)?;
        for (j, solved) in all.iter().enumerate() {
            // ∂(output)/∂φ_j and ∂(output)/∂p_k per component, each
            // row times √w_j.
            let w = self.root_weight(j);
            for c in 0..d {
                let row = j * d + c;
                // What the row compares: a point's component, or a
                // coordinate (times ℓ for a body's angle).
                let (point, coordinate) = match s.output {
                    Output::Point(i) => (Some(i), None),
                    Output::Coordinate(i, _) => (None, Some((i, 1.0))),
                    Output::Motion(i, _, _) if c < dim => (Some(i), None),
                    Output::Motion(_, a, l) => (None, Some((a, l))),
                };
                let (value, rate) = match (point, coordinate) {
                    (Some(i), _) => (
                        solved.positions[i * dim + c],
                        solved.velocities[i * dim + c],
                    ),
                    (None, Some((i, l))) => (
                        l * solved.q.get(i).copied().unwrap_or(f64::NAN),
                        l * solved.qd.get(i).copied().unwrap_or(f64::NAN),
                    ),
                    (None, None) => (f64::NAN, f64::NAN),
                };
                let target = s.targets[row];
                res[row] = w * match s.output {
                    Output::Coordinate(_, Kind::Angle) => wrapped(value - target),
                    Output::Motion(_, _, l) if c == dim => l * wrapped((value / l) - target),
                    _ => value - target,
                };
                if !jacobian {
                    continue;
                }
                let jr = &mut jac[row * nx..(row + 1) * nx];
                for (i, &k) in s.varied.iter().enumerate() {
                    let dp = match (point, coordinate) {
                        (Some(pi), _) => solved.dr[(k * npoints + pi) * dim + c],
                        (None, Some((ci, l))) => l * solved.dq[k * ncoord + ci],
                        (None, None) => f64::NAN,
                    };
                    jr[i] = w * dp * dpdx[i];
                }
                match &s.timing {
                    Timing::Free => jr[nv + j] = w * rate,
                    Timing::Relative(_) => jr[nv] = w * rate,
                    Timing::Prescribed(_) => {}
                }
            }
        }
        for (l, (terms, h)) in s.linear.iter().enumerate() {
            let row = n * d + l;
            let g = terms
                .iter()
                .map(|&(k, c)| c * design.parameter_at(k))
                .sum::<f64>()
                - h;
            if g > 0.0 {
                res[row] = self.weight * g;
                if jacobian {
                    for &(k, c) in terms {
                        if let Some(i) = s.varied.iter().position(|&v| v == k) {
                            jac[row * nx + i] += self.weight * c * dpdx[i];
                        }
                    }
                }
            }
        }
        let first = n * d + s.linear.len();
        for (l, (g, j, k)) in self.order_gaps(&values).into_iter().enumerate() {
            let row = first + l;
            if g > 0.0 {
                res[row] = self.weight * g;
                if jacobian {
                    jac[row * nx + nv + j] += self.weight;
                    jac[row * nx + nv + k] -= self.weight;
                }
            }
        }
        if res.iter().chain(&jac).any(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                input: crate::Input::Computed,
                name: "synthesis residual",
                value: f64::NAN,
            });
        }
        Ok((res, jac))
    }

    fn rows(&self) -> usize {
        let ordered = self.s.ordered && self.s.timing == Timing::Free;
        self.n * self.s.dim + self.s.linear.len() + if ordered { self.n } else { 0 }
    }
}

impl<M: Subject> LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, M> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.x = x.iter().copied().collect();
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_column_slice(&self.x)
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.evaluations.set(self.evaluations.get() + 1);
        let rows = self.rows();
        match self.evaluate(&self.x, false) {
            Ok((r, _)) => Some(DVector::from_vec(r)),
            // A design that does not assemble: a residual larger than any
            // accepted, so that the step is rejected.
            #[allow(clippy::cast_precision_loss)]
            Err(_) => {
                self.rejected.set(self.rejected.get() + 1);
                Some(DVector::from_element(
                    rows,
                    self.reject / (rows as f64).sqrt(),
                ))
            }
        }
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        self.jacobians.set(self.jacobians.get() + 1);
        let (_, j) = self.evaluate(&self.x, true).ok()?;
        Some(DMatrix::from_row_slice(self.rows(), self.x.len(), &j))
    }
}
