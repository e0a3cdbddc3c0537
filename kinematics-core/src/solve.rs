//! Dense linear solves and Newton–Raphson on fixed-size arrays.
//!
//! Everything here works on `[f64; N]` and `[[f64; N]; N]` on the stack, so
//! assembling near a known pose and analysing velocities and accelerations
//! allocate nothing.

// Elimination is written with explicit indices, as in the formulas.
#![allow(clippy::needless_range_loop)]

use crate::{Error, Options};

/// Why a numerical step failed, without names (those are added by
/// [`describe`], off the hot path).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Failure {
    /// Column `unknown` of Φ_u lost rank; `relative_pivot` = |pivot| / max|Φ_u|.
    Singular {
        /// Index of the unknown.
        unknown: usize,
        /// |pivot| / max |entry|.
        relative_pivot: f64,
    },
    /// Newton stopped with residual `residual` in equation `equation`.
    NotConverged {
        /// Iterations performed.
        iterations: usize,
        /// max |Φ_i|.
        residual: f64,
        /// Index of the equation with the largest residual.
        equation: usize,
    },
    /// Converged on the assembly branch other than the one asked for.
    WrongBranch,
    /// Equation `equation` evaluated to a non-finite number.
    NonFiniteResidual {
        /// Index of the equation.
        equation: usize,
        /// The value.
        value: f64,
    },
}

impl Failure {
    /// A failure found in a diagonal block of Φ_u whose unknowns are
    /// `columns` (indices into all unknowns): the unknown index is made
    /// global.
    #[cold]
    #[must_use]
    pub fn in_block(self, columns: &[usize]) -> Self {
        match self {
            Failure::Singular {
                unknown,
                relative_pivot,
            } => Failure::Singular {
                unknown: columns.get(unknown).copied().unwrap_or(unknown),
                relative_pivot,
            },
            other => other,
        }
    }
}

/// LU factorisation with partial pivoting, P·A = L·U, of a square matrix.
///
/// The reciprocals of the pivots are kept, so that [`Lu::solve`] has no
/// division. For N ≤ 2 the inverse itself is kept instead (A⁻¹ = adj A / det A,
/// one division), and a solve is a matrix–vector product; the singularity
/// test and [`Lu::conditioning`] are those of partial pivoting all the same:
/// the pivots of a 2×2 matrix are p₀ = max(|a₀₀|, |a₁₀|) and |det A| / p₀.
#[derive(Debug, Clone, Copy)]
pub struct Lu<const N: usize> {
    /// L and U below and above the diagonal (N > 2), or A⁻¹ (N ≤ 2).
    lu: [[f64; N]; N],
    inv_pivot: [f64; N],
    perm: [usize; N],
    conditioning: f64,
    sign: f64,
}

/// The largest |a_ij| (plain comparisons, not `f64::max`: a NaN entry is
/// caught by the pivot tests of the factorisation that uses this).
#[inline(always)]
#[must_use]
pub fn largest_entry<const R: usize, const C: usize>(a: &[[f64; C]; R]) -> f64 {
    let mut scale = 0.0f64;
    for row in a {
        for v in row {
            let m = v.abs();
            if m > scale {
                scale = m;
            }
        }
    }
    scale
}

/// The failure for pivot `unknown` of magnitude `pivot` (|pivot| / `scale`
/// relative), off the hot path.
#[cold]
fn singular(unknown: usize, pivot: f64, scale: f64) -> Failure {
    let rel = pivot / scale;
    Failure::Singular {
        unknown,
        relative_pivot: if rel.is_finite() { rel } else { 0.0 },
    }
}

impl<const N: usize> Lu<N> {
    /// Factors `a` (rows are equations, columns unknowns).
    ///
    /// # Errors
    /// [`Failure::Singular`] when a pivot, relative to the largest entry of
    /// `a`, is at or below `threshold` (or is not finite).
    #[inline(always)]
    pub fn factor(a: &[[f64; N]; N], threshold: f64) -> Result<Self, Failure> {
        Self::factor_in(a, threshold, largest_entry(a))
    }

    /// Factors `a` as a diagonal block of a larger matrix whose largest
    /// entry in magnitude is `scale`: as [`Lu::factor`], with the pivots and
    /// [`Lu::conditioning`] relative to `scale` instead of to `a`'s own
    /// largest entry (so that a 1×1 block near zero still counts as
    /// singular).
    ///
    /// # Errors
    /// [`Failure::Singular`] when a pivot, relative to `scale`, is at or
    /// below `threshold` (or is not finite).
    #[inline(always)]
    pub fn factor_in(a: &[[f64; N]; N], threshold: f64, scale: f64) -> Result<Self, Failure> {
        let scale = if scale > 0.0 { scale } else { 1.0 };
        if N == 1 {
            return Self::factor1(a, threshold, scale);
        }
        if N == 2 {
            return Self::factor2(a, threshold, scale);
        }
        let mut lu = *a;
        let mut perm = [0usize; N];
        let mut inv_pivot = [0.0; N];
        for (i, p) in perm.iter_mut().enumerate() {
            *p = i;
        }
        let mut min_pivot = f64::INFINITY;
        let mut sign = 1.0;
        for k in 0..N {
            let mut best = k;
            let mut best_val = lu[k][k].abs();
            for i in k + 1..N {
                if lu[i][k].abs() > best_val {
                    best = i;
                    best_val = lu[i][k].abs();
                }
            }
            // Written so that a NaN pivot also fails.
            let regular = best_val > threshold * scale && best_val.is_finite();
            if !regular {
                return Err(singular(k, best_val, scale));
            }
            if best != k {
                lu.swap(k, best);
                perm.swap(k, best);
                sign = -sign;
            }
            let pivot_row = lu[k];
            min_pivot = min_pivot.min(best_val);
            sign *= pivot_row[k].signum();
            let inv = 1.0 / pivot_row[k];
            inv_pivot[k] = inv;
            for i in k + 1..N {
                let m = lu[i][k] * inv;
                lu[i][k] = m;
                for c in k + 1..N {
                    lu[i][c] -= m * pivot_row[c];
                }
            }
        }
        Ok(Self {
            lu,
            inv_pivot,
            perm,
            conditioning: if N == 0 { 1.0 } else { min_pivot / scale },
            sign,
        })
    }

    /// The 1×1 case: A⁻¹ = 1 / a₀₀.
    #[inline]
    fn factor1(a: &[[f64; N]; N], threshold: f64, scale: f64) -> Result<Self, Failure> {
        let a00 = a[0][0];
        let p0 = a00.abs();
        // Written so that a NaN or infinite entry also fails.
        if !(p0 > threshold * scale && p0 < f64::INFINITY) {
            return Err(singular(0, p0, scale));
        }
        let mut lu = [[0.0; N]; N];
        lu[0][0] = 1.0 / a00;
        Ok(Self {
            lu,
            inv_pivot: [0.0; N],
            perm: [0; N],
            conditioning: p0 / scale,
            sign: a00.signum(),
        })
    }

    /// The 2×2 case: A⁻¹ = [[a₁₁, −a₀₁], [−a₁₀, a₀₀]] / det A, with the
    /// pivots of partial pivoting, p₀ = max(|a₀₀|, |a₁₀|) and |det A| / p₀,
    /// tested without dividing.
    #[inline]
    fn factor2(a: &[[f64; N]; N], threshold: f64, scale: f64) -> Result<Self, Failure> {
        let (a00, a01, a10, a11) = (a[0][0], a[0][1], a[1][0], a[1][1]);
        // A plain comparison, not `f64::max`: a NaN entry is caught by the
        // determinant test below.
        let p0 = if a10.abs() > a00.abs() {
            a10.abs()
        } else {
            a00.abs()
        };
        let det = a00 * a11 - a01 * a10;
        let tol = threshold * scale;
        // A NaN or an infinity in `a` makes the tolerance or the determinant
        // NaN or infinite, and these comparisons false.
        let first_regular = p0 > tol;
        if !first_regular {
            return Err(singular(0, p0, scale));
        }
        if !(det.abs() > tol * p0 && det.abs() < f64::INFINITY) {
            return Err(singular(1, det.abs() / p0, scale));
        }
        let inv = 1.0 / det;
        let mut lu = [[0.0; N]; N];
        lu[0][0] = a11 * inv;
        lu[0][1] = -a01 * inv;
        lu[1][0] = -a10 * inv;
        lu[1][1] = a00 * inv;
        Ok(Self {
            lu,
            inv_pivot: [0.0; N],
            perm: [0; N],
            conditioning: (p0 * p0).min(det.abs()) / (p0 * scale),
            sign: det.signum(),
        })
    }

    /// Conditioning of the factored matrix: its smallest pivot relative to
    /// its largest entry, in (0, 1]; near 0 the matrix is nearly singular.
    #[inline]
    #[must_use]
    pub fn conditioning(&self) -> f64 {
        self.conditioning
    }

    /// Sign of the determinant, ±1.
    #[inline]
    #[must_use]
    pub fn det_sign(&self) -> f64 {
        self.sign
    }

    /// Solves A·x = b.
    #[inline(always)]
    #[must_use]
    pub fn solve(&self, b: &[f64; N]) -> [f64; N] {
        if N <= 2 {
            // x = A⁻¹ b.
            let mut x = [0.0; N];
            for i in 0..N {
                for j in 0..N {
                    x[i] += self.lu[i][j] * b[j];
                }
            }
            return x;
        }
        let mut x = [0.0; N];
        for i in 0..N {
            let mut s = b[self.perm[i]];
            for j in 0..i {
                s -= self.lu[i][j] * x[j];
            }
            x[i] = s;
        }
        for i in (0..N).rev() {
            let mut s = x[i];
            for j in i + 1..N {
                s -= self.lu[i][j] * x[j];
            }
            x[i] = s * self.inv_pivot[i];
        }
        x
    }
}

/// Checks the requested assembly branch: the sign of det Φ_u.
#[inline]
fn branch_check<const N: usize>(jac: &[[f64; N]; N], options: &Options) -> Result<(), Failure> {
    let wanted = match options.branch {
        crate::Branch::Any => return Ok(()),
        crate::Branch::Positive => 1.0,
        crate::Branch::Negative => -1.0,
    };
    let lu = Lu::factor(jac, options.singularity_threshold)?;
    if lu.det_sign() == wanted {
        Ok(())
    } else {
        Err(Failure::WrongBranch)
    }
}

/// ½‖v‖² and max|v_i| (infinite when some entry is not finite) in one pass.
#[inline]
fn norms<const N: usize>(v: &[f64; N]) -> (f64, f64) {
    let mut sq = 0.0;
    let mut max = 0.0f64;
    for x in v {
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

fn worst<const N: usize>(v: &[f64; N]) -> usize {
    let mut at = 0;
    for (i, x) in v.iter().enumerate() {
        if !x.is_finite() {
            return i;
        }
        if x.abs() > v[at].abs() {
            at = i;
        }
    }
    at
}

/// The Armijo fraction: a step of length t must decrease f = ½‖Φ‖² to at
/// most (1 − `ARMIJO`·t) times its value.
const ARMIJO: f64 = 2e-4;

/// Solves Φ(u) = 0 for `u` by Newton–Raphson from the value in `u`. `eval`
/// writes Φ(u) and Φ_u(u); when it returns `Ok`, the last call was at the
/// returned `u`.
///
/// Each Newton step Δu = −Φ_u⁻¹ Φ is a descent direction of the merit
/// f = ½‖Φ‖²; the step length t is halved until f decreases by at least the
/// Armijo fraction, f(u + tΔu) ≤ (1 − 2·10⁻⁴ t) f(u), which keeps a poor
/// guess from wandering to a far solution. Converged when max|Φ_i| ≤
/// `tolerance`, or when a full Newton step that fails to decrease f is at
/// the level of round-off (|Δu_i| ≤ 10⁻¹⁴·(1 + |u_i|) for every i): then u
/// is left where it was. Returns the iterations used.
///
/// Near a solution the full step is accepted at once, and an iteration is one
/// evaluation, one factorisation and one solve; damping and the round-off
/// test run only when the full step fails.
///
/// # Errors
/// A [`Failure`] when Φ_u is singular, Φ is not finite, no step length
/// decreases the merit (a local minimum of ‖Φ‖ that is not a solution), or the
/// iteration cap is reached; `u` then holds the last iterate.
#[inline]
pub fn newton<const N: usize>(
    u: &mut [f64; N],
    options: &Options,
    mut eval: impl FnMut(&[f64; N], &mut [f64; N], &mut [[f64; N]; N]),
) -> Result<usize, Failure> {
    let mut phi = [0.0; N];
    let mut jac = [[0.0; N]; N];
    eval(u, &mut phi, &mut jac);
    let (mut f0, mut max) = norms(&phi);
    let mut iterations = 0;
    loop {
        if max <= options.tolerance {
            return branch_check(&jac, options).map(|()| iterations);
        }
        // `norms` makes both infinite when Φ is not finite.
        if max == f64::INFINITY {
            return Err(non_finite(&phi));
        }
        if iterations >= options.max_iterations {
            return Err(Failure::NotConverged {
                iterations,
                residual: max,
                equation: worst(&phi),
            });
        }
        iterations += 1;
        let step = Lu::factor(&jac, options.singularity_threshold)?.solve(&phi);
        let start = *u;
        for i in 0..N {
            u[i] = start[i] - step[i];
        }
        eval(u, &mut phi, &mut jac);
        let (f, m) = norms(&phi);
        if f <= (1.0 - ARMIJO) * f0 {
            (f0, max) = (f, m);
            continue;
        }
        let search = Search {
            start: &start,
            step: &step,
            f0,
            last_max: m,
            iterations,
        };
        match search.run(u, &mut phi, &mut jac, &mut eval)? {
            Some((f, m)) => (f0, max) = (f, m),
            None => return branch_check(&jac, options).map(|()| iterations),
        }
    }
}

/// What [`FastNewton::assess`] found at the latest evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    /// Not converged: take the full Newton step with
    /// [`FastNewton::advance`], then evaluate again at the new u.
    Continue,
    /// max|Φ_i| ≤ tolerance (and the branch is the one asked for).
    Converged,
    /// Anything else: solve again from the start with [`newton`], whose
    /// common path this is, so that it damps, detects round-off or reports
    /// the failure.
    Fallback,
}

/// The common path of [`newton`], driven by the caller's own loop, so that
/// generated code evaluates Φ and Φ_u inline rather than through a closure:
/// near a solution every full Newton step passes the Armijo test, and then
/// the iterates are those of [`newton`] (bit for bit when the step is
/// solved with [`Lu`] on the whole of Φ_u; to rounding in generated code,
/// which solves Φ_u block by block and carries sines and cosines from one
/// iterate to the next with [`sin_cos_after`]). On the first event
/// off that path (a full step that does not decrease f = ½‖Φ‖² enough, a
/// singular or non-finite Φ_u, the iteration cap, the wrong branch) it
/// answers [`Next::Fallback`], and the caller runs [`newton`] from the start,
/// which retraces the same iterates up to that point and takes over.
#[derive(Debug, Clone, Copy)]
pub struct FastNewton {
    /// f at the current iterate's predecessor (infinite before the first).
    f0: f64,
    /// f at the current iterate, once assessed.
    f: f64,
    iterations: usize,
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
        }
    }

    /// Given Φ and Φ_u at the current iterate: converged, off the common
    /// path, or [`Next::Continue`]: take the full Newton step
    /// Δu = −Φ_u⁻¹ Φ with [`FastNewton::advance`].
    #[inline(always)]
    pub fn assess<const N: usize>(
        &mut self,
        phi: &[f64; N],
        jac: &[[f64; N]; N],
        options: &Options,
    ) -> Next {
        let (f, max) = norms(phi);
        // The Armijo test of the full step that led here (vacuous at the
        // first evaluation, where f0 is infinite and f is at most infinite).
        let decreased = f <= (1.0 - ARMIJO) * self.f0;
        if !decreased {
            return Next::Fallback;
        }
        if max <= options.tolerance {
            return match branch_check(jac, options) {
                Ok(()) => Next::Converged,
                Err(_) => Next::Fallback,
            };
        }
        if max == f64::INFINITY || self.iterations >= options.max_iterations {
            return Next::Fallback;
        }
        self.f = f;
        Next::Continue
    }

    /// u ← u − `step`, where `step` = Φ_u⁻¹ Φ at the assessed iterate.
    #[inline(always)]
    pub fn advance<const N: usize>(&mut self, u: &mut [f64; N], step: &[f64; N]) {
        self.iterations += 1;
        self.f0 = self.f;
        for i in 0..N {
            u[i] -= step[i];
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
/// infinite or NaN `d` (before the first iterate) computes afresh.
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
        x.sin_cos()
    }
}

/// The failure for a residual vector with a NaN or an infinite entry.
#[cold]
fn non_finite<const N: usize>(phi: &[f64; N]) -> Failure {
    let i = worst(phi);
    Failure::NonFiniteResidual {
        equation: i,
        value: phi[i],
    }
}

/// A Newton step whose full length did not decrease the merit f = ½‖Φ‖²
/// enough: the slow path of [`newton`].
struct Search<'a, const N: usize> {
    start: &'a [f64; N],
    step: &'a [f64; N],
    /// f at `start`.
    f0: f64,
    /// max|Φ_i| after the full step.
    last_max: f64,
    iterations: usize,
}

impl<const N: usize> Search<'_, N> {
    /// `Ok(None)` when the step is at the level of round-off: u is put back
    /// at the start (and Φ, Φ_u evaluated there). Else halves t from 1 until
    /// the Armijo test passes, `Ok(Some((f, max|Φ_i|)))` at the new u.
    #[cold]
    fn run(
        &self,
        u: &mut [f64; N],
        phi: &mut [f64; N],
        jac: &mut [[f64; N]; N],
        eval: &mut impl FnMut(&[f64; N], &mut [f64; N], &mut [[f64; N]; N]),
    ) -> Result<Option<(f64, f64)>, Failure> {
        let (start, step) = (self.start, self.step);
        let mut tiny = true;
        for i in 0..N {
            tiny &= step[i].abs() <= 1e-14 * (1.0 + start[i].abs());
        }
        if tiny {
            *u = *start;
            eval(u, phi, jac);
            return Ok(None);
        }
        let mut t = 1.0;
        let mut m = self.last_max;
        loop {
            if t < 1e-3 {
                if m == f64::INFINITY {
                    return Err(non_finite(phi));
                }
                // No decrease along the Newton direction: a local minimum
                // of ‖Φ‖ that is not a solution.
                return Err(Failure::NotConverged {
                    iterations: self.iterations,
                    residual: m,
                    equation: worst(phi),
                });
            }
            t *= 0.5;
            for i in 0..N {
                u[i] = start[i] - t * step[i];
            }
            eval(u, phi, jac);
            let (f, max) = norms(phi);
            m = max;
            if f <= (1.0 - ARMIJO * t) * self.f0 {
                return Ok(Some((f, max)));
            }
        }
    }
}

/// Names of the items of a mechanism, for error messages.
#[derive(Debug, Clone, Copy)]
pub struct Names {
    /// Coordinate names, drivers first.
    pub coordinates: &'static [&'static str],
    /// Number of drivers.
    pub drivers: usize,
    /// Equations as written.
    pub equations: &'static [&'static str],
}

/// Turns a [`Failure`] into an [`Error`] naming the items, with the
/// configuration `q` (drivers then unknowns) where it happened.
#[must_use]
pub fn describe(failure: Failure, names: &Names, q: &[f64]) -> Error {
    let configuration: Vec<(&'static str, f64)> = names
        .coordinates
        .iter()
        .copied()
        .zip(q.iter().copied())
        .collect();
    let equation = |i: usize| names.equations.get(i).copied().unwrap_or("?");
    match failure {
        Failure::Singular {
            unknown,
            relative_pivot,
        } => Error::Singular {
            unknown: names
                .coordinates
                .get(names.drivers + unknown)
                .copied()
                .unwrap_or("?"),
            relative_pivot,
            configuration,
        },
        Failure::NotConverged {
            iterations,
            residual,
            equation: e,
        } => Error::NotConverged {
            iterations,
            residual,
            equation: equation(e),
            configuration,
        },
        Failure::WrongBranch => Error::WrongBranch { configuration },
        Failure::NonFiniteResidual { equation: e, value } => Error::NonFinite {
            input: crate::Input::Computed,
            name: equation(e),
            value,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lu_solves_a_permuted_system() {
        let a = [[0.0, 2.0, 1.0], [1.0, -1.0, 0.0], [3.0, 0.0, 1.0]];
        let x = [1.0, -2.0, 0.5];
        let mut b = [0.0; 3];
        for i in 0..3 {
            b[i] = (0..3).map(|j| a[i][j] * x[j]).sum();
        }
        let lu = Lu::factor(&a, 1e-12).map_err(|_| ()).expect("regular");
        let got = lu.solve(&b);
        for i in 0..3 {
            assert!((got[i] - x[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn lu_names_the_dependent_column() {
        // Column 1 is twice column 0.
        let a = [[1.0, 2.0, 0.0], [3.0, 6.0, 1.0], [0.5, 1.0, 4.0]];
        match Lu::factor(&a, 1e-12) {
            Err(Failure::Singular { unknown, .. }) => assert_eq!(unknown, 1),
            other => panic!("expected singular, got {other:?}"),
        }
    }

    #[test]
    fn sin_cos_after_matches_the_library_functions() {
        // Angles over several turns and steps up to the series' limit (and
        // beyond it, where it computes afresh), from a fixed-seed generator.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            #[allow(clippy::cast_precision_loss)]
            let x = (state >> 11) as f64 / (1u64 << 53) as f64;
            x
        };
        let mut worst = 0.0f64;
        for _ in 0..100_000 {
            let x0 = 40.0 * (uniform() - 0.5);
            let d = 0.07 * (uniform() - 0.5) * if uniform() < 0.5 { 1.0 } else { 1e-6 };
            let (s, c) = x0.sin_cos();
            let x = x0 + d;
            let (s1, c1) = sin_cos_after(s, c, x, x - x0);
            let (se, ce) = x.sin_cos();
            worst = worst.max((s1 - se).abs()).max((c1 - ce).abs());
        }
        assert!(worst < 4e-16, "largest error {worst:e}");
        // No previous value: computed afresh.
        assert_eq!(
            sin_cos_after(0.0, 0.0, 0.7, f64::INFINITY),
            0.7f64.sin_cos()
        );
        assert_eq!(sin_cos_after(0.0, 0.0, 0.7, f64::NAN), 0.7f64.sin_cos());
    }

    #[test]
    fn fast_newton_follows_newton_and_hands_over() {
        // x² + y² = 4, y = x, as in the test below.
        let eval = |u: &[f64; 2]| {
            (
                [u[0] * u[0] + u[1] * u[1] - 4.0, u[1] - u[0]],
                [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]],
            )
        };
        // The protocol generated code follows: assess, solve, advance.
        let drive = |mut u: [f64; 2]| {
            let mut fast = FastNewton::new();
            loop {
                let (phi, jac) = eval(&u);
                match fast.assess(&phi, &jac, &Options::DEFAULT) {
                    Next::Continue => {}
                    end => return (end, u),
                }
                let Ok(lu) = Lu::factor(&jac, Options::DEFAULT.singularity_threshold) else {
                    return (Next::Fallback, u);
                };
                fast.advance(&mut u, &lu.solve(&phi));
            }
        };
        let mut reference = [1.0, 0.5];
        newton(&mut reference, &Options::DEFAULT, |u, phi, jac| {
            (*phi, *jac) = eval(u);
        })
        .map_err(|_| ())
        .expect("converges");
        let (end, u) = drive([1.0, 0.5]);
        assert_eq!(end, Next::Converged);
        assert_eq!(u, reference, "the same iterates, bit for bit");
        // From (0.1, −3) the full first step overshoots and the merit grows:
        // the fast path hands over to the damped solver.
        let (end, _) = drive([0.1, -3.0]);
        assert_eq!(end, Next::Fallback);
        // A non-finite residual hands over at once, and so does the
        // iteration cap once reached.
        let (phi, jac) = eval(&[1.0, 0.5]);
        let mut fast = FastNewton::new();
        assert_eq!(
            fast.assess(&[f64::NAN, 0.0], &jac, &Options::DEFAULT),
            Next::Fallback
        );
        let one = Options {
            max_iterations: 1,
            ..Options::DEFAULT
        };
        let mut fast = FastNewton::new();
        let mut u = [1.0, 0.5];
        assert_eq!(fast.assess(&phi, &jac, &one), Next::Continue);
        let step = Lu::factor(&jac, one.singularity_threshold)
            .map_err(|_| ())
            .expect("regular")
            .solve(&phi);
        fast.advance(&mut u, &step);
        let (phi, jac) = eval(&u);
        assert_eq!(fast.assess(&phi, &jac, &one), Next::Fallback);
    }

    #[test]
    fn newton_stops_at_round_off() {
        // Φ = 10⁶ (x² − 2): no double makes it smaller than about
        // 10⁶ · 2√2 · ulp(√2) / 2 ≈ 3·10⁻¹⁰, far above the tolerance 10⁻¹²,
        // so the iteration must end by the round-off test, next to √2.
        let mut u = [1.3];
        let it = newton(&mut u, &Options::DEFAULT, |u, phi, jac| {
            phi[0] = 1e6 * (u[0] * u[0] - 2.0);
            jac[0][0] = 2e6 * u[0];
        });
        assert!(matches!(it, Ok(n) if n < 10), "{it:?}");
        assert!(
            (u[0] - std::f64::consts::SQRT_2).abs() <= 2.3e-16,
            "{}",
            u[0]
        );
    }

    #[test]
    fn newton_finds_the_root_near_the_guess() {
        // x² + y² = 4, y = x: roots ±(√2, √2).
        let mut u = [1.0, 0.5];
        let it = newton(&mut u, &Options::DEFAULT, |u, phi, jac| {
            phi[0] = u[0] * u[0] + u[1] * u[1] - 4.0;
            phi[1] = u[1] - u[0];
            *jac = [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]];
        });
        assert!(it.is_ok());
        assert!((u[0] - 2f64.sqrt()).abs() < 1e-12 && (u[1] - 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn newton_reports_no_solution() {
        // x² + 1 = 0 has no real root.
        let mut u = [0.3];
        let r = newton(&mut u, &Options::DEFAULT, |u, phi, jac| {
            phi[0] = u[0] * u[0] + 1.0;
            jac[0][0] = 2.0 * u[0];
        });
        assert!(matches!(
            r,
            Err(Failure::NotConverged { .. } | Failure::Singular { .. })
        ));
    }
}
