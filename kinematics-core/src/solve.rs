//! Dense linear solves and Newton–Raphson on fixed-size arrays.
//!
//! Everything here works on `[f64; N]` and `[[f64; N]; N]` on the stack, so
//! assembling near a known pose and analysing velocities and accelerations
//! allocate nothing.

// Elimination is written with explicit indices, as in the formulas.
#![allow(clippy::needless_range_loop)]

use crate::{Error, Options};
use alloc::vec::Vec;

/// Why a numerical step failed, without names (generated code turns it
/// into an [`Error`] naming the equation or unknown, off the hot path).
///
/// ```
/// use kinematics_core::solve::{Failure, Lu};
/// // Column 1 is twice column 0: the matrix is singular.
/// match Lu::factor(&[[1.0, 2.0], [3.0, 6.0]], 1e-12) {
///     Err(Failure::Singular { unknown, .. }) => assert_eq!(unknown, 1),
///     other => panic!("{other:?}"),
/// }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Failure {
    /// The scaled Φ_u is singular or nearly so: its distance to the nearest
    /// singular matrix, `conditioning` (see [`Lu::conditioning`]), is at or
    /// below the threshold; `unknown` is the unknown it determines worst.
    Singular {
        /// Index of the unknown.
        unknown: usize,
        /// The conditioning, 1 / ‖Φ̃_u⁻¹‖_∞ of the scaled matrix (0 when a
        /// pivot vanished).
        conditioning: f64,
    },
    /// Newton stopped with residual `residual` in equation `equation`.
    NotConverged {
        /// Iterations performed.
        iterations: usize,
        /// max |Φ_i| (in the equation's own units).
        residual: f64,
        /// |Φ_i| relative to the size S_i of the equation's terms.
        relative: f64,
        /// Index of the equation with the largest relative residual.
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
    /// global. Used by generated code.
    #[doc(hidden)]
    #[cold]
    #[must_use]
    pub fn in_block(self, columns: &[usize]) -> Self {
        match self {
            Failure::Singular {
                unknown,
                conditioning,
            } => Failure::Singular {
                unknown: columns.get(unknown).copied().unwrap_or(unknown),
                conditioning,
            },
            other => other,
        }
    }

    /// A failure found in a subsystem of Φ = 0 (a diagonal block solved
    /// alone) whose equations are `rows` and unknowns `columns` (indices
    /// into all of them): the equation and unknown indices are made
    /// global. Used by generated code.
    #[doc(hidden)]
    #[cold]
    #[must_use]
    pub fn in_subsystem(self, rows: &[usize], columns: &[usize]) -> Self {
        let row = |i: usize| rows.get(i).copied().unwrap_or(i);
        match self.in_block(columns) {
            Failure::NotConverged {
                iterations,
                residual,
                relative,
                equation,
            } => Failure::NotConverged {
                iterations,
                residual,
                relative,
                equation: row(equation),
            },
            Failure::NonFiniteResidual { equation, value } => Failure::NonFiniteResidual {
                equation: row(equation),
                value,
            },
            other => other,
        }
    }
}

/// The scales that make Newton's tests and the singularity measure
/// independent of the units and the size of a mechanism.
///
/// Row i is scaled by 1/S_i, where S_i, the *term scale* of equation i, is
/// the sum of the magnitudes of the equation's terms with every sine and
/// cosine bounded by 1, every unknown angle counted as 1 rad and every
/// unknown length as the characteristic length L (for the four-bar loop
/// a cos φ + b cos θ3 − d − c cos θ4 = 0, S = |a| + |b| + |c| + |d|).
/// L is the largest term scale of the equations with the unknown lengths
/// left out (1 when that is zero). Column j is scaled by the unknown's
/// natural unit: 1 rad for an angle, L for a length. The macro derives
/// S_i at compile time; it is evaluated from the parameters and drivers.
///
/// The scaled Jacobian Φ̃_u = diag(1/S) Φ_u diag(unit) has entries of order
/// one at a generic configuration, whatever the units of the model, and a
/// mechanism drawn in millimetres, metres or kilometres gives the same
/// Φ̃_u, the same relative residuals and the same conditioning.
///
/// ```
/// use kinematics_core::solve::{characteristic_length, Scaling};
/// // A slider-crank with a = 0.1, b = 0.3: its x loop a cos φ + b cos θ − x
/// // and y loop a sin φ + b sin θ have, with x left out, the term scales
/// // 0.4 and 0.4, so L = 0.4 and x counts as 0.4 in the x loop.
/// let fixed = [0.4, 0.4];
/// let l = characteristic_length(&fixed);
/// let s = Scaling::new(&[0.4 + l, 0.4], l, [false, true])?;
/// assert_eq!(s.row, [1.0 / 0.8, 1.0 / 0.4]);
/// assert_eq!(s.col, [1.0, 0.4]); // θ in radians, x in units of L
/// # Ok::<(), kinematics_core::solve::Failure>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaling<const N: usize> {
    /// 1 / S_i for each equation.
    pub row: [f64; N],
    /// The natural unit of each unknown: 1 for an angle, L for a length.
    pub col: [f64; N],
}

impl<const N: usize> Scaling<N> {
    /// No scaling: every row and column scale 1 (the equations' own units).
    pub const UNIT: Self = Self {
        row: [1.0; N],
        col: [1.0; N],
    };

    /// The scaling for term scales `terms` (S_i), the characteristic length
    /// `length` and which unknowns are lengths.
    ///
    /// ```
    /// use kinematics_core::solve::Scaling;
    /// let s = Scaling::new(&[2.0], 1.0, [false])?;
    /// assert_eq!(s.row, [0.5]);
    /// // An overflowed scale is an error, not a zero weight.
    /// assert!(Scaling::new(&[f64::INFINITY], 1.0, [false]).is_err());
    /// # Ok::<(), kinematics_core::solve::Failure>(())
    /// ```
    ///
    /// # Errors
    /// [`Failure::NonFiniteResidual`] naming the first equation whose term
    /// scale overflowed (an input too large for `f64` arithmetic).
    #[inline(always)]
    pub fn new(terms: &[f64; N], length: f64, is_length: [bool; N]) -> Result<Self, Failure> {
        let mut row = [1.0; N];
        let mut col = [1.0; N];
        for i in 0..N {
            let s = terms[i];
            if s.is_nan() || s == f64::INFINITY {
                return Err(overflow(i, s));
            }
            // An equation with no term of fixed size (every term zero at
            // these parameters) keeps its own units.
            row[i] = if s > 0.0 { 1.0 / s } else { 1.0 };
            if is_length[i] {
                col[i] = length;
            }
        }
        Ok(Self { row, col })
    }

    /// The weights of the convergence test for `options`: 1/S_i for
    /// [`Convergence::Relative`](crate::Convergence::Relative), 1 for
    /// [`Convergence::Absolute`](crate::Convergence::Absolute).
    ///
    /// ```
    /// use kinematics_core::{solve::Scaling, Convergence, Options};
    /// let s = Scaling::new(&[4.0], 1.0, [false])?;
    /// assert_eq!(s.weights(&Options::DEFAULT), [0.25]);
    /// let absolute = Options { convergence: Convergence::Absolute, ..Options::DEFAULT };
    /// assert_eq!(s.weights(&absolute), [1.0]);
    /// # Ok::<(), kinematics_core::solve::Failure>(())
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn weights(&self, options: &Options) -> [f64; N] {
        match options.convergence {
            crate::Convergence::Relative => self.row,
            crate::Convergence::Absolute => [1.0; N],
        }
    }

    /// The scaled matrix diag(row) · `a` · diag(col).
    ///
    /// ```
    /// use kinematics_core::solve::Scaling;
    /// let s = Scaling::new(&[2.0, 4.0], 10.0, [false, true])?;
    /// assert_eq!(s.matrix(&[[1.0, 1.0], [1.0, 1.0]]), [[0.5, 5.0], [0.25, 2.5]]);
    /// # Ok::<(), kinematics_core::solve::Failure>(())
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn matrix(&self, a: &[[f64; N]; N]) -> [[f64; N]; N] {
        let mut out = *a;
        for i in 0..N {
            for j in 0..N {
                out[i][j] *= self.row[i] * self.col[j];
            }
        }
        out
    }
}

/// The characteristic length L of a mechanism from the term scales of its
/// equations with the unknown lengths left out: the largest of them, or 1
/// when they are all zero (a model whose every term holds an unknown
/// length). An overflowed value is returned as it is, and reported by
/// [`Scaling::new`].
///
/// ```
/// use kinematics_core::solve::characteristic_length;
/// assert_eq!(characteristic_length(&[0.37, 0.26]), 0.37);
/// assert_eq!(characteristic_length(&[0.0, 0.0]), 1.0);
/// ```
#[inline(always)]
#[must_use]
pub fn characteristic_length<const N: usize>(fixed: &[f64; N]) -> f64 {
    let mut m = 0.0f64;
    for &v in fixed {
        // A plain comparison: a NaN cannot arise from finite, validated
        // inputs, and an overflow is an infinity, which this keeps.
        if v > m {
            m = v;
        }
    }
    if m > 0.0 {
        m
    } else {
        1.0
    }
}

/// The failure for a term scale that overflowed.
#[cold]
fn overflow(equation: usize, value: f64) -> Failure {
    Failure::NonFiniteResidual { equation, value }
}

/// LU factorisation with partial pivoting, P·A = L·U, of a square matrix.
///
/// The reciprocals of the pivots are kept, so that [`Lu::solve`] has no
/// division. For N ≤ 2 the inverse itself is kept instead (A⁻¹ = adj A / det A,
/// one division), and a solve is a matrix–vector product; the pivots are
/// those of partial pivoting all the same: p₀ = max(|a₀₀|, |a₁₀|) and
/// |det A| / p₀. Generated code factors the scaled Jacobian Φ̃_u (see
/// [`Scaling`]), whose entries are of order one, so that the pivots and
/// [`Lu::conditioning`] are absolute numbers with a meaning of their own.
///
/// ```
/// use kinematics_core::solve::Lu;
/// let a = [[0.0, 2.0, 1.0], [1.0, -1.0, 0.0], [3.0, 0.0, 1.0]];
/// let lu = Lu::factor(&a, 1e-12)?;
/// let x = lu.solve(&[-3.5, 3.0, 3.5]);
/// for (xi, ei) in x.iter().zip([1.0, -2.0, 0.5]) {
///     assert!((xi - ei).abs() < 1e-14);
/// }
/// # Ok::<(), kinematics_core::solve::Failure>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Lu<const N: usize> {
    /// L and U below and above the diagonal (N > 2), or A⁻¹ (N ≤ 2).
    lu: [[f64; N]; N],
    /// The reciprocals of the pivots (N > 2), |a₀₀| (N = 1), unused (N = 2).
    inv_pivot: [f64; N],
    perm: [usize; N],
    sign: f64,
}

/// The failure for pivot `unknown` of magnitude `pivot`, off the hot path.
#[cold]
fn singular(unknown: usize, pivot: f64) -> Failure {
    Failure::Singular {
        unknown,
        conditioning: if pivot.is_finite() { pivot } else { 0.0 },
    }
}

impl<const N: usize> Lu<N> {
    /// Factors `a` (rows are equations, columns unknowns).
    ///
    /// ```
    /// use kinematics_core::solve::Lu;
    /// assert!(Lu::factor(&[[2.0, 0.0], [0.0, 1e-14]], 1e-10).is_err());
    /// assert!(Lu::factor(&[[2.0, 0.0], [0.0, 1e-3]], 1e-10).is_ok());
    /// ```
    ///
    /// # Errors
    /// [`Failure::Singular`] when a pivot is at or below `threshold` in
    /// magnitude (or is not finite).
    #[inline(always)]
    pub fn factor(a: &[[f64; N]; N], threshold: f64) -> Result<Self, Failure> {
        if N == 1 {
            return Self::factor1(a, threshold);
        }
        if N == 2 {
            return Self::factor2(a, threshold);
        }
        let mut lu = *a;
        let mut perm = [0usize; N];
        let mut inv_pivot = [0.0; N];
        for (i, p) in perm.iter_mut().enumerate() {
            *p = i;
        }
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
            let regular = best_val > threshold && best_val.is_finite();
            if !regular {
                return Err(singular(k, best_val));
            }
            if best != k {
                lu.swap(k, best);
                perm.swap(k, best);
                sign = -sign;
            }
            let pivot_row = lu[k];
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
            sign,
        })
    }

    /// The 1×1 case: A⁻¹ = 1 / a₀₀.
    #[inline]
    fn factor1(a: &[[f64; N]; N], threshold: f64) -> Result<Self, Failure> {
        let a00 = a[0][0];
        let p0 = a00.abs();
        // Written so that a NaN or infinite entry also fails.
        if !(p0 > threshold && p0 < f64::INFINITY) {
            return Err(singular(0, p0));
        }
        let mut lu = [[0.0; N]; N];
        lu[0][0] = 1.0 / a00;
        // |a₀₀| itself: the conditioning, with no second division.
        let mut inv_pivot = [0.0; N];
        inv_pivot[0] = p0;
        Ok(Self {
            lu,
            inv_pivot,
            perm: [0; N],
            sign: a00.signum(),
        })
    }

    /// The 2×2 case: A⁻¹ = [[a₁₁, −a₀₁], [−a₁₀, a₀₀]] / det A, with the
    /// pivots of partial pivoting, p₀ = max(|a₀₀|, |a₁₀|) and |det A| / p₀,
    /// tested without dividing.
    #[inline]
    fn factor2(a: &[[f64; N]; N], threshold: f64) -> Result<Self, Failure> {
        let (a00, a01, a10, a11) = (a[0][0], a[0][1], a[1][0], a[1][1]);
        // A plain comparison, not `f64::max`: a NaN entry is caught by the
        // determinant test below.
        let p0 = if a10.abs() > a00.abs() {
            a10.abs()
        } else {
            a00.abs()
        };
        let det = a00 * a11 - a01 * a10;
        // A NaN or an infinity in `a` makes the determinant NaN or
        // infinite, and these comparisons false.
        let first_regular = p0 > threshold;
        if !first_regular {
            return Err(singular(0, p0));
        }
        if !(det.abs() > threshold * p0 && det.abs() < f64::INFINITY) {
            return Err(singular(1, det.abs() / p0));
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
            sign: det.signum(),
        })
    }

    /// The conditioning of the factored matrix A: its distance to the
    /// nearest singular matrix, 1 / ‖A⁻¹‖_∞ = min { ‖E‖_∞ : A + E singular }
    /// (Gastinel–Kahan), and the row of A⁻¹ with the largest sum (the
    /// unknown that a change of the right-hand side moves most).
    ///
    /// For the scaled Jacobian Φ̃_u it bounds the error of an accepted
    /// pose: if every scaled residual |Φ_i| / S_i is at most τ, each
    /// unknown is within τ / conditioning of the solution (in radians for
    /// an angle, in units of the characteristic length for a length), to
    /// first order. It tends to 0 at a dead-centre or toggle position, in
    /// proportion to the distance from it.
    ///
    /// ```
    /// use kinematics_core::solve::Lu;
    /// // diag(1, ε) is ε from the singular diag(1, 0); unknown 1 is the weak one.
    /// let lu = Lu::factor(&[[1.0, 0.0], [0.0, 1e-6]], 0.0)?;
    /// let (c, unknown) = lu.conditioning();
    /// assert!((c - 1e-6).abs() < 1e-18 && unknown == 1);
    /// # Ok::<(), kinematics_core::solve::Failure>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn conditioning(&self) -> (f64, usize) {
        if N == 1 {
            // 1 / |1 / a₀₀| = |a₀₀|, kept by the factorisation.
            return (self.inv_pivot[0], 0);
        }
        let mut worst = 0.0f64;
        let mut at = 0;
        let mut row_sum = |i: usize, sum: f64| {
            if sum > worst || i == 0 {
                worst = sum;
                at = i;
            }
        };
        if N <= 2 {
            for i in 0..N {
                let mut sum = 0.0;
                for j in 0..N {
                    sum += self.lu[i][j].abs();
                }
                row_sum(i, sum);
            }
        } else {
            // Columns of A⁻¹, one solve each.
            let mut inv = [[0.0; N]; N];
            for j in 0..N {
                let mut e = [0.0; N];
                e[j] = 1.0;
                let x = self.solve(&e);
                for i in 0..N {
                    inv[i][j] = x[i];
                }
            }
            for (i, r) in inv.iter().enumerate() {
                row_sum(i, r.iter().map(|v| v.abs()).sum());
            }
        }
        if N == 0 {
            return (1.0, 0);
        }
        let c = 1.0 / worst;
        (if c.is_finite() { c } else { 0.0 }, at)
    }

    /// The conditioning, or [`Failure::Singular`] when it is at or below
    /// `threshold`.
    ///
    /// ```
    /// use kinematics_core::solve::Lu;
    /// let lu = Lu::factor(&[[1.0, 0.0], [0.0, 1e-6]], 0.0)?;
    /// assert!(lu.check(1e-10).is_ok() && lu.check(1e-5).is_err());
    /// # Ok::<(), kinematics_core::solve::Failure>(())
    /// ```
    ///
    /// # Errors
    /// [`Failure::Singular`] naming the unknown the matrix determines worst.
    #[inline]
    pub fn check(&self, threshold: f64) -> Result<f64, Failure> {
        let (c, at) = self.conditioning();
        if c > threshold {
            Ok(c)
        } else {
            Err(singular(at, c))
        }
    }

    /// Sign of the determinant, ±1.
    ///
    /// ```
    /// use kinematics_core::solve::Lu;
    /// assert_eq!(Lu::factor(&[[0.0, 1.0], [1.0, 0.0]], 0.0)?.det_sign(), -1.0);
    /// # Ok::<(), kinematics_core::solve::Failure>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn det_sign(&self) -> f64 {
        self.sign
    }

    /// Solves A·x = b.
    ///
    /// ```
    /// use kinematics_core::solve::Lu;
    /// let x = Lu::factor(&[[2.0, 1.0], [1.0, 3.0]], 0.0)?.solve(&[3.0, 4.0]);
    /// assert!((x[0] - 1.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15);
    /// # Ok::<(), kinematics_core::solve::Failure>(())
    /// ```
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

/// Checks the assembly branch asked for in `options` against the sign of
/// det Φ_u, `sign` (the product of the signs of the diagonal blocks'
/// determinants; the row and column scales are positive and do not change
/// it).
///
/// # Errors
/// [`Failure::WrongBranch`] when the signs differ.
#[doc(hidden)]
#[inline(always)]
pub fn branch_check(sign: f64, options: &Options) -> Result<(), Failure> {
    let wanted = match options.branch {
        crate::Branch::Any => return Ok(()),
        crate::Branch::Positive => 1.0,
        crate::Branch::Negative => -1.0,
    };
    if sign == wanted {
        Ok(())
    } else {
        Err(Failure::WrongBranch)
    }
}

/// ½‖w∘v‖² and max|w_i v_i| (infinite when some entry is not finite) in one
/// pass.
#[inline(always)]
fn norms<const N: usize>(v: &[f64; N], w: &[f64; N]) -> (f64, f64) {
    let mut sq = 0.0;
    let mut max = 0.0f64;
    for i in 0..N {
        let x = v[i] * w[i];
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
fn worst<const N: usize>(v: &[f64; N], w: &[f64; N]) -> usize {
    let mut at = 0;
    for i in 0..N {
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
    mut eval: impl FnMut(&[f64; N], &mut [f64; N], &mut J),
    solve: impl Fn(&J, &[f64; N]) -> Result<[f64; N], Failure>,
) -> Result<usize, Failure> {
    let w = scaling.weights(options);
    eval(u, phi, jac);
    let (mut f0, mut max) = norms(phi, &w);
    let mut iterations = 0;
    loop {
        if max <= options.tolerance {
            break;
        }
        // `norms` makes both infinite when Φ is not finite.
        if max == f64::INFINITY {
            return Err(non_finite(phi, &w));
        }
        if iterations >= options.max_iterations {
            return Err(not_converged(iterations, phi, scaling, &w));
        }
        iterations += 1;
        let step = solve(jac, phi)?;
        let start = *u;
        for i in 0..N {
            u[i] = start[i] - step[i];
        }
        eval(u, phi, jac);
        let (f, m) = norms(phi, &w);
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
            scaling,
            w: &w,
        };
        match search.run(u, phi, jac, &mut eval)? {
            Some((f, m)) => (f0, max) = (f, m),
            None => return Ok(iterations),
        }
    }
    polish(u, phi, jac, scaling, options, &mut eval, &solve);
    Ok(iterations)
}

/// x = Φ_u⁻¹ `rhs` for a dense Φ_u (`jac`, rows are equations) through the
/// scaled matrix: Φ̃_u y = diag(1/S) rhs, x = diag(unit) y. The linear
/// solve for [`newton`] when Φ_u is stored whole; generated code passes its
/// own, which factors the diagonal blocks of Φ_u and stores only its
/// nonzero entries.
///
/// # Errors
/// [`Failure::Singular`] when a pivot of Φ̃_u is at or below `threshold`.
///
/// ```
/// use kinematics_core::solve::{dense_solve, Scaling};
/// let x = dense_solve(&[[2.0, 1.0], [1.0, 3.0]], &[3.0, 4.0], &Scaling::UNIT, 1e-10)?;
/// assert!((x[0] - 1.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15);
/// # Ok::<(), kinematics_core::solve::Failure>(())
/// ```
#[inline]
pub fn dense_solve<const N: usize>(
    jac: &[[f64; N]; N],
    rhs: &[f64; N],
    scaling: &Scaling<N>,
    threshold: f64,
) -> Result<[f64; N], Failure> {
    let lu = Lu::factor(&scaling.matrix(jac), threshold)?;
    let mut b = *rhs;
    for i in 0..N {
        b[i] *= scaling.row[i];
    }
    let mut x = lu.solve(&b);
    for i in 0..N {
        x[i] *= scaling.col[i];
    }
    Ok(x)
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
fn polish<const N: usize, J>(
    u: &mut [f64; N],
    phi: &mut [f64; N],
    jac: &mut J,
    scaling: &Scaling<N>,
    options: &Options,
    eval: &mut impl FnMut(&[f64; N], &mut [f64; N], &mut J),
    solve: &impl Fn(&J, &[f64; N]) -> Result<[f64; N], Failure>,
) {
    let w = scaling.weights(options);
    for _ in 0..options.max_iterations {
        let (_, before) = norms(phi, &scaling.row);
        let (_, weighted) = norms(phi, &w);
        if before == 0.0 || weighted <= POLISH * options.tolerance {
            return;
        }
        let Ok(step) = solve(jac, phi) else {
            return;
        };
        let start = *u;
        for i in 0..N {
            u[i] -= step[i];
        }
        eval(u, phi, jac);
        let (_, after) = norms(phi, &scaling.row);
        let kept = after < before;
        if !kept {
            *u = start;
            eval(u, phi, jac);
            return;
        }
    }
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

    /// Given Φ at the current iterate and the weights `w` of the
    /// convergence test ([`Scaling::weights`]): converged, off the common
    /// path, or [`Next::Continue`]: take the full Newton step
    /// Δu = −Φ_u⁻¹ Φ with [`FastNewton::advance`].
    #[inline(always)]
    pub fn assess<const N: usize>(
        &mut self,
        phi: &[f64; N],
        w: &[f64; N],
        options: &Options,
    ) -> Next {
        let (f, max) = norms(phi, w);
        // The Armijo test of the full step that led here (vacuous at the
        // first evaluation, where f0 is infinite and f is at most infinite).
        let decreased = f <= (1.0 - ARMIJO) * self.f0;
        if !decreased {
            return Next::Fallback;
        }
        if max <= options.tolerance {
            return Next::Converged;
        }
        if max == f64::INFINITY || self.iterations >= options.max_iterations {
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
    pub fn unpolished<const N: usize>(phi: &[f64; N], w: &[f64; N], options: &Options) -> bool {
        let (_, max) = norms(phi, w);
        max > POLISH * options.tolerance || max.is_nan()
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

/// The failure for a residual vector with a NaN or an infinite entry.
#[cold]
fn non_finite<const N: usize>(phi: &[f64; N], w: &[f64; N]) -> Failure {
    let i = worst(phi, w);
    Failure::NonFiniteResidual {
        equation: i,
        value: phi[i],
    }
}

/// The failure of an iteration that ended away from a solution.
#[cold]
fn not_converged<const N: usize>(
    iterations: usize,
    phi: &[f64; N],
    scaling: &Scaling<N>,
    w: &[f64; N],
) -> Failure {
    let i = worst(phi, w);
    Failure::NotConverged {
        iterations,
        residual: phi[i].abs(),
        relative: (phi[i] * scaling.row[i]).abs(),
        equation: i,
    }
}

/// A Newton step whose full length did not decrease the merit f = ½‖w∘Φ‖²
/// enough: the slow path of [`newton`].
struct Search<'a, const N: usize> {
    start: &'a [f64; N],
    step: &'a [f64; N],
    /// f at `start`.
    f0: f64,
    /// max|w_i Φ_i| after the full step.
    last_max: f64,
    iterations: usize,
    scaling: &'a Scaling<N>,
    w: &'a [f64; N],
}

impl<const N: usize> Search<'_, N> {
    /// `Ok(None)` when the step is at the level of round-off and so is the
    /// residual at the start: u is put back at the start (and Φ, Φ_u
    /// evaluated there). Else halves t from 1 until the Armijo test
    /// passes, `Ok(Some((f, max|w_i Φ_i|)))` at the new u.
    #[cold]
    fn run<J>(
        &self,
        u: &mut [f64; N],
        phi: &mut [f64; N],
        jac: &mut J,
        eval: &mut impl FnMut(&[f64; N], &mut [f64; N], &mut J),
    ) -> Result<Option<(f64, f64)>, Failure> {
        let (start, step) = (self.start, self.step);
        let mut tiny = true;
        for i in 0..N {
            tiny &= step[i].abs() <= 1e-14 * (1.0 + start[i].abs());
        }
        if tiny {
            *u = *start;
            eval(u, phi, jac);
            let (_, relative) = norms(phi, &self.scaling.row);
            if relative <= ROUND_OFF {
                return Ok(None);
            }
            // A step that cannot move u (an unknown so large that its
            // floating-point spacing exceeds the step) while the equations
            // are far from closed: no solution is reachable from here.
            return Err(not_converged(self.iterations, phi, self.scaling, self.w));
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
                return Err(not_converged(self.iterations, phi, self.scaling, self.w));
            }
            t *= 0.5;
            for i in 0..N {
                u[i] = start[i] - t * step[i];
            }
            eval(u, phi, jac);
            let (f, max) = norms(phi, self.w);
            m = max;
            if f <= (1.0 - ARMIJO * t) * self.f0 {
                return Ok(Some((f, max)));
            }
        }
    }
}

/// Names of the items of a mechanism, for error messages. Used by generated
/// code.
#[doc(hidden)]
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
/// configuration `q` (drivers then unknowns) where it happened. Used by
/// generated code.
#[doc(hidden)]
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
            conditioning,
        } => Error::Singular {
            unknown: names
                .coordinates
                .get(names.drivers + unknown)
                .copied()
                .unwrap_or("?"),
            conditioning,
            configuration,
        },
        Failure::NotConverged {
            iterations,
            residual,
            relative,
            equation: e,
        } => Error::NotConverged {
            iterations,
            residual,
            relative,
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
        let mut rng = fastrand::Rng::with_seed(0x2545_f491_4f6c_dd1d);
        let mut uniform = || rng.f64();
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

    /// Newton on `eval` from `u` with the given scaling and options.
    fn solve2(
        u: &mut [f64; 2],
        scaling: &Scaling<2>,
        options: &Options,
        eval: impl Fn(&[f64; 2]) -> ([f64; 2], [[f64; 2]; 2]),
    ) -> Result<usize, Failure> {
        let (mut phi, mut jac) = ([0.0; 2], [[0.0; 2]; 2]);
        newton(
            u,
            &mut phi,
            &mut jac,
            scaling,
            options,
            |u, p, j| {
                (*p, *j) = eval(u);
            },
            |j, r| dense_solve(j, r, scaling, options.singularity_threshold),
        )
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
        let scaling = Scaling::<2>::UNIT;
        let w = scaling.weights(&Options::DEFAULT);
        // The protocol generated code follows: assess, solve, advance.
        let drive = |mut u: [f64; 2]| {
            let mut fast = FastNewton::new();
            let mut steps = 0;
            loop {
                let (phi, jac) = eval(&u);
                match fast.assess(&phi, &w, &Options::DEFAULT) {
                    Next::Continue => {}
                    end => return (end, u, steps),
                }
                let Ok(lu) = Lu::factor(&jac, Options::DEFAULT.singularity_threshold) else {
                    return (Next::Fallback, u, steps);
                };
                fast.advance(&mut u, &lu.solve(&phi));
                steps += 1;
            }
        };
        // Newton's iterates without its final polishing step.
        let mut reference = [1.0, 0.5];
        let (end, u, steps) = drive([1.0, 0.5]);
        assert_eq!(end, Next::Converged);
        for _ in 0..steps {
            let (phi, jac) = eval(&reference);
            let step = Lu::factor(&jac, 1e-10)
                .map_err(|_| ())
                .expect("regular")
                .solve(&phi);
            reference = [reference[0] - step[0], reference[1] - step[1]];
        }
        assert_eq!(u, reference, "the same iterates, bit for bit");
        let mut full = [1.0, 0.5];
        let it = solve2(&mut full, &scaling, &Options::DEFAULT, eval);
        assert_eq!(it, Ok(steps));
        // From (0.1, −3) the full first step overshoots and the merit grows:
        // the fast path hands over to the damped solver.
        let (end, _, _) = drive([0.1, -3.0]);
        assert_eq!(end, Next::Fallback);
        // A non-finite residual hands over at once, and so does the
        // iteration cap once reached.
        let (phi, jac) = eval(&[1.0, 0.5]);
        let mut fast = FastNewton::new();
        assert_eq!(
            fast.assess(&[f64::NAN, 0.0], &w, &Options::DEFAULT),
            Next::Fallback
        );
        let one = Options {
            max_iterations: 1,
            ..Options::DEFAULT
        };
        let mut fast = FastNewton::new();
        let mut u = [1.0, 0.5];
        assert_eq!(fast.assess(&phi, &w, &one), Next::Continue);
        let step = Lu::factor(&jac, one.singularity_threshold)
            .map_err(|_| ())
            .expect("regular")
            .solve(&phi);
        fast.advance(&mut u, &step);
        let (phi, _) = eval(&u);
        assert_eq!(fast.assess(&phi, &w, &one), Next::Fallback);
    }

    #[test]
    fn newton_stops_at_round_off() {
        // Φ = 10⁶ (x² − 2), with the absolute test max|Φ| ≤ 10⁻¹²: no double
        // makes |Φ| smaller than about 10⁶ · 2√2 · ulp(√2) / 2 ≈ 3·10⁻¹⁰,
        // so the iteration must end by the round-off test, next to √2. The
        // term scale is S = 10⁶ (x² + 2) ≈ 4·10⁶, and 3·10⁻¹⁰ / S is far
        // below ROUND_OFF.
        let absolute = Options {
            convergence: crate::Convergence::Absolute,
            ..Options::DEFAULT
        };
        let scaling = Scaling::new(&[4e6], 1.0, [false]).expect("finite");
        let mut u = [1.3];
        let (mut phi, mut jac) = ([0.0], [[0.0]]);
        let it = newton(
            &mut u,
            &mut phi,
            &mut jac,
            &scaling,
            &absolute,
            |u, phi, jac| {
                phi[0] = 1e6 * (u[0] * u[0] - 2.0);
                jac[0][0] = 2e6 * u[0];
            },
            |j, r| dense_solve(j, r, &scaling, 1e-10),
        );
        assert!(matches!(it, Ok(n) if n < 10), "{it:?}");
        assert!(
            (u[0] - std::f64::consts::SQRT_2).abs() <= 2.3e-16,
            "{}",
            u[0]
        );
    }

    #[test]
    fn a_step_that_cannot_move_u_is_not_a_solution() {
        // cos u = 0.5 from u = 10²⁰: the spacing of doubles there is 16384,
        // every Newton step is "at round-off" relative to u, but the
        // residual is not: this must fail, not return the guess as a root.
        // (It returned Ok before the round-off exit looked at the residual.)
        let scaling = Scaling::new(&[1.5], 1.0, [false]).expect("finite");
        let mut u = [1e20];
        let (mut phi, mut jac) = ([0.0], [[0.0]]);
        let r = newton(
            &mut u,
            &mut phi,
            &mut jac,
            &scaling,
            &Options::DEFAULT,
            |u, phi, jac| {
                phi[0] = u[0].cos() - 0.5;
                jac[0][0] = -u[0].sin();
            },
            |j, r| dense_solve(j, r, &scaling, 1e-10),
        );
        match r {
            Ok(_) => assert!(
                (u[0].cos() - 0.5).abs() <= 1.5e-12,
                "Ok at {u:?}, Φ = {phi:?}"
            ),
            Err(f) => assert!(
                matches!(f, Failure::NotConverged { .. } | Failure::Singular { .. }),
                "{f:?}"
            ),
        }
    }

    #[test]
    fn the_convergence_test_is_relative_to_the_term_scale() {
        // x² + y² = r², y = x for r from 1 nm to 1000 km: the same relative
        // accuracy, and the absolute option still available.
        for r in [1e-9, 1e-3, 1.0, 1e3, 1e6] {
            let scaling = Scaling::new(&[3.0 * r * r, 2.0 * r], r, [true, true]).expect("finite");
            let eval = move |u: &[f64; 2]| {
                (
                    [u[0] * u[0] + u[1] * u[1] - r * r, u[1] - u[0]],
                    [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]],
                )
            };
            let mut u = [0.9 * r, 0.5 * r];
            solve2(&mut u, &scaling, &Options::DEFAULT, eval).expect("converges");
            let exact = r * std::f64::consts::FRAC_1_SQRT_2;
            assert!((u[0] / exact - 1.0).abs() < 1e-14, "r = {r}: {u:?}");
        }
        // With the absolute test at 10⁻¹², a nanometre-sized problem is
        // "converged" after one step, still far from the root: the reason
        // the default is relative.
        let r = 1e-9;
        let scaling = Scaling::new(&[3.0 * r * r, 2.0 * r], r, [true, true]).expect("finite");
        let absolute = Options {
            convergence: crate::Convergence::Absolute,
            ..Options::DEFAULT
        };
        let mut u = [0.9 * r, 0.5 * r];
        let it = solve2(&mut u, &scaling, &absolute, |u| {
            (
                [u[0] * u[0] + u[1] * u[1] - r * r, u[1] - u[0]],
                [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]],
            )
        });
        assert_eq!(it, Ok(1));
        let exact = r * std::f64::consts::FRAC_1_SQRT_2;
        assert!((u[0] / exact - 1.0).abs() > 1e-4, "{u:?}");
    }

    #[test]
    fn conditioning_is_the_distance_to_singularity_of_the_scaled_matrix() {
        // 1×1: |a|, not 1 (a 1×1 matrix used to have conditioning 1 always).
        let lu = Lu::factor(&[[1e-7]], 1e-10)
            .map_err(|_| ())
            .expect("regular");
        assert!((lu.conditioning().0 - 1e-7).abs() < 1e-22);
        // diag(1, ε): the nearest singular matrix is ε away in any norm.
        for eps in [1e-2, 1e-5, 1e-9] {
            let lu = Lu::factor(&[[1.0, 0.0], [0.0, eps]], 1e-12)
                .map_err(|_| ())
                .expect("regular");
            let (c, at) = lu.conditioning();
            assert!((c / eps - 1.0).abs() < 1e-12 && at == 1, "{c} {at}");
            let lu3 = Lu::factor(&[[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, eps]], 1e-12)
                .map_err(|_| ())
                .expect("regular");
            let (c, at) = lu3.conditioning();
            assert!((c / eps - 1.0).abs() < 1e-12 && at == 2, "{c} {at}");
        }
        // A + E singular with ‖E‖_∞ = 1 / ‖A⁻¹‖_∞ (Gastinel–Kahan), checked
        // on a full matrix: E = −(y zᵀ)/‖A⁻¹‖ for the maximising row.
        let a = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let lu = Lu::factor(&a, 1e-12).map_err(|_| ()).expect("regular");
        let (c, _) = lu.conditioning();
        let mut inv = [[0.0; 3]; 3];
        for j in 0..3 {
            let mut e = [0.0; 3];
            e[j] = 1.0;
            let x = lu.solve(&e);
            for i in 0..3 {
                inv[i][j] = x[i];
            }
        }
        let norm = inv
            .iter()
            .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        assert!((c * norm - 1.0).abs() < 1e-14);
        assert!(matches!(lu.check(c * 1.01), Err(Failure::Singular { .. })));
        assert_eq!(lu.check(c * 0.99), Ok(c));
    }

    #[test]
    fn newton_finds_the_root_near_the_guess() {
        // x² + y² = 4, y = x: roots ±(√2, √2).
        let mut u = [1.0, 0.5];
        let it = solve2(&mut u, &Scaling::UNIT, &Options::DEFAULT, |u| {
            (
                [u[0] * u[0] + u[1] * u[1] - 4.0, u[1] - u[0]],
                [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]],
            )
        });
        assert!(it.is_ok());
        assert!((u[0] - 2f64.sqrt()).abs() < 1e-12 && (u[1] - 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn newton_reports_no_solution() {
        // x² + 1 = 0 has no real root.
        let mut u = [0.3];
        let (mut phi, mut jac) = ([0.0], [[0.0]]);
        let r = newton(
            &mut u,
            &mut phi,
            &mut jac,
            &Scaling::UNIT,
            &Options::DEFAULT,
            |u, phi, jac| {
                phi[0] = u[0] * u[0] + 1.0;
                jac[0][0] = 2.0 * u[0];
            },
            |j, r| dense_solve(j, r, &Scaling::UNIT, 1e-10),
        );
        assert!(matches!(
            r,
            Err(Failure::NotConverged { .. } | Failure::Singular { .. })
        ));
    }
}
