//! Dynamics of mechanisms defined at run time ([`crate::runtime::Model`]):
//! the same description resolved against a model's names, and the same
//! sums over its motions.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::sync::Arc;
use alloc::vec;
use alloc::vec::Vec;

use nalgebra::Vector3;

use super::sections::SectionCode;
use super::{Model, Motion, Sample, Sensitivity, Sweep};
use crate::dynamics::evaluate::{View, WithUnit};
use crate::dynamics::sensitivity::Tangent;
use crate::dynamics::{
    Dynamics, DynamicsBuilder, EffortSensitivity, ForceSample, ForceSweep, Forces, MassSensitivity,
    Names, Reactions,
};
use crate::error::Error;
use crate::mechanism::{FrameState, Kind, Role};

impl DynamicsBuilder {
    /// Resolves the names against the run-time model `model`, with the
    /// checks of [`DynamicsBuilder::build`].
    ///
    /// ```
    /// use kinematics_core::dynamics::{Body, Dynamics};
    /// use kinematics_core::runtime::Model;
    /// let m = Model::compile(
    ///     "struct Crank { params { a } drivers { phi } unknowns { } points { G = polar(a, phi); } }",
    /// )?
    /// .with_values(&[0.1])?;
    /// let dynamics = Dynamics::builder()
    ///     .body(Body::new("crank", 2.0).center("G").angle("phi"))
    ///     .gravity([0.0, -9.81, 0.0])
    ///     .build_for(&m)?;
    /// // Held at rest, horizontal: the torque holds the weight, m g a.
    /// let motion = m.analyze(&[0.0], &[0.0], &[0.0])?;
    /// let forces = dynamics.inverse_of(&m, &motion)?;
    /// assert!((forces.effort[0] - 2.0 * 9.81 * 0.1).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`DynamicsBuilder::build`].
    pub fn build_for(self, model: &Model) -> Result<Dynamics, Error> {
        let coordinates: Vec<(String, Role, Kind)> = model
            .coordinates()
            .iter()
            .map(|c| (c.name.to_string(), c.role, c.kind))
            .collect();
        let points: Vec<String> = model.point_names().iter().map(|n| n.to_string()).collect();
        let frames: Vec<String> = model.frame_names().iter().map(|n| n.to_string()).collect();
        self.resolve(&Names {
            coordinates: &coordinates,
            points: &points,
            frames: &frames,
            dim: model.point_dimension(),
        })
    }
}

/// The view of a run-time motion.
pub(super) struct RunTime<'a>(pub(super) &'a Motion);

impl View for RunTime<'_> {
    fn point(&self, i: usize) -> Option<[Vector3<f64>; 3]> {
        let p = self.0.points.get(i)?;
        Some([
            crate::dynamics::evaluate::padded(&p.position),
            crate::dynamics::evaluate::padded(&p.velocity),
            crate::dynamics::evaluate::padded(&p.acceleration),
        ])
    }
    fn velocity(&self, i: usize) -> Option<Vector3<f64>> {
        self.0
            .points
            .get(i)
            .map(|p| crate::dynamics::evaluate::padded(&p.velocity))
    }
    fn acceleration(&self, i: usize) -> Option<Vector3<f64>> {
        self.0
            .points
            .get(i)
            .map(|p| crate::dynamics::evaluate::padded(&p.acceleration))
    }
    fn rate(&self, j: usize) -> f64 {
        self.0.qd.get(j).copied().unwrap_or(f64::NAN)
    }
    fn frame(&self, i: usize) -> Option<&FrameState> {
        self.0.frames.get(i)
    }
    fn coordinate(&self, j: usize) -> [f64; 3] {
        let get = |v: &[f64]| v.get(j).copied().unwrap_or(f64::NAN);
        [get(&self.0.q), get(&self.0.qd), get(&self.0.qdd)]
    }
}

impl Dynamics {
    /// [`Dynamics::inverse`] for a model defined at run time: the forces at
    /// `motion`, a motion of `model`; the efforts in a vector of the
    /// coordinates, in declaration order (the drivers' entries hold their
    /// efforts, the unknowns' are zero).
    ///
    /// # Errors
    /// As [`Dynamics::inverse`].
    pub fn inverse_of(&self, model: &Model, motion: &Motion) -> Result<Forces<Vec<f64>>, Error> {
        self.fits_model(model)?;
        let mut effort = vec![0.0; self.coordinates];
        let (totals, power) = self.sums(
            &RunTime(motion),
            &mut unit_analyses(model, &motion.q, self.drivers),
            &mut |k, q| {
                if let Some(e) = effort.get_mut(k) {
                    *e = q;
                }
            },
        )?;
        Ok(Forces::new(effort, &totals, power))
    }

    /// [`Dynamics::mass_sensitivities`] for a model defined at run time:
    /// how each driver's effort at `motion`, a motion of `model`, changes
    /// with each body's mass and moment of inertia.
    ///
    /// # Errors
    /// As [`Dynamics::inverse`].
    pub fn mass_sensitivities_of(
        &self,
        model: &Model,
        motion: &Motion,
    ) -> Result<Vec<MassSensitivity>, Error> {
        self.fits_model(model)?;
        self.mass_partials(
            &RunTime(motion),
            &mut unit_analyses(model, &motion.q, self.drivers),
        )
    }
}

impl Dynamics {
    /// [`Dynamics::effort_sensitivities`] for a model defined at run
    /// time: how each driver's effort at `motion`, a motion of `model`,
    /// changes with each parameter of its `sensitivities` section (empty
    /// without one), from [`Model::sensitivities`] of the motion and of
    /// each unit-rate analysis.
    ///
    /// ```
    /// use kinematics_core::runtime::Model;
    /// let m = Model::compile(
    ///     "struct Crank {
    ///          params   { a, m }
    ///          drivers  { phi }
    ///          unknowns { }
    ///          points   { G = polar(a, phi); }
    ///          bodies   { crank(mass = m, center = G, angle = phi); }
    ///          loads    { gravity(vec2(0.0, -9.81)); }
    ///          sensitivities { a, m }
    ///      }",
    /// )?
    /// .with_values(&[0.1, 2.0])?;
    /// // Q = m g a cos φ at constant speed: ∂Q/∂a = m g cos φ.
    /// let motion = m.analyze(&[0.3], &[4.0], &[0.0])?;
    /// let s = m.dynamics()?.effort_sensitivities_of(&m, &motion)?;
    /// assert!((s[0].effort[0] - 2.0 * 9.81 * 0.3f64.cos()).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`Dynamics::effort_sensitivities`] and [`Model::sensitivities`].
    pub fn effort_sensitivities_of(
        &self,
        model: &Model,
        motion: &Motion,
    ) -> Result<Vec<EffortSensitivity>, Error> {
        self.effort_sensitivities_of_at(model, motion, f64::NAN)
    }

    /// [`Dynamics::effort_sensitivities_of`] at the time `time` of a
    /// forward simulation (NaN: none), which the loads of the time read.
    pub(crate) fn effort_sensitivities_of_at(
        &self,
        model: &Model,
        motion: &Motion,
        time: f64,
    ) -> Result<Vec<EffortSensitivity>, Error> {
        self.fits_model(model)?;
        let names: Vec<&str> = model
            .sensitivity_parameters()
            .iter()
            .map(|n| n.as_ref())
            .collect();
        let ds = tangents(&model.sensitivities(motion)?);
        let mut rates = vec![0.0; self.drivers];
        let zeros = vec![0.0; self.drivers];
        let view = RunTime(motion);
        let view = crate::dynamics::forward::run::Timed(&view, time);
        self.effort_partials(&names, &view, &ds, &mut |d, with| {
            rates
                .iter_mut()
                .enumerate()
                .for_each(|(i, x)| *x = if i == d { 1.0 } else { 0.0 });
            let u = model.analyze(&motion.q, &rates, &zeros)?;
            with(&RunTime(&u), &tangents(&model.sensitivities(&u)?));
            Ok(())
        })
    }
}

/// The tangents of a run-time model's sensitivities, one per parameter.
fn tangents(s: &[Sensitivity]) -> Vec<Tangent> {
    s.iter()
        .map(|s| Tangent {
            coordinates: s
                .q
                .iter()
                .zip(&s.qd)
                .zip(&s.qdd)
                .map(|((q, qd), qdd)| [*q, *qd, *qdd])
                .collect(),
            points: s
                .points
                .iter()
                .map(|p| {
                    [
                        crate::dynamics::evaluate::padded(&p.position),
                        crate::dynamics::evaluate::padded(&p.velocity),
                        crate::dynamics::evaluate::padded(&p.acceleration),
                    ]
                })
                .collect(),
        })
        .collect()
}

/// The unit analyses of `model` at `pose`, as the generated mechanisms'
/// (driver k at unit rate, the others at rest, no acceleration).
pub(super) fn unit_analyses<'a>(
    model: &'a Model,
    pose: &'a [f64],
    drivers: usize,
) -> impl FnMut(usize, WithUnit<'_>) -> Result<(), Error> + 'a {
    let mut rates = vec![0.0; drivers];
    let zeros = vec![0.0; drivers];
    move |k, with| {
        rates
            .iter_mut()
            .enumerate()
            .for_each(|(i, x)| *x = if i == k { 1.0 } else { 0.0 });
        let u = model.analyze(pose, &rates, &zeros)?;
        with(&RunTime(&u));
        Ok(())
    }
}

impl Dynamics {
    /// [`Dynamics::along`] for a model defined at run time: the forces at
    /// every sample of `sweep`, a sweep of `model`.
    ///
    /// # Errors
    /// As [`Dynamics::along`].
    pub fn along_of(&self, model: &Model, sweep: &Sweep) -> Result<ForceSweep, Error> {
        self.along_samples_of(model, sweep.variable, &sweep.samples)
    }

    /// The forces at each of `samples`, motions of `model` in the order of
    /// the driver `variable`'s values (their `at`): [`Dynamics::along_of`]
    /// for samples gathered some other way than by a [`Sweep`] (a sweep
    /// kept in columns, read back one motion at a time; a simulation).
    ///
    /// ```
    /// use kinematics_core::runtime::{Model, Sample};
    /// let m = Model::compile(
    ///     "struct Crank {
    ///          params   { a }
    ///          drivers  { phi }
    ///          unknowns { }
    ///          points   { G = polar(a, phi); }
    ///          bodies   { crank(mass = 2.0, center = G, angle = phi); }
    ///          loads    { gravity(vec2(0.0, -9.81)); }
    ///      }",
    /// )?
    /// .with_values(&[0.1])?;
    /// let samples = (0..=4)
    ///     .map(|k| {
    ///         let phi = f64::from(k) * 0.25 * std::f64::consts::PI;
    ///         Ok(Sample { at: phi, motion: m.analyze(&[phi], &[1.0], &[0.0])? })
    ///     })
    ///     .collect::<Result<Vec<_>, kinematics_core::Error>>()?;
    /// let forces = m.dynamics()?.along_samples_of(&m, "phi", &samples)?;
    /// // Holding the crank's weight: Q = m g a cos φ at constant speed.
    /// let q = forces.samples[1].effort[0];
    /// assert!((q - 2.0 * 9.81 * 0.1 * (0.25 * std::f64::consts::PI).cos()).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when `variable` is not one of the model's
    /// drivers; otherwise as [`Dynamics::along`].
    pub fn along_samples_of(
        &self,
        model: &Model,
        variable: &str,
        samples: &[Sample],
    ) -> Result<ForceSweep, Error> {
        let swept = model
            .coordinates()
            .iter()
            .find(|c| c.role == Role::Driver && c.name == variable)
            .ok_or_else(|| Error::InvalidOption {
                name: crate::names::intern(variable),
                value: f64::NAN,
                requirement: "must be one of the model's drivers",
            })?;
        let drivers: Vec<(String, Kind)> = model
            .coordinates()
            .iter()
            .filter(|c| c.role == Role::Driver)
            .map(|c| (c.name.to_string(), c.kind))
            .collect();
        let n = drivers.len();
        self.sweep_of(swept.name, swept.kind, drivers, samples, |s| {
            let f = self.inverse_of(model, &s.motion)?;
            let reactions = self
                .has_joints()
                .then(|| self.reactions_of(model, &s.motion))
                .transpose()?;
            let effort = f.effort.iter().copied().take(n).collect();
            Ok(ForceSample::new(s.at, effort, &f, reactions))
        })
    }

    /// [`Dynamics::reactions`] for a model defined at run time.
    ///
    /// # Errors
    /// As [`Dynamics::reactions`].
    pub fn reactions_of(&self, model: &Model, motion: &Motion) -> Result<Reactions, Error> {
        self.fits_model(model)?;
        self.reactions_in(
            &RunTime(motion),
            &mut unit_analyses(model, &motion.q, self.drivers),
        )
    }
}

impl Dynamics {
    /// Checks that this description was resolved against a model of
    /// `model`'s sizes.
    pub(super) fn fits_model(&self, model: &Model) -> Result<(), Error> {
        self.fits(
            model.coordinates().len(),
            model.point_names().len(),
            model.frame_names().len(),
            model.point_dimension(),
        )
    }
}

impl Model {
    /// Whether the definition has a `bodies` or a `loads` section (then
    /// [`Model::dynamics`] describes its masses and loads).
    #[must_use]
    pub fn has_dynamics(&self) -> bool {
        self.sections().is_some()
    }

    /// Whether a load's value in the definition reads the time (`time`):
    /// its forces have a value only in a forward simulation
    /// ([`Dynamics::forward_of`]), not along a kinematic sweep or at one
    /// motion.
    #[must_use]
    pub fn loads_read_time(&self) -> bool {
        self.sections().is_some_and(|c| c.reads_time())
    }

    /// The masses and loads of the definition's `bodies` and `loads`
    /// sections (and the joints of `joints`), with the model's parameter
    /// values: the constants (masses, inertias, gravity, springs, axes)
    /// evaluated now, each load a function of the instant in machine
    /// code. Add more joints for the reactions, then resolve it with
    /// [`DynamicsBuilder::build_for`], or take [`Model::dynamics`].
    ///
    /// # Errors
    /// [`Error::InvalidDynamics`] when the definition has neither section.
    pub fn dynamics_builder(&self) -> Result<DynamicsBuilder, Error> {
        use crate::dynamics::{Body, Spring};
        use kinematics_compiler::dynamics::{JointKind, LoadTarget, Turning};
        let Some(shared) = self.sections() else {
            return Err(Error::InvalidDynamics {
                item: format!("model `{}`", self.name()),
                detail: "its definition has no `bodies` or `loads` section: describe the \
                         links' masses there (`bodies { rod(mass = m3, center = G3, angle = \
                         th3, inertia = j3); }`), or build the description with \
                         `Dynamics::builder()`"
                    .to_string(),
            });
        };
        let code: &SectionCode = shared;
        let values: Vec<f64> = self.all_values().to_vec();
        let d = code.sections();
        let mut constants = vec![0.0; code.outputs(0)];
        code.eval(0, &values, None, &mut constants);
        // Each constant read at its place in the evaluated list: the
        // compiler's layout, made by the walk that made the list.
        let places = d.places();
        let at = |i: usize| constants.get(i).copied().unwrap_or(f64::NAN);
        let padded = |v: &[f64]| {
            [
                v.first().copied().unwrap_or(0.0),
                v.get(1).copied().unwrap_or(0.0),
                v.get(2).copied().unwrap_or(0.0),
            ]
        };
        let mut b = DynamicsBuilder::new();
        if !places.gravity.is_empty() {
            let g: Vec<f64> = places.gravity.iter().map(|&i| at(i)).collect();
            b = b.gravity(padded(&g));
        }
        for (body, place) in d.bodies.iter().zip(&places.bodies) {
            let mut made = Body::new(&body.name, at(place.mass)).center(&body.center);
            match &body.turning {
                Turning::No => {}
                Turning::Angle(terms) => {
                    let terms: Vec<(&str, f64)> = terms
                        .iter()
                        .zip(&place.angle)
                        .map(|((n, _), &i)| (n.as_str(), at(i)))
                        .collect();
                    made = made.angle_sum(&terms);
                }
                Turning::Frame(f) => made = made.frame(f),
            }
            match place.inertia.as_slice() {
                [] => {}
                [moment] => made = made.inertia(at(*moment)),
                all => {
                    let mut t = [[0.0; 3]; 3];
                    for (x, &i) in t.iter_mut().flatten().zip(all) {
                        *x = at(i);
                    }
                    made = made.inertia_tensor(t);
                }
            }
            b = b.body(made);
        }
        for (s, place) in d.springs.iter().zip(&places.springs) {
            let mut spring = Spring::new(&s.from, &s.to)
                .stiffness(at(place.stiffness))
                .free_length(at(place.free_length))
                .damping(at(place.damping));
            if let Some([first, second]) = &s.between {
                spring = spring.between(first, second);
            }
            b = b.spring(spring);
        }
        for (k, load) in d.loads.iter().enumerate() {
            let (code, at) = (Arc::clone(shared), values.clone());
            let vector = move |i: &crate::dynamics::Instant<'_>| -> [f64; 3] {
                let mut out = [0.0; 3];
                let n = code.outputs(k + 1).min(3);
                code.eval(k + 1, &at, Some(i), &mut out[..n]);
                match n {
                    1 => [0.0, 0.0, out[0]],
                    _ => out,
                }
            };
            b = match &load.target {
                LoadTarget::Point { point, body: None } => b.force(point, vector),
                LoadTarget::Point {
                    point,
                    body: Some(on),
                } => b.force_on(on, point, vector),
                LoadTarget::Torque { body } => b.torque(body, vector),
                LoadTarget::Coordinate { coordinate } => {
                    b.coordinate_force(coordinate, move |i| vector(i)[2])
                }
            };
            if d.partials.is_some() {
                let (code, values) = (Arc::clone(shared), values.clone());
                let stage = d.loads.len() + 2 + k;
                let load = load.clone();
                b = b.load_partials(move |i, out| {
                    let m = load.value.len();
                    let mut flat = vec![0.0; code.outputs(stage)];
                    code.eval(stage, &values, Some(i), &mut flat);
                    for (x, o) in out.iter_mut().enumerate() {
                        *o = [0.0; 3];
                        for c in 0..m {
                            o[load.slot(c)] = flat.get(x * m + c).copied().unwrap_or(f64::NAN);
                        }
                    }
                });
            }
        }
        if d.partials.is_some() {
            let stage = d.loads.len() + 1;
            let mut flat = vec![0.0; code.outputs(stage)];
            code.eval(stage, &values, None, &mut flat);
            let per = constants.len().max(1);
            let design: Vec<f64> = flat
                .chunks(per)
                .flat_map(|chunk| d.design_layout(chunk))
                .map(|x| x.unwrap_or(0.0))
                .collect();
            let names: Vec<&str> = self
                .sensitivity_parameters()
                .iter()
                .map(|n| n.as_ref())
                .collect();
            b = b.design_parameters(&names, if constants.is_empty() { &[] } else { &design });
            for (f, (frame, _)) in d.partials.iter().flat_map(|p| &p.frames).enumerate() {
                let (code, at) = (Arc::clone(shared), values.clone());
                let stage = 2 + 2 * d.loads.len() + f;
                b = b.frame_partials(frame, move |i, out| {
                    let mut flat = vec![0.0; code.outputs(stage)];
                    code.eval(stage, &at, Some(i), &mut flat);
                    for (x, o) in out.iter_mut().enumerate() {
                        for (c, v) in o.iter_mut().enumerate() {
                            *v = flat.get(x * 15 + c).copied().unwrap_or(f64::NAN);
                        }
                    }
                });
            }
        }
        for (j, place) in d.joints.iter().zip(&places.joints) {
            let (name, point, [first, second]) = (&j.name, &j.point, &j.between);
            let axis: Vec<f64> = place.iter().map(|&i| at(i)).collect();
            let mut joint = match (j.kind, axis.as_slice()) {
                (JointKind::Prismatic, &[x, y]) => {
                    crate::dynamics::Joint::prismatic(name, point, first, second, [x, y])
                }
                (JointKind::Prismatic, &[x, y, z]) => {
                    crate::dynamics::Joint::prismatic(name, point, first, second, [x, y, z])
                }
                (JointKind::Cylindrical, &[x, y, z]) => {
                    crate::dynamics::Joint::cylindrical(name, point, first, second, [x, y, z])
                }
                (JointKind::Spherical, _) => {
                    crate::dynamics::Joint::spherical(name, point, first, second)
                }
                (JointKind::Revolute, &[x, y, z]) => {
                    crate::dynamics::Joint::revolute(name, point, first, second).about([x, y, z])
                }
                _ => crate::dynamics::Joint::revolute(name, point, first, second),
            };
            if let Some(d) = &j.driver {
                joint = joint.driven_by(d);
            }
            if let Some(q) = &j.coordinate {
                joint = joint.coordinate(q);
            }
            b = b.joint(joint);
        }
        Ok(b)
    }

    /// The definition's masses and loads resolved against the model
    /// ([`Model::dynamics_builder`], then [`DynamicsBuilder::build_for`]).
    ///
    /// ```
    /// use kinematics_core::runtime::Model;
    /// let m = Model::compile(
    ///     "struct Crank {
    ///          params   { a, m }
    ///          drivers  { phi }
    ///          unknowns { }
    ///          points   { G = polar(a, phi); }
    ///          bodies   { crank(mass = m, center = G, angle = phi); }
    ///          loads    { gravity(vec2(0.0, -9.81)); }
    ///      }",
    /// )?
    /// .with_values(&[0.1, 2.0])?;
    /// // Held at rest, horizontal: the torque holds the weight, m g a.
    /// let motion = m.analyze(&[0.0], &[0.0], &[0.0])?;
    /// let forces = m.dynamics()?.inverse_of(&m, &motion)?;
    /// assert!((forces.effort[0] - 2.0 * 9.81 * 0.1).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`Model::dynamics_builder`] and [`DynamicsBuilder::build_for`].
    pub fn dynamics(&self) -> Result<Dynamics, Error> {
        let mut d = self.dynamics_builder()?.build_for(self)?;
        if let Some(code) = self.sections() {
            d.mark_sections(code.owner(), self.all_values());
        }
        Ok(d)
    }
}
