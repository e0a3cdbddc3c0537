//! The `Sweep` class: the samples of a run-time model's sweep as numpy
//! columns handed over without a copy, the stop as a dict, and the views
//! the Python layer builds its `Sweep` from.

use std::sync::Mutex;

use pyo3::sync::PyOnceLock;

use super::*;

/// A sweep's stop as a dict: "kind" ("limit_position", "change_point",
/// "singular", "not_assembled" or "invalid"), "at", "message" and, where
/// the reason has them, "unknowns", "from" and "to"; `None` for none.
pub(crate) fn stop_dict<'py>(
    py: Python<'py>,
    stop: Option<&Stop>,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(stop) = stop else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    d.set_item("at", stop.at)?;
    d.set_item(
        "message",
        stop.message_with("change_points=\"smooth\" (or \"switch\")"),
    )?;
    match &stop.reason {
        StopReason::LimitPosition { unknowns } => d.set_item("unknowns", *unknowns)?,
        StopReason::ChangePoint { from, to } => {
            d.set_item("from", *from)?;
            d.set_item("to", *to)?;
        }
        _ => {}
    }
    d.set_item("kind", stop_kind(&stop.reason))?;
    Ok(Some(d))
}

/// The kind of a stop as Python names it.
pub(crate) fn stop_kind(reason: &StopReason) -> &'static str {
    match reason {
        StopReason::LimitPosition { .. } => "limit_position",
        StopReason::ChangePoint { .. } => "change_point",
        StopReason::Singular(_) => "singular",
        StopReason::NotAssembled(_) => "not_assembled",
        StopReason::Invalid(_) => "invalid",
    }
}

/// Degrees where asked, else radians.
fn angle_unit(degrees: bool) -> kinematics_core::units::AngleUnit {
    if degrees {
        kinematics_core::units::AngleUnit::Degrees
    } else {
        kinematics_core::units::AngleUnit::Radians
    }
}

pub(crate) fn change_points(s: &str) -> PyResult<ChangePoints> {
    match s {
        "stop" => Ok(ChangePoints::Stop),
        "smooth" => Ok(ChangePoints::Smooth),
        "switch" => Ok(ChangePoints::Switch),
        other => Err(PyValueError::new_err(format!(
            "change_points must be \"stop\", \"smooth\" or \"switch\", not {other:?}"
        ))),
    }
}

/// The samples of a sweep of a run-time model, and how it ended: each
/// data column handed to numpy without a copy when it is first asked for
/// (`arrays`; until then its values wait in `pending`), and what else the
/// sweep knows (`columns`, whose data columns were moved out).
#[pyclass(frozen, module = "loopkin._native")]
pub(crate) struct Sweep {
    pub(crate) columns: Columns,
    /// The values of each column not yet made an array, in the order of
    /// [`DATA`], then the frames'.
    pending: [Mutex<Option<Vec<f64>>>; COLUMNS],
    /// The arrays made, in the same order.
    arrays: [PyOnceLock<Py<PyAny>>; COLUMNS],
    pub(crate) rows: usize,
    pub(crate) model: std::sync::Arc<Runtime>,
}

/// The number of columns of a sweep: [`DATA`]'s and the frames'.
const COLUMNS: usize = DATA.len() + 1;

/// The names of the data columns, in the order of `Columns::take_data`.
const DATA: [&str; 8] = [
    "at",
    "q",
    "qd",
    "qdd",
    "points",
    "conditioning",
    "det_sign",
    "residual",
];

impl Sweep {
    /// The sweep of `model` whose samples are `columns`, their data
    /// columns moved out, to be handed to numpy as they are asked for
    /// ([`Sweep::array`]).
    pub(crate) fn new(
        _py: Python<'_>,
        mut columns: Columns,
        model: std::sync::Arc<Runtime>,
    ) -> PyResult<Self> {
        let n = columns.rows();
        let frames: Vec<f64> = columns
            .frames
            .iter()
            .flat_map(convert::frame_values)
            .collect();
        let [a, b, c, d, e, f, g, h] = columns.take_data().map(Some);
        Ok(Self {
            columns,
            pending: [a, b, c, d, e, f, g, h, Some(frames)].map(Mutex::new),
            arrays: std::array::from_fn(|_| PyOnceLock::new()),
            rows: n,
            model,
        })
    }

    /// Column `i` (of [`DATA`], then the frames) as a read-only array, made
    /// at the first call from its values (no copy), the same array at
    /// every call after: "q", "qd", "qdd" n × coordinates, "points" n ×
    /// points × 3 × dim, the frames n × frames × 24, the others n.
    fn array<'a>(&'a self, py: Python<'_>, i: usize) -> PyResult<&'a Py<PyAny>> {
        let (Some(cell), Some(pending)) = (self.arrays.get(i), self.pending.get(i)) else {
            return Err(PyValueError::new_err(format!(
                "a sweep has {COLUMNS} columns, not column {i}"
            )));
        };
        cell.get_or_try_init(py, || {
            let values = pending
                .lock()
                .map_err(|_| PyValueError::new_err("a column of the sweep was lost"))?
                .take()
                .ok_or_else(|| PyValueError::new_err("a column of the sweep was lost"))?;
            let n = self.rows;
            let m = &self.model;
            let a = match i {
                1..=3 => shaped(py, values, vec![n, m.coordinates().len()])?,
                4 => shaped(
                    py,
                    values,
                    vec![n, m.point_names().len(), 3, m.point_dimension()],
                )?,
                8 => shaped(py, values, vec![n, m.frame_names().len(), 24])?,
                _ => array(py, values).into_any(),
            };
            // Read-only: they hold the sweep's data, which `full` reads.
            Ok(frozen_any(a)?.unbind())
        })
    }

    /// Calls `write` with the columns, every point's role, the links
    /// (`links`, or those found from the motion) and the projection named
    /// `projection`: what a drawing of the sweep is made from.
    fn draw(
        &self,
        py: Python<'_>,
        links: Option<Vec<(String, String)>>,
        projection: &str,
        write: impl FnOnce(&Columns, &[PointRole], &[(&str, &str)], Projection) -> Result<(), Error>,
    ) -> PyResult<()> {
        let projection = plane(projection)?;
        let c = self.full(py)?;
        let roles = self.roles(py, &c)?;
        let links = links.unwrap_or_else(|| found_pairs(&c));
        let links: Vec<(&str, &str)> = links
            .iter()
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .collect();
        write(&c, &roles, &links, projection).map_err(|e| error(py, &e))
    }

    /// The role of every point (ground pivot, slider, moving), from the
    /// first sample.
    fn roles(&self, py: Python<'_>, c: &Columns) -> PyResult<Vec<PointRole>> {
        let nc = self.model.coordinates().len();
        let first = c.q[0]
            .get(..nc)
            .ok_or_else(|| PyValueError::new_err("the sweep has no sample to draw"))?;
        self.model.point_roles(first).map_err(|e| error(py, &e))
    }

    /// The columns with their data, read back from the arrays (a copy):
    /// what the tables, the CSV, the text, the animation and the
    /// deviations read.
    fn full(&self, py: Python<'_>) -> PyResult<Columns> {
        let mut held = Vec::with_capacity(DATA.len());
        for i in 0..DATA.len() {
            let a = self.array(py, i)?.bind(py);
            held.push(a.cast::<numpy::PyArrayDyn<f64>>()?.readonly());
        }
        let mut data: [&[f64]; 8] = [&[]; 8];
        for (slot, a) in data.iter_mut().zip(&held) {
            *slot = a.as_slice()?;
        }
        Ok(self.columns.with_data(data))
    }
}

#[pymethods]
impl Sweep {
    /// The swept driver's name.
    #[getter]
    fn variable(&self) -> &'static str {
        self.columns.variable()
    }
    /// The number of samples.
    fn __len__(&self) -> usize {
        self.rows
    }
    /// Every column as arrays: "at" (n), "q", "qd", "qdd" (n × coordinates),
    /// "points" (n × points × 3 × dim: position, velocity, acceleration),
    /// "frames" (n × frames × 24: rotation by rows, origin, velocity,
    /// acceleration, ω, α), "conditioning", "det_sign", "residual" (n).
    /// The same arrays at every call: they hold the sweep's data (made
    /// read-only by the Python class that wraps them).
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (i, key) in DATA.iter().chain(&["frames"]).enumerate() {
            d.set_item(key, self.array(py, i)?.bind(py))?;
        }
        Ok(d)
    }

    /// Column `i` of the sweep as an array, made when first asked for and
    /// the same array after: 0 "at", 1 "q", 2 "qd", 3 "qdd", 4 "points",
    /// 5 "conditioning", 6 "det_sign", 7 "residual", 8 "frames" (shaped as
    /// [`Sweep::columns`] gives them).
    fn column<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyAny>> {
        Ok(self.array(py, i)?.bind(py).clone())
    }

    /// `None` when the sweep ran to its end; else a dict with "kind"
    /// ("limit_position", "change_point", "singular", "not_assembled" or
    /// "invalid"), "at", "message" and, where the reason has them,
    /// "unknowns", "from" and "to".
    fn stop<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        stop_dict(py, self.columns.stop.as_ref())
    }

    /// The change points passed (estimates of the driver's value at each).
    #[getter]
    fn change_points(&self) -> Vec<f64> {
        self.columns.change_points.clone()
    }

    /// The column headers, with units (lengths in `unit`, angles in
    /// degrees where `degrees`), and the rows as a 2-D array, as the CSV
    /// has them.
    #[pyo3(signature = (unit, degrees = false))]
    fn table<'py>(
        &self,
        py: Python<'py>,
        unit: &str,
        degrees: bool,
    ) -> PyResult<(Vec<String>, Bound<'py, PyAny>)> {
        let c = self.full(py)?;
        let angle = angle_unit(degrees);
        let headers = c.headers_with(unit, angle);
        let width = headers.len();
        let rows: Vec<f64> = (0..c.rows()).flat_map(|i| c.row_with(i, angle)).collect();
        let n = c.rows();
        Ok((headers, shaped(py, rows, vec![n, width])?))
    }

    /// The CSV text (lengths in `unit`, angles in degrees where
    /// `degrees`).
    #[pyo3(signature = (unit, degrees = false))]
    fn to_csv(&self, py: Python<'_>, unit: &str, degrees: bool) -> PyResult<String> {
        Ok(self.full(py)?.csv_with(unit, angle_unit(degrees)))
    }

    /// A figure of merit of the sweep (see `merit::figure`).
    fn figure<'py>(
        &self,
        py: Python<'py>,
        which: &str,
        names: Vec<String>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let c = self.full(py)?;
        super::merit::figure(py, &c, which, &names)
    }

    /// The aligned text table, every `every`-th sample.
    fn to_text(&self, py: Python<'_>, every: usize) -> PyResult<String> {
        Ok(self.full(py)?.text(every))
    }

    /// Writes the HTML animation of the sweep to `path`, drawing the links
    /// `links` (pairs of point names; the links found from the motion
    /// where `None`) in the projection `projection` ("xy", "xz" or "yz").
    #[pyo3(signature = (path, links, projection))]
    fn write_animation(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        links: Option<Vec<(String, String)>>,
        projection: &str,
    ) -> PyResult<()> {
        self.draw(py, links, projection, |c, roles, links, projection| {
            kinematics_core::animate::write_table_html(
                c,
                self.model.name(),
                roles,
                links,
                projection,
                &path,
            )
        })
    }

    /// Writes the DXF drawing of the sweep to `path`: the skeleton at
    /// sample `sample` (the links `links`, or those found where `None`)
    /// and every moving point's path, in the projection `projection`.
    #[pyo3(signature = (path, links, sample, projection))]
    fn write_dxf(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        links: Option<Vec<(String, String)>>,
        sample: usize,
        projection: &str,
    ) -> PyResult<()> {
        self.draw(py, links, projection, |c, roles, links, projection| {
            kinematics_core::dxf::write_dxf(c, sample, roles, links, projection, &path)
        })
    }

    /// The links found from the motion: each the names of the points that
    /// move rigidly together, with whether it is the frame.
    fn links(&self, py: Python<'_>) -> PyResult<Vec<(Vec<String>, bool)>> {
        let c = self.full(py)?;
        let names = c.point_names();
        Ok(kinematics_core::links::links(&c)
            .into_iter()
            .map(|l| {
                (
                    l.points.iter().map(|&k| names[k].to_string()).collect(),
                    l.frame,
                )
            })
            .collect())
    }

    /// The forces at every sample, from the definition's `bodies` and
    /// `loads` sections.
    fn forces(&self, py: Python<'_>) -> PyResult<forces::ForceSweep> {
        let c = self.full(py)?;
        let model = &self.model;
        let sweep = py
            .detach(|| {
                let dynamics = model.dynamics()?;
                let samples: Vec<Sample> = (0..c.rows())
                    .map(|i| {
                        let mut motion = Motion::default();
                        let at = c.motion(i, &mut motion);
                        Sample { at, motion }
                    })
                    .collect();
                dynamics.along_samples_of(model, c.variable(), &samples)
            })
            .map_err(|e| error(py, &e))?;
        Ok(forces::ForceSweep::new(sweep))
    }

    /// How each driver's effort at every sample changes with each
    /// parameter of the `sensitivities` section, the drivers' motion held:
    /// a dict from each parameter to an array of shape (samples, drivers).
    fn effort_sensitivities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.full(py)?;
        let model = &self.model;
        let nd = model.drivers();
        let names: Vec<String> = model
            .sensitivity_parameters()
            .iter()
            .map(|n| n.to_string())
            .collect();
        let rows = c.rows();
        let columns = py
            .detach(|| -> Result<Vec<Vec<f64>>, Error> {
                let dynamics = model.dynamics()?;
                let mut columns = vec![Vec::with_capacity(rows * nd); names.len()];
                let mut motion = Motion::default();
                for i in 0..rows {
                    c.motion(i, &mut motion);
                    let s = dynamics.effort_sensitivities_of(model, &motion)?;
                    for (column, one) in columns.iter_mut().zip(s) {
                        column.extend(one.effort);
                    }
                }
                Ok(columns)
            })
            .map_err(|e| error(py, &e))?;
        let out = PyDict::new(py);
        for (name, column) in names.into_iter().zip(columns) {
            out.set_item(name, shaped(py, column, vec![rows, nd])?)?;
        }
        Ok(out)
    }

    /// The first-order deviations of point `point` for the tolerances
    /// `tolerances` ((parameter, ±t) pairs of the `sensitivities`
    /// section): a dict of arrays "at", "position_worst",
    /// "position_components" (n × dim), "position_rss" (n × dim),
    /// "velocity_worst", "velocity_components", "velocity_rss".
    fn deviations<'py>(
        &self,
        py: Python<'py>,
        point: &str,
        tolerances: Vec<(String, f64)>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let t: Vec<(&str, f64)> = tolerances.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        let c = self.full(py)?;
        let devs = py
            .detach(|| {
                self.model.point_deviations_over(
                    c.rows(),
                    |i, motion| c.motion(i, motion),
                    point,
                    &t,
                )
            })
            .map_err(|e| error(py, &e))?;
        let n = devs.len();
        let dim = self.model.point_dimension();
        let d = PyDict::new(py);
        d.set_item("at", array(py, devs.iter().map(|x| x.at).collect()))?;
        d.set_item(
            "position_worst",
            array(py, devs.iter().map(|x| x.position_worst).collect()),
        )?;
        d.set_item(
            "velocity_worst",
            array(py, devs.iter().map(|x| x.velocity_worst).collect()),
        )?;
        for (key, pick) in [
            (
                "position_components",
                (|x: &kinematics_core::tolerance::Deviation| &x.position_components)
                    as fn(&kinematics_core::tolerance::Deviation) -> &Vec<f64>,
            ),
            ("position_rss", |x| &x.position_rss),
            ("velocity_components", |x| &x.velocity_components),
            ("velocity_rss", |x| &x.velocity_rss),
        ] {
            let flat: Vec<f64> = devs.iter().flat_map(|x| pick(x).iter().copied()).collect();
            d.set_item(key, shaped(py, flat, vec![n, dim])?)?;
        }
        Ok(d)
    }
}

/// A projection by name.
fn plane(projection: &str) -> PyResult<Projection> {
    match projection {
        "xy" => Ok(Projection::XY),
        "xz" => Ok(Projection::XZ),
        "yz" => Ok(Projection::YZ),
        other => Err(PyValueError::new_err(format!(
            "projection must be \"xy\", \"xz\" or \"yz\", not {other:?}"
        ))),
    }
}

/// The point pairs drawn for the links found from the motion of `c`.
fn found_pairs(c: &Columns) -> Vec<(String, String)> {
    let names = c.point_names();
    kinematics_core::links::drawn_pairs(&kinematics_core::links::links(c))
        .into_iter()
        .map(|(a, b)| (names[a].to_string(), names[b].to_string()))
        .collect()
}

/// An array handed out as `PyAny`, made read-only ([`convert::frozen`]).
pub(crate) fn frozen_any(a: Bound<'_, PyAny>) -> PyResult<Bound<'_, PyAny>> {
    Ok(convert::frozen(a.cast_into::<numpy::PyUntypedArray>()?).into_any())
}
