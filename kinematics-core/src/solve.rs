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
    #[inline]
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
        let mut scale = 0.0f64;
        for (i, row) in a.iter().enumerate() {
            perm[i] = i;
            for v in row {
                scale = scale.max(v.abs());
            }
        }
        let scale = if scale > 0.0 { scale } else { 1.0 };
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
    fn factor1(a: &[[f64; N]; N], threshold: f64) -> Result<Self, Failure> {
        let a00 = a[0][0];
        let p0 = a00.abs();
        let scale = if p0 > 0.0 { p0 } else { 1.0 };
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
            conditioning: 1.0,
            sign: a00.signum(),
        })
    }

    /// The 2×2 case: A⁻¹ = [[a₁₁, −a₀₁], [−a₁₀, a₀₀]] / det A, with the
    /// pivots of partial pivoting, p₀ = max(|a₀₀|, |a₁₀|) and |det A| / p₀,
    /// tested without dividing.
    #[inline]
    fn factor2(a: &[[f64; N]; N], threshold: f64) -> Result<Self, Failure> {
        let (a00, a01, a10, a11) = (a[0][0], a[0][1], a[1][0], a[1][1]);
        // Plain comparisons, not `f64::max`: a NaN entry is caught by the
        // determinant test below.
        let larger = |x: f64, y: f64| if y > x { y } else { x };
        let p0 = larger(a00.abs(), a10.abs());
        let scale = larger(p0, larger(a01.abs(), a11.abs()));
        let scale = if scale > 0.0 { scale } else { 1.0 };
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
    #[inline]
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
    if sq.is_finite() {
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

/// Solves Φ(u) = 0 for `u` by Newton–Raphson from the value in `u`. `eval`
/// writes Φ(u) and Φ_u(u); when it returns `Ok`, the last call was at the
/// returned `u`.
///
/// Each Newton step Δu = −Φ_u⁻¹ Φ is a descent direction of the merit
/// f = ½‖Φ‖²; the step length t is halved until f decreases by at least the
/// Armijo fraction, f(u + tΔu) ≤ (1 − 2·10⁻⁴ t) f(u), which keeps a poor
/// guess from wandering to a far solution. Converged when max|Φ_i| ≤
/// `tolerance`, or when the full Newton step is at the level of round-off
/// (|Δu_i| ≤ 10⁻¹⁴·(1 + |u_i|) for every i). Returns the iterations used.
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
        if !max.is_finite() {
            let i = worst(&phi);
            return Err(Failure::NonFiniteResidual {
                equation: i,
                value: phi[i],
            });
        }
        if max <= options.tolerance {
            return branch_check(&jac, options).map(|()| iterations);
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
        let mut tiny = true;
        for i in 0..N {
            tiny &= step[i].abs() <= 1e-14 * (1.0 + u[i].abs());
        }
        if tiny {
            return branch_check(&jac, options).map(|()| iterations);
        }
        let start = *u;
        let mut t = 1.0;
        loop {
            for i in 0..N {
                u[i] = start[i] - t * step[i];
            }
            eval(u, &mut phi, &mut jac);
            let (f, m) = norms(&phi);
            if f <= (1.0 - 2e-4 * t) * f0 {
                f0 = f;
                max = m;
                break;
            }
            if t < 1e-3 {
                if !m.is_finite() {
                    let i = worst(&phi);
                    return Err(Failure::NonFiniteResidual {
                        equation: i,
                        value: phi[i],
                    });
                }
                // No decrease along the Newton direction: a local minimum
                // of ‖Φ‖ that is not a solution.
                return Err(Failure::NotConverged {
                    iterations,
                    residual: m,
                    equation: worst(&phi),
                });
            }
            t *= 0.5;
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
