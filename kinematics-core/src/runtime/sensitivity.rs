//! Design sensitivities of run-time models: the derivatives of a solved
//! motion with respect to the parameters of the `sensitivities { … }`
//! section, from the exact partial derivatives the compiler finds for the
//! macro, evaluated by a machine-code stage of their own.

use alloc::vec;
use alloc::vec::Vec;

use kinematics_jit::Program;

use super::solve::{apply_factors, factor_jacobian};
use super::{Model, Motion, PointState, Sweep, Vector};
use crate::error::{Error, Input};
use crate::names::Name;
use crate::options::Options;
use crate::tolerance::{Deviation, deviations_by};

/// The derivatives of a motion with respect to one parameter p: of the
/// coordinates, their rates and accelerations (zero for the drivers), and
/// of every point's position, velocity and acceleration, in the point's
/// units per unit of the parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensitivity {
    /// The parameter p.
    pub parameter: Name,
    /// ∂q/∂p, drivers first.
    pub q: Vec<f64>,
    /// ∂q'/∂p.
    pub qd: Vec<f64>,
    /// ∂q''/∂p.
    pub qdd: Vec<f64>,
    /// ∂r/∂p, ∂v/∂p and ∂a/∂p of every point, in declaration order.
    pub points: Vec<PointState>,
}

impl Model {
    /// The parameters of the definition's `sensitivities` section, in its
    /// order (empty without one).
    #[must_use]
    pub fn sensitivity_parameters(&self) -> &[Name] {
        &self.sensitivity_params
    }

    /// Design sensitivities of `motion` (a solved motion of this model,
    /// from `step`, `analyze`, a stepper or a sweep), as a generated
    /// mechanism's `sensitivities` gives them: for each parameter p of the
    /// `sensitivities` section, ∂u/∂p from Φ_u ∂u/∂p = −Φ_p, ∂u'/∂p from
    /// Φ_u ∂u'/∂p = −(V_p + V_u ∂u/∂p) and ∂u''/∂p from
    /// Φ_u ∂u''/∂p = −(A_p + A_u ∂u/∂p + A_u' ∂u'/∂p), with V = Φ_q q' and
    /// A = Φ_q q'' + (Φ_q q')_q q'; and every point's
    /// ∂r/∂p = r_p + r_u ∂u/∂p, ∂v/∂p = v_p + v_u ∂u/∂p + v_u' ∂u'/∂p and
    /// ∂a/∂p likewise. Every partial derivative is exact; the solves share
    /// one factorisation of Φ_u. Empty for a definition without a
    /// `sensitivities` section.
    ///
    /// ```
    /// use kinematics_core::runtime::Model;
    /// let mut m = Model::compile(
    ///     "struct Crank {
    ///          params   { a }
    ///          drivers  { phi }
    ///          unknowns { }
    ///          points   { B = polar(a, phi); }
    ///          sensitivities { a }
    ///      }",
    /// )?;
    /// m.set_values(&[0.1])?;
    /// let s = m.step(&[0.5], &[2.0], &[0.0])?;
    /// let ds = m.sensitivities(&s)?;
    /// // ∂B/∂a = (cos φ, sin φ), ∂v_B/∂a = φ' (−sin φ, cos φ).
    /// let b = &ds[0].points[0];
    /// assert!((b.position[0] - 0.5f64.cos()).abs() < 1e-15);
    /// assert!((b.velocity[1] - 2.0 * 0.5f64.cos()).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] for a motion of another model,
    /// [`Error::Singular`] when Φ_u is singular at the pose,
    /// [`Error::NonFinite`] when a result is not finite, and invalid
    /// parameters.
    pub fn sensitivities(&self, motion: &Motion) -> Result<Vec<Sensitivity>, Error> {
        self.validate()?;
        let n = self.coordinates.len();
        for (what, len) in [
            ("motion's q", motion.q.len()),
            ("motion's q'", motion.qd.len()),
            ("motion's q''", motion.qdd.len()),
        ] {
            self.length(what, n, len)?;
        }
        let (nd, nu, np, dim) = (
            self.drivers,
            self.unknowns(),
            self.points.len(),
            self.point_dim,
        );
        let k = self.sensitivity_params.len();
        if k == 0 {
            return Ok(Vec::new());
        }
        let q = &motion.q;
        let mut w = self.work();
        // Φ_u factored once for the three solves of every parameter.
        self.scaling(q, &mut w, &Options::DEFAULT);
        self.newton_eval(q, &mut w);
        let mut out = vec![0.0; self.program.outputs(Program::SENSITIVITIES)];
        self.eval(
            Program::SENSITIVITIES,
            &w.params,
            q,
            &motion.qd,
            &motion.qdd,
            &w.trig,
            &mut out,
        );
        // The stage's layout (`Partials::roots`).
        let mut at = 0;
        let mut take = |len: usize| {
            let s = at;
            at += len;
            s
        };
        let (phi_p, vel_p, vel_u) = (take(k * nu), take(k * nu), take(nu * nu));
        let (acc_p, acc_u, acc_ud) = (take(k * nu), take(nu * nu), take(nu * nu));
        let (pos_p, pos_u) = (take(k * np * dim), take(np * dim * nu));
        let (vel_pt_p, vel_pt_u, vel_pt_ud) =
            (take(k * np * dim), take(np * dim * nu), take(np * dim * nu));
        let (acc_pt_p, acc_pt_u) = (take(k * np * dim), take(np * dim * nu));
        let (acc_pt_ud, acc_pt_udd) = (take(np * dim * nu), take(np * dim * nu));
        // Σ_j m[row][j] x[j] for a row-major block of `nu` columns at `base`.
        let dot = |base: usize, row: usize, x: &[f64]| -> f64 {
            x.iter()
                .enumerate()
                .map(|(j, v)| out[base + row * nu + j] * v)
                .sum()
        };
        let singular = || Error::Singular {
            unknown: self.coordinates[nd.min(n - 1)].name,
            conditioning: 0.0,
            configuration: self.configuration(q),
        };
        if !factor_jacobian(&mut w, nu) {
            return Err(singular());
        }
        let mut all = Vec::with_capacity(k);
        for (p, &parameter) in self.sensitivity_params.iter().enumerate() {
            let rhs: Vec<f64> = (0..nu).map(|i| -out[phi_p + p * nu + i]).collect();
            let s = apply_factors(&w, &rhs, nu).ok_or_else(singular)?;
            let rhs: Vec<f64> = (0..nu)
                .map(|i| -(out[vel_p + p * nu + i] + dot(vel_u, i, &s)))
                .collect();
            let sd = apply_factors(&w, &rhs, nu).ok_or_else(singular)?;
            let rhs: Vec<f64> = (0..nu)
                .map(|i| -(out[acc_p + p * nu + i] + dot(acc_u, i, &s) + dot(acc_ud, i, &sd)))
                .collect();
            let sdd = apply_factors(&w, &rhs, nu).ok_or_else(singular)?;
            let points = (0..np)
                .map(|pt| {
                    let c = |cc: usize| pt * dim + cc;
                    let kp = |cc: usize| (p * np + pt) * dim + cc;
                    PointState {
                        position: Vector::from_fn(dim, |cc| {
                            out[pos_p + kp(cc)] + dot(pos_u, c(cc), &s)
                        }),
                        velocity: Vector::from_fn(dim, |cc| {
                            out[vel_pt_p + kp(cc)]
                                + dot(vel_pt_u, c(cc), &s)
                                + dot(vel_pt_ud, c(cc), &sd)
                        }),
                        acceleration: Vector::from_fn(dim, |cc| {
                            out[acc_pt_p + kp(cc)]
                                + dot(acc_pt_u, c(cc), &s)
                                + dot(acc_pt_ud, c(cc), &sd)
                                + dot(acc_pt_udd, c(cc), &sdd)
                        }),
                    }
                })
                .collect::<Vec<_>>();
            let with_drivers = |x: Vec<f64>| -> Vec<f64> {
                let mut v = vec![0.0; nd];
                v.extend(x);
                v
            };
            let one = Sensitivity {
                parameter,
                q: with_drivers(s),
                qd: with_drivers(sd),
                qdd: with_drivers(sdd),
                points,
            };
            let sum: f64 = one
                .q
                .iter()
                .chain(&one.qd)
                .chain(&one.qdd)
                .chain(
                    one.points
                        .iter()
                        .flat_map(|p| p.position.iter().chain(&p.velocity).chain(&p.acceleration)),
                )
                .sum();
            if !sum.is_finite() {
                return Err(Error::NonFinite {
                    input: Input::Computed,
                    name: parameter,
                    value: sum,
                });
            }
            all.push(one);
        }
        Ok(all)
    }

    /// The first-order deviations of point `point` over the run-time
    /// sweep `sweep` for the parameter tolerances `tolerances` (name, ±t),
    /// as [`point_deviations`](crate::tolerance::point_deviations) gives
    /// them for a generated mechanism (the same formulas, worst case and
    /// root-sum-square; see [`tolerance`](crate::tolerance)), from
    /// [`Model::sensitivities`] at each sample.
    ///
    /// # Errors
    /// As [`point_deviations`](crate::tolerance::point_deviations).
    pub fn point_deviations(
        &self,
        sweep: &Sweep,
        point: &str,
        tolerances: &[(&str, f64)],
    ) -> Result<Vec<Deviation>, Error> {
        self.point_deviations_over(
            sweep.samples.len(),
            |i, motion| {
                let sample = &sweep.samples[i];
                motion.clone_from(&sample.motion);
                sample.at
            },
            point,
            tolerances,
        )
    }

    /// [`Model::point_deviations`] over `samples` motions of this model
    /// kept elsewhere than in a [`Sweep`] (in columns, say): `motion(i,
    /// buffer)` writes sample i's motion into `buffer` and returns its
    /// swept value.
    ///
    /// # Errors
    /// As [`point_deviations`](crate::tolerance::point_deviations), and
    /// as [`Model::sensitivities`] for each motion.
    pub fn point_deviations_over(
        &self,
        samples: usize,
        mut motion: impl FnMut(usize, &mut Motion) -> f64,
        point: &str,
        tolerances: &[(&str, f64)],
    ) -> Result<Vec<Deviation>, Error> {
        let mut buffer = self.shaped_motion();
        deviations_by(
            (&self.points, &self.sensitivity_params, self.point_dim),
            point,
            tolerances,
            samples,
            |i, buf| {
                let at = motion(i, &mut buffer);
                let all = self.sensitivities(&buffer)?;
                let values = all.iter().flat_map(|one| {
                    one.points.iter().flat_map(|p| {
                        p.position
                            .iter()
                            .chain(&p.velocity)
                            .chain(&p.acceleration)
                            .copied()
                    })
                });
                for (b, v) in buf.iter_mut().zip(values) {
                    *b = v;
                }
                Ok(at)
            },
        )
    }
}
