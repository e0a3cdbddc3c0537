//! An implicit integrator for stiff motions (stiff springs, large
//! damping, a steep motor curve): TR-BDF2, the L-stable one-step method
//! of Bank et al. in the form of Hosea and Shampine (MATLAB's `ode23tb`),
//! with its embedded third-order error estimate and a cubic Hermite
//! interpolant between the ends of a step.
//!
//! With γ = 2 − √2, d = γ/2 and w = √2/4, a step of size h from (t, y)
//! solves, by Newton's method with the iteration matrix I − d h J (J the
//! Jacobian of the controlled components by finite differences, kept
//! while it serves),
//!
//! z − d h f(t + γh, z) = y + d h f(t, y)                  (trapezoidal),
//! y₁ − d h f(t + h, y₁) = y + w h (f(t, y) + f(t + γh, z)) (BDF2),
//!
//! and estimates the error as (I − d h J)⁻¹ h [((1 − w)/3 − w) f₀ +
//! ((3w + 1)/3 − w) f_γ + (d/3 − d) f₁], the difference from the
//! third-order formula on the same stages, filtered as Hosea and Shampine
//! do so that it stays bounded where the motion is stiff. The step grows
//! or shrinks by 0.9 ‖e‖^(−1/3), between h/5 and 5 h. The components past
//! the controlled ones (the works) are quadratures of the same stages.

use alloc::vec;
use alloc::vec::Vec;

use super::ode::{Stepped, System, Tolerances};
use crate::error::Error;
use crate::math;
use crate::solve::dense::{lu, lu_apply};

const GAMMA: f64 = 2.0 - core::f64::consts::SQRT_2;
const D: f64 = GAMMA / 2.0;
const W: f64 = core::f64::consts::SQRT_2 / 4.0;
/// The weights of the error estimate: the third-order formula's less
/// the method's.
const E: [f64; 3] = [(1.0 - W) / 3.0 - W, (3.0 * W + 1.0) / 3.0 - W, D / 3.0 - D];

/// The state of a TR-BDF2 integration.
pub(crate) struct TrBdf2 {
    n: usize,
    c: usize,
    pub(crate) t: f64,
    pub(crate) y: Vec<f64>,
    pub(crate) t_old: f64,
    y_old: Vec<f64>,
    /// f at (t_old, y_old) and at (t, y), for the interpolant.
    f_old: Vec<f64>,
    f: Vec<f64>,
    f_gamma: Vec<f64>,
    z: Vec<f64>,
    y_new: Vec<f64>,
    f_new: Vec<f64>,
    work: Vec<f64>,
    delta: Vec<f64>,
    /// The Jacobian of the controlled components (c × c), current or not.
    jacobian: Vec<f64>,
    fresh: bool,
    /// The iteration matrix's factors, for the step size `h_lu`.
    lu: Vec<f64>,
    perm: Vec<usize>,
    h_lu: f64,
    h: f64,
    tolerances: Tolerances,
    pub(crate) max_step: f64,
    pub(crate) evaluations: usize,
    pub(crate) accepted: usize,
    pub(crate) rejected: usize,
    pub(crate) refused: Option<Error>,
}

impl TrBdf2 {
    /// An integrator for `system` from (t0, y0), its first step 1e-3 of
    /// the time to the scale of the motion (|y|/|f|), at most `max_step`.
    ///
    /// # Errors
    /// The system's error at (t0, y0).
    pub(crate) fn new<S: System>(
        system: &mut S,
        t0: f64,
        y0: &[f64],
        tolerances: Tolerances,
        max_step: f64,
    ) -> Result<Self, Error> {
        let (n, c) = (system.len(), system.controlled());
        let zeros = |k: usize| vec![0.0; k];
        let mut me = TrBdf2 {
            n,
            c,
            t: t0,
            y: y0.to_vec(),
            t_old: t0,
            y_old: y0.to_vec(),
            f_old: zeros(n),
            f: zeros(n),
            f_gamma: zeros(n),
            z: zeros(n),
            y_new: zeros(n),
            f_new: zeros(n),
            work: zeros(n),
            delta: zeros(n),
            jacobian: zeros(c * c),
            fresh: false,
            lu: zeros(c * c),
            perm: vec![0; c],
            h_lu: f64::NAN,
            h: 0.0,
            tolerances,
            max_step,
            evaluations: 0,
            accepted: 0,
            rejected: 0,
            refused: None,
        };
        system.rhs(t0, y0, &mut me.f)?;
        me.evaluations += 1;
        me.f_old.copy_from_slice(&me.f);
        let scale = me.norm(&me.y, &me.y);
        let rate = me.norm(&me.f, &me.y);
        me.h = if rate > 0.0 && scale > 0.0 {
            1e-3 * scale / rate
        } else {
            1e-6
        }
        .max(1e-8)
        .min(max_step);
        Ok(me)
    }

    /// The scaled norm of the controlled part of `v`, scaled at `at`.
    fn norm(&self, v: &[f64], at: &[f64]) -> f64 {
        self.tolerances.norm(v, at, at, self.c)
    }

    /// The Jacobian of the controlled components at (t, y) by forward
    /// differences, f(t, y) being `self.f`.
    fn differentiate<S: System>(&mut self, system: &mut S) -> Result<(), Error> {
        let c = self.c;
        self.work.copy_from_slice(&self.y);
        for j in 0..c {
            let scale = self.tolerances.absolute.get(j).copied().unwrap_or(0.0);
            let step = math::sqrt(f64::EPSILON) * math::abs(self.y[j]).max(scale.max(1e-8));
            self.work[j] = self.y[j] + step;
            system.rhs(self.t, &self.work, &mut self.delta)?;
            self.evaluations += 1;
            self.work[j] = self.y[j];
            for i in 0..c {
                self.jacobian[i * c + j] = (self.delta[i] - self.f[i]) / step;
            }
        }
        self.fresh = true;
        self.h_lu = f64::NAN;
        Ok(())
    }

    /// Factors I − d h J (once per step size).
    fn factor(&mut self, h: f64) -> bool {
        if self.h_lu == h {
            return true;
        }
        let c = self.c;
        for i in 0..c {
            for j in 0..c {
                let identity = if i == j { 1.0 } else { 0.0 };
                self.lu[i * c + j] = identity - D * h * self.jacobian[i * c + j];
            }
        }
        self.h_lu = h;
        lu(&mut self.lu, &mut self.perm, c).is_some()
    }

    /// Solves `x − d h f(t1, x) = base` by Newton's method from the value
    /// in `x`, f at the solution into `fx`; `Ok(false)` when it does not
    /// converge in six iterations.
    // The loops run over several arrays at once, by index.
    #[allow(clippy::needless_range_loop)]
    fn newton<S: System>(
        &mut self,
        system: &mut S,
        t1: f64,
        h: f64,
        (x, fx, base): (&mut [f64], &mut [f64], &[f64]),
    ) -> Result<bool, Error> {
        let c = self.c;
        let mut last = f64::INFINITY;
        for _ in 0..6 {
            system.rhs(t1, x, fx)?;
            self.evaluations += 1;
            for i in 0..c {
                self.work[i] = -(x[i] - D * h * fx[i] - base[i]);
            }
            lu_apply(
                &self.lu,
                &self.perm,
                &self.work[..c],
                &mut self.delta[..c],
                c,
            );
            for i in 0..c {
                x[i] += self.delta[i];
            }
            let size = self.norm(&self.delta, x);
            // Diverging, or converging too slowly to be trusted: a new
            // Jacobian and a shorter step.
            if !size.is_finite() || size > 0.9 * last {
                return Ok(false);
            }
            last = size;
            if size <= 0.03 {
                system.rhs(t1, x, fx)?;
                self.evaluations += 1;
                // The quadratures follow the stage.
                for i in c..self.n {
                    x[i] = base[i] + D * h * fx[i];
                }
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// One attempt at a step of size h: the stages, and the error norm.
    #[allow(clippy::needless_range_loop)]
    fn attempt<S: System>(&mut self, system: &mut S, h: f64) -> Result<Option<f64>, Error> {
        let n = self.n;
        // The trapezoidal stage, from an Euler predictor.
        let mut base = vec![0.0; n];
        for i in 0..n {
            base[i] = self.y[i] + D * h * self.f[i];
            self.z[i] = self.y[i] + GAMMA * h * self.f[i];
        }
        let (mut z, mut fz) = (
            core::mem::take(&mut self.z),
            core::mem::take(&mut self.f_gamma),
        );
        let ok = self.newton(system, self.t + GAMMA * h, h, (&mut z, &mut fz, &base));
        (self.z, self.f_gamma) = (z, fz);
        if !ok? {
            return Ok(None);
        }
        // The BDF2 stage, from the line through y and z.
        for i in 0..n {
            base[i] = self.y[i] + W * h * (self.f[i] + self.f_gamma[i]);
            self.y_new[i] = self.y[i] + (self.z[i] - self.y[i]) / GAMMA;
        }
        let (mut y1, mut f1) = (
            core::mem::take(&mut self.y_new),
            core::mem::take(&mut self.f_new),
        );
        let ok = self.newton(system, self.t + h, h, (&mut y1, &mut f1, &base));
        (self.y_new, self.f_new) = (y1, f1);
        if !ok? {
            return Ok(None);
        }
        let c = self.c;
        for i in 0..c {
            self.work[i] = h * (E[0] * self.f[i] + E[1] * self.f_gamma[i] + E[2] * self.f_new[i]);
        }
        lu_apply(
            &self.lu,
            &self.perm,
            &self.work[..c],
            &mut self.delta[..c],
            c,
        );
        Ok(Some(self.tolerances.norm(
            &self.delta,
            &self.y,
            &self.y_new,
            c,
        )))
    }

    /// Takes one accepted step toward `t_end` (never past it).
    pub(crate) fn step<S: System>(&mut self, system: &mut S, t_end: f64) -> Stepped {
        loop {
            let room = t_end - self.t;
            let mut h = self.h.min(self.max_step);
            let last = h >= room * (1.0 - 1e-12);
            if last {
                h = room;
            }
            if h.is_nan() || h <= 1e-14 * (1.0 + math::abs(self.t)) {
                return Stepped::TooSmall;
            }
            if !self.fresh
                && let Err(e) = self.differentiate(system)
            {
                // A difference past a limit: a shorter step, which the
                // next Jacobian's differences follow.
                self.refused = Some(e);
                self.rejected += 1;
                self.h = h * 0.25;
                continue;
            }
            if !self.factor(h) {
                self.rejected += 1;
                self.h = h * 0.25;
                continue;
            }
            match self.attempt(system, h) {
                Err(e) => {
                    self.refused = Some(e);
                    self.rejected += 1;
                    self.h = h * 0.25;
                }
                Ok(None) => {
                    // Newton failed: a new Jacobian, a shorter step.
                    self.rejected += 1;
                    self.fresh = false;
                    self.h = h * 0.25;
                }
                Ok(Some(err)) if err.is_finite() && err <= 1.0 => {
                    let grow = if err > 0.0 {
                        0.9 * math::exp(-math::ln(err) / 3.0)
                    } else {
                        5.0
                    };
                    self.t_old = self.t;
                    self.y_old.copy_from_slice(&self.y);
                    self.f_old.copy_from_slice(&self.f);
                    self.t = if last { t_end } else { self.t + h };
                    self.y.copy_from_slice(&self.y_new);
                    self.f.copy_from_slice(&self.f_new);
                    // The Jacobian is kept while Newton converges.
                    self.h = h * grow.clamp(0.2, 5.0);
                    self.accepted += 1;
                    self.refused = None;
                    return Stepped::Accepted;
                }
                Ok(Some(err)) => {
                    self.rejected += 1;
                    let shrink = if err.is_finite() {
                        0.9 * math::exp(-math::ln(err) / 3.0)
                    } else {
                        0.2
                    };
                    self.h = h * shrink.clamp(0.2, 0.9);
                }
            }
        }
    }

    /// The cubic Hermite interpolant at time t within the last step.
    pub(crate) fn interpolate(&self, t: f64, out: &mut [f64]) {
        let h = self.t - self.t_old;
        let s = if h > 0.0 {
            ((t - self.t_old) / h).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let (h00, h10) = (
            (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s),
            s * (1.0 - s) * (1.0 - s),
        );
        let (h01, h11) = (s * s * (3.0 - 2.0 * s), s * s * (s - 1.0));
        for (i, o) in out.iter_mut().enumerate().take(self.n) {
            *o = h00 * self.y_old[i]
                + h10 * h * self.f_old[i]
                + h01 * self.y[i]
                + h11 * h * self.f[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::forward::ode::Dopri;

    /// A stiff damped oscillator, x'' + 2 ζ ω x' + ω² x = 0 with ω = 1000,
    /// ζ = 1000 (overdamped: rates −ω(ζ ± √(ζ² − 1)), one of them
    /// −2e6, the other about −0.5).
    struct Stiff;

    const OMEGA: f64 = 1000.0;
    const ZETA: f64 = 1000.0;

    impl System for Stiff {
        fn len(&self) -> usize {
            2
        }
        fn rhs(&mut self, _: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
            dy[0] = y[1];
            dy[1] = -2.0 * ZETA * OMEGA * y[1] - OMEGA * OMEGA * y[0];
            Ok(())
        }
    }

    /// x(t) from x(0) = 1, x'(0) = 0.
    fn exact(t: f64) -> f64 {
        let root = (ZETA * ZETA - 1.0).sqrt();
        let (r1, r2) = (-OMEGA * (ZETA - root), -OMEGA * (ZETA + root));
        // x = A e^{r1 t} + B e^{r2 t}, A + B = 1, r1 A + r2 B = 0.
        let a = r2 / (r2 - r1);
        a * (r1 * t).exp() + (1.0 - a) * (r2 * t).exp()
    }

    #[test]
    fn a_stiff_oscillator_takes_few_implicit_steps_and_follows_its_closed_form() {
        let tolerances = Tolerances {
            relative: 1e-6,
            absolute: vec![1e-9, 1e-9],
        };
        let mut implicit = TrBdf2::new(
            &mut Stiff,
            0.0,
            &[1.0, 0.0],
            tolerances.clone(),
            f64::INFINITY,
        )
        .unwrap();
        let mut out = [0.0; 2];
        let mut worst: f64 = 0.0;
        while implicit.t < 4.0 {
            assert_eq!(implicit.step(&mut Stiff, 4.0), Stepped::Accepted);
            let mid = 0.5 * (implicit.t_old + implicit.t);
            implicit.interpolate(mid, &mut out);
            worst = worst.max((implicit.y[0] - exact(implicit.t)).abs());
            if implicit.t > 1e-3 {
                worst = worst.max((out[0] - exact(mid)).abs());
            }
        }
        // The global error over the run, at the steps and between them,
        // within twenty times the local tolerance.
        assert!(worst < 2e-5, "{worst}");
        // The explicit pair is held to its stability bound, |h λ| ≲ 3.3
        // with λ = −2e6: hundreds of thousands of steps.
        let mut explicit =
            Dopri::new(&mut Stiff, 0.0, &[1.0, 0.0], tolerances, f64::INFINITY).unwrap();
        while explicit.t < 0.1 {
            assert_eq!(explicit.step(&mut Stiff, 0.1), Stepped::Accepted);
        }
        assert!(
            explicit.accepted > 100 * implicit.accepted,
            "{} explicit steps over 0.1 s, {} implicit over 4 s",
            explicit.accepted,
            implicit.accepted
        );
    }
}
