//! The figures of merit and the units of `kinematics_core` for Python:
//! a number with a unit read into radians (`read_quantity`), a four-bar's
//! Grashof class (`grashof`), and the figures of a sweep
//! ([`figure`], which the `Sweep` class's methods call).

use kinematics_core::merit::{self, GrashofClass};
use kinematics_core::units::{self, Order};

use super::*;

/// `text`, a number with an optional unit, read as the value (`order`
/// 0), rate (1) or acceleration (2) of an angle (`angle`, in radians then)
/// or a length (the number as written); a `ValueError` saying what is
/// wrong.
/// Order 3 reads a parameter's value: a number as written, or with any
/// angle's unit (of any order) in radians.
#[pyfunction]
pub(crate) fn read_quantity(text: &str, order: u8, angle: bool) -> PyResult<f64> {
    let failed = |e: units::UnitError| PyValueError::new_err(format!("{text:?}: {e}"));
    if order == 3 {
        return units::read_parameter(text).map(|r| r.value).map_err(failed);
    }
    let order = match order {
        0 => Order::Value,
        1 => Order::Rate,
        2 => Order::Acceleration,
        other => {
            return Err(PyValueError::new_err(format!(
                "order must be 0, 1 or 2, not {other}"
            )))
        }
    };
    units::read(text, order, angle)
        .map(|r| r.value)
        .map_err(failed)
}

/// The Grashof class of the four-bar with these link lengths, as
/// (class, S + L, P + Q); the class one of "crank-rocker",
/// "double-crank", "rocker-crank", "double-rocker", "triple-rocker",
/// "change-point".
#[pyfunction]
pub(crate) fn grashof(
    py: Python<'_>,
    ground: f64,
    input: f64,
    coupler: f64,
    output: f64,
) -> PyResult<(&'static str, f64, f64)> {
    let g = merit::grashof(ground, input, coupler, output).map_err(|e| error(py, &e))?;
    let class = match g.class {
        GrashofClass::CrankRocker => "crank-rocker",
        GrashofClass::DoubleCrank => "double-crank",
        GrashofClass::RockerCrank => "rocker-crank",
        GrashofClass::DoubleRocker => "double-rocker",
        GrashofClass::TripleRocker => "triple-rocker",
        GrashofClass::ChangePoint => "change-point",
    };
    Ok((class, g.s_plus_l, g.p_plus_q))
}

/// One figure of the sweep `c` as Python values: "dead_centres" of
/// `names[0]` (a list of (at, value, is_maximum)), its "stroke" (min,
/// max), its "time_ratio" (rising, falling), its "mechanical_advantage"
/// (values, (at, least |MA|)), or the "transmission" angle between
/// `names[0]` and `names[1]` (values, (at, min), (at, max)).
pub(crate) fn figure<'py>(
    py: Python<'py>,
    c: &Columns,
    which: &str,
    names: &[String],
) -> PyResult<Bound<'py, PyAny>> {
    let failed = |e: Error| error(py, &e);
    let first = names
        .first()
        .ok_or_else(|| PyValueError::new_err("a figure needs a coordinate's name"))?;
    Ok(match which {
        "dead_centres" => merit::dead_centres(c, first)
            .map_err(failed)?
            .iter()
            .map(|d| (d.at, d.value, d.maximum))
            .collect::<Vec<_>>()
            .into_pyobject(py)?
            .into_any(),
        "stroke" => {
            let s = merit::stroke(c, first).map_err(failed)?;
            (s.min, s.max).into_pyobject(py)?.into_any()
        }
        "time_ratio" => {
            let r = merit::time_ratio(c, first).map_err(failed)?;
            (r.rising, r.falling).into_pyobject(py)?.into_any()
        }
        "transmission" => {
            let second = names
                .get(1)
                .ok_or_else(|| PyValueError::new_err("a transmission angle needs two angles"))?;
            let t = merit::transmission(c, first, second).map_err(failed)?;
            (array(py, t.values), t.min, t.max)
                .into_pyobject(py)?
                .into_any()
        }
        "mechanical_advantage" => {
            let ma = merit::mechanical_advantage(c, first).map_err(failed)?;
            (array(py, ma.values), ma.least)
                .into_pyobject(py)?
                .into_any()
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "no figure {other:?}: dead_centres, stroke, time_ratio, transmission or \
                 mechanical_advantage"
            )))
        }
    })
}
