//! The integration of a forward simulation, written once for every kind
//! of model: the equations of motion as a [`System`], the output samples
//! from the dense output, the events located on it, and how a run ends.
//! A model takes part through [`Analysis`]: an assembly and analysis at
//! given drivers, and the equations at its current motion.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;

use super::eom::Eom;
use super::equations::Equations;
use super::ode::{Dopri, Solver, Stepped, System, Tolerances};
use super::stiff::TrBdf2;
use super::{Ended, Energy, Event, Impact, Method, Sensitivities, Statistics};
use crate::dynamics::Dynamics;
use crate::dynamics::evaluate::View;
use crate::dynamics::terms::Terms;
use crate::error::Error;
use crate::mechanism::FrameState;
use crate::options::Options;
use crate::sweep::{Stop, StopReason};

/// What the integration needs of a model.
pub(crate) trait Analysis {
    /// The prescribed drivers' values, rates and accelerations at time `t`
    /// (every driver's entry is written; the free ones are overwritten).
    fn profile(&mut self, t: f64, d: &mut [f64], dd: &mut [f64], ddd: &mut [f64]);
    /// Assembles at the drivers `d` from the last committed pose and
    /// analyses the motion with the drivers' rates `dd` and accelerations
    /// `ddd`: the current motion.
    ///
    /// # Errors
    /// The assembly's and the analysis' errors.
    fn analyze(&mut self, d: &[f64], dd: &[f64], ddd: &[f64]) -> Result<(), Error>;
    /// [`Analysis::analyze`] for an evaluation of the equations of motion,
    /// which reads the coordinates' motion and [`Analysis::equations`]
    /// only: a model may leave the points' outputs until the motion is
    /// read otherwise ([`Analysis::energies`], [`Analysis::record`]).
    ///
    /// # Errors
    /// As [`Analysis::analyze`].
    fn analyze_for_equations(&mut self, d: &[f64], dd: &[f64], ddd: &[f64]) -> Result<(), Error> {
        self.analyze(d, dd, ddd)
    }
    /// The equations of motion at the current motion, at time `t`.
    ///
    /// # Errors
    /// As [`Dynamics::equations`].
    fn equations(
        &mut self,
        dynamics: &Dynamics,
        t: f64,
        out: &mut Equations<'_>,
    ) -> Result<(), Error>;
    /// How many evaluations of [`Analysis::equations`] the model's
    /// compiled equations of motion gave, and how many summed the bodies
    /// and loads.
    fn equation_counts(&self) -> [usize; 2] {
        [0, 0]
    }
    /// T and V at the current motion.
    ///
    /// # Errors
    /// As [`Dynamics::inverse`].
    fn energies(&mut self, dynamics: &Dynamics, t: f64) -> Result<(f64, f64), Error>;
    /// q, q̇ and q̈ of coordinate j at the current motion.
    fn coordinate(&mut self, j: usize) -> [f64; 3];
    /// Makes the current motion the start of the next assemblies.
    fn commit(&mut self);
    /// Keeps the current motion as the output sample at time `t`.
    fn record(&mut self, t: f64);
    /// ∂Q_k/∂p of every driver at the current motion, the drivers' motion
    /// held, for each sensitivity parameter, into `out` (parameter-major).
    ///
    /// # Errors
    /// As [`Dynamics::effort_sensitivities`]; the model offers none.
    fn effort_partials(
        &mut self,
        dynamics: &Dynamics,
        t: f64,
        out: &mut [f64],
    ) -> Result<(), Error> {
        let _ = (dynamics, t, out);
        Err(Error::InvalidDynamics {
            item: "sensitivities of the trajectory".to_string(),
            detail: "this kind of model gives no partial derivatives of its efforts".to_string(),
        })
    }
}

/// A motion's view at a time, for the loads that read it.
pub(crate) struct Timed<'a>(pub(crate) &'a dyn View, pub(crate) f64);

impl View for Timed<'_> {
    fn point(&self, i: usize) -> Option<[nalgebra::Vector3<f64>; 3]> {
        self.0.point(i)
    }
    fn velocity(&self, i: usize) -> Option<nalgebra::Vector3<f64>> {
        self.0.velocity(i)
    }
    fn acceleration(&self, i: usize) -> Option<nalgebra::Vector3<f64>> {
        self.0.acceleration(i)
    }
    fn rate(&self, j: usize) -> f64 {
        self.0.rate(j)
    }
    fn frame(&self, i: usize) -> Option<&FrameState> {
        self.0.frame(i)
    }
    fn coordinate(&self, j: usize) -> [f64; 3] {
        self.0.coordinate(j)
    }
    fn time(&self) -> f64 {
        self.1
    }
}

/// What a forward simulation is asked for, before it is checked: the
/// part of its builder that is the same for every kind of model.
#[derive(Clone, Debug)]
pub(crate) struct Course {
    /// The free drivers (`None`: every driver).
    pub(crate) free: Option<Vec<usize>>,
    pub(crate) until: f64,
    pub(crate) intervals: usize,
    pub(crate) relative: f64,
    pub(crate) absolute: Option<[f64; 2]>,
    pub(crate) max_step: f64,
    pub(crate) max_steps: usize,
    pub(crate) events: Vec<Event>,
    pub(crate) options: Options,
    pub(crate) method: Method,
}

impl Default for Course {
    fn default() -> Self {
        Course {
            free: None,
            until: 1.0,
            intervals: 100,
            relative: 1e-9,
            absolute: None,
            max_step: f64::INFINITY,
            max_steps: 10_000_000,
            events: Vec::new(),
            options: Options::DEFAULT,
            method: Method::Explicit,
        }
    }
}

/// The setters of a forward simulation's builder, written once for the
/// builders of both kinds of model (each has a field `course`).
macro_rules! course_settings {
    () => {
        /// The end time (s).
        pub fn until(mut self, seconds: f64) -> Self {
            self.course.until = seconds;
            self
        }

        /// The number of equal intervals between output samples (`n + 1`
        /// samples from 0 to the end time, each a full analysis with the
        /// accelerations of the equations of motion).
        pub fn samples(mut self, n: usize) -> Self {
            self.course.intervals = n;
            self
        }

        /// The relative tolerance of the local error, also the absolute
        /// one unless `absolute` sets those.
        pub fn tolerance(mut self, relative: f64) -> Self {
            self.course.relative = relative;
            self
        }

        /// The absolute tolerances of the free drivers' positions (m or
        /// rad) and velocities (m/s or rad/s).
        pub fn absolute(mut self, position: f64, velocity: f64) -> Self {
            self.course.absolute = Some([position, velocity]);
            self
        }

        /// The largest step (s), for loads that change faster than the
        /// motion shows.
        pub fn max_step(mut self, seconds: f64) -> Self {
            self.course.max_step = seconds;
            self
        }

        /// The most steps taken before the run ends with
        /// [`Ended::StepLimit`](crate::dynamics::Ended::StepLimit) (ten
        /// million by default).
        pub fn max_steps(mut self, steps: usize) -> Self {
            self.course.max_steps = steps;
            self
        }

        /// Ends the run when `event` happens (the first of those given).
        pub fn stop_when(mut self, event: crate::dynamics::Event) -> Self {
            self.course.events.push(event);
            self
        }

        /// The options of the assemblies.
        pub fn options(mut self, options: &crate::Options) -> Self {
            self.course.options = *options;
            self
        }

        /// The integrator: the explicit Dormand–Prince pair (the default)
        /// or, for a stiff motion, the implicit TR-BDF2
        /// ([`Method`](crate::dynamics::Method)).
        pub fn method(mut self, method: crate::dynamics::Method) -> Self {
            self.course.method = method;
            self
        }
    };
}
pub(crate) use course_settings;

impl Course {
    /// Frees driver `k` (the first call makes the others prescribed).
    pub(crate) fn free(&mut self, k: usize) {
        let list = self.free.get_or_insert_with(Vec::new);
        if !list.contains(&k) {
            list.push(k);
        }
    }

    /// The free drivers and the settings, checked against the coordinates'
    /// `names` and the number of drivers.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a value out of its range;
    /// [`Error::InvalidDynamics`] for an event on no coordinate, or no
    /// free driver.
    pub(crate) fn settings(
        &self,
        names: &[&str],
        drivers: usize,
    ) -> Result<(Vec<usize>, Settings), Error> {
        let free = self.free.clone().unwrap_or_else(|| (0..drivers).collect());
        if let Some(k) = free.iter().find(|&&k| k >= drivers) {
            return Err(Error::InvalidDynamics {
                item: "forward simulation".to_string(),
                detail: format!("driver {k} is freed, but the mechanism has {drivers} drivers"),
            });
        }
        if free.is_empty() {
            return Err(Error::InvalidDynamics {
                item: "forward simulation".to_string(),
                detail: "no driver moves freely: free one, or use a kinematic simulation for \
                         a motion that is all prescribed"
                    .to_string(),
            });
        }
        let events = self
            .events
            .iter()
            .map(|e| {
                let item = format!("event on `{}`", e.coordinate);
                let j = names
                    .iter()
                    .position(|n| *n == e.coordinate)
                    .ok_or_else(|| Error::InvalidDynamics {
                        item: item.clone(),
                        detail: format!(
                            "the mechanism has no coordinate `{}` (its coordinates: {})",
                            e.coordinate,
                            names.join(", ")
                        ),
                    })?;
                if !e.value.is_finite() {
                    return Err(Error::InvalidDynamics {
                        item,
                        detail: format!("its value {} must be finite", e.value),
                    });
                }
                if let Some(r) = e.restitution
                    && !(0.0..=1.0).contains(&r)
                {
                    return Err(Error::InvalidDynamics {
                        item,
                        detail: format!(
                            "its coefficient of restitution {r} must be between 0 (plastic) and \
                             1 (elastic)"
                        ),
                    });
                }
                Ok((j, e.rate, e.value))
            })
            .collect::<Result<Vec<_>, Error>>()?;
        let range = |name, value: f64, ok: bool, requirement| {
            if ok {
                Ok(())
            } else {
                Err(Error::InvalidOption {
                    name,
                    value,
                    requirement,
                })
            }
        };
        let (until, relative) = (self.until, self.relative);
        range(
            "until",
            until,
            until.is_finite() && until > 0.0,
            "must be positive and finite (seconds)",
        )?;
        range(
            "tolerance",
            relative,
            relative > 0.0 && relative < 1.0,
            "must be between 0 and 1",
        )?;
        let absolute = self.absolute.unwrap_or([relative; 2]);
        for (name, v) in [
            ("absolute tolerance of the positions", absolute[0]),
            ("absolute tolerance of the velocities", absolute[1]),
        ] {
            range(
                name,
                v,
                v > 0.0 && v.is_finite(),
                "must be positive and finite",
            )?;
        }
        range(
            "max_step",
            self.max_step,
            self.max_step > 1e-9 * until,
            "must be positive, above a billionth of the end time",
        )?;
        #[allow(clippy::cast_precision_loss)]
        range(
            "samples",
            self.intervals as f64,
            self.intervals > 0 && self.intervals <= MAX_INTERVALS,
            "must be at least 1 and at most 100 000 000 (each sample is a full analysis)",
        )?;
        Ok((
            free,
            Settings {
                until,
                intervals: self.intervals,
                relative,
                absolute,
                max_step: self.max_step,
                max_steps: self.max_steps,
                events,
                directions: self.events.iter().map(|e| e.direction).collect(),
                restitution: self.events.iter().map(|e| e.restitution).collect(),
                method: self.method,
                parameters: 0,
            },
        ))
    }
}

/// The free drivers' values and rates at the start, from every driver's
/// (`drivers`: their values and rates), checked: finite, and no rate
/// given for a prescribed driver (its profile gives it).
///
/// # Errors
/// [`Error::InvalidOption`] for a value or rate not finite,
/// [`Error::InvalidDynamics`] for a rate of a prescribed driver.
pub(crate) fn start_state(
    (values, rates): (&[f64], &[f64]),
    free: &[usize],
    names: &[&str],
) -> Result<(Vec<f64>, Vec<f64>), Error> {
    if let Some((k, r)) = rates
        .iter()
        .enumerate()
        .find(|(k, r)| **r != 0.0 && !free.contains(k))
    {
        let name = names.get(k).copied().unwrap_or("?");
        return Err(Error::InvalidDynamics {
            item: format!("the rate of `{name}`"),
            detail: format!(
                "is given as {r}, but `{name}` is not free: a prescribed driver moves as its \
                 profile says (held at its start value without one); free it, or give its \
                 motion as a profile"
            ),
        });
    }
    let pick = |v: &[f64]| -> Vec<f64> {
        free.iter()
            .map(|&k| v.get(k).copied().unwrap_or(0.0))
            .collect()
    };
    let (d0, r0) = (pick(values), pick(rates));
    if let Some(v) = d0.iter().chain(&r0).find(|v| !v.is_finite()) {
        return Err(Error::InvalidOption {
            name: "start",
            value: *v,
            requirement: "the free drivers' values and rates must be finite",
        });
    }
    Ok((d0, r0))
}

/// The names of a run's works: the loads', then `driver d` for each
/// prescribed driver, then `impacts at q` for each stop (`coordinates`
/// every coordinate's name, drivers first; `drivers` their number).
fn work_names(
    dynamics: &Dynamics,
    (free, drivers): (&[usize], usize),
    coordinates: &[&str],
    settings: &Settings,
) -> Vec<String> {
    let mut names = dynamics.working_load_names();
    for (k, name) in coordinates.iter().take(drivers).enumerate() {
        if !free.contains(&k) {
            names.push(format!("driver {name}"));
        }
    }
    for (&(j, _, _), r) in settings.events.iter().zip(&settings.restitution) {
        if r.is_some() {
            names.push(format!("impacts at {}", coordinates.get(j).unwrap_or(&"?")));
        }
    }
    names
}

/// The most output intervals a run takes.
const MAX_INTERVALS: usize = 100_000_000;

/// What a run was asked for.
pub(crate) struct Settings {
    pub(crate) until: f64,
    /// The number of equal intervals between the output samples.
    pub(crate) intervals: usize,
    pub(crate) relative: f64,
    /// The absolute tolerances of the positions and of the velocities.
    pub(crate) absolute: [f64; 2],
    pub(crate) max_step: f64,
    pub(crate) max_steps: usize,
    /// (coordinate, of its rate, value).
    pub(crate) events: Vec<(usize, bool, f64)>,
    /// Per event, the direction it counts in (1 increasing, −1
    /// decreasing, 0 either).
    pub(crate) directions: Vec<i8>,
    /// Per event, its coefficient of restitution where it is a stop.
    pub(crate) restitution: Vec<Option<f64>>,
    pub(crate) method: Method,
    /// The number of sensitivity parameters whose ∂/∂p of the trajectory
    /// is integrated (0: none).
    pub(crate) parameters: usize,
}

/// How a run went, besides its samples.
pub(crate) struct Outcome {
    pub(crate) energy: Vec<Energy>,
    /// The names of the works of each [`Energy`].
    pub(crate) work_names: Vec<String>,
    pub(crate) ended: Ended,
    /// Why it stopped before its end, where it failed: the sweep's stop.
    pub(crate) stop: Option<Stop>,
    pub(crate) statistics: Statistics,
    /// The impacts at the stops.
    pub(crate) impacts: Vec<Impact>,
    /// At each sample, the sensitivities of the free drivers' motion
    /// (empty unless asked).
    pub(crate) sensitivities: Vec<Sensitivities>,
}

/// Integrates from the committed start pose of `analysis`, the free
/// drivers `free` at `d0` with rates `rates0`, recording the samples.
pub(crate) fn integrate<A: Analysis>(
    analysis: A,
    dynamics: &Dynamics,
    (free, coordinates): (Vec<usize>, &[&str]),
    y0: (&[f64], &[f64]),
    settings: &Settings,
) -> Result<(A, Outcome), Error> {
    if settings.parameters > 0 && settings.method == Method::Implicit {
        return Err(Error::InvalidDynamics {
            item: "sensitivities of the trajectory".to_string(),
            detail: "are integrated with the explicit method only (TR-BDF2 iterates on the \
                     motion, not on its sensitivities): drop `Method::Implicit`, or the \
                     sensitivities"
                .to_string(),
        });
    }
    let nd = dynamics.drivers;
    let nf = free.len();
    let prescribed: Vec<usize> = (0..nd).filter(|k| !free.contains(k)).collect();
    let nw = dynamics.working_loads();
    let mut eom = Eom {
        analysis,
        dynamics,
        nd,
        d: vec![0.0; nd],
        dd: vec![0.0; nd],
        ddd: vec![0.0; nd],
        mass: vec![0.0; nd * nd],
        bias: vec![0.0; nd],
        powers: vec![0.0; nw],
        partials: vec![[nalgebra::Vector3::zeros(); 2]; nd * dynamics.body_count()],
        terms: Terms::default(),
        effort: vec![0.0; nd],
        names: coordinates.iter().map(|n| String::from(*n)).collect(),
        mff: vec![0.0; nf * nf],
        x: vec![0.0; nf],
        parameters: settings.parameters,
        effort_partials: vec![0.0; nd * settings.parameters],
        jacobian: vec![0.0; 2 * nf * nf],
        scratch: Vec::with_capacity(2 * nf),
        recorded: Vec::new(),
        stops: settings.restitution.iter().flatten().count(),
        lean: free.len() == 1 && prescribed.is_empty() && settings.parameters == 0,
        free,
        prescribed,
    };
    let n = eom.len();
    let mut y = vec![0.0; n];
    y[..nf].copy_from_slice(y0.0);
    y[nf..2 * nf].copy_from_slice(y0.1);
    let mut energy = Vec::with_capacity(settings.intervals.min(1 << 16) + 2);
    // The start: assembled from the given pose, its sample the first.
    energy.push(emit(&mut eom, 0.0, &y)?);
    eom.analysis.commit();
    let values = |eom: &mut Eom<'_, A>| -> Vec<f64> {
        settings
            .events
            .iter()
            .map(|&(j, rate, v)| eom.analysis.coordinate(j)[usize::from(rate)] - v)
            .collect()
    };
    let mut previous = values(&mut eom);
    let mut absolute = vec![settings.absolute[0]; nf];
    absolute.extend(core::iter::repeat_n(settings.absolute[1], nf));
    let tolerances = Tolerances {
        relative: settings.relative,
        absolute,
    };
    // A solver from (t0, y0): at the start, and again after an impact.
    let start = |eom: &mut Eom<'_, A>, t0: f64, y0: &[f64]| -> Result<Solver, Error> {
        let tolerances = tolerances.clone();
        let h = settings.max_step.min(settings.until - t0);
        Ok(match settings.method {
            Method::Explicit => Solver::Explicit(Dopri::new(eom, t0, y0, tolerances, h)?),
            Method::Implicit => Solver::Implicit(TrBdf2::new(eom, t0, y0, tolerances, h)?),
        })
    };
    let mut ode = start(&mut eom, 0.0, &y)?;
    // The counts of the solvers before the last impact, and the impacts.
    let mut counted = [0usize; 3];
    let mut impacts: Vec<Impact> = Vec::new();
    #[allow(clippy::cast_precision_loss)]
    let output = |k: usize| {
        if k == settings.intervals {
            settings.until
        } else {
            settings.until * (k as f64) / (settings.intervals as f64)
        }
    };
    let mut next = 1;
    let mut failure = None;
    // The interpolated state of an output sample or an event.
    let mut out = vec![0.0; n];
    let ended = loop {
        if ode.t() >= settings.until {
            break Ended::Complete;
        }
        if ode.counts()[0] + counted[0] >= settings.max_steps {
            break Ended::StepLimit { at: ode.t() };
        }
        if ode.step(&mut eom, settings.until) == Stepped::TooSmall {
            let at = ode.t();
            let e = ode.refused().unwrap_or_else(|| Error::InvalidDynamics {
                item: "forward simulation".to_string(),
                detail: format!(
                    "the step size fell below the resolution of the time at t = {at}: the \
                     motion is not smooth there (an impact, a load that jumps), or the \
                     tolerance is too tight for f64"
                ),
            });
            failure = Some((at, e));
            break Ended::Failed { at };
        }
        // The last evaluation was at the end of the step.
        eom.analysis.commit();
        let now = values(&mut eom);
        // Every event that changed sign in the step, located; the
        // earliest ends the run (the lowest index at a tie).
        let mut limit: Option<(usize, f64)> = None;
        for (i, (a, b)) in previous.iter().zip(&now).enumerate() {
            // From a < 0 increasing, from a > 0 decreasing.
            let direction = settings.directions.get(i).copied().unwrap_or(0);
            let counts = match direction {
                1 => *a < 0.0,
                -1 => *a > 0.0,
                _ => true,
            };
            if counts && *a != 0.0 && a * b <= 0.0 {
                let t = locate(&mut eom, &ode, settings.events[i], *a, *b);
                if limit.is_none_or(|(_, at)| t < at) {
                    limit = Some((i, t));
                }
            }
        }
        let upto = limit.map_or(ode.t(), |(_, t)| t);
        while next <= settings.intervals && output(next) <= upto {
            let t = output(next);
            let state = if t == ode.t() {
                ode.y()
            } else {
                ode.interpolate(t, &mut out);
                &out
            };
            match emit(&mut eom, t, state) {
                Ok(e) => energy.push(e),
                Err(e) => {
                    failure = Some((t, e));
                    break;
                }
            }
            next += 1;
        }
        if let Some((t, _)) = failure {
            break Ended::Failed { at: t };
        }
        if let Some((index, at)) = limit
            && let Some(e) = settings.restitution[index]
        {
            // A stop: the impact, then the run goes on from it.
            ode.interpolate(at, &mut out);
            let (j, _, _) = settings.events[index];
            let slot = eom.stop_offset() + settings.restitution[..index].iter().flatten().count();
            match eom.impact(at, &mut out, (j, e, slot)) {
                Ok((before, after)) => impacts.push(Impact {
                    t: at,
                    event: index,
                    before,
                    after,
                }),
                Err(e) => {
                    failure = Some((at, e));
                    break Ended::Failed { at };
                }
            }
            eom.analysis.commit();
            let first = impacts.first().map_or(0.0, |i| i.before.abs());
            let last = impacts.last().map_or(0.0, |i| i.after.abs());
            if last <= 1e-9 * first || impacts.len() >= 1000 {
                // At rest at the stop.
                if let Ok(e) = emit(&mut eom, at, &out) {
                    energy.push(e);
                }
                break Ended::Event { index, at };
            }
            for (c, n) in counted.iter_mut().zip(ode.counts()) {
                *c += n;
            }
            ode = match start(&mut eom, at, &out) {
                Ok(s) => s,
                Err(e) => {
                    failure = Some((at, e));
                    break Ended::Failed { at };
                }
            };
            eom.analysis.commit();
            previous = values(&mut eom);
            continue;
        }
        if let Some((index, at)) = limit {
            if next > settings.intervals || output(next - 1) < at {
                ode.interpolate(at, &mut out);
                match emit(&mut eom, at, &out) {
                    Ok(e) => energy.push(e),
                    Err(e) => {
                        failure = Some((at, e));
                        break Ended::Failed { at };
                    }
                }
            }
            break Ended::Event { index, at };
        }
        previous = now;
    };
    let [steps, rejected, evaluations] = ode.counts();
    let statistics = Statistics {
        steps: steps + counted[0],
        rejected: rejected + counted[1],
        evaluations: evaluations + counted[2],
        compiled: eom.analysis.equation_counts()[0],
        summed: eom.analysis.equation_counts()[1],
    };
    let stop = failure.map(|(at, e)| Stop {
        variable: "t",
        at,
        reason: StopReason::from_error(e),
    });
    let sensitivities = energy
        .iter()
        .zip(&eom.recorded)
        .map(|(e, s)| Sensitivities::from_state(e.t, s, nf))
        .collect();
    let work_names = work_names(dynamics, (&eom.free, nd), coordinates, settings);
    Ok((
        eom.analysis,
        Outcome {
            energy,
            work_names,
            ended,
            stop,
            statistics,
            impacts,
            sensitivities,
        },
    ))
}

/// The output sample at (t, y): the accelerations from the equations of
/// motion, the motion analysed with them and recorded, its energies.
fn emit<A: Analysis>(eom: &mut Eom<'_, A>, t: f64, y: &[f64]) -> Result<Energy, Error> {
    let nf = eom.free.len();
    let mut dy = vec![0.0; eom.len()];
    eom.rhs(t, y, &mut dy)?;
    let effort = eom.effort.clone();
    for (i, &k) in eom.free.iter().enumerate() {
        eom.ddd[k] = dy[nf + i];
    }
    eom.analysis.analyze(&eom.d, &eom.dd, &eom.ddd)?;
    let (kinetic, potential) = eom.analysis.energies(eom.dynamics, t)?;
    eom.analysis.record(t);
    let at = eom.sensitivity_offset();
    if eom.parameters > 0 {
        eom.recorded.push(y[at..].to_vec());
    }
    Ok(Energy {
        t,
        kinetic,
        potential,
        work: y[2 * nf..at].to_vec(),
        effort,
    })
}

/// The time in the last step at which the event `(j, rate, value)`
/// crosses, its values `ga` at the step's start and `gb` at its end, by
/// the Illinois method on the dense output (each trial an assembly).
fn locate<A: Analysis>(
    eom: &mut Eom<'_, A>,
    ode: &Solver,
    (j, rate, value): (usize, bool, f64),
    ga: f64,
    gb: f64,
) -> f64 {
    let (mut a, mut b) = (ode.t_old(), ode.t());
    let (mut fa, mut fb) = (ga, gb);
    if fb == 0.0 {
        return b;
    }
    let mut y = vec![0.0; eom.len()];
    let mut side = 0i8;
    for _ in 0..100 {
        if b - a <= 4.0 * f64::EPSILON * b.abs().max(1.0) {
            break;
        }
        let mut t = (a * fb - b * fa) / (fb - fa);
        if !(t > a && t < b) {
            t = 0.5 * (a + b);
        }
        ode.interpolate(t, &mut y);
        eom.set_drivers(t, &y);
        if eom.analysis.analyze(&eom.d, &eom.dd, &eom.ddd).is_err() {
            // Past a limit: the crossing is before it.
            b = t;
            continue;
        }
        let f = eom.analysis.coordinate(j)[usize::from(rate)] - value;
        if f == 0.0 {
            return t;
        }
        if f * fa < 0.0 {
            (b, fb) = (t, f);
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            (a, fa) = (t, f);
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    b
}
