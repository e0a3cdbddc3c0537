//! Forward dynamics from Python: the motion that a definition's `bodies`
//! and `loads` produce from a start pose (`Dynamics::forward_of`), its
//! samples as a [`Sweep`] and its energies, works and efforts as numpy
//! arrays.

use kinematics_core::dynamics::{Ended, Event, Method};
use kinematics_core::runtime::SweepEnd;

use super::*;

/// The forward simulation of `model` from the pose `start` with the
/// drivers' starting `rates`: the drivers named in `free` (all of them
/// when empty) move under the loads until `until` seconds, `samples`
/// equal intervals, relative and absolute tolerance `tolerance`, ended by
/// the first of `events` (coordinate, of its rate, value, direction: 1
/// increasing, −1 decreasing, 0 either) that happens,
/// integrated by `method` ("explicit" or "implicit"), each step at most
/// `max_step` seconds where given.
/// Returns the samples as a sweep in time and a dict: "t", "kinetic",
/// "potential" (one per sample), "work" (samples × works), "work_names",
/// "effort" (samples × drivers), "ended" ("complete", "event", "failed" or
/// "step limit"), "event" (its index, or None), "at" (the time it ended),
/// "steps", "rejected", "evaluations", "compiled" and "summed" (the
/// evaluations of M and b by the model's compiled equations of motion
/// and by the sums over its bodies and loads) and "energy_error"; with
/// `sensitivities`, "parameters" (the definition's sensitivity
/// parameters) and "position_sensitivity" and "rate_sensitivity"
/// (samples × parameters × free drivers: ∂d_f/∂p and ∂ḋ_f/∂p); the
/// `stops` (coordinate, value, restitution) the motion bounces off, after
/// the events, and "impacts" (t, event index, rate before, rate after).
#[pyfunction]
#[pyo3(signature = (model, start, rates, free, until, samples, tolerance, events, method, max_step=None, sensitivities=false, stops=Vec::new(), opts=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn forward<'py>(
    py: Python<'py>,
    model: &Model,
    start: Vec<f64>,
    rates: Vec<f64>,
    free: Vec<String>,
    until: f64,
    samples: usize,
    tolerance: f64,
    events: Vec<(String, bool, f64, i8)>,
    method: &str,
    max_step: Option<f64>,
    sensitivities: bool,
    stops: Vec<(String, f64, f64)>,
    opts: Option<OptionsTuple>,
) -> PyResult<(Sweep, Bound<'py, PyDict>)> {
    let method = match method {
        "explicit" => Method::Explicit,
        "implicit" => Method::Implicit,
        other => {
            return Err(PyValueError::new_err(format!(
                "method={other:?}: give \"explicit\" (Dormand–Prince 5(4)) or \"implicit\" \
                 (TR-BDF2, for stiff motions)"
            )))
        }
    };
    let m = &model.model;
    let o = options(py, opts.as_ref())?;
    let dynamics = m.dynamics().map_err(|e| error(py, &e))?;
    let mut builder = dynamics
        .forward_of(m, &start)
        .rates(&rates)
        .until(until)
        .samples(samples)
        .tolerance(tolerance)
        .method(method)
        .options(&o);
    if let Some(h) = max_step {
        builder = builder.max_step(h);
    }
    if sensitivities {
        builder = builder.sensitivities();
    }
    for (name, value, restitution) in &stops {
        builder = builder.stop_when(Event::stop(name, *value, *restitution));
    }
    for name in &free {
        builder = builder.free(name);
    }
    for (name, rate, value, direction) in &events {
        let event = if *rate {
            Event::rate_reaches(name, *value)
        } else {
            Event::reaches(name, *value)
        };
        builder = builder.stop_when(match direction {
            1 => event.increasing(),
            -1 => event.decreasing(),
            _ => event,
        });
    }
    let run = py.detach(|| builder.run()).map_err(|e| error(py, &e))?;
    // The samples as a sweep's columns, from the motions the run solved.
    let nd = m.drivers();
    let n = run.sweep.samples.len();
    let mut columns = Columns::new(m, "t", kinematics_core::Kind::Length, n);
    for s in &run.sweep.samples {
        columns.push_motion(s.at, &s.motion);
    }
    columns.end(SweepEnd {
        stop: run.sweep.stop.clone(),
        change_points: Vec::new(),
    });
    let sweep = Sweep::new(py, columns, m.clone())?;
    let d = PyDict::new(py);
    let e = &run.energy;
    d.set_item("t", array(py, e.iter().map(|x| x.t).collect()))?;
    d.set_item("kinetic", array(py, e.iter().map(|x| x.kinetic).collect()))?;
    d.set_item(
        "potential",
        array(py, e.iter().map(|x| x.potential).collect()),
    )?;
    let nw = run.work_names.len();
    let work = e.iter().flat_map(|x| x.work.iter().copied()).collect();
    d.set_item("work", shaped(py, work, vec![e.len(), nw])?)?;
    d.set_item("work_names", run.work_names.clone())?;
    let effort = e.iter().flat_map(|x| x.effort.iter().copied()).collect();
    d.set_item("effort", shaped(py, effort, vec![e.len(), nd])?)?;
    let (ended, event, at) = match run.ended {
        Ended::Complete => ("complete", None, run.energy.last().map_or(0.0, |x| x.t)),
        Ended::Event { index, at } => ("event", Some(index), at),
        Ended::Failed { at } => ("failed", None, at),
        Ended::StepLimit { at } => ("step limit", None, at),
    };
    d.set_item("ended", ended)?;
    d.set_item("event", event)?;
    d.set_item("at", at)?;
    d.set_item("steps", run.statistics.steps)?;
    d.set_item("rejected", run.statistics.rejected)?;
    d.set_item("evaluations", run.statistics.evaluations)?;
    d.set_item("compiled", run.statistics.compiled)?;
    d.set_item("summed", run.statistics.summed)?;
    d.set_item("energy_error", run.energy_error())?;
    d.set_item("parameters", run.parameters.clone())?;
    let impacts: Vec<(f64, usize, f64, f64)> = run
        .impacts
        .iter()
        .map(|i| (i.t, i.event, i.before, i.after))
        .collect();
    d.set_item("impacts", impacts)?;
    let (np, nf) = (
        run.parameters.len(),
        run.sensitivities
            .first()
            .map_or(0, |s| s.position.len() / run.parameters.len().max(1)),
    );
    for (key, pick) in [("position_sensitivity", true), ("rate_sensitivity", false)] {
        let flat: Vec<f64> = run
            .sensitivities
            .iter()
            .flat_map(|s| {
                if pick {
                    s.position.clone()
                } else {
                    s.rate.clone()
                }
            })
            .collect();
        d.set_item(
            key,
            shaped(py, flat, vec![run.sensitivities.len(), np, nf])?,
        )?;
    }
    Ok((sweep, d))
}
