//! The forces of the definition's `bodies` and `loads` sections, as numpy
//! arrays: at one motion (a dict) and along a sweep ([`ForceSweep`]).

use kinematics_core::dynamics::{ForceSweep as Sweep, Forces};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{array, shaped};
use crate::error;

/// The forces at one motion as a dict: "effort" (the first `drivers`
/// entries: one per driver), "kinetic_energy", "potential_energy",
/// "power", "shaking_force", "shaking_moment", "frame_force" and
/// "frame_moment" (3 each).
pub(crate) fn instant<'py>(
    py: Python<'py>,
    f: &Forces<Vec<f64>>,
    drivers: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let effort: Vec<f64> = f.effort.iter().copied().take(drivers).collect();
    d.set_item("effort", array(py, effort))?;
    d.set_item("kinetic_energy", f.kinetic_energy)?;
    d.set_item("potential_energy", f.potential_energy)?;
    d.set_item("power", f.power)?;
    d.set_item(
        "shaking_force",
        array(py, f.shaking_force.iter().copied().collect()),
    )?;
    d.set_item(
        "shaking_moment",
        array(py, f.shaking_moment.iter().copied().collect()),
    )?;
    d.set_item(
        "frame_force",
        array(py, f.frame_force.iter().copied().collect()),
    )?;
    d.set_item(
        "frame_moment",
        array(py, f.frame_moment.iter().copied().collect()),
    )?;
    Ok(d)
}

/// The reactions at one motion as a list of dicts, one per joint in the
/// order declared: "name", "force", "force_in_body", "moment" (3 each)
/// and "effort" (the driver's, or None).
pub(crate) fn reactions<'py>(
    py: Python<'py>,
    r: &kinematics_core::dynamics::Reactions,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    r.joints
        .iter()
        .map(|j| {
            let d = PyDict::new(py);
            d.set_item("name", &j.name)?;
            d.set_item("force", array(py, j.force.iter().copied().collect()))?;
            d.set_item(
                "force_in_body",
                array(py, j.force_in_body.iter().copied().collect()),
            )?;
            d.set_item("moment", array(py, j.moment.iter().copied().collect()))?;
            d.set_item("effort", j.effort)?;
            Ok(d)
        })
        .collect()
}

/// The forces along a sweep: each driver's effort, the energies, the
/// power and the shaking force and moment at every sample, the mean
/// effort and the energy fluctuation of each driver, the CSV table and
/// the plot.
#[pyclass(frozen, module = "loopkin._native")]
pub(crate) struct ForceSweep {
    sweep: Sweep,
}

impl ForceSweep {
    pub(crate) fn new(sweep: Sweep) -> Self {
        Self { sweep }
    }

    /// The index of driver `driver`.
    fn driver(&self, driver: &str) -> PyResult<usize> {
        self.sweep
            .drivers
            .iter()
            .position(|(n, _)| n == driver)
            .ok_or_else(|| {
                let names: Vec<&str> = self.sweep.drivers.iter().map(|(n, _)| n.as_str()).collect();
                PyValueError::new_err(format!("{driver:?} is not a driver: they are {names:?}"))
            })
    }

    /// A value of a driver's summary, or an error saying why there is none.
    fn summary(value: Option<f64>, what: &str) -> PyResult<f64> {
        value.ok_or_else(|| {
            PyValueError::new_err(format!(
                "no {what}: the sweep needs at least two samples over a range of the driver, \
                 and efforts whose integral over it is finite"
            ))
        })
    }
}

#[pymethods]
impl ForceSweep {
    /// The drivers' names, in declaration order.
    #[getter]
    fn drivers(&self) -> Vec<String> {
        self.sweep.drivers.iter().map(|(n, _)| n.clone()).collect()
    }

    /// Every column: "at" (n), "effort" (n × drivers),
    /// "kinetic_energy", "potential_energy", "power" (n each),
    /// "shaking_force", "shaking_moment", "frame_force", "frame_moment"
    /// (n × 3), and "reactions": for
    /// each joint by name, its "force" and "moment" (n × 3) and "effort"
    /// (n, or None where no driver acts in it).
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.sweep.samples;
        let n = s.len();
        let nd = self.sweep.drivers.len();
        let d = PyDict::new(py);
        let column =
            |f: fn(&kinematics_core::dynamics::ForceSample) -> f64| -> Bound<'py, PyArray1<f64>> {
                array(py, s.iter().map(f).collect())
            };
        d.set_item("at", column(|x| x.at))?;
        d.set_item("kinetic_energy", column(|x| x.kinetic_energy))?;
        d.set_item("potential_energy", column(|x| x.potential_energy))?;
        d.set_item("power", column(|x| x.power))?;
        let effort: Vec<f64> = s
            .iter()
            .flat_map(|x| (0..nd).map(|k| x.effort.get(k).copied().unwrap_or(f64::NAN)))
            .collect();
        d.set_item("effort", shaped(py, effort, vec![n, nd])?)?;
        let force: Vec<f64> = s
            .iter()
            .flat_map(|x| x.shaking_force.iter().copied())
            .collect();
        d.set_item("shaking_force", shaped(py, force, vec![n, 3])?)?;
        let moment: Vec<f64> = s
            .iter()
            .flat_map(|x| x.shaking_moment.iter().copied())
            .collect();
        d.set_item("shaking_moment", shaped(py, moment, vec![n, 3])?)?;
        let force: Vec<f64> = s
            .iter()
            .flat_map(|x| x.frame_force.iter().copied())
            .collect();
        d.set_item("frame_force", shaped(py, force, vec![n, 3])?)?;
        let moment: Vec<f64> = s
            .iter()
            .flat_map(|x| x.frame_moment.iter().copied())
            .collect();
        d.set_item("frame_moment", shaped(py, moment, vec![n, 3])?)?;
        // Each joint's force, moment (n × 3) and effort (n, or None), by
        // name, where the description declares joints.
        let joints = PyDict::new(py);
        let names: Vec<String> = s
            .first()
            .and_then(|x| x.reactions.as_ref())
            .map_or_else(Vec::new, |r| {
                r.joints.iter().map(|j| j.name.clone()).collect()
            });
        for (k, name) in names.iter().enumerate() {
            fn joint(
                x: &kinematics_core::dynamics::ForceSample,
                k: usize,
            ) -> Option<&kinematics_core::dynamics::JointReaction> {
                x.reactions.as_ref().and_then(|r| r.joints.get(k))
            }
            let vectors = |pick: fn(&kinematics_core::dynamics::JointReaction) -> [f64; 3]| {
                s.iter()
                    .flat_map(|x| joint(x, k).map_or([f64::NAN; 3], pick))
                    .collect::<Vec<f64>>()
            };
            let j = PyDict::new(py);
            j.set_item(
                "force",
                shaped(py, vectors(|r| r.force.into()), vec![n, 3])?,
            )?;
            j.set_item(
                "moment",
                shaped(py, vectors(|r| r.moment.into()), vec![n, 3])?,
            )?;
            let driven = s
                .first()
                .and_then(|x| joint(x, k))
                .is_some_and(|r| r.effort.is_some());
            if driven {
                let e: Vec<f64> = s
                    .iter()
                    .map(|x| joint(x, k).and_then(|r| r.effort).unwrap_or(f64::NAN))
                    .collect();
                j.set_item("effort", array(py, e))?;
            } else {
                j.set_item("effort", py.None())?;
            }
            joints.set_item(name, j)?;
        }
        d.set_item("reactions", joints)?;
        Ok(d)
    }

    /// The mean effort of driver `driver` over the swept range
    /// (trapezoidal).
    fn mean_effort(&self, driver: &str) -> PyResult<f64> {
        Self::summary(self.sweep.mean_effort(self.driver(driver)?), "mean effort")
    }

    /// The largest fluctuation of energy about the mean effort of driver
    /// `driver`.
    fn energy_fluctuation(&self, driver: &str) -> PyResult<f64> {
        Self::summary(
            self.sweep.energy_fluctuation(self.driver(driver)?),
            "energy fluctuation",
        )
    }

    /// The coefficient of speed fluctuation of driver `driver` with a
    /// flywheel of moment of inertia `inertia` at the mean speed `speed`.
    fn speed_fluctuation(&self, driver: &str, inertia: f64, speed: f64) -> PyResult<f64> {
        let k = self.driver(driver)?;
        if !(inertia * speed * speed > 0.0 && (inertia * speed * speed).is_finite()) {
            return Err(PyValueError::new_err(format!(
                "the flywheel's inertia and the mean speed must make I ω² positive and finite \
                 (I = {inertia}, ω = {speed})"
            )));
        }
        Self::summary(
            self.sweep.speed_fluctuation(k, inertia, speed),
            "speed fluctuation",
        )
    }

    /// The CSV text, a column per quantity with its unit.
    fn to_csv(&self) -> String {
        self.sweep.to_csv()
    }

    /// Writes the SVG plot of the driving effort beside its mean and the
    /// polar diagram of the shaking force to `path`.
    fn write_svg(&self, py: Python<'_>, path: std::path::PathBuf) -> PyResult<()> {
        kinematics_core::plot::plot_forces(&self.sweep, &path).map_err(|e| error(py, &e))
    }

    fn __len__(&self) -> usize {
        self.sweep.samples.len()
    }
}
