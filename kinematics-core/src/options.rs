//! Solver settings.

use crate::error::Error;

/// Settings of the Newton–Raphson assembly and of the linear solves.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # fn main() -> Result<(), kinematics_core::Error> {
/// use kinematics_core::{Branch, Options};
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// // A tighter tolerance, and the rod required to point forward (det Φ_u > 0).
/// let options = Options { tolerance: 1e-14, branch: Branch::Positive, ..Options::DEFAULT };
/// let pose = m.assemble_with(&SliderCrankCoords { phi: 1.0, th: 0.0, x: 0.3 }, &options)?;
/// assert!(pose.th.cos() > 0.0);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Options {
    /// Newton–Raphson has converged when every residual |Φ_i| is at most
    /// `tolerance` times the term scale S_i of its equation (the sum of the
    /// sizes of the equation's terms, see
    /// [`Scaling`](crate::solve::Scaling)): a relative accuracy, the same
    /// for a mechanism drawn in millimetres, metres or kilometres. With
    /// [`Convergence::Absolute`] it is in the units of the equations
    /// instead. Default 1e-12.
    pub tolerance: f64,
    /// Whether [`Options::tolerance`] is relative to each equation's term
    /// scale (the default) or absolute.
    pub convergence: Convergence,
    /// Largest number of Newton iterations. Default 50.
    pub max_iterations: usize,
    /// Φ_u is treated as singular when its conditioning, the distance of
    /// the scaled Jacobian Φ̃_u to the nearest singular matrix (see
    /// [`MotionState::conditioning`](crate::MotionState::conditioning)), or
    /// a pivot of its factorisation during the iteration, is at or below
    /// this value. Default 1e-10.
    pub singularity_threshold: f64,
    /// The assembly branch required of a solution, by the sign of det Φ_u
    /// (for a four-bar, the sign of sin(θ3 − θ4): which way its dyad's elbow
    /// points). Default [`Branch::Any`]: the branch nearest the guess. For a
    /// mechanism solved in closed form it is a choice (the modes that give
    /// it are taken); solved by Newton–Raphson, a check
    /// ([`Error::WrongBranch`](crate::Error::WrongBranch)).
    pub branch: Branch,
}

/// What [`Options::tolerance`] is measured against.
///
/// ```
/// use kinematics_core::{Convergence, Options};
/// assert_eq!(Options::DEFAULT.convergence, Convergence::Relative);
/// // The residuals in the model's units (metres for a loop in metres).
/// let absolute = Options { convergence: Convergence::Absolute, tolerance: 1e-9, ..Options::DEFAULT };
/// assert!(absolute.validate().is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Convergence {
    /// max_i |Φ_i| / S_i ≤ tolerance, with S_i the term scale of equation
    /// i: independent of the units and size of the mechanism.
    #[default]
    Relative,
    /// max_i |Φ_i| ≤ tolerance, in the units of the equations (metres for
    /// a loop written in metres).
    Absolute,
}

/// An assembly branch (mode), identified by the sign of det Φ_u, which
/// changes only through a singular configuration.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # fn main() -> Result<(), kinematics_core::Error> {
/// use kinematics_core::{Branch, Error, Options};
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let forward = SliderCrankCoords { phi: 1.0, th: 0.0, x: 0.3 };
/// let wants = |branch| Options { branch, ..Options::DEFAULT };
/// assert!(m.assemble_with(&forward, &wants(Branch::Positive))?.x > 0.0);
/// // Solved in closed form, the branch is a choice: the other assembly,
/// // the rod reaching back past the crank's pivot.
/// assert!(m.assemble_with(&forward, &wants(Branch::Negative))?.x < 0.0);
/// # let _ = Error::WrongBranch { configuration: vec![] };
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Branch {
    /// Whichever branch Newton–Raphson reaches from the guess.
    #[default]
    Any,
    /// det Φ_u > 0.
    Positive,
    /// det Φ_u < 0.
    Negative,
}

impl Options {
    /// The default settings, usable in `const` context: tolerance 1e-12
    /// relative, 50 iterations, singularity threshold 1e-10, any branch.
    ///
    /// ```
    /// use kinematics_core::Options;
    /// const TIGHT: Options = Options { tolerance: 1e-14, ..Options::DEFAULT };
    /// assert_eq!(TIGHT.max_iterations, 50);
    /// ```
    pub const DEFAULT: Options = Options {
        tolerance: 1e-12,
        convergence: Convergence::Relative,
        max_iterations: 50,
        singularity_threshold: 1e-10,
        branch: Branch::Any,
    };

    /// Checks that every setting is in range.
    ///
    /// ```
    /// use kinematics_core::{Error, Options};
    /// let bad = Options { tolerance: -1.0, ..Options::DEFAULT };
    /// assert!(matches!(bad.validate(), Err(Error::InvalidOption { name: "tolerance", .. })));
    /// ```
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the first setting out of range.
    #[inline]
    pub fn validate(&self) -> Result<(), Error> {
        // One branch in the common case (NaN fails every comparison).
        let valid = (self.tolerance > 0.0)
            & (self.tolerance < f64::INFINITY)
            & (self.max_iterations > 0)
            & (self.singularity_threshold >= 0.0)
            & (self.singularity_threshold < 1.0);
        if valid { Ok(()) } else { self.invalid() }
    }

    /// The error naming the first setting out of range.
    #[cold]
    fn invalid(&self) -> Result<(), Error> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(Error::InvalidOption {
                name: "tolerance",
                value: self.tolerance,
                requirement: "must be a positive finite number, e.g. 1e-12",
            });
        }
        if self.max_iterations == 0 {
            return Err(Error::InvalidOption {
                name: "max_iterations",
                value: 0.0,
                requirement: "must be at least 1",
            });
        }
        if !(self.singularity_threshold.is_finite()
            && (0.0..1.0).contains(&self.singularity_threshold))
        {
            return Err(Error::InvalidOption {
                name: "singularity_threshold",
                value: self.singularity_threshold,
                requirement: "must be in [0, 1), e.g. 1e-10",
            });
        }
        Ok(())
    }
}

impl Default for Options {
    fn default() -> Self {
        Self::DEFAULT
    }
}
