//! Run-time models as the subject of a dimensional synthesis: the same
//! Levenberg–Marquardt with exact derivatives as for a generated
//! mechanism, the parameters varied those of the definition's
//! `sensitivities` section, the driver named by a string.

use alloc::format;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use super::Model;
use crate::error::Error;
use crate::mechanism::Role;
use crate::options::Options;
use crate::synthesis::{DriverOf, Sealed, Shape, Solved, Subject};

impl Sealed for Model {}

/// What one analysis of a run-time model carries: its options and the
/// assembly modes, as signs (NaN: from the next pose).
#[doc(hidden)]
#[derive(Clone, Debug)]
pub struct SynthesisState {
    options: Options,
    modes: Vec<f64>,
}

impl Model {
    /// The index among the parameters of parameter `k` of the
    /// `sensitivities` section.
    fn sensitivity_index(&self, k: usize) -> Option<usize> {
        let name = self.sensitivity_params.get(k)?;
        self.params.iter().position(|p| p == name)
    }
}

/// A run-time model in a [`Synthesis`](crate::synthesis::Synthesis): the
/// driver named by a string, poses as `Vec<f64>` (drivers first), the
/// parameters varied those of the definition's `sensitivities` section
/// (by default all of them), the design found a model with the same
/// machine code and the new values.
///
/// ```
/// use kinematics_core::runtime::Model;
/// use kinematics_core::synthesis::Synthesis;
/// let text = "struct FourBar {
///     params { a, b, c, d, p, beta }
///     drivers { phi }
///     unknowns { th3, th4 }
///     points { P = polar(a, phi) + polar(p, th3 + beta); }
///     loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
///     sensitivities { a, b, c, p, beta }
/// }";
/// let mut truth = Model::compile(text)?;
/// truth.set_values(&[1.0, 3.0, 2.5, 3.0, 1.5, 0.6])?;
/// let start = truth.assemble(&[0.0, 0.5, 1.5])?;
/// // Five points of the true design's coupler curve, as targets.
/// let phis = [0.3, 1.1, 2.0, 3.5, 5.0];
/// let targets: Vec<Vec<f64>> = phis
///     .iter()
///     .map(|&phi| {
///         let s = truth.step(&[phi, start[1], start[2]], &[0.0], &[0.0])?;
///         Ok(s.points[0].position.to_vec())
///     })
///     .collect::<Result<_, kinematics_core::Error>>()?;
/// // From a design 10 % off, with the crank angles prescribed.
/// let guess = truth.with_values(&[1.1, 2.8, 2.7, 3.0, 1.3, 0.5])?;
/// let found = Synthesis::path(&guess, "phi", "P", &targets, &start)
///     .prescribed(&phis)
///     .run()?;
/// assert!(found.sum_squares < 1e-20);
/// assert!((found.design.values()[2] - 2.5).abs() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
impl Subject for Model {
    type Pose = Vec<f64>;
    type State = SynthesisState;

    fn shape(&self) -> Shape {
        Shape {
            coordinates: self.coordinates.clone(),
            points: self.points.clone(),
            point_dim: self.point_dim,
            parameters: self.sensitivity_params.clone(),
        }
    }

    fn parameter_at(&self, k: usize) -> f64 {
        self.sensitivity_index(k)
            .map_or(f64::NAN, |i| self.values[i])
    }

    fn set_parameter_at(&mut self, k: usize, value: f64) -> bool {
        match self.sensitivity_index(k) {
            Some(i) => {
                self.values[i] = value;
                true
            }
            None => false,
        }
    }

    fn coordinate(pose: &Vec<f64>, i: usize) -> f64 {
        pose.get(i).copied().unwrap_or(f64::NAN)
    }

    fn set_coordinate(pose: &mut Vec<f64>, i: usize, value: f64) {
        if let Some(x) = pose.get_mut(i) {
            *x = value;
        }
    }

    fn state(&self, options: &Options) -> Result<SynthesisState, Error> {
        options.validate()?;
        self.validate()?;
        Ok(SynthesisState {
            options: *options,
            modes: vec![f64::NAN; self.mode_count()],
        })
    }

    fn modes(state: &mut SynthesisState) -> &mut [f64] {
        &mut state.modes
    }

    fn solve(
        &self,
        pose: &mut Vec<f64>,
        driver: usize,
        state: &mut SynthesisState,
        sensitivities: bool,
        out: &mut Solved,
    ) -> Result<(), Error> {
        let mut stepper = self.stepper(&state.options)?;
        let modes = state.modes.clone();
        self.solve_with(&mut stepper, (pose, driver), &modes, sensitivities, out)?;
        state.modes.copy_from_slice(stepper.signs_mut());
        Ok(())
    }

    fn solve_each(
        &self,
        poses: &mut [Vec<f64>],
        driver: usize,
        state: &SynthesisState,
        sensitivities: bool,
        out: &mut [Solved],
    ) -> Result<(), Error> {
        // One stepper for the design (its parameters' constants prepared
        // once), the modes set afresh at each pose.
        let mut stepper = self.stepper(&state.options)?;
        for (pose, out) in poses.iter_mut().zip(out) {
            self.solve_with(
                &mut stepper,
                (pose, driver),
                &state.modes,
                sensitivities,
                out,
            )?;
        }
        Ok(())
    }

    fn path(
        &self,
        driver: usize,
        start: &Vec<f64>,
        to: f64,
        steps: usize,
        options: &Options,
    ) -> (Vec<(f64, Vec<f64>)>, bool) {
        let Some(name) = self.coordinates.get(driver).map(|c| c.name) else {
            return (Vec::new(), true);
        };
        let Ok(builder) = self.sweep(name, start) else {
            return (Vec::new(), true);
        };
        let sweep = builder.to(to).steps(steps).options(options).run();
        let samples = sweep
            .samples
            .iter()
            .map(|x| {
                let r = x
                    .motion
                    .points
                    .iter()
                    .flat_map(|p| p.position.iter().copied());
                (x.at, r.collect())
            })
            .collect();
        (samples, sweep.stop.is_some())
    }

    fn turns(&self, driver: usize, start: &Vec<f64>, options: &Options) -> bool {
        let Some(name) = self.coordinates.get(driver).map(|c| c.name) else {
            return false;
        };
        self.sweep(name, start)
            .is_ok_and(|b| b.turn().options(options).run().stop.is_none())
    }
}

impl DriverOf<Model> for &str {
    fn driver_index(&self, m: &Model) -> Result<usize, String> {
        m.coordinates
            .iter()
            .position(|c| c.name == *self && c.role == Role::Driver)
            .ok_or_else(|| {
                let drivers: Vec<&str> =
                    m.coordinates[..m.drivers].iter().map(|c| c.name).collect();
                format!(
                    "the model has no driver `{self}`; its drivers are {}",
                    drivers.join(", ")
                )
            })
    }
}

impl Model {
    /// One analysis of a synthesis with `stepper`, in `modes`, at `pose`
    /// (solved into it) with a unit rate of `driver`, into `out`.
    fn solve_with(
        &self,
        stepper: &mut super::Stepper<'_>,
        (pose, driver): (&mut Vec<f64>, usize),
        modes: &[f64],
        sensitivities: bool,
        out: &mut Solved,
    ) -> Result<(), Error> {
        stepper.signs_mut().copy_from_slice(modes);
        let mut rates = vec![0.0; self.drivers];
        if let Some(r) = rates.get_mut(driver) {
            *r = 1.0;
        }
        let zeros = vec![0.0; self.drivers];
        let motion = stepper.step(pose, &rates, &zeros)?;
        pose.copy_from_slice(&motion.q);
        out.q.copy_from_slice(&motion.q);
        out.qd.copy_from_slice(&motion.qd);
        let d = self.point_dim;
        for ((p, r), v) in motion
            .points
            .iter()
            .zip(out.positions.chunks_exact_mut(d))
            .zip(out.velocities.chunks_exact_mut(d))
        {
            r.copy_from_slice(&p.position);
            v.copy_from_slice(&p.velocity);
        }
        if sensitivities {
            let n = self.coordinates.len();
            let np = self.points.len();
            for (k, s) in self.sensitivities(motion)?.iter().enumerate() {
                out.dq[k * n..(k + 1) * n].copy_from_slice(&s.q);
                for (i, p) in s.points.iter().enumerate() {
                    let at = (k * np + i) * d;
                    out.dr[at..at + d].copy_from_slice(&p.position);
                }
            }
        }
        Ok(())
    }
}
