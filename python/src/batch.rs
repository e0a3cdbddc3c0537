//! Batches of designs of one model, run on every core with the
//! interpreter released: for each design a step at one pose or a sweep,
//! of which only the outputs asked for are kept, as arrays with a row per
//! design.

use kinematics_core::runtime::{Flat, Model, Motion};
use kinematics_core::sweep::ChangePoints;
use kinematics_core::{Error, Options};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{array, shaped};

/// The sweep each design of a batch runs.
pub(crate) struct SweepSpec {
    pub driver: &'static str,
    /// The driver's index among the coordinates.
    pub index: usize,
    pub from: Option<f64>,
    pub to: Option<f64>,
    pub turns: Option<f64>,
    pub steps: usize,
    pub change: ChangePoints,
}

impl SweepSpec {
    /// The samples of a sweep that runs to its end: steps + 1 with a
    /// given end (included), else steps (a whole turn leaves its end out).
    fn count(&self) -> usize {
        self.steps.max(1) + usize::from(self.to.is_some())
    }
}

/// What every design of a batch runs, and what is kept of it: outputs
/// are (kind, index) with kind "q", "qd", "qdd" (a coordinate), "position",
/// "velocity", "acceleration" (a point) or "conditioning".
pub(crate) struct Job<'a> {
    pub model: &'a Model,
    pub start: &'a [f64],
    pub rates: &'a [f64],
    pub accelerations: &'a [f64],
    pub sweep: Option<SweepSpec>,
    pub outputs: &'a [(String, usize)],
    pub options: Options,
    pub dim: usize,
}

/// One design's result: its outputs (each sample's values in a row), the
/// number of samples, and the stop or error that ended it early.
pub(crate) struct Outcome {
    values: Vec<Vec<f64>>,
    samples: usize,
    stop: Option<String>,
}

impl Job<'_> {
    fn width(&self, kind: &str) -> usize {
        match kind {
            "position" | "velocity" | "acceleration" => self.dim,
            _ => 1,
        }
    }

    fn rows(&self) -> usize {
        self.sweep.as_ref().map_or(1, SweepSpec::count)
    }

    fn keep(&self, m: &Motion, values: &mut [Vec<f64>]) {
        self.keep_values(
            (&m.q, &m.qd, &m.qdd, m.conditioning),
            |i, k| {
                m.points
                    .get(i)
                    .map(|p| [&p.position, &p.velocity, &p.acceleration][k].as_slice())
            },
            values,
        );
    }

    /// [`Job::keep`] of a sample as flat arrays.
    fn keep_flat(&self, m: &Flat<'_>, values: &mut [Vec<f64>]) {
        let d = self.dim;
        self.keep_values(
            (m.q, m.qd, m.qdd, m.conditioning),
            |i, k| m.outputs.get((3 * i + k) * d..(3 * i + k + 1) * d),
            values,
        );
    }

    /// Appends the outputs asked for to `values`, from q, q', q'', the
    /// conditioning and point i's position (k = 0), velocity (1) or
    /// acceleration (2).
    fn keep_values<'a>(
        &self,
        (q, qd, qdd, conditioning): (&[f64], &[f64], &[f64], f64),
        point: impl Fn(usize, usize) -> Option<&'a [f64]>,
        values: &mut [Vec<f64>],
    ) {
        for ((kind, i), out) in self.outputs.iter().zip(values) {
            match kind.as_str() {
                "q" => out.push(q.get(*i).copied().unwrap_or(f64::NAN)),
                "qd" => out.push(qd.get(*i).copied().unwrap_or(f64::NAN)),
                "qdd" => out.push(qdd.get(*i).copied().unwrap_or(f64::NAN)),
                "position" | "velocity" | "acceleration" => {
                    let k = match kind.as_str() {
                        "position" => 0,
                        "velocity" => 1,
                        _ => 2,
                    };
                    match point(*i, k) {
                        Some(v) => out.extend_from_slice(v),
                        None => out.extend(core::iter::repeat_n(f64::NAN, self.dim)),
                    }
                }
                _ => out.push(conditioning),
            }
        }
    }

    /// Runs the design with parameter values `values`.
    pub(crate) fn run(&self, values: &[f64]) -> Outcome {
        let mut kept: Vec<Vec<f64>> = self
            .outputs
            .iter()
            .map(|(k, _)| Vec::with_capacity(self.rows() * self.width(k)))
            .collect();
        let failed = |e: Error, kept| Outcome {
            values: kept,
            samples: 0,
            stop: Some(e.to_string()),
        };
        let model = match self.model.with_values(values) {
            Ok(m) => m,
            Err(e) => return failed(e, kept),
        };
        let Some(spec) = &self.sweep else {
            return match model.step(self.start, self.rates, self.accelerations) {
                Ok(m) => {
                    self.keep(&m, &mut kept);
                    Outcome {
                        values: kept,
                        samples: 1,
                        stop: None,
                    }
                }
                Err(e) => failed(e, kept),
            };
        };
        let builder = match model.sweep(spec.driver, self.start) {
            Ok(b) => b,
            Err(e) => return failed(e, kept),
        };
        let j = spec.index;
        let mut builder = builder
            .steps(spec.steps)
            .rate(self.rates.get(j).copied().unwrap_or(0.0))
            .acceleration(self.accelerations.get(j).copied().unwrap_or(0.0))
            .options(&self.options)
            .change_points(spec.change);
        if let Some(f) = spec.from {
            builder = builder.from(f);
        }
        builder = match (spec.to, spec.turns) {
            (Some(t), _) => builder.to(t),
            (None, Some(n)) => builder.turns(n),
            (None, None) => builder,
        };
        let mut samples = 0;
        let end = builder.for_each_flat(|_, sample| {
            self.keep_flat(sample, &mut kept);
            samples += 1;
        });
        Outcome {
            values: kept,
            samples,
            stop: end.stop.map(|s| s.to_string()),
        }
    }
}

/// The outcomes as a dict: "outputs", a list with an array per output of
/// shape (designs, samples) or (designs, samples, dim) for a sweep,
/// (designs,) or (designs, dim) for a step, NaN past the samples a design
/// has; "samples", the count per design; "stops", the message of the stop
/// or error that ended each design early, or None.
pub(crate) fn gather<'py>(
    py: Python<'py>,
    job: &Job<'_>,
    outcomes: Vec<Outcome>,
) -> PyResult<Bound<'py, PyDict>> {
    let designs = outcomes.len();
    let rows = job.rows();
    let mut outputs = Vec::with_capacity(job.outputs.len());
    for (k, (kind, _)) in job.outputs.iter().enumerate() {
        let width = job.width(kind);
        let mut flat = vec![f64::NAN; designs * rows * width];
        for (d, o) in outcomes.iter().enumerate() {
            let v = &o.values[k];
            let at = d * rows * width;
            let n = v.len().min(rows * width);
            flat[at..at + n].copy_from_slice(&v[..n]);
        }
        let mut shape = vec![designs];
        if job.sweep.is_some() {
            shape.push(rows);
        }
        if width > 1 {
            shape.push(width);
        }
        outputs.push(shaped(py, flat, shape)?);
    }
    let d = PyDict::new(py);
    d.set_item("outputs", outputs)?;
    d.set_item(
        "samples",
        array(py, outcomes.iter().map(|o| o.samples as f64).collect()),
    )?;
    d.set_item(
        "stops",
        outcomes.into_iter().map(|o| o.stop).collect::<Vec<_>>(),
    )?;
    Ok(d)
}
