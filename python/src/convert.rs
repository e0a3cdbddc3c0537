//! Conversions of the library's results into numpy arrays and dicts.

use kinematics_core::runtime::{Motion, PointState};
use kinematics_core::FrameState;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A one-dimensional array that owns `v`.
pub(crate) fn array(py: Python<'_>, v: Vec<f64>) -> Bound<'_, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// The values `v` (in C order) as an array of shape `shape`.
pub(crate) fn shaped(py: Python<'_>, v: Vec<f64>, shape: Vec<usize>) -> PyResult<Bound<'_, PyAny>> {
    Ok(PyArray1::from_vec(py, v).reshape(shape)?.into_any())
}

/// A frame's 24 values: the rotation matrix by rows (9), the origin, its
/// velocity and acceleration, ω and α (3 each).
pub(crate) fn frame_values(f: &FrameState) -> impl Iterator<Item = f64> + '_ {
    (0..3)
        .flat_map(move |r| (0..3).map(move |c| f.rotation[(r, c)]))
        .chain(f.origin.iter().copied())
        .chain(f.velocity.iter().copied())
        .chain(f.acceleration.iter().copied())
        .chain(f.angular_velocity.iter().copied())
        .chain(f.angular_acceleration.iter().copied())
}

/// Every point's position, velocity and acceleration, one after the
/// other (points × 3 × dim values).
pub(crate) fn point_values(points: &[PointState]) -> Vec<f64> {
    points
        .iter()
        .flat_map(|p| {
            p.position
                .iter()
                .chain(&p.velocity)
                .chain(&p.acceleration)
                .copied()
        })
        .collect()
}

/// A motion as a dict: "q", "qd", "qdd" (one value per coordinate),
/// "points" (points × 3 × dim: position, velocity, acceleration), "frames"
/// (frames × 24, see [`frame_values`]), "conditioning", "det_sign",
/// "residual".
pub(crate) fn motion_dict<'py>(
    py: Python<'py>,
    m: &Motion,
    dim: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("q", array(py, m.q.clone()))?;
    d.set_item("qd", array(py, m.qd.clone()))?;
    d.set_item("qdd", array(py, m.qdd.clone()))?;
    d.set_item(
        "points",
        shaped(py, point_values(&m.points), vec![m.points.len(), 3, dim])?,
    )?;
    let frames: Vec<f64> = m.frames.iter().flat_map(frame_values).collect();
    d.set_item("frames", shaped(py, frames, vec![m.frames.len(), 24])?)?;
    d.set_item("conditioning", m.conditioning)?;
    d.set_item("det_sign", m.det_sign)?;
    d.set_item("residual", m.residual)?;
    Ok(d)
}
