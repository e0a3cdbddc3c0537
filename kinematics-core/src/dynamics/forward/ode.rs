//! An explicit Runge–Kutta integrator with error control and dense
//! output: the Dormand–Prince pair of orders 5 and 4 (seven stages, the
//! last one reused as the first of the next step), its step size chosen
//! from the local error estimate with a PI controller, and its
//! continuous extension of order 4 between the ends of a step.
//!
//! It knows no mechanism: a [`System`] gives y' = f(t, y), and may refuse
//! a state (an error), which the integrator answers by a shorter step.
//! Its work vectors are allocated once, when it is made.
//!
//! # The method
//!
//! With the stages k_i = f(t + c_i h, y + h Σ_j a_ij k_j), the solution of
//! order 5 is y₁ = y + h Σ b_i k_i and the error estimate
//! e = h Σ (b_i − b̂_i) k_i, b̂ the weights of order 4. The error norm is
//! ‖e‖ = √(1/n Σ (e_i / s_i)²) over the controlled components, with the
//! scale s_i = atol_i + rtol · max(|y_i|, |y₁_i|); a step is accepted when
//! ‖e‖ ≤ 1. The next step is h · 0.9 · ‖e‖^(−0.17) · ‖e‖_prev^(0.04)
//! (between h/5 and 10 h). The dense output at θ ∈ [0, 1] of a step is
//! y(θ) = y₀ + θ (Δ + (1 − θ) (B + θ (Δ − h k₇ − B + (1 − θ) D))), with
//! Δ = y₁ − y₀, B = h k₁ − Δ and D = h Σ d_i k_i (Dormand and Prince's
//! fourth-order extension, as in Hairer, Nørsett and Wanner, *Solving
//! Ordinary Differential Equations I*, section II.6).

use alloc::vec;
use alloc::vec::Vec;

use crate::error::Error;
use crate::math;

/// A system of first-order equations y' = f(t, y).
pub(crate) trait System {
    /// The number of components of y.
    fn len(&self) -> usize;
    /// The number of leading components the error is controlled on (the
    /// rest are quadratures that follow the same stages).
    fn controlled(&self) -> usize {
        self.len()
    }
    /// The number of leading components f reads: the rest are
    /// quadratures f never reads, whose stages are formed only at the
    /// end of a step.
    fn inputs(&self) -> usize {
        self.len()
    }
    /// Writes f(t, y) into `dy`.
    ///
    /// # Errors
    /// A state the system cannot evaluate (the integrator retries with a
    /// shorter step).
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error>;
}

// The Dormand–Prince 5(4) tableau.
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// b − b̂: the weights of the error estimate.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339_200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// The weights of the dense output's last term.
const D: [f64; 7] = [
    -12_715_105_075.0 / 11_282_082_432.0,
    0.0,
    87_487_479_700.0 / 32_700_410_799.0,
    -10_690_763_975.0 / 1_880_347_072.0,
    701_980_252_875.0 / 199_316_789_632.0,
    -1_453_857_185.0 / 822_651_844.0,
    69_997_945.0 / 29_380_423.0,
];

/// The tolerances of the error control: component i's scale is
/// `absolute[i] + relative · max(|y_i|, |y₁_i|)`.
#[derive(Clone, Debug)]
pub(crate) struct Tolerances {
    pub(crate) relative: f64,
    /// One per controlled component.
    pub(crate) absolute: Vec<f64>,
}

impl Tolerances {
    /// The scaled root-mean-square norm of `v` over its first
    /// `controlled` components, component i scaled by
    /// `absolute[i] + relative · max(|y_i|, |y1_i|)`.
    pub(crate) fn norm(&self, v: &[f64], y: &[f64], y1: &[f64], controlled: usize) -> f64 {
        let mut sum = 0.0;
        for i in 0..controlled {
            let scale = self.absolute.get(i).copied().unwrap_or(0.0)
                + self.relative * math::abs(y[i]).max(math::abs(y1[i]));
            let x = v[i] / scale;
            sum += x * x;
        }
        #[allow(clippy::cast_precision_loss)]
        let count = controlled.max(1) as f64;
        math::sqrt(sum / count)
    }
}

/// How a call to [`Dopri::step`] ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Stepped {
    /// A step was accepted: the state is at the new time, the previous one
    /// and the dense output span the step.
    Accepted,
    /// The step size fell below the resolution of the time: the system
    /// refused every state ahead (its last error is returned with it) or
    /// the error could not be controlled.
    TooSmall,
}

/// The integrator's state: the time and solution, the last step and what
/// its dense output needs.
pub(crate) struct Dopri {
    n: usize,
    pub(crate) t: f64,
    pub(crate) y: Vec<f64>,
    /// The time and solution at the start of the last accepted step.
    pub(crate) t_old: f64,
    y_old: Vec<f64>,
    /// The seven stages by component (component i's at `k[i]`), stage 0
    /// f at (t, y).
    k: Vec<[f64; 7]>,
    stage: Vec<f64>,
    /// f at the last stage, before it is spread over `k`.
    f: Vec<f64>,
    y_new: Vec<f64>,
    /// The last accepted step's first stage, by component (its last is
    /// the next step's first, in `k`), and its size: with `k`'s other
    /// stages, what the dense output is made of, formed only where it
    /// is asked for (a sample or an event falls in one step of many).
    first: Vec<f64>,
    h_last: f64,
    h: f64,
    /// The last accepted step's error norm, at least 1e-4, raised to the
    /// PI controller's 0.04.
    previous_factor: f64,
    tolerances: Tolerances,
    /// The largest step allowed.
    pub(crate) max_step: f64,
    /// The counts of evaluations of f, of accepted and of rejected steps.
    pub(crate) evaluations: usize,
    pub(crate) accepted: usize,
    pub(crate) rejected: usize,
    /// The last error of the system, after a refused state.
    pub(crate) refused: Option<Error>,
}

impl Dopri {
    /// An integrator for `system` from (t0, y0), its first step chosen
    /// from the derivatives there (Hairer's starting step).
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
        let n = system.len();
        let zeros = || vec![0.0; n];
        let mut me = Dopri {
            n,
            t: t0,
            y: y0.to_vec(),
            t_old: t0,
            y_old: y0.to_vec(),
            k: vec![[0.0; 7]; n],
            stage: zeros(),
            f: zeros(),
            y_new: zeros(),
            first: zeros(),
            h_last: 0.0,
            h: 0.0,
            previous_factor: math::exp(0.04 * math::ln(1e-4)),
            tolerances,
            max_step,
            evaluations: 0,
            accepted: 0,
            rejected: 0,
            refused: None,
        };
        system.rhs(t0, y0, &mut me.f)?;
        me.spread(0);
        me.evaluations += 1;
        me.h = me.starting_step(system)?;
        Ok(me)
    }

    /// The scaled norm of `v` ([`Tolerances::norm`]).
    fn norm(&self, v: &[f64], y: &[f64], y1: &[f64], controlled: usize) -> f64 {
        self.tolerances.norm(v, y, y1, controlled)
    }

    /// Hairer's estimate of a first step: h₀ = 0.01 ‖y‖/‖f‖, then the
    /// step of order 5 from the change of f over h₀.
    fn starting_step<S: System>(&mut self, system: &mut S) -> Result<f64, Error> {
        let c = system.controlled();
        let d0 = self.norm(&self.y, &self.y, &self.y, c);
        let first: Vec<f64> = self.k.iter().map(|k| k[0]).collect();
        let d1 = self.norm(&first, &self.y, &self.y, c);
        let mut h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        h0 = h0.min(self.max_step);
        let mut f1 = vec![0.0; self.n];
        // A probe the system refuses (past a limit near the start) is
        // tried again ten times closer, up to six times.
        let mut tries = 0;
        loop {
            for ((s, y), k) in self.stage.iter_mut().zip(&self.y).zip(&first) {
                *s = y + h0 * k;
            }
            self.evaluations += 1;
            match system.rhs(self.t + h0, &self.stage, &mut f1) {
                Ok(()) => break,
                Err(e) if tries >= 6 => return Err(e),
                Err(_) => {
                    tries += 1;
                    h0 *= 0.1;
                }
            }
        }
        for (f, k) in f1.iter_mut().zip(&first) {
            *f -= k;
        }
        let d2 = self.norm(&f1, &self.y, &self.y, c) / h0;
        let h1 = if d1.max(d2) <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            math::exp(math::ln(0.01 / d1.max(d2)) / 5.0)
        };
        Ok((100.0 * h0).min(h1).min(self.max_step))
    }

    /// Takes one accepted step toward `t_end` (never past it), retrying
    /// with shorter steps while the error is too large or the system
    /// refuses a stage.
    pub(crate) fn step<S: System>(&mut self, system: &mut S, t_end: f64) -> Stepped {
        let controlled = system.controlled();
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
            if let Err(e) = self.stages(system, h) {
                // A stage the system refused (past a limit, a singular
                // pose): a quarter of the step.
                self.refused = Some(e);
                self.rejected += 1;
                self.h = h * 0.25;
                continue;
            }
            // The error estimate of the controlled components, in `stage`.
            let c = controlled.min(self.n);
            for (e, k) in self.stage[..c].iter_mut().zip(&self.k[..c]) {
                *e = h * combine(&E, k);
            }
            let err = self.norm(&self.stage, &self.y, &self.y_new, controlled);
            if !err.is_finite() {
                self.rejected += 1;
                self.h = h * 0.25;
                continue;
            }
            // The PI controller: exponents 1/5 − 0.75 β and β, β = 0.04
            // (ln err taken once).
            let ln_err = if err > 0.0 { math::ln(err) } else { f64::NAN };
            let fac11 = if err > 0.0 {
                math::exp(0.17 * ln_err)
            } else {
                0.0
            };
            if err <= 1.0 {
                let fac = fac11 / self.previous_factor;
                let fac = (fac / 0.9).clamp(0.1, 5.0);
                let floor = if err >= 1e-4 { ln_err } else { math::ln(1e-4) };
                self.previous_factor = math::exp(0.04 * floor);
                self.accept(h, last.then_some(t_end));
                self.h = h / fac;
                self.refused = None;
                return Stepped::Accepted;
            }
            self.rejected += 1;
            self.h = h / (fac11 / 0.9).min(5.0);
        }
    }

    /// The stages k₂ … k₇ of a step of size h from (t, y), and y₁ in
    /// `y_new`.
    fn stages<S: System>(&mut self, system: &mut S, h: f64) -> Result<(), Error> {
        // Stages 2 to 6 in the components f reads; the last, at y₁, in all
        // of them.
        let inputs = system.inputs();
        self.form_stage::<1, S>(system, h, inputs)?;
        self.form_stage::<2, S>(system, h, inputs)?;
        self.form_stage::<3, S>(system, h, inputs)?;
        self.form_stage::<4, S>(system, h, inputs)?;
        self.form_stage::<5, S>(system, h, inputs)?;
        self.form_stage::<6, S>(system, h, self.n)?;
        // Stage 7 is at y₁ (the weights of order 5 are A's last row).
        math::copy_small(&mut self.y_new, &self.stage);
        Ok(())
    }

    /// Stage `K` (0-based) of a step of size h: its state y + h Σ_{j<K}
    /// a_Kj k_j in the first `formed` components, f there, spread over
    /// the components' stages.
    #[inline(always)]
    fn form_stage<const K: usize, S: System>(
        &mut self,
        system: &mut S,
        h: f64,
        formed: usize,
    ) -> Result<(), Error> {
        let (a, n) = (&A[K], formed.min(self.n));
        let components = self.stage[..n].iter_mut().zip(&self.y[..n]);
        for ((x, y), k) in components.zip(&self.k[..n]) {
            let mut sum = 0.0;
            for j in 0..K {
                sum += a[j] * k[j];
            }
            *x = y + h * sum;
        }
        system.rhs(self.t + C[K] * h, &self.stage, &mut self.f)?;
        for (k, f) in self.k.iter_mut().zip(&self.f) {
            k[K] = *f;
        }
        self.evaluations += 1;
        Ok(())
    }

    /// Makes the step of size h the last accepted one: its first stage
    /// kept for the dense output, then (t, y) moved to its end (`end`
    /// exactly, for the last step to the end).
    fn accept(&mut self, h: f64, end: Option<f64>) {
        for (first, k) in self.first.iter_mut().zip(&mut self.k) {
            *first = k[0];
            // The last stage is f at the new point: the next step's first.
            k[0] = k[6];
        }
        self.h_last = h;
        self.t_old = self.t;
        math::copy_small(&mut self.y_old, &self.y);
        self.t = end.unwrap_or(self.t + h);
        math::copy_small(&mut self.y, &self.y_new);
        self.accepted += 1;
    }

    /// f of stage `s`, in `f`, spread over the components' stages.
    #[inline(always)]
    fn spread(&mut self, s: usize) {
        for (k, f) in self.k.iter_mut().zip(&self.f) {
            if let Some(slot) = k.get_mut(s) {
                *slot = *f;
            }
        }
    }

    /// The dense output at time t within the last accepted step, written
    /// into `out`: valid until the next [`Dopri::step`], whose stages
    /// overwrite those the terms are formed from (a run interpolates
    /// between its steps only, and not after a step that failed).
    pub(crate) fn interpolate(&self, t: f64, out: &mut [f64]) {
        let span = self.t - self.t_old;
        let theta = if span > 0.0 {
            ((t - self.t_old) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let (rest, h) = (1.0 - theta, self.h_last);
        let components = self.y_old.iter().zip(&self.y).zip(&self.first);
        for (o, (((y0, y1), first), k)) in out.iter_mut().zip(components.zip(&self.k)) {
            // The terms Δ, B, the fourth and the fifth of the step (its
            // first stage apart from `k`, whose entry 0 is the next's).
            let delta = y1 - y0;
            let b = h * first - delta;
            let c = delta - h * k[6] - b;
            let d = h * combine_from(&D, *first, k);
            *o = y0 + theta * (delta + rest * (b + theta * (c + rest * d)));
        }
    }
}

/// [`combine`] with `first` in place of stage 0.
#[inline(always)]
fn combine_from(weights: &[f64; 7], first: f64, k: &[f64; 7]) -> f64 {
    let mut sum = 0.0;
    sum += weights[0] * first;
    for (w, v) in weights.iter().zip(k).skip(1) {
        sum += w * v;
    }
    sum
}

/// Σ_s w_s k_s over the seven stages, in the order of s.
#[inline(always)]
fn combine(weights: &[f64; 7], k: &[f64; 7]) -> f64 {
    let mut sum = 0.0;
    for (w, v) in weights.iter().zip(k) {
        sum += w * v;
    }
    sum
}

/// The integrator a run uses: the explicit pair or the implicit method
/// of [`super::stiff`], behind one interface.
pub(crate) enum Solver {
    Explicit(Dopri),
    Implicit(super::stiff::TrBdf2),
}

impl Solver {
    /// The time reached.
    pub(crate) fn t(&self) -> f64 {
        match self {
            Solver::Explicit(s) => s.t,
            Solver::Implicit(s) => s.t,
        }
    }

    /// The start of the last accepted step.
    pub(crate) fn t_old(&self) -> f64 {
        match self {
            Solver::Explicit(s) => s.t_old,
            Solver::Implicit(s) => s.t_old,
        }
    }

    /// The solution at [`Solver::t`].
    pub(crate) fn y(&self) -> &[f64] {
        match self {
            Solver::Explicit(s) => &s.y,
            Solver::Implicit(s) => &s.y,
        }
    }

    /// One accepted step toward `t_end`.
    pub(crate) fn step<S: System>(&mut self, system: &mut S, t_end: f64) -> Stepped {
        match self {
            Solver::Explicit(s) => s.step(system, t_end),
            Solver::Implicit(s) => s.step(system, t_end),
        }
    }

    /// The interpolant at t within the last step.
    pub(crate) fn interpolate(&self, t: f64, out: &mut [f64]) {
        match self {
            Solver::Explicit(s) => s.interpolate(t, out),
            Solver::Implicit(s) => s.interpolate(t, out),
        }
    }

    /// The accepted and rejected steps and the evaluations.
    pub(crate) fn counts(&self) -> [usize; 3] {
        match self {
            Solver::Explicit(s) => [s.accepted, s.rejected, s.evaluations],
            Solver::Implicit(s) => [s.accepted, s.rejected, s.evaluations],
        }
    }

    /// The system's last refusal, taken.
    pub(crate) fn refused(&mut self) -> Option<Error> {
        match self {
            Solver::Explicit(s) => s.refused.take(),
            Solver::Implicit(s) => s.refused.take(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The harmonic oscillator x'' = −x, y = (x, x').
    struct Oscillator;

    impl System for Oscillator {
        fn len(&self) -> usize {
            2
        }
        fn rhs(&mut self, _: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
            dy[0] = y[1];
            dy[1] = -y[0];
            Ok(())
        }
    }

    fn run(tol: f64) -> (Dopri, f64) {
        let tolerances = Tolerances {
            relative: tol,
            absolute: vec![tol; 2],
        };
        let mut s = Oscillator;
        let mut d = Dopri::new(&mut s, 0.0, &[1.0, 0.0], tolerances, f64::INFINITY).unwrap();
        // The largest error of the dense output at 20 points of each step.
        let mut worst: f64 = 0.0;
        let mut out = [0.0; 2];
        while d.t < 10.0 {
            assert_eq!(d.step(&mut s, 10.0), Stepped::Accepted);
            for j in 0..=20 {
                let t = d.t_old + (d.t - d.t_old) * f64::from(j) / 20.0;
                d.interpolate(t, &mut out);
                worst = worst
                    .max((out[0] - t.cos()).abs())
                    .max((out[1] + t.sin()).abs());
            }
        }
        (d, worst)
    }

    #[test]
    fn the_oscillator_is_followed_to_its_tolerance_between_and_at_the_steps() {
        for tol in [1e-6, 1e-9, 1e-12] {
            let (d, worst) = run(tol);
            assert_eq!(d.t, 10.0);
            // The global error is of the order of the tolerance (a few
            // times it over 1.6 periods), at the ends and in between.
            assert!(
                (d.y[0] - 10f64.cos()).abs() < 30.0 * tol,
                "{tol}: {:?}",
                d.y
            );
            assert!(worst < 30.0 * tol, "{tol}: dense output off by {worst}");
        }
        // Tighter tolerance, more steps, by about the fifth root of 1000.
        let (coarse, _) = run(1e-6);
        let (fine, _) = run(1e-9);
        #[allow(clippy::cast_precision_loss)]
        let ratio = fine.accepted as f64 / coarse.accepted as f64;
        assert!((3.0..5.5).contains(&ratio), "{ratio}");
    }

    /// x' = −x with its integral as a quadrature, y = (x, ∫x), f reading
    /// x only; `inputs` says so or not.
    struct Decay {
        says: bool,
    }

    impl System for Decay {
        fn len(&self) -> usize {
            2
        }
        fn controlled(&self) -> usize {
            1
        }
        fn inputs(&self) -> usize {
            if self.says { 1 } else { 2 }
        }
        fn rhs(&mut self, _: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
            dy[0] = -y[0];
            dy[1] = y[0];
            Ok(())
        }
    }

    #[test]
    fn a_quadrature_is_formed_at_the_end_of_a_step_only_and_integrated_the_same() {
        let run = |says| {
            let tolerances = Tolerances {
                relative: 1e-10,
                absolute: vec![1e-10],
            };
            let mut s = Decay { says };
            let mut d = Dopri::new(&mut s, 0.0, &[1.0, 0.0], tolerances, 0.25).unwrap();
            let mut path = Vec::new();
            while d.t < 3.0 {
                assert_eq!(d.step(&mut s, 3.0), Stepped::Accepted);
                let mut mid = [0.0; 2];
                d.interpolate(0.5 * (d.t_old + d.t), &mut mid);
                path.push((d.t, d.y.clone(), mid));
            }
            path
        };
        let (lean, full) = (run(true), run(false));
        // Bit for bit the same steps, ends and dense output.
        assert_eq!(lean, full);
        let (t, y, _) = lean.last().unwrap();
        assert_eq!(*t, 3.0);
        // ∫₀³ e^(−t) dt = 1 − e^(−3).
        assert!((y[1] - (1.0 - (-3.0f64).exp())).abs() < 1e-9, "{y:?}");
    }

    /// y' = 1 refused past t = 1: the integrator closes in on it.
    struct Wall;

    impl System for Wall {
        fn len(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, _: &[f64], dy: &mut [f64]) -> Result<(), Error> {
            if t > 1.0 {
                return Err(Error::InvalidOption {
                    name: "t",
                    value: t,
                    requirement: "at most 1",
                });
            }
            dy[0] = 1.0;
            Ok(())
        }
    }

    #[test]
    fn a_refused_state_shortens_the_step_until_the_time_resolution() {
        let tolerances = Tolerances {
            relative: 1e-8,
            absolute: vec![1e-8],
        };
        let mut d = Dopri::new(&mut Wall, 0.0, &[0.0], tolerances, 0.3).unwrap();
        let mut last = Stepped::Accepted;
        for _ in 0..10_000 {
            last = d.step(&mut Wall, 2.0);
            if last == Stepped::TooSmall {
                break;
            }
        }
        assert_eq!(last, Stepped::TooSmall);
        assert!(d.refused.is_some());
        assert!(d.t <= 1.0 && d.t > 1.0 - 1e-12, "{}", d.t);
        assert!((d.y[0] - d.t).abs() < 1e-12);
    }
}
