//! Dense linear algebra on the stack: the LU factorisation with partial
//! pivoting behind every Jacobian solve, its conditioning and determinant
//! sign, and one-shot dense solves.

// Elimination is written with explicit indices, as in the formulas.
#![allow(clippy::needless_range_loop)]

use super::failure::Failure;
use super::scaling::Scaling;

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

/// x = Φ_u⁻¹ `rhs` for a dense Φ_u (`jac`, rows are equations) through the
/// scaled matrix: Φ̃_u y = diag(1/S) rhs, x = diag(unit) y. The linear
/// solve for [`newton`](super::newton()) when Φ_u is stored whole; generated code passes its
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
