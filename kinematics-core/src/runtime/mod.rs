//! Mechanisms defined at run time: the text of a definition, exactly as
//! written inside `mechanism! { … }`, compiled by the compiler the macro
//! uses (`kinematics-compiler`: the same checks, the same messages, the
//! same exact derivatives) and turned into machine code by Cranelift
//! (`kinematics-jit`).
//!
//! A [`Model`] holds the compiled stages and the parameter values. Its
//! arrays are in declaration order: the coordinates q = (d, u), drivers
//! first, then unknowns; the rates and accelerations of the drivers only.
//!
//! * [`Model::assemble`]: Newton–Raphson on Φ(q) = 0 for the unknowns,
//!   the drivers held, from a guess, each step solving Φ_u Δu = −Φ by LU
//!   with partial pivoting, halved while it does not decrease Σ (Φ_i/S_i)²;
//!   converged when every |Φ_i| / S_i (S_i the equation's term scale) is at
//!   most the tolerance, then one more step unless already at 16 ε;
//! * [`Model::analyze`]: Φ_u u' = −Φ_d d', Φ_u u'' = −Φ_d d'' − γ, then
//!   every point's r, v, a and every frame's motion;
//! * [`Model::step`]: assembly, then analysis.
//!
//! A model is `Send` and `Sync`: threads may share one and step it at
//! once (each call has its own scratch arrays).
//!
//! A [`Stepper`] keeps its arrays from step to step; where every block has
//! a closed form, it steps through one fused machine-code function (see
//! [`Stepper::is_fused`] and the [guide](crate::guide::runtime)). Sweeps,
//! sweeps of poses and simulations go through steppers.
//!
//! ```
//! use kinematics_core::runtime::Model;
//! let mut m = Model::compile(
//!     "/// Slider-crank.
//!      pub struct SliderCrank {
//!          params   { a, b }
//!          drivers  { phi }
//!          unknowns { th, x }
//!          points   { B = polar(a, phi); }
//!          loops    { B + polar(b, th) == vec2(x, 0.0); }
//!      }",
//! )?;
//! m.set("a", 0.1)?;
//! m.set("b", 0.3)?;
//! let q = m.assemble(&[0.5, -0.1, 0.35])?;
//! // x = a cos φ + √(b² − a² sin² φ).
//! let x = 0.1 * 0.5f64.cos() + (0.09 - 0.01 * 0.5f64.sin().powi(2)).sqrt();
//! assert!((q[2] - x).abs() < 1e-15);
//! let motion = m.analyze(&q, &[10.0], &[0.0])?;
//! // The crank pin B turns at a ω = 1 m/s.
//! let v = &motion.points[0].velocity;
//! assert!(((v[0] * v[0] + v[1] * v[1]).sqrt() - 1.0).abs() < 1e-14);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;
use core::fmt;
use std::sync::Arc;

use kinematics_compiler::{Diagnostics, compile_str};
use kinematics_jit::{JitError, Program};

use crate::closed::Block;
use crate::error::{Error, Input};
use crate::mechanism::{Coordinate, FrameState, Kind, Role};
use crate::names::{Name, intern, intern_list};
use crate::options::Options;

mod batch;
mod closed;
mod describe;
mod drive;
mod dynamics;
mod forward;
mod fused;
mod invariant;
mod motion;
mod sections;
mod sensitivity;
mod solve;
mod stepper;
mod sweep;
#[cfg(feature = "synthesis")]
mod synthesis;
#[cfg(test)]
mod test_models;
mod vector;

pub use batch::{Batch, BatchResults, BatchSweep, Early, Output, Reduce};
pub use forward::{ForwardOf, TrajectoryOf};
pub use sensitivity::Sensitivity;
pub use stepper::Stepper;
pub use sweep::{ProfileFn, Sample, Simulation, Sweep, SweepBuilder, SweepEnd};
#[cfg(feature = "synthesis")]
#[doc(hidden)]
pub use synthesis::SynthesisState;
pub use vector::Vector;

/// Why a definition given as text did not become a [`Model`].
#[derive(Debug)]
pub enum CompileError {
    /// The definition has errors: each with its message (the one
    /// `mechanism!` gives), line and column.
    Definition(Diagnostics),
    /// No machine code could be generated on this host.
    Native(JitError),
}

impl fmt::Display for CompileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Definition(d) => write!(f, "{d}"),
            Self::Native(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for CompileError {}

/// A point's position r, velocity v and acceleration a (2 or 3
/// components each, held inline: see [`Vector`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointState {
    /// r.
    pub position: Vector,
    /// v = dr/dt.
    pub velocity: Vector,
    /// a = dv/dt.
    pub acceleration: Vector,
}

impl PointState {
    /// r = v = a = 0, of `dimension` components (2 or 3).
    #[must_use]
    pub const fn zeros(dimension: usize) -> Self {
        let z = Vector::zeros(dimension);
        Self {
            position: z,
            velocity: z,
            acceleration: z,
        }
    }
}

/// The motion at one pose as flat arrays, borrowed from the stepper or
/// sweep that solved it ([`SweepBuilder::for_each_flat`]): what a
/// [`Motion`] holds, without copying it into one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flat<'a> {
    /// q.
    pub q: &'a [f64],
    /// q'.
    pub qd: &'a [f64],
    /// q''.
    pub qdd: &'a [f64],
    /// For each point in declaration order, its position, velocity and
    /// acceleration ([`Model::point_dimension`] components each); then for
    /// each frame its rotation (row by row), ω, α, and its origin's
    /// position, velocity and acceleration (24 values).
    pub outputs: &'a [f64],
    /// As [`Motion::conditioning`].
    pub conditioning: f64,
    /// As [`Motion::det_sign`].
    pub det_sign: f64,
    /// As [`Motion::residual`].
    pub residual: f64,
}

/// The motion at one pose: coordinates, rates and accelerations (drivers
/// first, then unknowns), points, frames and diagnostics. The default is
/// empty (no coordinate, point or frame; zero diagnostics): storage for a
/// motion to be written into.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    /// q.
    pub q: Vec<f64>,
    /// q'.
    pub qd: Vec<f64>,
    /// q''.
    pub qdd: Vec<f64>,
    /// Every point, in declaration order.
    pub points: Vec<PointState>,
    /// Every frame, in declaration order.
    pub frames: Vec<FrameState>,
    /// 1/‖Φ̃_u⁻¹‖∞ of the scaled Jacobian (rows by 1/S_i, length columns by
    /// the characteristic length): 0 at a singular pose.
    pub conditioning: f64,
    /// The sign of det Φ_u (the assembly branch).
    pub det_sign: f64,
    /// max |Φ_i| / S_i at q.
    pub residual: f64,
}

/// A mechanism compiled from text at run time, with its parameter values
/// (NaN until set). A clone shares the machine code
/// ([`Model::with_values`]).
#[derive(Clone)]
pub struct Model {
    name: String,
    params: Vec<Name>,
    length_params: Vec<bool>,
    values: Vec<f64>,
    coordinates: Vec<Coordinate>,
    drivers: usize,
    equations: Vec<Name>,
    points: Vec<Name>,
    point_dim: usize,
    frames: Vec<Name>,
    length_unknowns: Vec<bool>,
    /// The diagonal blocks of Φ_u: equations and unknowns.
    blocks: Vec<(Vec<usize>, Vec<usize>)>,
    /// How each block is solved, as a generated mechanism's `BLOCKS`.
    described: Vec<Block>,
    /// The blocks as the assembly solves them, in solve order.
    parts: Vec<closed::Part>,
    /// 0, 1, …: every equation, and every unknown.
    all: Vec<usize>,
    /// Whether the term scales read no coordinate (then a stepper or a
    /// sweep computes the scaling once).
    fixed_scaling: bool,
    /// The parameters of the `sensitivities` section, in its order.
    sensitivity_params: Vec<Name>,
    /// The machine code, shared by the clones of the model.
    program: Arc<Program>,
    /// The fused step of a stepper, where the model has one (every block
    /// in closed form, none of more than four unknowns).
    fused: Option<Arc<fused::Plan>>,
    /// The `bodies` and `loads` sections in machine code, where the
    /// definition has them.
    sections: Option<Arc<sections::SectionCode>>,
    /// The Kutzbach–Gruebler count of a `joints` section of counts.
    mobility: Option<kinematics_compiler::Mobility>,
    /// Work arrays kept for the next stepper or call.
    spare: solve::Spare,
}

impl fmt::Debug for Model {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Model")
            .field("name", &self.name)
            .field(
                "params",
                &self.params.iter().zip(&self.values).collect::<Vec<_>>(),
            )
            .field("coordinates", &self.coordinates)
            .finish_non_exhaustive()
    }
}

impl Model {
    /// Compiles a definition given as text.
    ///
    /// # Errors
    /// [`CompileError::Definition`] with every error of the definition,
    /// located by line and column; [`CompileError::Native`] on a machine
    /// Cranelift does not support.
    pub fn compile(text: &str) -> Result<Self, CompileError> {
        let c = compile_str(text).map_err(CompileError::Definition)?;
        let program = Program::for_model(&c).map_err(CompileError::Native)?;
        let fused = fused::Plan::new(&c).map(Arc::new);
        let sections = sections::SectionCode::new(&c)
            .map_err(CompileError::Native)?
            .map(Arc::new);
        let drivers = c.drivers();
        let coordinates = c
            .coordinates()
            .into_iter()
            .enumerate()
            .map(|(j, (name, kind))| Coordinate {
                name: intern(&name),
                role: if j < drivers {
                    Role::Driver
                } else {
                    Role::Unknown
                },
                kind: match kind {
                    kinematics_compiler::Kind::Angle => Kind::Angle,
                    kinematics_compiler::Kind::Length => Kind::Length,
                },
            })
            .collect::<Vec<Coordinate>>();
        let described = c
            .blocks()
            .iter()
            .map(|b| {
                let names: Vec<Name> = b
                    .unknowns
                    .iter()
                    .map(|&k| coordinates[drivers + k].name)
                    .collect();
                Block {
                    unknowns: intern_list(&names),
                    method: b.method,
                    modes: b.has_modes(),
                }
            })
            .collect();
        let parts = c
            .blocks()
            .iter()
            .map(|b| {
                let names: Vec<&str> = b
                    .unknowns
                    .iter()
                    .map(|&k| coordinates[drivers + k].name)
                    .collect();
                closed::Part {
                    form: b.form.as_ref().map(kinematics_compiler::ClosedForm::places),
                    rows: b.equations.clone(),
                    cols: b.unknowns.clone(),
                    names: intern(&names.join(", ")),
                }
            })
            .collect();
        let points = c.points();
        let point_dim = points.first().map_or(2, |p| p.position.len());
        let params: Vec<Name> = c.parameters().iter().map(|p| intern(p)).collect();
        let sensitivity_params = c
            .sensitivities()
            .map(|s| {
                s.params
                    .iter()
                    .filter_map(|&i| params.get(i as usize).copied())
                    .collect()
            })
            .unwrap_or_default();
        Ok(Self {
            name: c.name(),
            // The parameters, then the characteristic length L.
            values: vec![f64::NAN; params.len() + 1],
            params,
            length_params: c.length_parameters(),
            coordinates,
            drivers,
            equations: c.residuals().iter().map(|(_, t)| intern(t)).collect(),
            points: points.iter().map(|p| intern(&p.name)).collect(),
            point_dim,
            frames: c.frames().iter().map(|f| intern(&f.name)).collect(),
            length_unknowns: c.length_unknowns().to_vec(),
            described,
            parts,
            all: (0..c.unknowns()).collect(),
            sensitivity_params,
            fixed_scaling: !program.reads_coordinates(Program::SCALES)
                && !program.reads_coordinates(Program::FULL_SCALES),
            blocks: c
                .blocks()
                .into_iter()
                .map(|b| (b.equations, b.unknowns))
                .collect(),
            program: Arc::new(program),
            fused,
            sections,
            mobility: c.mobility(),
            spare: solve::Spare::default(),
        })
    }

    /// How each diagonal block of the loop equations is solved, in solve
    /// order, described as a generated mechanism's `BLOCKS` describes it
    /// (the same compiler finds them, and the run-time model solves them
    /// the same way: each closed-form block by its form, each other block
    /// by Newton–Raphson on its own unknowns).
    #[must_use]
    pub fn blocks(&self) -> &[Block] {
        &self.described
    }

    /// The mechanism's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The parameters' names, in declaration order.
    #[must_use]
    pub fn parameters(&self) -> &[Name] {
        &self.params
    }

    /// The compiled `bodies` and `loads` sections, where written.
    pub(crate) fn sections(&self) -> Option<&Arc<sections::SectionCode>> {
        self.sections.as_ref()
    }

    /// The parameters' values with the characteristic length last, as the
    /// machine code reads them.
    pub(crate) fn all_values(&self) -> &[f64] {
        &self.values
    }

    /// The parameters' values, in declaration order (NaN where not set).
    #[must_use]
    pub fn values(&self) -> &[f64] {
        &self.values[..self.params.len()]
    }

    /// Sets the parameter `name` to `value`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a name the model does not declare.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), Error> {
        match self.params.iter().position(|p| *p == name) {
            Some(i) => {
                self.values[i] = value;
                Ok(())
            }
            None => Err(Error::InvalidParameter {
                name: intern(name),
                value,
                requirement: "must be one of the model's parameters",
            }),
        }
    }

    /// A copy of the model with the parameter values `values` (in
    /// declaration order): the machine code is shared, not compiled again,
    /// so that many designs of one definition cost one compilation (for
    /// [`batch`](crate::batch), say).
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless there is one value per parameter.
    pub fn with_values(&self, values: &[f64]) -> Result<Self, Error> {
        let mut m = self.clone();
        m.set_values(values)?;
        Ok(m)
    }

    /// Sets every parameter, in declaration order (as a generated
    /// mechanism's `parameter_values` gives them).
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless there is one value per parameter.
    pub fn set_values(&mut self, values: &[f64]) -> Result<(), Error> {
        let n = self.params.len();
        self.length("parameter values", n, values.len())?;
        self.values[..n].copy_from_slice(values);
        Ok(())
    }

    /// The coordinates: drivers, then unknowns, in declaration order.
    #[must_use]
    pub fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    /// The position of coordinate `name` in the arrays.
    #[must_use]
    pub fn index(&self, name: &str) -> Option<usize> {
        self.coordinates.iter().position(|c| c.name == name)
    }

    /// Number of drivers.
    #[must_use]
    pub fn drivers(&self) -> usize {
        self.drivers
    }

    /// Number of unknowns (and of scalar equations).
    #[must_use]
    pub fn unknowns(&self) -> usize {
        self.coordinates.len() - self.drivers
    }

    /// The points' names, in declaration order.
    #[must_use]
    pub fn point_names(&self) -> &[Name] {
        &self.points
    }

    /// The points' dimension: 2 for a planar model, 3 for a spatial one.
    #[must_use]
    pub fn point_dimension(&self) -> usize {
        self.point_dim
    }

    /// The positions of the points at the coordinates `q` (drivers
    /// first), whether or not q closes the loops: r_k(q) as the definition
    /// writes each point, [`Self::point_dimension`] components per point
    /// in declaration order.
    ///
    /// # Errors
    /// [`Error::InvalidGeometry`] for a `q` of the wrong length.
    pub fn point_positions(&self, q: &[f64]) -> Result<Vec<f64>, Error> {
        self.length("coordinates", self.coordinates.len(), q.len())?;
        Ok(self.positions(q))
    }

    /// The frames' names, in declaration order.
    #[must_use]
    pub fn frame_names(&self) -> &[Name] {
        &self.frames
    }

    /// The equations, as written in the definition.
    #[must_use]
    pub fn equation_names(&self) -> &[Name] {
        &self.equations
    }

    /// Checks that every parameter is finite, and positive where it is
    /// declared a length.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::InvalidParameter`] naming the first
    /// parameter at fault.
    pub fn validate(&self) -> Result<(), Error> {
        for ((name, &value), &length) in self
            .params
            .iter()
            .zip(&self.values)
            .zip(&self.length_params)
        {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    input: Input::Parameter,
                    name,
                    value,
                });
            }
            if length && value <= 0.0 {
                return Err(Error::InvalidParameter {
                    name,
                    value,
                    requirement: "must be positive: it is declared a length",
                });
            }
        }
        Ok(())
    }

    /// Φ(q), one value per equation.
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `q` has one value per coordinate; as
    /// [`Model::validate`].
    pub fn residual(&self, q: &[f64]) -> Result<Vec<f64>, Error> {
        self.validate()?;
        self.length("coordinates", self.coordinates.len(), q.len())?;
        let mut w = self.work();
        self.scaling(q, &mut w, &Options::DEFAULT);
        self.newton_eval(q, &mut w);
        Ok(w.phi.clone())
    }

    /// Assembles at the drivers of `guess` from its unknowns, with the
    /// default options (see the module's documentation).
    ///
    /// # Errors
    /// As [`Model::assemble_with`].
    pub fn assemble(&self, guess: &[f64]) -> Result<Vec<f64>, Error> {
        self.assemble_with(guess, &Options::DEFAULT)
    }

    /// Assembles at the drivers of `guess` from its unknowns.
    ///
    /// # Errors
    /// [`Error::WrongLength`], [`Error::NonFinite`] for a NaN or infinite
    /// input, invalid options or parameters, [`Error::NotConverged`] when
    /// Newton–Raphson stops above the tolerance, [`Error::Singular`] when
    /// the solution's conditioning is at or below the threshold.
    pub fn assemble_with(&self, guess: &[f64], options: &Options) -> Result<Vec<f64>, Error> {
        options.validate()?;
        self.validate()?;
        self.check_pose(guess)?;
        let mut q = guess.to_vec();
        let mut w = self.work();
        let mut modes = vec![f64::NAN; self.mode_count()];
        self.assemble_into(&mut q, &mut w, &mut modes, options, false)?;
        self.factor(&q, &mut w, options, true)?;
        Ok(q)
    }

    /// The motion at the closed pose `q` with the drivers' rates and
    /// accelerations.
    ///
    /// # Errors
    /// [`Error::WrongLength`], [`Error::NonFinite`] for a NaN or infinite
    /// input or output, invalid parameters, [`Error::Singular`] at a
    /// singular pose.
    pub fn analyze(
        &self,
        q: &[f64],
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<Motion, Error> {
        self.analyze_with(q, rates, accelerations, &Options::DEFAULT)
    }

    /// [`Model::analyze`] with explicit options.
    ///
    /// # Errors
    /// As [`Model::analyze`], and invalid options.
    pub fn analyze_with(
        &self,
        q: &[f64],
        rates: &[f64],
        accelerations: &[f64],
        options: &Options,
    ) -> Result<Motion, Error> {
        options.validate()?;
        self.validate()?;
        self.check_inputs(q, rates, accelerations)?;
        let mut w = self.work();
        self.analyze_at(q, rates, accelerations, &mut w, options, false)
    }

    /// Assembles at the drivers of `start` from its unknowns (as
    /// [`Model::assemble`]) and analyses the motion there (as
    /// [`Model::analyze`]).
    ///
    /// # Errors
    /// As [`Model::assemble`] and [`Model::analyze`].
    pub fn step(
        &self,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
    ) -> Result<Motion, Error> {
        let options = Options::DEFAULT;
        self.validate()?;
        self.check_inputs(start, rates, accelerations)?;
        let mut q = start.to_vec();
        let mut w = self.work();
        let mut modes = vec![f64::NAN; self.mode_count()];
        self.assemble_into(&mut q, &mut w, &mut modes, &options, false)?;
        self.analyze_at(&q, rates, accelerations, &mut w, &options, true)
    }

    /// The positions of the points at q (drivers first), `point_dim`
    /// components each; NaN where q does not give one.
    fn positions(&self, q: &[f64]) -> Vec<f64> {
        let n = self.coordinates.len();
        let d = self.point_dim;
        let mut out = vec![0.0; self.program.outputs(Program::OUTPUTS)];
        let zeros = vec![0.0; n];
        let mut params = self.values.clone();
        if let Some(l) = params.last_mut() {
            // The characteristic length scales nothing the points read.
            *l = 1.0;
        }
        if q.len() == n {
            let mut trig = vec![0.0; 2 * n];
            self.program.trig(q, &mut trig, 0);
            self.eval(
                Program::OUTPUTS,
                &params,
                q,
                &zeros,
                &zeros,
                &trig,
                &mut out,
            );
        }
        out.chunks_exact(3 * d)
            .take(self.points.len())
            .flat_map(|c| c[..d].iter().copied())
            .collect()
    }

    /// The lengths of the arrays, and every value finite.
    fn check_inputs(&self, q: &[f64], rates: &[f64], accelerations: &[f64]) -> Result<(), Error> {
        let nd = self.drivers;
        // The common case first: every length right and every value
        // finite (x·0 is 0 for a finite x, NaN otherwise); the errors are
        // found by the checks below.
        if q.len() == self.coordinates.len() && rates.len() == nd && accelerations.len() == nd {
            let mut zero = 0.0;
            for v in q {
                zero += v * 0.0;
            }
            for (r, a) in rates.iter().zip(accelerations) {
                zero += r * 0.0 + a * 0.0;
            }
            if zero == 0.0 {
                return Ok(());
            }
        }
        self.check_pose(q)?;
        self.length("driver rates", nd, rates.len())?;
        self.length("driver accelerations", nd, accelerations.len())?;
        let drivers = self.coordinates[..nd].iter();
        let rates_in = drivers
            .clone()
            .zip(rates)
            .map(|(c, &v)| (Input::DriverRate, c.name, v));
        let accels_in = drivers
            .zip(accelerations)
            .map(|(c, &v)| (Input::DriverAcceleration, c.name, v));
        for (input, name, value) in rates_in.chain(accels_in) {
            if !value.is_finite() {
                return Err(Error::NonFinite { input, name, value });
            }
        }
        Ok(())
    }

    /// A pose of the model's length with every value finite (drivers,
    /// then guesses of the unknowns).
    fn check_pose(&self, q: &[f64]) -> Result<(), Error> {
        self.length("coordinates", self.coordinates.len(), q.len())?;
        for (c, &value) in self.coordinates.iter().zip(q) {
            if !value.is_finite() {
                let input = match c.role {
                    Role::Driver => Input::Driver,
                    Role::Unknown => Input::Guess,
                };
                return Err(Error::NonFinite {
                    input,
                    name: c.name,
                    value,
                });
            }
        }
        Ok(())
    }

    fn length(&self, what: Name, expected: usize, found: usize) -> Result<(), Error> {
        if expected == found {
            Ok(())
        } else {
            Err(Error::WrongLength {
                what,
                expected,
                found,
            })
        }
    }
}
