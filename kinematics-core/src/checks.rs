//! Checks that the code `mechanism!` generates calls (through
//! `__private`): driver arrays of the right length, finite inputs and
//! outputs, positive lengths. Not a stable API.

use crate::error::{Error, Input};
use crate::mechanism::{FrameState, PointMotion};

/// `rates` and `accelerations` as arrays of one value per driver, or
/// [`Error::InvalidOption`] when a slice has another length.
#[inline]
pub fn driver_arrays<const N: usize>(
    rates: &[f64],
    accelerations: &[f64],
) -> Result<([f64; N], [f64; N]), Error> {
    match (
        <[f64; N]>::try_from(rates),
        <[f64; N]>::try_from(accelerations),
    ) {
        (Ok(r), Ok(a)) => Ok((r, a)),
        _ => Err(Error::InvalidOption {
            name: "rates and accelerations",
            #[allow(clippy::cast_precision_loss)]
            value: rates.len().max(accelerations.len()) as f64,
            requirement: "must have one value per driver",
        }),
    }
}

/// Fails with [`Error::InvalidParameter`] unless `value` > 0 (a
/// parameter declared `name: length`).
#[inline]
pub fn positive(name: &'static str, value: f64) -> Result<(), Error> {
    positive_because(name, value, "must be positive: it is declared a length")
}

/// Fails with [`Error::InvalidParameter`] unless `value` > 0: the
/// distance b of a constraint `norm(v) == b`, which the generated code
/// solves as v·v = b² (the same solutions only for b > 0).
#[inline]
pub fn positive_distance(name: &'static str, value: f64) -> Result<(), Error> {
    positive_because(
        name,
        value,
        "must be positive: it is the distance in a `norm(…) == …` constraint",
    )
}

/// Fails with [`Error::InvalidParameter`] and `requirement` unless
/// `value` > 0 (a NaN fails too).
#[inline]
fn positive_because(
    name: &'static str,
    value: f64,
    requirement: &'static str,
) -> Result<(), Error> {
    if value > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            requirement,
        })
    }
}

/// Fails with [`Error::NonFinite`] when `value` is NaN or infinite.
#[inline]
pub fn finite(input: Input, name: &'static str, value: f64) -> Result<(), Error> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::NonFinite { input, name, value })
    }
}

/// Fails with [`Error::NonFinite`] naming the first point or frame whose
/// position, velocity, acceleration, rotation or angular rates hold a NaN
/// or an infinity. Generated code calls it only after a cheap sum of all
/// outputs has come out non-finite, so it stays off the hot path.
#[cold]
#[inline(never)]
pub fn finite_outputs<const D: usize>(
    points: &[PointMotion<D>],
    point_names: &[&'static str],
    frames: &[FrameState],
    frame_names: &[&'static str],
) -> Result<(), Error> {
    for (name, p) in point_names.iter().zip(points) {
        for v in p.position.iter().chain(&p.velocity).chain(&p.acceleration) {
            finite(Input::Computed, name, *v)?;
        }
    }
    for (name, f) in frame_names.iter().zip(frames) {
        let vectors = [
            f.origin,
            f.velocity,
            f.acceleration,
            f.angular_velocity,
            f.angular_acceleration,
        ];
        for v in f
            .rotation
            .iter()
            .chain(vectors.iter().flat_map(|v| v.iter()))
        {
            finite(Input::Computed, name, *v)?;
        }
    }
    Ok(())
}

/// Whether `a` and `b` hold the same values bit for bit (a NaN equal to
/// the same NaN): a description marked with the parameter values it was
/// made at is a model's own only at exactly those values.
#[must_use]
pub fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}
