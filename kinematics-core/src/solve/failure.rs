//! How a solve fails ([`Failure`], in the solver's indices) and how that
//! becomes an [`Error`](crate::error::Error) naming the mechanism's own
//! coordinates and equations ([`describe`]).

use crate::error::Error;

use crate::options::Options;
use alloc::vec::Vec;

use super::newton::worst;

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
    /// singular matrix, `conditioning` (see [`Lu::conditioning`](super::Lu::conditioning)), is at or
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

/// The failure for a residual vector with a NaN or an infinite entry.
#[cold]
pub(super) fn non_finite(phi: &[f64], w: &[f64]) -> Failure {
    let i = worst(phi, w);
    Failure::NonFiniteResidual {
        equation: i,
        value: phi.get(i).copied().unwrap_or(f64::NAN),
    }
}

/// The failure of an iteration that ended away from a solution.
#[cold]
pub(super) fn not_converged(iterations: usize, phi: &[f64], row: &[f64], w: &[f64]) -> Failure {
    let i = worst(phi, w);
    let value = phi.get(i).copied().unwrap_or(f64::NAN);
    Failure::NotConverged {
        iterations,
        residual: value.abs(),
        relative: (value * row.get(i).copied().unwrap_or(1.0)).abs(),
        equation: i,
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
    describe_by(
        failure,
        |u| {
            names
                .coordinates
                .get(names.drivers + u)
                .copied()
                .unwrap_or("?")
        },
        |i| names.equations.get(i).copied().unwrap_or("?"),
        configuration,
    )
}

/// [`describe`] with the names of unknown `u` (0 the first unknown) and of
/// equation `i` given by functions: for either kind of model.
pub(crate) fn describe_by(
    failure: Failure,
    unknown: impl Fn(usize) -> &'static str,
    equation: impl Fn(usize) -> &'static str,
    configuration: Vec<(&'static str, f64)>,
) -> Error {
    match failure {
        Failure::Singular {
            unknown: u,
            conditioning,
        } => Error::Singular {
            unknown: unknown(u),
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
