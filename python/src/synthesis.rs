//! The library's synthesis for Python: a problem handed over as the JSON
//! of `kinematics_core::synthesis::Spec` (the Python layer builds it from
//! keywords, so that the problem is read by one parser), solved by the
//! global search with the interpreter released, the optima returned as
//! plain dictionaries for the Python layer to wrap.

use kinematics_core::synthesis::{Budget, Found, Optimum, Progress, Spec};

use super::*;

/// The problem `spec` (JSON) read, or a `ValueError` saying what is wrong.
fn read_spec(spec: &str) -> PyResult<Spec> {
    serde_json::from_str(spec).map_err(|e| PyValueError::new_err(format!("synthesis problem: {e}")))
}

/// One optimum as a dictionary: the design's values, its driver values,
/// E, each target's error, whether it turns, its smallest transmission
/// angle, feasibility, how many starts reached it and its poses.
fn optimum<'py>(py: Python<'py>, o: &Optimum<Runtime>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let f = &o.found;
    d.set_item("values", f.design.values().to_vec())?;
    d.set_item("driver_values", f.driver_values.clone())?;
    d.set_item("error", f.sum_squares)?;
    d.set_item("target_errors", f.target_errors.clone())?;
    d.set_item("max_error", f.max_error)?;
    d.set_item("full_turn", f.full_turn)?;
    d.set_item("constraints_met", f.constraints_met)?;
    d.set_item("min_transmission", o.min_transmission)?;
    d.set_item("feasible", o.feasible)?;
    d.set_item("one_branch", o.one_branch)?;
    d.set_item("reached_by", o.reached_by)?;
    d.set_item("poses", o.poses.clone())?;
    Ok(d)
}

fn found<'py>(py: Python<'py>, f: &Found<Runtime>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let optima = f
        .optima
        .iter()
        .map(|o| optimum(py, o))
        .collect::<PyResult<Vec<_>>>()?;
    d.set_item("optima", optima)?;
    d.set_item("evaluations", f.evaluations)?;
    d.set_item("starts", f.starts)?;
    d.set_item("undrawn", f.undrawn)?;
    d.set_item(
        "stopped_by",
        f.stopped_by.map(|b| match b {
            Budget::Evaluations => "evaluations",
            Budget::Time => "time",
        }),
    )?;
    Ok(d)
}

/// The global search of the problem `spec` (the JSON of a `Spec`) for
/// the design `model` from the pose `start`; `progress`, if given, is
/// called with (screened, starts, refined, keep, best E, evaluations)
/// between groups of starts.
#[pyfunction]
#[pyo3(signature = (model, spec, start, progress=None))]
pub(crate) fn synthesize<'py>(
    py: Python<'py>,
    model: &Model,
    spec: &str,
    start: Vec<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let spec = read_spec(spec)?;
    let m: &Runtime = &model.model;
    let mut search = spec.search(m, &start).map_err(|e| error(py, &e))?;
    if let Some(callback) = progress {
        search = search.progress(move |p: &Progress| {
            Python::attach(|py| {
                let args = (
                    p.screened,
                    p.starts,
                    p.refined,
                    p.keep,
                    p.best,
                    p.evaluations,
                );
                if let Err(e) = callback.call1(py, args) {
                    e.print(py);
                }
            });
        });
    }
    let result = py.detach(|| search.run());
    let f = result.map_err(|e| error(py, &e))?;
    found(py, &f)
}
