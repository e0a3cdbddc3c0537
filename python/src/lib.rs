//! The native module of the `loopkin` Python package (`loopkin._native`):
//! a mechanism compiled from text at run time ([`runtime::Model`]), its
//! assembly, analysis, sweeps, sensitivities and batches, with arrays
//! passed as numpy arrays.
//!
//! This module is the thin layer under the Python API of `loopkin`
//! (`python/loopkin/`), which names things, checks keyword arguments and
//! builds the result objects. Everything numerical happens in
//! `kinematics-core`; sweeps and batches run with the interpreter released,
//! batches on every core.

use kinematics_core::closed::Mode;
use kinematics_core::runtime::{
    Batch, BatchSweep, CompileError, Model as Runtime, Motion, Reduce, Sample,
};
use kinematics_core::sweep::{ChangePoints, Stop, StopReason, Table};
use kinematics_core::view::{PointRole, Projection};
use kinematics_core::Error;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

mod batch;
mod columns;
mod convert;
mod errors;
mod forces;
mod forward;
mod merit;
mod runs;
mod settings;
mod sweep;
mod synthesis;

use columns::Columns;
use sweep::{change_points, stop_dict, Sweep};

use convert::{array, motion_tuple, shaped};
pub(crate) use errors::{error, raise};
use settings::{default_options, options, OptionsTuple, SweepSpec};

/// What `__reduce__` gives pickle: the function that rebuilds a model,
/// and its arguments (the text and the parameter values).
type Reduced<'py> = (Bound<'py, PyAny>, (String, Vec<f64>));

fn modes_text(modes: &[Mode]) -> Vec<&'static str> {
    modes
        .iter()
        .map(|m| match m {
            Mode::Plus => "+",
            Mode::Minus => "-",
        })
        .collect()
}

/// A mechanism compiled from the text of its definition, with its
/// parameter values (NaN until set). Immutable: `with_values` makes a
/// design that shares the machine code.
#[pyclass(frozen, module = "loopkin._native")]
struct Model {
    /// Shared with the sweeps made from it, which read it back.
    model: std::sync::Arc<Runtime>,
    text: String,
}

/// Compiles the definition `text` (as written inside `mechanism! { … }`),
/// raising `loopkin.errors.DefinitionError` with every error, its line and
/// column.
#[pyfunction]
fn compile(py: Python<'_>, text: &str) -> PyResult<Model> {
    let owned = text.to_owned();
    let compiled = py.detach(move || Runtime::compile(&owned));
    match compiled {
        Ok(model) => Ok(Model {
            model: std::sync::Arc::new(model),
            text: text.to_owned(),
        }),
        Err(CompileError::Definition(d)) => {
            let message = d.to_string();
            // One Python string per line of the text, shared by the
            // diagnostics on that line (a line with thousands of errors is
            // not copied thousands of times).
            let mut excerpts: std::collections::HashMap<usize, Py<PyString>> =
                std::collections::HashMap::new();
            let list: Vec<(String, usize, usize, Py<PyString>)> =
                d.0.iter()
                    .map(|x| {
                        let excerpt = excerpts
                            .entry(x.line)
                            .or_insert_with(|| PyString::new(py, x.excerpt.as_str()).unbind())
                            .clone_ref(py);
                        (x.message.clone(), x.line, x.column, excerpt)
                    })
                    .collect();
            Err(raise(py, "DefinitionError", &message, |inst| {
                let first = list
                    .first()
                    .map(|(m, l, c, e)| (m.clone(), *l, *c, e.clone_ref(py)));
                inst.setattr("diagnostics", list)?;
                if let Some((msg, line, column, excerpt)) = first {
                    inst.setattr("line", line)?;
                    inst.setattr("column", column)?;
                    inst.setattr("excerpt", excerpt)?;
                    inst.setattr("first", msg)?;
                }
                Ok(())
            }))
        }
        Err(CompileError::Native(e)) => {
            Err(raise(py, "NativeCodeError", &e.to_string(), |_| Ok(())))
        }
    }
}

impl Model {
    /// `f` of the definition's dynamics, the model and its motion at the
    /// closed pose `q` with the drivers' rates and accelerations (`at`:
    /// q, rates, accelerations), run with the interpreter released.
    fn at_motion<T: Send>(
        &self,
        py: Python<'_>,
        at: [&[f64]; 3],
        f: impl FnOnce(&kinematics_core::dynamics::Dynamics, &Runtime, &Motion) -> Result<T, Error>
            + Send,
    ) -> PyResult<T> {
        let model = &self.model;
        py.detach(|| {
            let dynamics = model.dynamics()?;
            let motion = model.analyze(at[0], at[1], at[2])?;
            f(&dynamics, model, &motion)
        })
        .map_err(|e| error(py, &e))
    }
}

#[pymethods]
impl Model {
    /// The definition's text.
    #[getter]
    fn text(&self) -> &str {
        &self.text
    }
    /// The mechanism's name.
    #[getter]
    fn name(&self) -> &str {
        self.model.name()
    }
    /// The parameters' names, in declaration order.
    #[getter]
    fn parameters(&self) -> Vec<&'static str> {
        self.model.parameters().to_vec()
    }
    /// The parameters' values, in declaration order.
    #[getter]
    fn values(&self) -> Vec<f64> {
        self.model.values().to_vec()
    }
    /// (name, "driver" or "unknown", "angle" or "length") per coordinate,
    /// drivers first.
    #[getter]
    fn coordinates(&self) -> Vec<(&'static str, &'static str, &'static str)> {
        let nd = self.model.drivers();
        self.model
            .coordinates()
            .iter()
            .enumerate()
            .map(|(j, c)| {
                let role = if j < nd { "driver" } else { "unknown" };
                let kind = match c.kind {
                    kinematics_core::Kind::Angle => "angle",
                    kinematics_core::Kind::Length => "length",
                };
                (c.name, role, kind)
            })
            .collect()
    }
    /// The number of drivers.
    #[getter]
    fn drivers(&self) -> usize {
        self.model.drivers()
    }
    /// The points' names.
    #[getter]
    fn points(&self) -> Vec<&'static str> {
        self.model.point_names().to_vec()
    }
    /// The frames' names.
    #[getter]
    fn frames(&self) -> Vec<&'static str> {
        self.model.frame_names().to_vec()
    }
    /// 2 (planar) or 3 (spatial).
    #[getter]
    fn point_dim(&self) -> usize {
        self.dim()
    }
    /// The equations' names.
    #[getter]
    fn equations(&self) -> Vec<&'static str> {
        self.model.equation_names().to_vec()
    }
    /// The model described as `kinematics check` prints it.
    #[getter]
    fn description(&self) -> String {
        self.model.describe()
    }
    /// (unknowns, method, has two modes) per block, in solve order.
    #[getter]
    fn blocks(&self) -> Vec<(Vec<&'static str>, &'static str, bool)> {
        self.model
            .blocks()
            .iter()
            .map(|b| (b.unknowns.to_vec(), b.method, b.modes))
            .collect()
    }
    /// The number of blocks with two assembly modes.
    #[getter]
    fn mode_count(&self) -> usize {
        self.model.mode_count()
    }
    /// The parameters of the `sensitivities` section.
    #[getter]
    fn sensitivity_parameters(&self) -> Vec<&'static str> {
        self.model.sensitivity_parameters().to_vec()
    }

    /// A design of the same definition with the parameter values `values`
    /// (in declaration order), sharing the machine code.
    fn with_values(&self, py: Python<'_>, values: Vec<f64>) -> PyResult<Model> {
        let model = self.model.with_values(&values).map_err(|e| error(py, &e))?;
        Ok(Model {
            model: std::sync::Arc::new(model),
            text: self.text.clone(),
        })
    }

    /// Checks the parameter values (finite; lengths positive).
    fn validate(&self, py: Python<'_>) -> PyResult<()> {
        self.model.validate().map_err(|e| error(py, &e))
    }

    /// Φ(q).
    fn residual<'py>(&self, py: Python<'py>, q: Vec<f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let r = self.model.residual(&q).map_err(|e| error(py, &e))?;
        Ok(array(py, r))
    }

    /// Assembles at the drivers of `q` from its unknowns.
    fn assemble<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        opts: Option<OptionsTuple>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let o = options(py, opts.as_ref())?;
        let q = self
            .model
            .assemble_with(&q, &o)
            .map_err(|e| error(py, &e))?;
        Ok(array(py, q))
    }

    /// Assembles at the drivers of `q` in the modes `modes` ("+" or "-" per
    /// block with two modes).
    fn assemble_in<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        modes: Vec<String>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let modes = modes
            .iter()
            .map(|m| match m.as_str() {
                "+" => Ok(Mode::Plus),
                "-" => Ok(Mode::Minus),
                other => Err(PyValueError::new_err(format!(
                    "a mode is \"+\" or \"-\", not {other:?}"
                ))),
            })
            .collect::<PyResult<Vec<Mode>>>()?;
        let q = self
            .model
            .assemble_in(&q, &modes)
            .map_err(|e| error(py, &e))?;
        Ok(array(py, q))
    }

    /// Every combination of modes at the drivers of `q`: (modes, pose or
    /// the exception saying why it does not assemble).
    fn assemble_all<'py>(&self, py: Python<'py>, q: Vec<f64>) -> PyResult<Bound<'py, PyList>> {
        self.model.validate().map_err(|e| error(py, &e))?;
        let out = PyList::empty(py);
        for (modes, pose) in self.model.assemble_all(&q) {
            let value: Bound<'py, PyAny> = match pose {
                Ok(p) => array(py, p).into_any(),
                Err(e) => error(py, &e).into_value(py).into_bound(py).into_any(),
            };
            out.append((modes_text(&modes), value))?;
        }
        Ok(out)
    }

    /// The motion at the closed pose `q` with the drivers' rates and
    /// accelerations, as a dict of arrays.
    fn analyze<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
        opts: Option<OptionsTuple>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let o = options(py, opts.as_ref())?;
        let m = self
            .model
            .analyze_with(&q, &rates, &accelerations, &o)
            .map_err(|e| error(py, &e))?;
        motion_tuple(py, &m)
    }

    /// Assembles at the drivers of `start` and analyses the motion there.
    fn step<'py>(
        &self,
        py: Python<'py>,
        start: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let m = self
            .model
            .step(&start, &rates, &accelerations)
            .map_err(|e| error(py, &e))?;
        motion_tuple(py, &m)
    }

    /// Whether the definition has a `bodies` or `loads` section.
    fn has_dynamics(&self) -> bool {
        self.model.has_dynamics()
    }

    /// The forces at the closed pose `q` with the drivers' rates and
    /// accelerations, from the definition's `bodies` and `loads`
    /// sections: a dict of "effort" (one per driver), "kinetic_energy",
    /// "potential_energy", "power", "shaking_force" and "shaking_moment"
    /// (3 each).
    fn forces<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let f = self.at_motion(py, [&q, &rates, &accelerations], |d, m, motion| {
            d.inverse_of(m, motion)
        })?;
        forces::instant(py, &f, self.model.drivers())
    }

    /// The joint reactions at the closed pose `q` with the drivers' rates
    /// and accelerations, from the definition's `bodies`, `loads` and
    /// `joints` sections: a list of dicts, one per joint.
    fn reactions<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
    ) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let r = self.at_motion(py, [&q, &rates, &accelerations], |d, m, motion| {
            d.reactions_of(m, motion)
        })?;
        forces::reactions(py, &r)
    }

    /// How each driver's effort at the closed pose `q` with the drivers'
    /// rates and accelerations changes with each body's mass and moment
    /// of inertia: a list of dicts, one per body of `bodies`, of "body",
    /// "mass" (one per driver) and "inertia" (one per driver, or None).
    fn mass_sensitivities<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
    ) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let s = self.at_motion(py, [&q, &rates, &accelerations], |d, m, motion| {
            d.mass_sensitivities_of(m, motion)
        })?;
        s.into_iter()
            .map(|b| {
                let d = PyDict::new(py);
                d.set_item("body", b.body)?;
                d.set_item("mass", array(py, b.mass))?;
                d.set_item("inertia", b.inertia.map(|i| array(py, i)))?;
                Ok(d)
            })
            .collect()
    }

    /// How each driver's effort at the closed pose `q` with the drivers'
    /// rates and accelerations changes with each parameter of the
    /// `sensitivities` section, the drivers' motion held: a dict from each
    /// parameter to ∂Q_k/∂p, one per driver.
    fn effort_sensitivities<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let s = self.at_motion(py, [&q, &rates, &accelerations], |d, m, motion| {
            d.effort_sensitivities_of(m, motion)
        })?;
        let out = PyDict::new(py);
        for p in s {
            out.set_item(p.parameter, array(py, p.effort))?;
        }
        Ok(out)
    }

    /// The design sensitivities at the closed pose `q` with the drivers'
    /// rates and accelerations: a dict from each parameter of the
    /// `sensitivities` section to a dict of ∂q/∂p, ∂q'/∂p, ∂q''/∂p and the
    /// points' derivatives.
    fn sensitivities<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let m = self
            .model
            .analyze(&q, &rates, &accelerations)
            .map_err(|e| error(py, &e))?;
        let all = self.model.sensitivities(&m).map_err(|e| error(py, &e))?;
        let out = PyDict::new(py);
        let dim = self.dim();
        for s in all {
            let d = PyDict::new(py);
            d.set_item("q", array(py, s.q))?;
            d.set_item("qd", array(py, s.qd))?;
            d.set_item("qdd", array(py, s.qdd))?;
            let flat = convert::point_values(&s.points);
            d.set_item("points", shaped(py, flat, vec![s.points.len(), 3, dim])?)?;
            out.set_item(s.parameter, d)?;
        }
        Ok(out)
    }

    /// A sweep of the driver `driver` from the pose `start`; `spec` is
    /// (from or None, to or None, turns or None, steps, rate,
    /// acceleration, change points "stop" | "smooth" | "switch").
    #[allow(clippy::type_complexity)]
    fn sweep(
        &self,
        py: Python<'_>,
        driver: &str,
        start: Vec<f64>,
        spec: SweepSpec,
        opts: Option<OptionsTuple>,
    ) -> PyResult<Sweep> {
        let o = options(py, opts.as_ref())?;
        let (columns, _) = self.swept(py, driver, &start, &spec, &o)?;
        Sweep::new(py, columns, self.model.clone())
    }

    /// Positions only along a sweep of the driver `driver` from `start`
    /// (`SweepBuilder::for_each_pose`): the grid of `spec` (from, to,
    /// turns, steps, as `sweep`'s). A tuple of read-only arrays "at" (n),
    /// "q" (n × coordinates), "points" (n × points × dim), then the stop
    /// (as `Sweep.stop` gives it, or None).
    #[allow(clippy::type_complexity)]
    fn poses<'py>(
        &self,
        py: Python<'py>,
        driver: &str,
        start: Vec<f64>,
        spec: (Option<f64>, Option<f64>, Option<f64>, usize),
        opts: Option<OptionsTuple>,
    ) -> PyResult<(
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Option<Bound<'py, PyDict>>,
    )> {
        let o = options(py, opts.as_ref())?;
        let ((at, qs, points), end) = self.posed(py, driver, &start, spec, &o)?;
        let (nc, np, dim) = (
            self.model.coordinates().len(),
            self.model.point_names().len(),
            self.dim(),
        );
        let n = at.len();
        // Read-only: the result's own data.
        Ok((
            convert::frozen(array(py, at)).into_any(),
            sweep::frozen_any(shaped(py, qs, vec![n, nc])?)?,
            sweep::frozen_any(shaped(py, points, vec![n, np, dim])?)?,
            stop_dict(py, end.stop.as_ref())?,
        ))
    }

    /// The native work of `sweep` (`kind` "sweep") or of `poses` ("poses")
    /// done `repeats` times over, nothing handed to Python: the same
    /// builder, the same columns filled, then dropped. The benchmark
    /// `python/benchmarks/python_overhead.py` times it against the calls
    /// from Python, to measure what the binding adds. `spec` is `sweep`'s.
    /// Returns the last run's samples and its stop's kind (`None` where
    /// it ran to its end), as a check that it did the work.
    #[allow(clippy::type_complexity, clippy::too_many_arguments)]
    fn _repeat_in_rust(
        &self,
        py: Python<'_>,
        kind: &str,
        driver: &str,
        start: Vec<f64>,
        spec: SweepSpec,
        opts: Option<OptionsTuple>,
        repeats: usize,
    ) -> PyResult<(usize, Option<String>)> {
        let o = options(py, opts.as_ref())?;
        let grid = (spec.0, spec.1, spec.2, spec.3);
        let mut last = (0, None);
        let kind_of = |stop: Option<&Stop>| stop.map(|s| sweep::stop_kind(&s.reason).to_owned());
        match kind {
            "sweep" => {
                for _ in 0..repeats {
                    let (columns, stop) = self.swept(py, driver, &start, &spec, &o)?;
                    std::hint::black_box(&columns);
                    last = (columns.rows(), kind_of(stop.as_ref()));
                }
            }
            "poses" => {
                for _ in 0..repeats {
                    let ((at, qs, points), end) = self.posed(py, driver, &start, grid, &o)?;
                    std::hint::black_box((&at, &qs, &points));
                    last = (at.len(), kind_of(end.stop.as_ref()));
                }
            }
            _ => {
                return Err(PyValueError::new_err(format!(
                    "kind {kind:?}: \"sweep\" or \"poses\""
                )))
            }
        }
        Ok(last)
    }

    /// A simulation in time from the pose `start` over `duration` seconds
    /// in `steps` steps: at sample k (t = duration·k/steps) the drivers
    /// take the values, rates and accelerations of row k of `values`,
    /// `rates` and `accelerations` (`(steps + 1)` rows of one value per
    /// driver, row-major).
    #[allow(clippy::too_many_arguments)]
    fn simulate(
        &self,
        py: Python<'_>,
        start: Vec<f64>,
        duration: f64,
        steps: usize,
        values: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
        opts: Option<OptionsTuple>,
    ) -> PyResult<Sweep> {
        let o = options(py, opts.as_ref())?;
        let (nd, steps) = (self.model.drivers(), steps.max(1));
        let rows = (steps + 1) * nd;
        for (what, v) in [
            ("driver values", &values),
            ("driver rates", &rates),
            ("driver accelerations", &accelerations),
        ] {
            if v.len() != rows {
                return Err(error(
                    py,
                    &Error::WrongLength {
                        what,
                        expected: rows,
                        found: v.len(),
                    },
                ));
            }
        }
        let mut columns = Columns::new(&self.model, "t", kinematics_core::Kind::Length, steps + 1);
        py.detach(|| {
            #[allow(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                clippy::cast_precision_loss
            )]
            let end = self
                .model
                .simulate(&start)
                .duration(duration)
                .steps(steps)
                .options(&o)
                .profile(|t, d, dd, ddd| {
                    // t = duration·k/steps exactly: k back by rounding.
                    let k = ((t / duration * steps as f64).round() as usize).min(steps);
                    let row = k * nd..(k + 1) * nd;
                    d.copy_from_slice(&values[row.clone()]);
                    dd.copy_from_slice(&rates[row.clone()]);
                    ddd.copy_from_slice(&accelerations[row]);
                })
                .for_each_flat(|at, sample| columns.push(at, sample));
            columns.end(end);
        });
        Sweep::new(py, columns, self.model.clone())
    }

    /// Runs a batch of designs (one row of `values` per design, a value
    /// per parameter) on every core: `kinematics_core::runtime::Batch`. The arguments are
    /// those of `Mechanism.batch` in the Python layer, one for one.
    #[allow(clippy::type_complexity, clippy::too_many_arguments)]
    #[pyo3(signature = (values, start, rates, accelerations, sweep, outputs, opts, reduce, positions_only=false))]
    fn batch<'py>(
        &self,
        py: Python<'py>,
        values: PyReadonlyArray2<'py, f64>,
        start: Vec<f64>,
        rates: Vec<f64>,
        accelerations: Vec<f64>,
        sweep: Option<(String, Option<f64>, Option<f64>, Option<f64>, usize, String)>,
        outputs: Vec<(String, usize)>,
        opts: Option<OptionsTuple>,
        reduce: Option<String>,
        positions_only: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let o = options(py, opts.as_ref())?;
        let reduce = batch::reduce(reduce.as_deref())?;
        let shape = values.shape();
        let (designs, width) = (shape[0], shape[1]);
        if width != self.model.parameters().len() {
            return Err(error(
                py,
                &Error::WrongLength {
                    what: "parameter values per design",
                    expected: self.model.parameters().len(),
                    found: width,
                },
            ));
        }
        let table: Vec<f64> = values.as_array().iter().copied().collect();
        let spec = match sweep {
            Some((driver, from, to, turns, steps, change)) => {
                let j = self
                    .model
                    .coordinates()
                    .iter()
                    .position(|c| c.name == driver)
                    .filter(|&j| j < self.model.drivers())
                    .ok_or_else(|| {
                        PyValueError::new_err(format!(
                            "{driver:?} is not a driver of {}: the drivers are {:?}",
                            self.model.name(),
                            &self.model.coordinates()[..self.model.drivers()]
                                .iter()
                                .map(|c| c.name)
                                .collect::<Vec<_>>()
                        ))
                    })?;
                Some(BatchSweep {
                    driver: j,
                    from,
                    to,
                    turns,
                    steps,
                    change_points: change_points(&change)?,
                })
            }
            None => None,
        };
        let swept = spec.is_some();
        let kept = outputs
            .iter()
            .map(|(kind, i)| batch::output(kind, *i))
            .collect::<PyResult<Vec<_>>>()?;
        let mut job = Batch::new(&self.model, &start, &rates, &accelerations, spec, &kept, &o)
            .map_err(|e| error(py, &e))?
            .reduced(reduce);
        if positions_only {
            job = job.positions_only().map_err(|e| error(py, &e))?;
        }
        // The table copied before the interpreter is released: no other
        // thread can change it under the batch.
        // A model without parameters takes a row of one (unread) value
        // per design.
        let design_rows = if width == 0 {
            vec![0.0; designs]
        } else {
            table
        };
        let results = py.detach(|| job.run(&design_rows));
        let rows = swept && reduce == Reduce::Samples;
        batch::gather(py, &job, rows, kept.len(), results)
    }

    /// Pickles as the definition's text and the parameter values: a
    /// worker process compiles the text again (once per process).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Reduced<'py>> {
        let rebuild = py.import("loopkin._model")?.getattr("_native_model")?;
        Ok((rebuild, (self.text.clone(), self.model.values().to_vec())))
    }

    fn __repr__(&self) -> String {
        format!("<compiled mechanism {}>", self.model.name())
    }
}

/// The native module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Model>()?;
    m.add_class::<Sweep>()?;
    m.add_class::<forces::ForceSweep>()?;
    m.add_function(wrap_pyfunction!(compile, m)?)?;
    m.add_function(wrap_pyfunction!(default_options, m)?)?;
    m.add_function(wrap_pyfunction!(merit::read_quantity, m)?)?;
    m.add_function(wrap_pyfunction!(merit::grashof, m)?)?;
    m.add_function(wrap_pyfunction!(synthesis::synthesize, m)?)?;
    m.add_function(wrap_pyfunction!(forward::forward, m)?)?;
    Ok(())
}
