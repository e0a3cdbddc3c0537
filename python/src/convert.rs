//! Conversions of the library's results into numpy arrays and dicts.

use kinematics_core::runtime::{Motion, PointState};
use kinematics_core::FrameState;
use numpy::{PyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

/// A one-dimensional array that owns `v`.
pub(crate) fn array(py: Python<'_>, v: Vec<f64>) -> Bound<'_, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// The values `v` (in C order) as an array of shape `shape`.
pub(crate) fn shaped(py: Python<'_>, v: Vec<f64>, shape: Vec<usize>) -> PyResult<Bound<'_, PyAny>> {
    // One array object over the vector's memory (a reshape would make a
    // second, a view of the first).
    let a = numpy::ndarray::ArrayD::from_shape_vec(shape, v)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    Ok(numpy::PyArrayDyn::from_owned_array(py, a).into_any())
}

/// `a`, a new array nothing else refers to, made read-only: the arrays a
/// result hands out hold its data, which later calls read back. (One
/// flag cleared in the array's header, where `a.flags.writeable = False`
/// from Python would cost a method call per array.)
pub(crate) fn frozen<'py, T: PyUntypedArrayMethods<'py>>(a: T) -> T {
    // SAFETY: `as_array_ptr` points at the live array object `a` holds;
    // clearing WRITEABLE only narrows what may be done with its data, and
    // the interpreter is held (a `Bound`), so no other thread reads the
    // flags meanwhile.
    #[allow(unsafe_code)]
    unsafe {
        (*a.as_array_ptr()).fields.flags &= !numpy::npyffi::flags::NPY_ARRAY_WRITEABLE;
    }
    a
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

/// A motion as a tuple: q, q' and q'' one after the other (3 ×
/// coordinates values), the points (points × 3 × dim: position, velocity,
/// acceleration), the frames (frames × 24, see [`frame_values`]), each a
/// flat array the Python side shapes where it is read, then the
/// conditioning, the sign of det Φ_u and the residual.
pub(crate) fn motion_tuple<'py>(py: Python<'py>, m: &Motion) -> PyResult<Bound<'py, PyTuple>> {
    let n = m.q.len();
    let mut qs = Vec::with_capacity(3 * n);
    qs.extend_from_slice(&m.q);
    qs.extend_from_slice(&m.qd);
    qs.extend_from_slice(&m.qdd);
    let frames: Vec<f64> = m.frames.iter().flat_map(frame_values).collect();
    (
        frozen(array(py, qs)),
        frozen(array(py, point_values(&m.points))),
        frozen(array(py, frames)),
        m.conditioning,
        m.det_sign,
        m.residual,
    )
        .into_pyobject(py)
}
