//! The settings a call takes from Python: the solver's options and a
//! sweep's range, rates and rule at change points, as tuples.

use kinematics_core::{Branch, Convergence, Options};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::error;

/// The options of a call, from the tuple the Python layer passes:
/// (tolerance, max_iterations, singularity_threshold, branch, absolute),
/// branch one of "any", "positive", "negative".
pub(crate) type OptionsTuple = (f64, usize, f64, String, bool);

/// A sweep's settings as Python hands them over: from, to and turns (or
/// None), steps, rate, acceleration, and the rule at change points.
pub(crate) type SweepSpec = (
    Option<f64>,
    Option<f64>,
    Option<f64>,
    usize,
    f64,
    f64,
    String,
);

pub(crate) fn options(py: Python<'_>, o: Option<&OptionsTuple>) -> PyResult<Options> {
    // `None`: the defaults, with nothing to read.
    let Some(o) = o else {
        return Ok(Options::DEFAULT);
    };
    let branch = match o.3.as_str() {
        "any" => Branch::Any,
        "positive" => Branch::Positive,
        "negative" => Branch::Negative,
        other => {
            return Err(PyValueError::new_err(format!(
                "branch must be \"any\", \"positive\" or \"negative\", not {other:?}"
            )))
        }
    };
    let opts = Options {
        tolerance: o.0,
        max_iterations: o.1,
        singularity_threshold: o.2,
        branch,
        convergence: if o.4 {
            Convergence::Absolute
        } else {
            Convergence::Relative
        },
    };
    opts.validate().map_err(|e| error(py, &e))?;
    Ok(opts)
}

/// The default options as the tuple [`options`] reads.
#[pyfunction]
pub(crate) fn default_options() -> OptionsTuple {
    let o = Options::DEFAULT;
    (
        o.tolerance,
        o.max_iterations,
        o.singularity_threshold,
        "any".to_owned(),
        false,
    )
}
