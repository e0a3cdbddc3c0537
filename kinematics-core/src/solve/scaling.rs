//! The scaling of the loop equations and unknowns (term scales S_i, the
//! characteristic length L), in which convergence and singularity are
//! judged.

// Matrices are written with explicit indices, as in the formulas.
#![allow(clippy::needless_range_loop)]

use crate::options::Options;

use super::failure::Failure;

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
    if m > 0.0 { m } else { 1.0 }
}

/// The failure for a term scale that overflowed.
#[cold]
fn overflow(equation: usize, value: f64) -> Failure {
    Failure::NonFiniteResidual { equation, value }
}
