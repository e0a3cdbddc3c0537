//! Batches of designs of one model, run on every core with the
//! interpreter released through the library's batch
//! (`kinematics_core::runtime::Batch`): for each design a step at one
//! pose or a sweep, of which only the outputs asked for are kept, as
//! arrays with a row per design.

use kinematics_core::runtime::{Batch, BatchResults, Output, Reduce};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PySlice};

use crate::convert::{array, shaped};

/// The output (kind, index) of the Python layer: kind "q", "qd", "qdd"
/// (a coordinate), "position", "velocity", "acceleration" (a point) or
/// "conditioning".
pub(crate) fn output(kind: &str, index: usize) -> PyResult<Output> {
    Ok(match kind {
        "q" => Output::Coordinate(index),
        "qd" => Output::Rate(index),
        "qdd" => Output::Acceleration(index),
        "position" => Output::Position(index),
        "velocity" => Output::Velocity(index),
        "acceleration" => Output::PointAcceleration(index),
        "conditioning" => Output::Conditioning,
        _ => {
            return Err(PyValueError::new_err(format!(
                "{kind:?} is not a kind of output"
            )))
        }
    })
}

/// The reduction `reduce` of the Python layer: None (every sample),
/// "max", "min" or "peak".
pub(crate) fn reduce(reduce: Option<&str>) -> PyResult<Reduce> {
    Ok(match reduce {
        None => Reduce::Samples,
        Some("max") => Reduce::Max,
        Some("min") => Reduce::Min,
        Some("peak") => Reduce::Peak,
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "reduce must be None, 'max', 'min' or 'peak', not {other:?}"
            )))
        }
    })
}

/// The results as a dict: "outputs", a list with an array per output of
/// shape (designs, samples) or (designs, samples, dim) for a sweep,
/// (designs,) or (designs, dim) for a step, NaN past the samples a design
/// has (without the samples' axis where the outputs are reduced, `swept`
/// false); "samples", the count per design; "stops", the message of the stop
/// or error that ended each design early, or None.
pub(crate) fn gather<'py>(
    py: Python<'py>,
    batch: &Batch<'_>,
    swept: bool,
    outputs: usize,
    results: BatchResults,
) -> PyResult<Bound<'py, PyDict>> {
    let designs = results.samples.len();
    let rows = batch.rows();
    let shape = |k: usize| {
        let mut shape = vec![designs];
        if swept {
            shape.push(rows);
        }
        if batch.width(k) > 1 {
            shape.push(batch.width(k));
        }
        shape
    };
    let mut arrays = Vec::with_capacity(outputs);
    let samples = array(py, results.samples.iter().map(|&n| n as f64).collect());
    let stops: Vec<Option<String>> = results
        .early
        .iter()
        .map(|e| e.as_ref().map(ToString::to_string))
        .collect();
    if outputs == 1 {
        // One output: the records are its array, handed over as they are.
        arrays.push(shaped(py, results.values, shape(0))?);
    } else {
        // Several: each is a view of the records, taken as one designs ×
        // record array (its columns offset … offset + rows · width), with
        // no copy; the views share no value (the Python `Batch` makes them
        // read-only).
        let record = results.record;
        let base = shaped(py, results.values, vec![designs, record])?;
        let index = |i: usize| {
            isize::try_from(i).map_err(|_| PyValueError::new_err("a batch too large to index"))
        };
        for k in 0..outputs {
            let start = batch.offset(k).unwrap_or(0);
            let end = start + rows * batch.width(k);
            let columns = (
                PySlice::full(py),
                PySlice::new(py, index(start)?, index(end)?, 1),
            );
            let view = base
                .get_item(columns)?
                .call_method1("reshape", (shape(k),))?;
            arrays.push(view);
        }
    }
    let d = PyDict::new(py);
    d.set_item("outputs", arrays)?;
    d.set_item("samples", samples)?;
    d.set_item("stops", stops)?;
    Ok(d)
}
