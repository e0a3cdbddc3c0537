//! Errors of assembly and analysis.

use alloc::string::String;
use core::fmt;

pub use crate::names::{Configuration, Name};

/// What kind of input a non-finite value was found in.
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
/// use kinematics_core::{Error, Input};
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let start = SliderCrankCoords { phi: f64::NAN, th: 0.0, x: 0.4 };
/// match m.assemble(&start) {
///     Err(Error::NonFinite { input, name, .. }) => assert_eq!((input, name), (Input::Driver, "phi")),
///     other => panic!("{other:?}"),
/// }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Input {
    /// A field of the mechanism struct (a link length, an offset).
    Parameter,
    /// A driver value of the starting pose.
    Driver,
    /// A starting guess of an unknown.
    Guess,
    /// A prescribed driver rate q'.
    DriverRate,
    /// A prescribed driver acceleration q''.
    DriverAcceleration,
    /// A value computed by the model (for example `sqrt` of a negative
    /// number, or a division by zero in a user expression).
    Computed,
}

impl fmt::Display for Input {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Input::Parameter => "parameter",
            Input::Driver => "driver",
            Input::Guess => "starting guess of unknown",
            Input::DriverRate => "rate of driver",
            Input::DriverAcceleration => "acceleration of driver",
            Input::Computed => "computed value",
        })
    }
}

/// Why an assembly or an analysis failed. Every variant names the items
/// involved, so the message says what to change.
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
/// use kinematics_core::Error;
/// // A rod too short to reach the slider line at φ = 90°.
/// let m = SliderCrank { a: 0.3, b: 0.1 };
/// let e = m.assemble(&SliderCrankCoords { phi: 1.5708, th: 0.0, x: 0.1 }).unwrap_err();
/// // The loop is solved in closed form: no real solution is an exact answer.
/// assert!(matches!(e, Error::CannotAssemble { unknowns: "th", .. }));
/// println!("{e}"); // names the drivers and the unknowns that cannot close
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Error {
    /// Newton–Raphson did not bring the loop-closure residual below the
    /// tolerance: the mechanism probably cannot be assembled at this driver
    /// value (a link too short, a crank past its limit position), or the
    /// guess is too far from a solution.
    NotConverged {
        /// Iterations performed.
        iterations: usize,
        /// Largest |Φ_i| at the last iterate, in the equation's units.
        residual: f64,
        /// That residual relative to the term scale S_i of its equation
        /// (see [`Scaling`](crate::solve::Scaling)).
        relative: f64,
        /// The equation with that residual, as written in the definition.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        equation: Name,
        /// Coordinates at the last iterate, by name.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::names::configuration")
        )]
        configuration: Configuration,
    },
    /// The Jacobian Φ_u is singular (or nearly so) at this configuration:
    /// the unknowns are not determined by the equations. This is a dead
    /// centre, a toggle position, or a redundant or missing constraint.
    Singular {
        /// The unknown the equations determine worst there.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        unknown: Name,
        /// The conditioning: the distance of the scaled Jacobian to the
        /// nearest singular matrix (see
        /// [`MotionState::conditioning`](crate::MotionState::conditioning)).
        conditioning: f64,
        /// Coordinates at the configuration, by name.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::names::configuration")
        )]
        configuration: Configuration,
    },
    /// An input, or a value computed from valid inputs, is NaN or infinite.
    NonFinite {
        /// What kind of value it is.
        input: Input,
        /// Its name in the mechanism definition.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        name: Name,
        /// The value found.
        value: f64,
    },
    /// A geometric input of a transformation or rigid-body helper is
    /// degenerate or inconsistent (a zero axis, a matrix that is not a
    /// rotation, parallel vectors).
    InvalidGeometry {
        /// The function or quantity concerned.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        what: Name,
        /// What is wrong and what is expected.
        detail: String,
    },
    /// The solution found is on the assembly branch other than the one
    /// required by [`Options::branch`](crate::Options::branch).
    WrongBranch {
        /// Coordinates of the solution found, by name.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::names::configuration")
        )]
        configuration: Configuration,
    },
    /// A block of loop equations solved in closed form has no real solution
    /// at these driver values: its links are too short or too long to close
    /// the loop (see [`closed`](crate::closed)). The driver is past a limit
    /// position; an exact statement, not a failure to converge.
    CannotAssemble {
        /// The block's unknowns, joined by ", ".
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        unknowns: Name,
        /// The block's discriminant (negative).
        discriminant: f64,
        /// The drivers, by name.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::names::configuration")
        )]
        drivers: Configuration,
    },
    /// A file could not be written.
    Output {
        /// The file.
        path: String,
        /// What went wrong.
        detail: String,
    },
    /// A parameter is outside the range its declaration allows (a length
    /// that is zero or negative).
    InvalidParameter {
        /// The parameter.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        name: Name,
        /// The value given.
        value: f64,
        /// What the value must satisfy.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        requirement: Name,
    },
    /// A solver option is out of its valid range.
    InvalidOption {
        /// The option's field name in [`Options`](crate::options::Options).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        name: Name,
        /// The value given.
        value: f64,
        /// What the value must satisfy.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        requirement: Name,
    },
    /// A description of masses and loads
    /// ([`dynamics`](crate::dynamics)) that does not fit the mechanism or
    /// the physics: a point, frame, coordinate or body it names that does
    /// not exist, a negative mass, an inertia tensor that is not
    /// symmetric, a load whose value is not finite.
    InvalidDynamics {
        /// The body, load or spring concerned.
        item: String,
        /// What is wrong and how to put it right.
        detail: String,
    },
    /// An array handed to a model defined at run time has the wrong number
    /// of values (the sizes of a generated mechanism are in its types).
    WrongLength {
        /// What the array holds ("coordinates", "driver rates", …).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
        what: Name,
        /// The number of values the model needs.
        expected: usize,
        /// The number given.
        found: usize,
    },
}

fn write_configuration(f: &mut fmt::Formatter<'_>, cfg: &[(&'static str, f64)]) -> fmt::Result {
    for (i, (name, v)) in cfg.iter().enumerate() {
        if i > 0 {
            f.write_str(", ")?;
        }
        write!(f, "{name} = {v:.6}")?;
    }
    Ok(())
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NotConverged {
                iterations,
                residual,
                relative,
                equation,
                configuration,
            } => {
                write!(
                    f,
                    "the mechanism did not assemble: after {iterations} Newton iterations the \
                     residual of `{equation}` is still {residual:.3e} ({relative:.1e} of the size \
                     of its terms; at "
                )?;
                write_configuration(f, configuration)?;
                f.write_str(
                    "); check that the links can close the loop at this driver value, or start \
                     from a guess closer to the intended assembly",
                )
            }
            Error::Singular {
                unknown,
                conditioning,
                configuration,
            } => {
                write!(
                    f,
                    "the equations do not determine unknown `{unknown}` at this configuration \
                     (singular Jacobian, conditioning {conditioning:.1e}; at "
                )?;
                write_configuration(f, configuration)?;
                f.write_str(
                    "): the mechanism is at a dead-centre or toggle position, or the model has a \
                     redundant constraint",
                )
            }
            Error::NonFinite { input, name, value } => {
                if *input == Input::Computed && value.is_infinite() {
                    write!(
                        f,
                        "`{name}` evaluated to {value}: a value overflowed the range of f64 \
                         (an input, parameter, rate or acceleration too large, about 1e154 or \
                         more once squared), or the model divides by zero here"
                    )
                } else if *input == Input::Computed {
                    write!(
                        f,
                        "`{name}` evaluated to {value}: an expression of the model is undefined \
                         here (square root of a negative number, 0/0, asin/acos outside \
                         [-1, 1]), or an intermediate value overflowed (an input too large)"
                    )
                } else {
                    write!(f, "{input} `{name}` is {value}; it must be a finite number")
                }
            }
            Error::InvalidGeometry { what, detail } => write!(f, "{what}: {detail}"),
            Error::Output { path, detail } => write!(f, "could not write `{path}`: {detail}"),
            Error::CannotAssemble {
                unknowns,
                discriminant,
                drivers,
            } => {
                f.write_str("the mechanism cannot be assembled at ")?;
                write_configuration(f, drivers)?;
                write!(
                    f,
                    ": the loop equations of {unknowns} have no real solution (discriminant \
                     {discriminant:.3e} < 0), the links cannot reach to close the loop; the \
                     driver is past a limit position"
                )
            }
            Error::WrongBranch { configuration } => {
                f.write_str(
                    "the mechanism assembled on the other branch than the one asked for (at ",
                )?;
                write_configuration(f, configuration)?;
                f.write_str("); start from a guess on the wanted branch, e.g. with the elbow of the dyad on the other side")
            }
            Error::InvalidParameter {
                name,
                value,
                requirement,
            } => write!(
                f,
                "parameter `{name}` = {value} is invalid: it {requirement}"
            ),
            Error::InvalidOption {
                name,
                value,
                requirement,
            } => write!(f, "option `{name}` = {value} is invalid: it {requirement}"),
            Error::InvalidDynamics { item, detail } => write!(f, "{item}: {detail}"),
            Error::WrongLength {
                what,
                expected,
                found,
            } => write!(
                f,
                "{found} {what} given; this model has {expected} (in declaration order)"
            ),
        }
    }
}

impl core::error::Error for Error {}
