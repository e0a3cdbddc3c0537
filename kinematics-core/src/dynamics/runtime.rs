//! Dynamics of mechanisms defined at run time ([`crate::runtime::Model`]):
//! the same description resolved against a model's names, and the same
//! sums over its motions.

use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;

use nalgebra::Vector3;

use super::evaluate::{View, WithUnit};
use super::{
    Dynamics, DynamicsBuilder, ForceSample, ForceSweep, Forces, MassSensitivity, Names, Reactions,
};
use crate::error::Error;
use crate::mechanism::{FrameState, Kind, Role};
use crate::runtime::{Model, Motion, Sweep};

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
struct RunTime<'a>(&'a Motion);

impl View for RunTime<'_> {
    fn point(&self, i: usize) -> Option<[Vector3<f64>; 3]> {
        let p = self.0.points.get(i)?;
        Some([
            super::evaluate::padded(&p.position),
            super::evaluate::padded(&p.velocity),
            super::evaluate::padded(&p.acceleration),
        ])
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

/// The unit analyses of `model` at `pose`, as the generated mechanisms'
/// (driver k at unit rate, the others at rest, no acceleration).
fn unit_analyses<'a>(
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
        let drivers: Vec<(String, Kind)> = model
            .coordinates()
            .iter()
            .filter(|c| c.role == Role::Driver)
            .map(|c| (c.name.to_string(), c.kind))
            .collect();
        let n = drivers.len();
        self.sweep_of(sweep.variable, sweep.kind, drivers, &sweep.samples, |s| {
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
        self.reactions_in(&RunTime(motion))
    }
}

impl Dynamics {
    /// Checks that this description was resolved against a model of
    /// `model`'s sizes.
    fn fits_model(&self, model: &Model) -> Result<(), Error> {
        self.fits(
            model.coordinates().len(),
            model.point_names().len(),
            model.frame_names().len(),
            model.point_dimension(),
        )
    }
}
