//! Forward dynamics of a model defined at run time: the builder
//! ([`Dynamics::forward_of`]) and the model's part in the one
//! integration of [`crate::dynamics::forward`], through a stepper.

use alloc::format;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use super::sweep::{Sample, sweep_of};
use super::{Model, Stepper, Sweep, SweepEnd};
use crate::dynamics::Dynamics;
use crate::dynamics::evaluate::WithUnit;
use crate::dynamics::forward::equations::Equations;
use crate::dynamics::forward::run::{
    Analysis, Course, Timed, course_settings, integrate, start_state,
};
use crate::dynamics::forward::{Ended, Energy, Impact, Sensitivities, Statistics};
use crate::error::Error;
use crate::mechanism::Kind;

/// A forward simulation of a run-time model, built by
/// [`Dynamics::forward_of`]; the settings of
/// [`Forward`](crate::dynamics::Forward), the drivers by index or name.
#[must_use = "a forward simulation does nothing until it is run"]
pub struct ForwardOf<'a, P> {
    dynamics: &'a Dynamics,
    m: &'a Model,
    start: Vec<f64>,
    rates: Vec<f64>,
    profile: P,
    course: Course,
    /// A driver named to be freed that the model does not have.
    unknown: Option<String>,
    /// Whether the sensitivities of the trajectory are integrated.
    sensitivities: bool,
}

impl core::fmt::Debug for ForwardOf<'_, super::ProfileFn> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ForwardOf")
            .field("start", &self.start)
            .finish_non_exhaustive()
    }
}

/// The result of a run-time model's forward simulation, as
/// [`Trajectory`](crate::dynamics::Trajectory) for a generated one.
#[derive(Debug, Clone)]
pub struct TrajectoryOf {
    /// The samples, a sweep in time.
    pub sweep: Sweep,
    /// The energies and works at each sample.
    pub energy: Vec<Energy>,
    /// The names of the works.
    pub work_names: Vec<String>,
    /// The impacts at the stops, in order.
    pub impacts: Vec<Impact>,
    /// The sensitivity parameters ([`ForwardOf::sensitivities`]; empty
    /// unless asked).
    pub parameters: Vec<String>,
    /// At each sample, the sensitivities of the free drivers' positions
    /// and rates to each of `parameters`.
    pub sensitivities: Vec<Sensitivities>,
    /// How it ended.
    pub ended: Ended,
    /// Steps and evaluations.
    pub statistics: Statistics,
}

impl TrajectoryOf {
    /// The largest change of T + V − Σ W, relative
    /// ([`Trajectory::energy_error`](crate::dynamics::Trajectory::energy_error)).
    #[must_use]
    pub fn energy_error(&self) -> f64 {
        crate::dynamics::forward::energy_error(&self.energy)
    }
}

fn at_rest(_: f64, _: &mut [f64], _: &mut [f64], _: &mut [f64]) {}

impl Dynamics {
    /// [`Dynamics::forward`] for a model defined at run time, from the
    /// pose `start` (drivers, then guesses of the unknowns).
    ///
    /// ```
    /// use kinematics_core::dynamics::{Body, Dynamics};
    /// use kinematics_core::runtime::Model;
    /// let m = Model::compile(
    ///     "struct Swing { params { r } drivers { phi } unknowns { } points { G = polar(r, phi); } }",
    /// )?
    /// .with_values(&[1.0])?;
    /// let dynamics = Dynamics::builder()
    ///     .body(Body::new("bob", 1.0).center("G").angle("phi"))
    ///     .gravity([0.0, -9.81, 0.0])
    ///     .build_for(&m)?;
    /// // From horizontal, at rest: at the bottom its speed is √(2 g l).
    /// let run = dynamics.forward_of(&m, &[0.0]).until(0.4).tolerance(1e-10).run()?;
    /// let e = run.energy.last().unwrap();
    /// assert!(run.energy_error() < 1e-9 && e.kinetic > 0.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn forward_of<'a>(
        &'a self,
        m: &'a Model,
        start: &[f64],
    ) -> ForwardOf<'a, super::ProfileFn> {
        ForwardOf {
            dynamics: self,
            m,
            start: start.to_vec(),
            rates: vec![0.0; m.drivers()],
            profile: at_rest,
            course: Course::default(),
            unknown: None,
            sensitivities: false,
        }
    }
}

impl<'a, P: FnMut(f64, &mut [f64], &mut [f64], &mut [f64])> ForwardOf<'a, P> {
    /// Moves the driver named `driver` freely (the first call makes the
    /// others prescribed, unless they are freed too).
    pub fn free(mut self, driver: &str) -> Self {
        match self.m.index(driver).filter(|&k| k < self.m.drivers()) {
            Some(k) => self.course.free(k),
            None => self.unknown = Some(driver.into()),
        }
        self
    }

    /// The drivers' rates at the start (the free ones' are read).
    pub fn rates(mut self, rates: &[f64]) -> Self {
        self.rates = rates.to_vec();
        self
    }

    /// The prescribed drivers' motion: `profile(t, d, d', d'')` writes the
    /// drivers' values (the start's until written), rates and
    /// accelerations (zero until written) at time t.
    pub fn profile<Q: FnMut(f64, &mut [f64], &mut [f64], &mut [f64])>(
        self,
        profile: Q,
    ) -> ForwardOf<'a, Q> {
        ForwardOf {
            dynamics: self.dynamics,
            m: self.m,
            start: self.start,
            rates: self.rates,
            profile,
            course: self.course,
            unknown: self.unknown,
            sensitivities: self.sensitivities,
        }
    }

    course_settings!();

    /// Integrates, with the motion, the sensitivities of the free
    /// drivers' positions and rates to the parameters of the definition's
    /// `sensitivities` section ([`Sensitivities`]): one more assembly and
    /// analysis, four per free driver for the state's differences, and the
    /// efforts' partial derivatives, per evaluation; with the explicit
    /// method only.
    pub fn sensitivities(mut self) -> Self {
        self.sensitivities = true;
        self
    }

    /// Runs the simulation.
    ///
    /// # Errors
    /// As [`Forward::run`](crate::dynamics::Forward::run); a start or rates
    /// of the wrong length, or a driver to free that the model does not
    /// have.
    pub fn run(self) -> Result<TrajectoryOf, Error> {
        self.dynamics.fits_model(self.m)?;
        let m = self.m;
        let (n, nd) = (m.coordinates().len(), m.drivers());
        let names: Vec<&str> = m.coordinates().iter().map(|c| c.name).collect();
        if let Some(name) = self.unknown {
            return Err(Error::InvalidDynamics {
                item: format!("free driver `{name}`"),
                detail: format!(
                    "the model has no driver `{name}` (its drivers: {})",
                    names[..nd].join(", ")
                ),
            });
        }
        for (what, len, want) in [
            ("start", self.start.len(), n),
            ("rates", self.rates.len(), nd),
        ] {
            if len != want {
                return Err(Error::InvalidOption {
                    name: what,
                    #[allow(clippy::cast_precision_loss)]
                    value: len as f64,
                    requirement: if what == "start" {
                        "must hold every coordinate, drivers first"
                    } else {
                        "must hold one rate per driver"
                    },
                });
            }
        }
        let (free, mut settings) = self.course.settings(&names, nd)?;
        let parameters: Vec<String> = if self.sensitivities {
            let p: Vec<String> = m
                .sensitivity_parameters()
                .iter()
                .map(|n| n.to_string())
                .collect();
            if p.is_empty() {
                return Err(Error::InvalidDynamics {
                    item: "sensitivities of the trajectory".into(),
                    detail: format!(
                        "model `{}` has no `sensitivities` section: list the parameters \
                         there, `sensitivities {{ k, m }}`",
                        m.name()
                    ),
                });
            }
            p
        } else {
            Vec::new()
        };
        settings.parameters = parameters.len();
        let (d0, r0) = start_state((&self.start[..nd], &self.rates), &free, &names)?;
        let compiled = super::motion::Compiled::new(m, self.dynamics);
        let mut stepper = m.stepper(&self.course.options)?;
        // The compiled equations of motion in the fused step itself, where
        // it has them: one call of machine code per evaluation.
        if compiled.is_some() {
            stepper.with_motion();
        }
        let analysis = RunTime {
            m,
            stepper,
            units: m.stepper(&self.course.options)?,
            compiled,
            counts: [0; 2],
            rates: vec![0.0; nd],
            zeros: vec![0.0; nd],
            profile: self.profile,
            start: self.start.clone(),
            guess: self.start,
            modes: Vec::new(),
            current: false,
            samples: Vec::with_capacity(settings.intervals.min(1 << 16) + 2),
        };
        let (analysis, outcome) = integrate(
            analysis,
            self.dynamics,
            (free, &names),
            (&d0, &r0),
            &settings,
        )?;
        let end = SweepEnd {
            stop: outcome.stop,
            change_points: Vec::new(),
        };
        let sweep = sweep_of(m, ("t", Kind::Length), analysis.samples, end);
        Ok(TrajectoryOf {
            sweep,
            parameters,
            sensitivities: outcome.sensitivities,
            energy: outcome.energy,
            impacts: outcome.impacts,
            work_names: outcome.work_names,
            ended: outcome.ended,
            statistics: outcome.statistics,
        })
    }
}

impl<P> RunTime<'_, P> {
    /// A step at the drivers `d` from the committed pose, in its modes:
    /// with the equations of motion after it and the points' outputs left
    /// out where `equations` ([`Stepper::advance_motion`]).
    #[inline(always)]
    fn step(&mut self, d: &[f64], dd: &[f64], ddd: &[f64], equations: bool) -> Result<(), Error> {
        let nd = d.len();
        let signs = self.stepper.signs_mut();
        if signs.len() == self.modes.len() {
            crate::math::copy_small(signs, &self.modes);
        }
        crate::math::copy_small(&mut self.guess[..nd], d);
        self.current = false;
        if equations {
            self.stepper.advance_motion(&self.guess, dd, ddd)?;
        } else {
            self.stepper.advance(&self.guess, dd, ddd)?;
        }
        self.current = true;
        Ok(())
    }

    /// The stepper's motion made whole, its points evaluated where an
    /// evaluation of the equations of motion left them out
    /// ([`Stepper::complete`]); where that fails, no motion is current.
    fn whole(&mut self) -> Result<(), Error> {
        let done = self.stepper.complete();
        if done.is_err() {
            self.current = false;
        }
        done
    }

    /// M, b and the powers summed over the bodies and loads with unit
    /// analyses: a description that is not the model's sections, or where
    /// the compiled equations gave no finite reduction.
    #[cold]
    #[inline(never)]
    fn summed(
        &mut self,
        dynamics: &Dynamics,
        t: f64,
        out: &mut Equations<'_>,
    ) -> Result<(), Error> {
        self.counts[1] += 1;
        self.whole()?;
        let (units, rates, zeros) = (&mut self.units, &mut self.rates, &self.zeros);
        let motion = self.stepper.motion_now();
        let view = super::dynamics::RunTime(motion);
        let mut unit = |k: usize, with: WithUnit<'_>| -> Result<(), Error> {
            for (i, r) in rates.iter_mut().enumerate() {
                *r = if i == k { 1.0 } else { 0.0 };
            }
            let u = units.step(&motion.q, rates, zeros)?;
            with(&super::dynamics::RunTime(u));
            Ok(())
        };
        dynamics.equations(&Timed(&view, t), &mut unit, out)
    }
}

/// A run-time model's part in the integration: a stepper, its assembly
/// modes restored to the committed pose's before each evaluation, and a
/// second one for the unit analyses, so that an evaluation allocates
/// nothing.
struct RunTime<'m, P> {
    m: &'m Model,
    stepper: Stepper<'m>,
    units: Stepper<'m>,
    /// The model's compiled equations of motion, where the description is
    /// its own sections: then no unit analysis is made.
    compiled: Option<super::motion::Compiled<'m>>,
    /// The evaluations of M and b it gave, and those summed.
    counts: [usize; 2],
    /// The unit rates and the zero accelerations of the unit analyses.
    rates: Vec<f64>,
    zeros: Vec<f64>,
    profile: P,
    start: Vec<f64>,
    /// The pose the next assembly starts from, and its modes.
    guess: Vec<f64>,
    modes: Vec<f64>,
    /// Whether the stepper holds a motion.
    current: bool,
    samples: Vec<Sample>,
}

impl<P: FnMut(f64, &mut [f64], &mut [f64], &mut [f64])> Analysis for RunTime<'_, P> {
    fn profile(&mut self, t: f64, d: &mut [f64], dd: &mut [f64], ddd: &mut [f64]) {
        let nd = d.len();
        d.copy_from_slice(&self.start[..nd]);
        dd.fill(0.0);
        ddd.fill(0.0);
        (self.profile)(t, d, dd, ddd);
    }

    fn analyze(&mut self, d: &[f64], dd: &[f64], ddd: &[f64]) -> Result<(), Error> {
        self.step(d, dd, ddd, false)
    }

    #[inline(always)]
    fn analyze_for_equations(&mut self, d: &[f64], dd: &[f64], ddd: &[f64]) -> Result<(), Error> {
        self.step(d, dd, ddd, true)
    }

    #[inline(always)]
    fn equations(
        &mut self,
        dynamics: &Dynamics,
        t: f64,
        out: &mut Equations<'_>,
    ) -> Result<(), Error> {
        if !self.current {
            return Ok(());
        }
        if let Some(c) = &mut self.compiled {
            if let Some(roots) = self.stepper.fused_motion()
                && c.reduce(roots, out)
            {
                self.counts[0] += 1;
                return Ok(());
            }
            let (flat, trig) = (self.stepper.flat(), self.stepper.fused_trig());
            if c.equations([flat.q, flat.qd, flat.qdd], t, trig, out) {
                self.counts[0] += 1;
                return Ok(());
            }
        }
        self.summed(dynamics, t, out)
    }

    fn equation_counts(&self) -> [usize; 2] {
        self.counts
    }

    fn energies(&mut self, dynamics: &Dynamics, t: f64) -> Result<(f64, f64), Error> {
        if !self.current {
            return Ok((f64::NAN, f64::NAN));
        }
        self.whole()?;
        let view = super::dynamics::RunTime(self.stepper.motion_now());
        let view = Timed(&view, t);
        dynamics.energies(&view)
    }

    fn coordinate(&mut self, j: usize) -> [f64; 3] {
        if !self.current {
            return [f64::NAN; 3];
        }
        // (The coordinates' motion, whole after any step.)
        let flat = self.stepper.flat();
        let get = |v: &[f64]| v.get(j).copied().unwrap_or(f64::NAN);
        [get(flat.q), get(flat.qd), get(flat.qdd)]
    }

    fn commit(&mut self) {
        if self.current {
            self.guess.clear();
            self.guess.extend_from_slice(self.stepper.flat().q);
            self.modes.clear();
            self.modes.extend_from_slice(self.stepper.signs_mut());
        }
    }

    fn record(&mut self, t: f64) {
        // (After the sample's energies, which completed the motion.)
        if self.current && self.whole().is_ok() {
            let motion = self.stepper.motion_now().clone();
            self.samples.push(Sample { at: t, motion });
        }
    }

    fn effort_partials(
        &mut self,
        dynamics: &Dynamics,
        t: f64,
        out: &mut [f64],
    ) -> Result<(), Error> {
        let nd = self.m.drivers();
        self.whole()?;
        let motion = self.stepper.motion_now();
        for (p, s) in dynamics
            .effort_sensitivities_of_at(self.m, motion, t)?
            .iter()
            .enumerate()
        {
            for (k, e) in s.effort.iter().take(nd).enumerate() {
                if let Some(slot) = out.get_mut(p * nd + k) {
                    *slot = *e;
                }
            }
        }
        Ok(())
    }
}
