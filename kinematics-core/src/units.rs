//! Numbers with units at the edges: what a user types (`90deg`,
//! `30 deg/s`, `120rpm`) read into the radians the library computes in,
//! and radians written back out in degrees where asked. The rule is
//! written once here, for the command's options and parameter files and
//! for the Python keywords; the library's core stays in radians.
//!
//! An angle is read in `rad`, `deg` (or `°`) or `rev` (one turn, 2π
//! rad); an angular rate in `rad/s`, `deg/s`, `rev/s`, `rpm` (or
//! `rev/min`); an angular acceleration in `rad/s2`, `deg/s2` or `rev/s2`
//! (`s^2` and `s²` too). A number with no unit is in radians (per second,
//! per second squared) for an angle, and in the definition's own length
//! unit for a length, which takes no unit here: the library does not
//! convert lengths, so `40mm` is refused rather than guessed at.
//!
//! ```
//! use kinematics_core::units::{read, Order};
//! use core::f64::consts::PI;
//! assert_eq!(read("90deg", Order::Value, true)?.value, PI / 2.0);
//! assert_eq!(read("30 deg/s", Order::Rate, true)?.value, PI / 6.0);
//! assert_eq!(read("60rpm", Order::Rate, true)?.value, 2.0 * PI);
//! assert_eq!(read("0.25", Order::Value, false)?.value, 0.25);
//! // A rate is not an angle, and a length takes no angle's unit.
//! assert!(read("30deg", Order::Rate, true).is_err());
//! assert!(read("30deg", Order::Value, false).is_err());
//! # Ok::<(), kinematics_core::units::UnitError>(())
//! ```

use core::f64::consts::{PI, TAU};
use core::fmt;

use alloc::string::String;

/// What a number gives of a coordinate: its value, its rate or its
/// acceleration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// The coordinate itself (rad).
    Value,
    /// Its rate (rad/s).
    Rate,
    /// Its acceleration (rad/s²).
    Acceleration,
}

impl Order {
    /// The units an angle of this order is read in, as a user writes the
    /// first of each group.
    #[must_use]
    pub fn angle_units(self) -> &'static str {
        match self {
            Order::Value => "deg, rad or rev",
            Order::Rate => "deg/s, rad/s, rev/s or rpm",
            Order::Acceleration => "deg/s2, rad/s2 or rev/s2",
        }
    }

    fn what(self) -> &'static str {
        match self {
            Order::Value => "an angle",
            Order::Rate => "a rate",
            Order::Acceleration => "an acceleration",
        }
    }
}

/// The units read, each with its order and its factor to radians (per
/// second, per second squared).
const UNITS: [(&str, Order, f64); 22] = [
    ("rad", Order::Value, 1.0),
    ("deg", Order::Value, PI / 180.0),
    ("°", Order::Value, PI / 180.0),
    ("rev", Order::Value, TAU),
    ("rad/s", Order::Rate, 1.0),
    ("deg/s", Order::Rate, PI / 180.0),
    ("°/s", Order::Rate, PI / 180.0),
    ("rev/s", Order::Rate, TAU),
    ("rpm", Order::Rate, TAU / 60.0),
    ("rev/min", Order::Rate, TAU / 60.0),
    ("rad/s2", Order::Acceleration, 1.0),
    ("rad/s^2", Order::Acceleration, 1.0),
    ("rad/s²", Order::Acceleration, 1.0),
    ("deg/s2", Order::Acceleration, PI / 180.0),
    ("deg/s^2", Order::Acceleration, PI / 180.0),
    ("deg/s²", Order::Acceleration, PI / 180.0),
    ("°/s2", Order::Acceleration, PI / 180.0),
    ("°/s^2", Order::Acceleration, PI / 180.0),
    ("°/s²", Order::Acceleration, PI / 180.0),
    ("rev/s2", Order::Acceleration, TAU),
    ("rev/s^2", Order::Acceleration, TAU),
    ("rev/s²", Order::Acceleration, TAU),
];

/// A number read, in the library's units, and the unit it was written
/// in (`None`: none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// The value: radians (per second, per second squared) for an angle,
    /// the number as written for a length.
    pub value: f64,
    /// The unit written after the number.
    pub unit: Option<&'static str>,
}

impl Reading {
    /// Whether an angle written without a unit is so large (more than two
    /// turns, 4π) that degrees were likely meant: `90` is 14.3 turns.
    #[must_use]
    pub fn looks_like_degrees(&self, order: Order) -> bool {
        self.unit.is_none() && order == Order::Value && self.value.abs() > 2.0 * TAU
    }
}

/// Why a number with a unit could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum UnitError {
    /// The text does not begin with a finite number.
    NotANumber(String),
    /// The unit is not one of those read.
    UnknownUnit {
        /// The unit as written.
        unit: String,
        /// The units that would be read for this quantity.
        expected: &'static str,
    },
    /// The unit is an angle's where the quantity is a length.
    LengthWithUnit(String),
    /// The unit is of another order (an angle given for a rate, …).
    WrongOrder {
        /// The unit as written.
        unit: String,
        /// What the quantity is ("a rate", …).
        wanted: &'static str,
        /// The units that would be read for it.
        expected: &'static str,
    },
}

impl fmt::Display for UnitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnitError::NotANumber(text) => {
                write!(f, "`{text}` is not a finite number (with an optional unit)")
            }
            UnitError::UnknownUnit { unit, expected } => {
                write!(f, "the unit `{unit}` is not known: give {expected}")
            }
            UnitError::LengthWithUnit(unit) => write!(
                f,
                "`{unit}` is an angle's unit, and this is a length: give the number in the \
                 definition's length unit, with no unit"
            ),
            UnitError::WrongOrder {
                unit,
                wanted,
                expected,
            } => write!(f, "`{unit}` is not the unit of {wanted}: give {expected}"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for UnitError {}

/// Splits `text` into its number and the unit after it (empty: none).
fn split(text: &str) -> Result<(f64, &str), UnitError> {
    let text = text.trim();
    // The number: the longest prefix of sign, digits, point and exponent
    // characters (no unit begins with `e`).
    let end = text
        .char_indices()
        .find(|&(_, c)| !(c.is_ascii_digit() || matches!(c, '+' | '-' | '.' | 'e' | 'E')))
        .map_or(text.len(), |(i, _)| i);
    let (number, unit) = text.split_at(end);
    match number.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok((x, unit.trim())),
        _ => Err(UnitError::NotANumber(String::from(text))),
    }
}

/// Reads `text`, a number and an optional unit, as the `order` of an
/// angle (`angle`) or of a length: the value in radians (per second, per
/// second squared) for an angle, the number as written for a length.
///
/// # Errors
/// [`UnitError`]: not a finite number, a unit not known, an angle's unit
/// on a length, or a unit of another order than `order`.
pub fn read(text: &str, order: Order, angle: bool) -> Result<Reading, UnitError> {
    let (x, unit) = split(text)?;
    if unit.is_empty() {
        return Ok(Reading {
            value: x,
            unit: None,
        });
    }
    let Some(&(name, of, factor)) = UNITS.iter().find(|(u, _, _)| *u == unit) else {
        return Err(UnitError::UnknownUnit {
            unit: String::from(unit),
            expected: if angle {
                order.angle_units()
            } else {
                "the number alone, in the definition's length unit"
            },
        });
    };
    if !angle {
        return Err(UnitError::LengthWithUnit(String::from(name)));
    }
    if of != order {
        return Err(UnitError::WrongOrder {
            unit: String::from(name),
            wanted: order.what(),
            expected: order.angle_units(),
        });
    }
    Ok(Reading {
        value: x * factor,
        unit: Some(name),
    })
}

/// Reads `text` as a parameter's value: a number with no unit as
/// written, or a number with any angle's unit (of any order) in radians
/// (per second, per second squared).
///
/// # Errors
/// [`UnitError::NotANumber`] or [`UnitError::UnknownUnit`].
pub fn read_parameter(text: &str) -> Result<Reading, UnitError> {
    let (x, unit) = split(text)?;
    if unit.is_empty() {
        return Ok(Reading {
            value: x,
            unit: None,
        });
    }
    match UNITS.iter().find(|(u, _, _)| *u == unit) {
        Some(&(name, _, factor)) => Ok(Reading {
            value: x * factor,
            unit: Some(name),
        }),
        None => Err(UnitError::UnknownUnit {
            unit: String::from(unit),
            expected: "a number alone, or an angle in deg, rad or rev (rates in deg/s, rad/s, \
                       rpm; accelerations in deg/s2, rad/s2)",
        }),
    }
}

/// How angles are written out: in radians, as computed, or in degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AngleUnit {
    /// Radians (rad, rad/s, rad/s²).
    #[default]
    Radians,
    /// Degrees (deg, deg/s, deg/s²).
    Degrees,
}

impl AngleUnit {
    /// The factor from radians: 1, or 180/π.
    #[must_use]
    pub fn factor(self) -> f64 {
        match self {
            AngleUnit::Radians => 1.0,
            AngleUnit::Degrees => 180.0 / PI,
        }
    }

    /// The unit's short name in column headers: `rad` or `deg`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            AngleUnit::Radians => "rad",
            AngleUnit::Degrees => "deg",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Order, UnitError, read, read_parameter};
    use alloc::string::ToString;
    use core::f64::consts::PI;

    #[test]
    fn every_unit_against_its_definition() {
        let close = |t: &str, o: Order, x: f64| {
            let v = read(t, o, true).map(|r| r.value);
            assert!(
                v.as_ref().is_ok_and(|v| (v - x).abs() <= 1e-15 * x.abs()),
                "{t}: {v:?}"
            );
        };
        close("180deg", Order::Value, PI);
        close("180 °", Order::Value, PI);
        close("0.5rev", Order::Value, PI);
        close("-2.5e-1 rad", Order::Value, -0.25);
        close("360deg/s", Order::Rate, 2.0 * PI);
        close("1rev/s", Order::Rate, 2.0 * PI);
        close("30rpm", Order::Rate, PI);
        close("30 rev/min", Order::Rate, PI);
        close("90deg/s2", Order::Acceleration, PI / 2.0);
        close("90deg/s^2", Order::Acceleration, PI / 2.0);
        close("90°/s²", Order::Acceleration, PI / 2.0);
        close("2rad/s²", Order::Acceleration, 2.0);
    }

    #[test]
    fn what_is_refused_says_why() {
        assert!(matches!(
            read("90degs", Order::Value, true),
            Err(UnitError::UnknownUnit { .. })
        ));
        assert!(matches!(
            read("40mm", Order::Value, false),
            Err(UnitError::UnknownUnit { .. })
        ));
        assert!(matches!(
            read("90deg", Order::Value, false),
            Err(UnitError::LengthWithUnit(_))
        ));
        assert!(matches!(
            read("10rpm", Order::Value, true),
            Err(UnitError::WrongOrder { .. })
        ));
        for bad in ["", "deg", "inf", "nan", "1e999", "1..2", "--3"] {
            assert!(
                matches!(read(bad, Order::Value, true), Err(UnitError::NotANumber(_))),
                "{bad}"
            );
        }
        let e = read("30deg", Order::Rate, true)
            .err()
            .map(|e| e.to_string());
        assert_eq!(
            e.as_deref(),
            Some("`deg` is not the unit of a rate: give deg/s, rad/s, rev/s or rpm")
        );
    }

    #[test]
    fn parameters_take_any_angle_unit_and_large_radians_are_flagged() {
        assert_eq!(read_parameter("0.12").map(|r| r.value), Ok(0.12));
        assert_eq!(read_parameter("180deg").map(|r| r.value), Ok(PI));
        assert_eq!(read_parameter("60rpm").map(|r| r.value), Ok(2.0 * PI));
        assert!(read_parameter("3 furlongs").is_err());
        let r = read("90", Order::Value, true).expect("a number");
        assert!(r.looks_like_degrees(Order::Value));
        let r = read("6.2", Order::Value, true).expect("a number");
        assert!(!r.looks_like_degrees(Order::Value));
        let r = read("90deg", Order::Value, true).expect("a number");
        assert!(!r.looks_like_degrees(Order::Value));
    }
}
