//! The stepper of a run-time model: the options and parameters checked
//! once, and every array of a step kept from one step to the next, so
//! that a step allocates nothing.

use super::solve::Work;
use super::{Model, Motion};
use crate::error::Error;
use crate::options::Options;

/// Steps of one run-time model with its arrays kept: made by
/// [`Model::stepper`], which checks the options and the parameters once
/// (the model is borrowed, so they cannot change while it steps). Each
/// [`Stepper::step`] assembles at the drivers of its start from the
/// start's unknowns and analyses the motion there, as [`Model::step`]
/// does, into a motion the stepper owns: no allocation per step.
///
/// ```
/// use kinematics_core::runtime::Model;
/// use kinematics_core::Options;
/// let mut m = Model::compile(
///     "struct SliderCrank {
///          params   { a, b }
///          drivers  { phi }
///          unknowns { th, x }
///          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
///      }",
/// )?;
/// m.set_values(&[0.1, 0.3])?;
/// let mut stepper = m.stepper(&Options::DEFAULT)?;
/// let mut q = vec![0.0, 0.0, 0.4];
/// for k in 1..=360 {
///     q[0] = f64::from(k).to_radians();
///     let s = stepper.step(&q, &[10.0], &[0.0])?;
///     // x = a cos φ + √(b² − a² sin² φ)
///     let x = 0.1 * q[0].cos() + (0.09 - 0.01 * q[0].sin().powi(2)).sqrt();
///     assert!((s.q[2] - x).abs() < 1e-14);
///     q.copy_from_slice(&s.q);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Stepper<'m> {
    m: &'m Model,
    options: Options,
    work: Work,
    motion: Motion,
    q: Vec<f64>,
}

impl core::fmt::Debug for Stepper<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Stepper")
            .field("model", &self.m.name)
            .field("options", &self.options)
            .finish_non_exhaustive()
    }
}

impl Model {
    /// A stepper with `options`, which keeps its arrays from step to step.
    ///
    /// # Errors
    /// Invalid options, or parameters not set or invalid.
    pub fn stepper(&self, options: &Options) -> Result<Stepper<'_>, Error> {
        options.validate()?;
        self.validate()?;
        Ok(Stepper {
            m: self,
            options: *options,
            work: self.work(),
            motion: self.shaped_motion(),
            q: vec![0.0; self.coordinates.len()],
        })
    }
}

impl Stepper<'_> {
    /// Assembles at the drivers of `start` from its unknowns and analyses
    /// the motion there with the drivers' `rates` and `accelerations`: the
    /// same numbers as [`Model::step`]. The motion is the stepper's, until
    /// the next step.
    ///
    /// # Errors
    /// As [`Model::step`], but for the options and the parameters, which
    /// [`Model::stepper`] checked.
    pub fn step(
        &mut self,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<&Motion, Error> {
        let m = self.m;
        m.check_inputs(start, rates, accelerations)?;
        self.q.copy_from_slice(start);
        m.solve(&mut self.q, &mut self.work, &self.options)?;
        m.analyze_into(
            &self.q,
            rates,
            accelerations,
            &mut self.work,
            &self.options,
            true,
            &mut self.motion,
        )?;
        Ok(&self.motion)
    }
}
