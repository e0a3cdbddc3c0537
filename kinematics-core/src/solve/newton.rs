//! Newton–Raphson: the general damped solver with its polish to
//! round-off, and the inline common path (`FastNewton`) that generated
//! code runs first.

// Elimination is written with explicit indices, as in the formulas.
#![allow(clippy::needless_range_loop)]

use crate::options::Options;

use super::failure::{Failure, non_finite, not_converged};
use super::scaling::Scaling;

/// ½‖w∘v‖² and max|w_i v_i| (infinite when some entry is not finite) in one
/// pass.
#[inline(always)]
fn norms(v: &[f64], w: &[f64]) -> (f64, f64) {
    let mut sq = 0.0;
    let mut max = 0.0f64;
    for (x, wi) in v.iter().zip(w) {
        let x = x * wi;
        sq += x * x;
        // A plain comparison (not `f64::max`, whose NaN rule costs more):
        // a NaN shows up in `sq` instead.
        let a = x.abs();
        if a > max {
            max = a;
        }
    }
    // A float comparison, false for NaN (cheaper than `is_finite`).
    if sq < f64::INFINITY {
        (0.5 * sq, max)
    } else {
        (f64::INFINITY, f64::INFINITY)
    }
}

/// The index of the largest |w_i v_i| (or of the first non-finite entry).
pub(super) fn worst(v: &[f64], w: &[f64]) -> usize {
    let mut at = 0;
    for i in 0..v.len().min(w.len()) {
        if !v[i].is_finite() {
            return i;
        }
        if (v[i] * w[i]).abs() > (v[at] * w[at]).abs() {
            at = i;
        }
    }
    at
}

/// The Armijo fraction: a step of length t must decrease f = ½‖Φ‖² to at
/// most (1 − `ARMIJO`·t) times its value.
const ARMIJO: f64 = 2e-4;

/// In [`newton`], a converged residual above `POLISH` times the tolerance
/// gets one more Newton step.
pub const POLISH: f64 = 1e-3;

/// The relative residual max_i |Φ_i| / S_i (16 units of round-off) below
/// which a step's pose counts as closed: above it (and above [`POLISH`]
/// times the tolerance), `step`, the stepper and sweeps take one more
/// Newton step from the pose (see [`FastNewton::assess_closing`]; a
/// closed-form pose there is handed to Newton–Raphson from itself, in the
/// same modes).
pub const CLOSED: f64 = 16.0 * f64::EPSILON;

/// The largest relative residual max_i |Φ_i| / S_i that counts as the
/// round-off of evaluating the equations (about 450 units of round-off
/// 2⁻⁵², a sum of some dozens of terms of the size S_i): Newton stops
/// there, even when the tolerance asked for is smaller.
pub const ROUND_OFF: f64 = 1e-13;

/// Solves Φ(u) = 0 for `u` by Newton–Raphson from the value in `u`. `eval`
/// writes Φ(u) and Φ_u(u); when it returns, `phi` and `jac` hold them at the
/// returned `u`.
///
/// Each Newton step Δu = −Φ_u⁻¹ Φ is solved with the scaled matrix
/// Φ̃_u = diag(1/S) Φ_u diag(unit) of `scaling` (pivots at or below
/// `options.singularity_threshold` fail), and is a descent direction of the
/// merit f = ½‖w∘Φ‖² with the weights w of [`Scaling::weights`]; the step
/// length t is halved until f decreases by at least the Armijo fraction,
/// f(u + tΔu) ≤ (1 − 2·10⁻⁴ t) f(u), which keeps a poor guess from
/// wandering to a far solution. Converged when max|w_i Φ_i| ≤
/// `options.tolerance`. When the tolerance is below what round-off allows, a
/// full step that fails to decrease f and is itself at the level of
/// round-off (|Δu_i| ≤ 10⁻¹⁴·(1 + |u_i|)) ends the iteration too, but only
/// if the relative residual max|Φ_i| / S_i is at most [`ROUND_OFF`]:
/// `Ok` always means a pose that closes. After convergence, full steps are
/// taken while they decrease the residual, until it is below [`POLISH`]
/// times the tolerance, so that the result is at round-off rather than
/// merely within the tolerance.
/// Returns the iterations used.
///
/// The singularity of the solution and its assembly branch are not judged
/// here: the caller factors Φ̃_u at the returned pose (block by block) and
/// checks both.
///
/// # Errors
/// A [`Failure`] when Φ̃_u is singular at an iterate, Φ is not finite, no
/// step length decreases the merit (a local minimum of ‖Φ‖ that is not a
/// solution), or the iteration cap is reached; `u` then holds the last
/// iterate.
///
/// ```
/// use kinematics_core::solve::{dense_solve, newton, Scaling};
/// use kinematics_core::Options;
/// // x² + y² = 4, y = x, from (1, 0.5): the root (√2, √2).
/// let scaling = Scaling::new(&[8.0, 2.0], 1.0, [false, false])?;
/// let (mut u, mut phi, mut jac) = ([1.0, 0.5], [0.0; 2], [[0.0; 2]; 2]);
/// newton(
///     &mut u, &mut phi, &mut jac, &scaling, &Options::DEFAULT,
///     |u, phi, jac| {
///         *phi = [u[0] * u[0] + u[1] * u[1] - 4.0, u[1] - u[0]];
///         *jac = [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]];
///     },
///     |jac, rhs| dense_solve(jac, rhs, &scaling, 1e-10),
/// )?;
/// assert!((u[0] - 2f64.sqrt()).abs() < 1e-15 && (u[1] - 2f64.sqrt()).abs() < 1e-15);
/// # Ok::<(), kinematics_core::solve::Failure>(())
/// ```
#[inline]
pub fn newton<const N: usize, J>(
    u: &mut [f64; N],
    phi: &mut [f64; N],
    jac: &mut J,
    scaling: &Scaling<N>,
    options: &Options,
    eval: impl FnMut(&[f64; N], &mut [f64; N], &mut J),
    solve: impl Fn(&J, &[f64; N]) -> Result<[f64; N], Failure>,
) -> Result<usize, Failure> {
    let w = scaling.weights(options);
    let mut system = Arrays::<N, J, _, _> { jac, eval, solve };
    let (mut start, mut step) = ([0.0; N], [0.0; N]);
    let space = Space {
        row: &scaling.row,
        weights: &w,
        start: &mut start,
        step: &mut step,
    };
    iterate(&mut system, u, phi, space, options)
}

/// What Newton–Raphson iterates on: Φ at a point, and the Newton step
/// there, for storage of any kind (generated code's arrays, a run-time
/// model's vectors), so that one iteration with one convergence rule
/// ([`iterate`]) serves both kinds of model.
pub trait System {
    /// Φ(u) into `phi`, keeping what [`System::step`] needs (Φ_u).
    fn eval(&mut self, u: &[f64], phi: &mut [f64]);
    /// Δ with Φ_u Δ = `phi`, Φ_u that of the last evaluation, into `step`:
    /// solved through the scaled matrix Φ̃_u = diag(1/S) Φ_u diag(unit),
    /// whose pivots at or below the singularity threshold fail.
    ///
    /// # Errors
    /// [`Failure::Singular`] at such a pivot.
    fn step(&mut self, phi: &[f64], step: &mut [f64]) -> Result<(), Failure>;
}

/// The scales and the scratch of [`iterate`], each of the system's size:
/// the row scales 1/S_i, the convergence weights
/// ([`Scaling::weights`]), and room for the iterate before a step and for
/// the step.
pub struct Space<'a> {
    /// 1/S_i.
    pub row: &'a [f64],
    /// The weights w of the convergence test max|w_i Φ_i| ≤ tolerance.
    pub weights: &'a [f64],
    /// Scratch: the iterate a step starts from.
    pub start: &'a mut [f64],
    /// Scratch: the step.
    pub step: &'a mut [f64],
}

/// [`newton`]'s closures over fixed-size arrays as a [`System`].
struct Arrays<'j, const N: usize, J, E, S> {
    jac: &'j mut J,
    eval: E,
    solve: S,
}

impl<const N: usize, J, E, S> System for Arrays<'_, N, J, E, S>
where
    E: FnMut(&[f64; N], &mut [f64; N], &mut J),
    S: Fn(&J, &[f64; N]) -> Result<[f64; N], Failure>,
{
    #[inline(always)]
    fn eval(&mut self, u: &[f64], phi: &mut [f64]) {
        // Always of length N: `newton` hands its own arrays.
        if let (Ok(u), Ok(phi)) = (<&[f64; N]>::try_from(u), <&mut [f64; N]>::try_from(phi)) {
            (self.eval)(u, phi, self.jac);
        }
    }

    #[inline(always)]
    fn step(&mut self, phi: &[f64], step: &mut [f64]) -> Result<(), Failure> {
        if let Ok(phi) = <&[f64; N]>::try_from(phi) {
            let x = (self.solve)(self.jac, phi)?;
            step.copy_from_slice(&x);
        }
        Ok(())
    }
}

/// Newton–Raphson on `system` from the value in `u`, as [`newton`]
/// describes it (the damped step, the Armijo test, the end at round-off,
/// the polish): the one iteration of both kinds of model. When it
/// returns, `phi` and the system's last evaluation are at the returned
/// `u`. Every slice has the system's size.
///
/// # Errors
/// As [`newton`]; `u` then holds the last iterate.
#[inline]
pub fn iterate(
    system: &mut impl System,
    u: &mut [f64],
    phi: &mut [f64],
    space: Space<'_>,
    options: &Options,
) -> Result<usize, Failure> {
    let Space {
        row,
        weights: w,
        start,
        step,
    } = space;
    system.eval(u, phi);
    let (mut f0, mut max) = norms(phi, w);
    let mut iterations = 0;
    loop {
        if max <= options.tolerance {
            break;
        }
        // `norms` makes both infinite when Φ is not finite.
        if max == f64::INFINITY {
            return Err(non_finite(phi, w));
        }
        if iterations >= options.max_iterations {
            return Err(not_converged(iterations, phi, row, w));
        }
        iterations += 1;
        system.step(phi, step)?;
        start.copy_from_slice(u);
        for ((ui, s), d) in u.iter_mut().zip(&*start).zip(&*step) {
            *ui = s - d;
        }
        system.eval(u, phi);
        let (f, m) = norms(phi, w);
        if f <= (1.0 - ARMIJO) * f0 {
            (f0, max) = (f, m);
            continue;
        }
        let search = Search {
            start,
            step,
            f0,
            last_max: m,
            iterations,
            row,
            w,
        };
        match search.run(u, phi, system)? {
            Some((f, m)) => (f0, max) = (f, m),
            None => return Ok(iterations),
        }
    }
    polish(system, u, phi, (row, w), (start, step), options);
    Ok(iterations)
}

/// Full Newton steps after convergence, while the residual is above
/// [`POLISH`] times the tolerance and each step decreases the largest
/// relative residual (a step that does not is undone, `u` put back and Φ
/// and Φ_u evaluated there again, so that the caller's last evaluation is
/// at the returned `u`). Near a regular solution one step reaches
/// round-off; near a dead-centre position, where Newton converges only
/// linearly, a few more bring the pose as close to the solution as
/// double precision resolves it.
#[cold]
fn polish(
    system: &mut impl System,
    u: &mut [f64],
    phi: &mut [f64],
    (row, w): (&[f64], &[f64]),
    (start, step): (&mut [f64], &mut [f64]),
    options: &Options,
) {
    for _ in 0..options.max_iterations {
        let (_, before) = norms(phi, row);
        let (_, weighted) = norms(phi, w);
        if before == 0.0 || weighted <= POLISH * options.tolerance {
            return;
        }
        if system.step(phi, step).is_err() {
            return;
        }
        start.copy_from_slice(u);
        for (ui, d) in u.iter_mut().zip(&*step) {
            *ui -= d;
        }
        system.eval(u, phi);
        let (_, after) = norms(phi, row);
        let kept = after < before;
        if !kept {
            u.copy_from_slice(start);
            system.eval(u, phi);
            return;
        }
    }
}

/// How the common path of [`fast_then_damped`] judges each iterate, as generated
/// code judges it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Judge {
    /// [`FastNewton::assess`]: converged within the tolerance (a block of
    /// an assembly in closed form and by Newton–Raphson, with the
    /// tolerance at most 1e-12).
    Assess,
    /// [`FastNewton::assess_closing`]: a step, which must close to
    /// round-off.
    Closing,
}

/// Newton–Raphson as generated code runs it: full steps while
/// [`FastNewton`] judges them on its common path (by `judge`, with the
/// options `fast`), and on the first event off it, [`iterate`] from the
/// start with `options`, which retraces the same iterates, damps, detects
/// round-off or reports the failure. `origin` is scratch of the system's
/// size. Returns the iterations used.
///
/// # Errors
/// As [`iterate`].
#[allow(clippy::too_many_arguments)]
pub fn fast_then_damped(
    system: &mut impl System,
    u: &mut [f64],
    phi: &mut [f64],
    space: Space<'_>,
    origin: &mut [f64],
    (judge, fast_options): (Judge, &Options),
    options: &Options,
) -> Result<usize, Failure> {
    origin.copy_from_slice(u);
    let mut fast = FastNewton::new();
    loop {
        system.eval(u, phi);
        let next = match judge {
            Judge::Assess => fast.assess(phi, space.weights, fast_options),
            Judge::Closing => fast.assess_closing(phi, space.weights, fast_options),
        };
        match next {
            Next::Converged => return Ok(fast.iterations),
            Next::Continue => {}
            Next::Fallback => break,
        }
        if system.step(phi, space.step).is_err() {
            break;
        }
        fast.advance(u, space.step);
    }
    u.copy_from_slice(origin);
    iterate(system, u, phi, space, options)
}

/// What [`FastNewton::assess`] found at the latest evaluation. Used by
/// generated code.
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    /// Not converged: take the full Newton step with
    /// [`FastNewton::advance`], then evaluate again at the new u.
    Continue,
    /// max|w_i Φ_i| ≤ tolerance.
    Converged,
    /// Anything else: solve again from the start with [`newton`], whose
    /// common path this is, so that it damps, detects round-off or reports
    /// the failure.
    Fallback,
}

/// The common path of [`newton`], driven by the caller's own loop, so that
/// generated code evaluates Φ and Φ_u inline rather than through a closure:
/// near a solution every full Newton step passes the Armijo test, and then
/// the iterates are those of [`newton`] (to rounding: generated code
/// solves Φ̃_u block by block and carries sines and cosines from one
/// iterate to the next with [`sin_cos_after`]). On the first event off
/// that path (a full step that does not decrease f = ½‖w∘Φ‖² enough, a
/// singular or non-finite Φ_u, the iteration cap) it answers
/// [`Next::Fallback`], and the caller runs [`newton`] from the start,
/// which retraces the same iterates up to that point and takes over. The
/// caller judges the singularity and the branch of the converged pose, as
/// after [`newton`]. Used by generated code.
#[doc(hidden)]
#[derive(Debug, Clone, Copy)]
pub struct FastNewton {
    /// f at the current iterate's predecessor (infinite before the first).
    f0: f64,
    /// f at the current iterate, once assessed.
    f: f64,
    iterations: usize,
    /// Whether the last step was taken from a converged iterate above the
    /// closing bound (see [`FastNewton::assess_closing`]).
    polishing: bool,
}

impl Default for FastNewton {
    fn default() -> Self {
        Self::new()
    }
}

impl FastNewton {
    /// Before the first evaluation.
    #[inline(always)]
    #[must_use]
    pub const fn new() -> Self {
        Self {
            f0: f64::INFINITY,
            f: f64::INFINITY,
            iterations: 0,
            polishing: false,
        }
    }

    /// Given Φ at the current iterate and the weights `w` of the
    /// convergence test ([`Scaling::weights`]): converged, off the common
    /// path, or [`Next::Continue`]: take the full Newton step
    /// Δu = −Φ_u⁻¹ Φ with [`FastNewton::advance`].
    #[inline(always)]
    pub fn assess(&mut self, phi: &[f64], w: &[f64], options: &Options) -> Next {
        self.judge(phi, w, options, false)
    }

    /// [`FastNewton::assess`] for a step, which must close to round-off:
    /// an iterate within the tolerance but above the larger of [`POLISH`]
    /// times the tolerance and [`CLOSED`] gets one more full Newton step
    /// ([`Next::Continue`]), whose result is kept if it is still within the
    /// tolerance (at the equations' own round-off floor a step need not
    /// decrease the residual further). Near a regular solution that one
    /// step takes a pose at 1e-13 to round-off; from a closed form that
    /// lost digits at extreme scales, likewise.
    #[inline(always)]
    pub fn assess_closing(&mut self, phi: &[f64], w: &[f64], options: &Options) -> Next {
        self.judge(phi, w, options, true)
    }

    /// [`FastNewton::assess`], or with `closing`
    /// [`FastNewton::assess_closing`].
    #[inline(always)]
    fn judge(&mut self, phi: &[f64], w: &[f64], options: &Options, closing: bool) -> Next {
        let (f, max) = norms(phi, w);
        if closing && self.polishing {
            return if max <= options.tolerance {
                Next::Converged
            } else {
                Next::Fallback
            };
        }
        // The Armijo test of the full step that led here (vacuous at the
        // first evaluation, where f0 is infinite and f is at most infinite).
        let decreased = f <= (1.0 - ARMIJO) * self.f0;
        if !decreased {
            return Next::Fallback;
        }
        if max <= options.tolerance {
            if !closing || max <= (POLISH * options.tolerance).max(CLOSED) {
                return Next::Converged;
            }
            self.polishing = true;
        } else if max == f64::INFINITY || self.iterations >= options.max_iterations {
            return Next::Fallback;
        }
        self.f = f;
        Next::Continue
    }

    /// Whether a converged Φ is above [`POLISH`] times the tolerance in
    /// the weighted norm of [`FastNewton::assess`]: then [`newton`], from
    /// the converged iterate, takes the polishing steps that an assembly
    /// takes.
    #[inline(always)]
    #[must_use]
    pub fn unpolished(phi: &[f64], w: &[f64], options: &Options) -> bool {
        let (_, max) = norms(phi, w);
        max > POLISH * options.tolerance || max.is_nan()
    }

    /// u ← u − `step`, where `step` = Φ_u⁻¹ Φ at the assessed iterate.
    #[inline(always)]
    pub fn advance(&mut self, u: &mut [f64], step: &[f64]) {
        self.iterations += 1;
        self.f0 = self.f;
        for (x, d) in u.iter_mut().zip(step) {
            *x -= d;
        }
    }
}

/// sin x and cos x, given `s` = sin(x − d) and `c` = cos(x − d): by the
/// angle-addition formulas, sin x = s cos d + c sin d and
/// cos x = c cos d − s sin d, with sin d and cos d − 1 from their Taylor
/// series when |d| ≤ 1/32 (truncated after d⁷ and d⁶: the first term
/// left out is below 3·10⁻¹⁷), else computed afresh. Each result is then
/// within a few units of 10⁻¹⁶ of the exact value. Generated code uses
/// it between Newton iterates, whose steps are small near a solution; an
/// infinite or NaN `d` (before the first iterate) computes afresh. Used by
/// generated code.
#[doc(hidden)]
#[inline(always)]
#[must_use]
pub fn sin_cos_after(s: f64, c: f64, x: f64, d: f64) -> (f64, f64) {
    if d.abs() <= 0.031_25 {
        let d2 = d * d;
        // sin d = d − d³/3! + d⁵/5! − d⁷/7! and cos d − 1 = −d²/2! +
        // d⁴/4! − d⁶/6!, in Horner form with rounded coefficients.
        let sin_d = d + d * d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0 - d2 * (1.0 / 5040.0)));
        let cos_d_m1 = d2 * (-0.5 + d2 * (1.0 / 24.0 - d2 * (1.0 / 720.0)));
        (
            s + (s * cos_d_m1 + c * sin_d),
            c + (c * cos_d_m1 - s * sin_d),
        )
    } else {
        crate::math::sin_cos(x)
    }
}

/// A Newton step whose full length did not decrease the merit f = ½‖w∘Φ‖²
/// enough: the slow path of [`iterate`].
struct Search<'a> {
    start: &'a [f64],
    step: &'a [f64],
    /// f at `start`.
    f0: f64,
    /// max|w_i Φ_i| after the full step.
    last_max: f64,
    iterations: usize,
    /// 1/S_i.
    row: &'a [f64],
    w: &'a [f64],
}

impl Search<'_> {
    /// `Ok(None)` when the step is at the level of round-off and so is the
    /// residual at the start: u is put back at the start (and Φ, Φ_u
    /// evaluated there). Else halves t from 1 until the Armijo test
    /// passes, `Ok(Some((f, max|w_i Φ_i|)))` at the new u.
    #[cold]
    fn run(
        &self,
        u: &mut [f64],
        phi: &mut [f64],
        system: &mut impl System,
    ) -> Result<Option<(f64, f64)>, Failure> {
        let (start, step) = (self.start, self.step);
        let tiny = step
            .iter()
            .zip(start)
            .all(|(d, s)| d.abs() <= 1e-14 * (1.0 + s.abs()));
        if tiny {
            u.copy_from_slice(start);
            system.eval(u, phi);
            let (_, relative) = norms(phi, self.row);
            if relative <= ROUND_OFF {
                return Ok(None);
            }
            // A step that cannot move u (an unknown so large that its
            // floating-point spacing exceeds the step) while the equations
            // are far from closed: no solution is reachable from here.
            return Err(not_converged(self.iterations, phi, self.row, self.w));
        }
        let mut t = 1.0;
        let mut m = self.last_max;
        loop {
            if t < 1e-3 {
                if m == f64::INFINITY {
                    return Err(non_finite(phi, self.w));
                }
                // No decrease along the Newton direction: a local minimum
                // of ‖Φ‖ that is not a solution.
                return Err(not_converged(self.iterations, phi, self.row, self.w));
            }
            t *= 0.5;
            for ((ui, s), d) in u.iter_mut().zip(start).zip(step) {
                *ui = s - t * d;
            }
            system.eval(u, phi);
            let (f, max) = norms(phi, self.w);
            m = max;
            if f <= (1.0 - ARMIJO * t) * self.f0 {
                return Ok(Some((f, max)));
            }
        }
    }
}
