//! A model's sweeps as the Python calls run them: the builder of a
//! sweep's range, its columns, and a sweep run into them with the
//! interpreter released.

use kinematics_core::runtime::{SweepBuilder, SweepEnd};
use kinematics_core::sweep::Stop;
use kinematics_core::Options;
use pyo3::prelude::*;

use crate::columns::Columns;
use crate::settings::SweepSpec;
use crate::sweep::change_points;
use crate::{error, Model};

/// A sweep of poses' columns: the driver's values, the coordinates (row
/// by row) and the points' positions.
type PoseColumns = (Vec<f64>, Vec<f64>, Vec<f64>);

impl Model {
    /// The sweep of `driver` from `start` over the grid `(from, to,
    /// turns, steps)`, as `sweep` and `poses` read it.
    pub(crate) fn grid<'a>(
        &'a self,
        py: Python<'_>,
        driver: &str,
        start: &[f64],
        spec: (Option<f64>, Option<f64>, Option<f64>, usize),
        o: &Options,
    ) -> PyResult<SweepBuilder<'a>> {
        let builder = self
            .model
            .sweep(driver, start)
            .map_err(|e| error(py, &e))?
            .steps(spec.3)
            .options(o);
        let builder = match spec.0 {
            Some(f) => builder.from(f),
            None => builder,
        };
        Ok(match (spec.1, spec.2) {
            (Some(t), _) => builder.to(t),
            (None, Some(n)) => builder.turns(n),
            (None, None) => builder,
        })
    }

    /// The sweep `spec` of `driver` from `start` run into its columns
    /// (with the interpreter released), and its stop.
    pub(crate) fn swept(
        &self,
        py: Python<'_>,
        driver: &str,
        start: &[f64],
        spec: &SweepSpec,
        o: &Options,
    ) -> PyResult<(Columns, Option<Stop>)> {
        let change = change_points(&spec.6)?;
        let builder = self
            .grid(py, driver, start, (spec.0, spec.1, spec.2, spec.3), o)?
            .rate(spec.4)
            .acceleration(spec.5)
            .change_points(change);
        let mut columns = self.columns(driver, spec.1.is_some(), spec.3);
        let stop = py.detach(|| {
            let end = builder.for_each_flat(|at, sample| columns.push(at, sample));
            let stop = end.stop.clone();
            columns.end(end);
            stop
        });
        Ok((columns, stop))
    }

    /// The columns of a sweep of `driver` over `steps` steps (one row
    /// more with an end value: its first sample).
    pub(crate) fn columns(&self, driver: &str, to: bool, steps: usize) -> Columns {
        // `grid` checked that the driver is one of the model's.
        let (name, kind) = self
            .model
            .coordinates()
            .iter()
            .find(|c| c.name == driver)
            .map_or(("", kinematics_core::Kind::Angle), |c| (c.name, c.kind));
        Columns::new(&self.model, name, kind, steps.max(1) + usize::from(to))
    }

    /// The sweep of poses of `driver` from `start` over the grid `spec`
    /// run into its three vectors ([`Model::pose_columns`]), with the
    /// interpreter released, and how it ended.
    pub(crate) fn posed(
        &self,
        py: Python<'_>,
        driver: &str,
        start: &[f64],
        spec: (Option<f64>, Option<f64>, Option<f64>, usize),
        o: &Options,
    ) -> PyResult<(PoseColumns, SweepEnd)> {
        let builder = self.grid(py, driver, start, spec, o)?;
        let (mut at, mut qs, mut points) = self.pose_columns(spec.1.is_some(), spec.3);
        let end = py.detach(|| {
            builder.for_each_pose(|value, q, r| {
                at.push(value);
                qs.extend_from_slice(q);
                points.extend_from_slice(r);
            })
        });
        Ok(((at, qs, points), end))
    }

    /// The three vectors a sweep of poses fills: the driver's values,
    /// the coordinates and the points' positions.
    fn pose_columns(&self, to: bool, steps: usize) -> PoseColumns {
        let rows = steps.max(1) + usize::from(to);
        let m = &self.model;
        (
            Vec::with_capacity(rows),
            Vec::with_capacity(rows * m.coordinates().len()),
            Vec::with_capacity(rows * m.point_names().len() * self.dim()),
        )
    }

    pub(crate) fn dim(&self) -> usize {
        // The model knows its point dimension; an empty sweep's layout
        // gives it without a pose.
        self.model.point_dimension()
    }
}
