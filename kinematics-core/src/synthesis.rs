//! Dimensional synthesis by Levenberg–Marquardt with exact derivatives.
//!
//! Path generation: find parameters p (link lengths, the coupler point,
//! the ground pivots: whatever the mechanism declares in its
//! `sensitivities` section and the synthesis varies) and, unless the
//! timing is prescribed, the driver values φ_j, so that a point passes
//! through N targets t_j:
//!
//! min over (p, φ) of  E = Σ_j |r(φ_j, p) − t_j|².
//!
//! Function generation: the same with an unknown coordinate u(φ_j, p)
//! instead of a point, against prescribed input–output pairs (φ_j, ψ_j),
//! with angle differences taken in (−π, π].
//!
//! Every residual's derivatives are exact: ∂r/∂p from the generated design
//! sensitivities (Φ_u ∂u/∂p = −Φ_p, ∂r/∂p = r_p + r_u ∂u/∂p) and ∂r/∂φ_j
//! as the point's velocity for a unit driver rate. The least-squares
//! problem is solved by the `levenberg-marquardt` crate (MINPACK's
//! trust-region algorithm).
//!
//! * **Assembly.** Every target is assembled in the same assembly modes,
//!   those of the starting pose (or those given by
//!   [`Synthesis::modes`]), so the design found works on one branch.
//!   A trial design that cannot be assembled at some target is rejected
//!   as a step that does not decrease E (the trust region shrinks).
//! * **Bounds** lo ≤ p ≤ hi are kept by the change of variables
//!   p = lo + (hi − lo)(1 + sin x)/2 (one bound: p = lo − 1 + √(x² + 1)),
//!   so every iterate is within them.
//! * **Linear inequalities** Σ c_k p_k ≤ h (and the Grashof condition for
//!   a crank, which is three of them) are added as residuals
//!   w · max(0, Σ c_k p_k − h); when the result violates one by more than
//!   10⁻¹⁰ of the design's scale, w grows a hundredfold and the
//!   minimisation goes on from there (at most six times).
//! * **Full turn.** For an angle driver, [`Synthesized::full_turn`] says
//!   whether the design sweeps a whole turn in its assembly modes.
//!
//! ```
//! use kinematics_core::{mechanism, synthesis::Synthesis};
//!
//! mechanism! {
//!     /// A four-bar with its coupler point P.
//!     struct FourBar {
//!         params { a, b, c, d, p, beta }
//!         drivers { phi }
//!         unknowns { th3, th4 }
//!         points { P = polar(a, phi) + polar(p, th3 + beta); }
//!         loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
//!         sensitivities { a, b, c, p, beta }
//!     }
//! }
//!
//! # fn main() -> Result<(), kinematics_core::Error> {
//! // Targets: five points of the coupler curve of a known design, at
//! // φ = 0.3, 1.1, 2.0, 3.5 and 5.0.
//! let truth = FourBar { a: 1.0, b: 3.0, c: 2.5, d: 3.0, p: 1.5, beta: 0.6 };
//! let start = truth.assemble(&FourBarCoords { phi: 0.0, th3: 0.5, th4: 1.5 })?;
//! let targets: Vec<[f64; 2]> = [0.3, 1.1, 2.0, 3.5, 5.0]
//!     .iter()
//!     .map(|&phi| {
//!         let pose = truth.assemble(&FourBarCoords { phi, ..start }).unwrap();
//!         let p = truth.positions(&pose).P;
//!         [p.x, p.y]
//!     })
//!     .collect();
//! // From a design 10 % off, with the same crank angles prescribed.
//! let guess = FourBar { a: 1.1, b: 2.8, c: 2.7, d: 3.0, p: 1.3, beta: 0.5 };
//! let found = Synthesis::path(&guess, FourBar::PHI, "P", &targets, &start)
//!     .prescribed(&[0.3, 1.1, 2.0, 3.5, 5.0])
//!     .run()?;
//! assert!(found.sum_squares < 1e-20);
//! assert!((found.design.c - 2.5).abs() < 1e-9);
//! # Ok(())
//! # }
//! ```

use core::cell::{Cell, RefCell};
use core::f64::consts::{PI, TAU};
use std::format;
use std::string::String;
use std::vec;
use std::vec::Vec;

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra_lm::{storage::Owned, DMatrix, DVector, Dyn};

use crate::closed::Mode;
use crate::sweep::{Driver, SweepBuilder};
use crate::tolerance::Sensitive;
use crate::{Coordinates, Error, Kind, MotionState, Options, PointState, Role};

/// How the driver values of the targets are found.
#[derive(Debug, Clone, PartialEq)]
pub enum Timing {
    /// Each target's driver value is an unknown of the synthesis (path
    /// generation without prescribed timing). Initial values: those of
    /// [`Synthesis::driver_guesses`], or N values evenly spaced over a turn
    /// (over [0, 1] for a length driver) from the start pose's.
    Free,
    /// The driver values are given, one per target.
    Prescribed(Vec<f64>),
    /// φ_j = φ₀ + Δ_j with the increments Δ_j given and φ₀ an unknown
    /// (initially the start pose's driver value).
    Relative(Vec<f64>),
}

/// What is compared with the targets.
#[derive(Debug, Clone, Copy)]
enum Output {
    /// A point (index), all its components.
    Point(usize),
    /// A coordinate (index), an angle or a length.
    Coordinate(usize, Kind),
}

/// A dimensional synthesis problem, set up with [`Synthesis::path`] or
/// [`Synthesis::function`] and solved with [`Synthesis::run`].
#[derive(Debug, Clone)]
pub struct Synthesis<M: Sensitive> {
    design: M,
    start: M::Coords,
    driver: usize,
    driver_kind: Kind,
    output: Output,
    dim: usize,
    targets: Vec<f64>,
    varied: Vec<usize>,
    bounds: Vec<(f64, f64)>,
    timing: Timing,
    guesses: Option<Vec<f64>>,
    linear: Vec<(Vec<(usize, f64)>, f64)>,
    modes: Option<Vec<f64>>,
    options: Options,
    patience: usize,
    problem: Option<Error>,
}

/// The result of a synthesis.
#[derive(Debug, Clone)]
pub struct Synthesized<M> {
    /// The design found (the varied parameters changed, the others as
    /// given).
    pub design: M,
    /// The driver value at each target.
    pub driver_values: Vec<f64>,
    /// E = Σ_j |output_j − target_j|² (angle differences in (−π, π]).
    pub sum_squares: f64,
    /// The largest |output_j − target_j|.
    pub max_error: f64,
    /// How many times the residuals were evaluated (each is one analysis
    /// per target).
    pub evaluations: usize,
    /// How many times the Jacobian was evaluated (each is one analysis and
    /// one sensitivity solve per target).
    pub jacobians: usize,
    /// How many trial designs could not be assembled at some target (each
    /// rejected as a step).
    pub rejected: usize,
    /// Whether every linear inequality holds (to 10⁻¹⁰ of the design's
    /// scale).
    pub constraints_met: bool,
    /// For an angle driver, whether the design sweeps a whole turn from the
    /// first target's pose in its assembly modes; `None` for a length
    /// driver.
    pub full_turn: Option<bool>,
    /// Why the last minimisation ended, as the solver reports it.
    pub termination: String,
}

impl<M: Sensitive + Clone> Synthesis<M> {
    /// Path generation: point `point` of `design` through `targets` (each
    /// with the point's number of components), driven by `driver`, with
    /// every parameter of the `sensitivities` section varied and free
    /// timing; `start` is a pose of `design` that fixes the assembly modes
    /// (and the guess of the unknowns for blocks solved by Newton–Raphson).
    pub fn path<U, T: AsRef<[f64]>>(
        design: &M,
        driver: Driver<M, U>,
        point: &str,
        targets: &[T],
        start: &M::Coords,
    ) -> Self {
        let mut s = Self::new(design, driver.index(), start);
        match M::POINT_NAMES.iter().position(|p| *p == point) {
            Some(i) => s.output = Output::Point(i),
            None => s.fail(format!(
                "the mechanism has no point `{point}`; its points are {}",
                M::POINT_NAMES.join(", ")
            )),
        }
        s.dim = M::POINT_DIM;
        for (j, t) in targets.iter().enumerate() {
            let t = t.as_ref();
            if t.len() != M::POINT_DIM {
                s.fail(format!(
                    "target {j} has {} components; point `{point}` has {}",
                    t.len(),
                    M::POINT_DIM
                ));
            }
            s.targets.extend(t.iter().copied());
        }
        s.timing = Timing::Free;
        s
    }

    /// Function generation: the unknown coordinate `output` of `design`
    /// through the input–output pairs (driver value, output value), with
    /// every parameter of the `sensitivities` section varied and the
    /// driver values prescribed as the pairs' first members; `start` as
    /// for [`Synthesis::path`].
    pub fn function<U>(
        design: &M,
        driver: Driver<M, U>,
        output: &str,
        pairs: &[(f64, f64)],
        start: &M::Coords,
    ) -> Self {
        let mut s = Self::new(design, driver.index(), start);
        match M::COORDINATES
            .iter()
            .position(|c| c.name == output && c.role == Role::Unknown)
        {
            Some(i) => s.output = Output::Coordinate(i, M::COORDINATES[i].kind),
            None => s.fail(format!(
                "the mechanism has no unknown `{output}`; its unknowns are {}",
                M::COORDINATES
                    .iter()
                    .filter(|c| c.role == Role::Unknown)
                    .map(|c| c.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
        s.dim = 1;
        s.targets = pairs.iter().map(|p| p.1).collect();
        s.timing = Timing::Prescribed(pairs.iter().map(|p| p.0).collect());
        s
    }

    fn new(design: &M, driver: usize, start: &M::Coords) -> Self {
        let driver_kind = M::COORDINATES.get(driver).map_or(Kind::Length, |c| c.kind);
        Self {
            design: design.clone(),
            start: *start,
            driver,
            driver_kind,
            output: Output::Point(0),
            dim: 0,
            targets: Vec::new(),
            varied: (0..M::PARAMETERS.len()).collect(),
            bounds: vec![(f64::NEG_INFINITY, f64::INFINITY); M::PARAMETERS.len()],
            timing: Timing::Free,
            guesses: None,
            linear: Vec::new(),
            modes: None,
            options: Options::DEFAULT,
            patience: 200,
            problem: None,
        }
    }

    fn fail(&mut self, detail: String) {
        if self.problem.is_none() {
            self.problem = Some(Error::InvalidGeometry {
                what: "synthesis",
                detail,
            });
        }
    }

    fn parameter_index(&mut self, name: &str) -> Option<usize> {
        let k = M::PARAMETERS.iter().position(|p| *p == name);
        if k.is_none() {
            self.fail(format!(
                "`{name}` is not a parameter of the `sensitivities` section, which lists {}",
                M::PARAMETERS.join(", ")
            ));
        }
        k
    }

    /// Varies only the parameters `names` (of the `sensitivities`
    /// section); the others keep the values of the design given.
    #[must_use]
    pub fn vary(mut self, names: &[&str]) -> Self {
        let varied: Vec<usize> = names
            .iter()
            .filter_map(|n| self.parameter_index(n))
            .collect();
        self.varied = varied;
        self
    }

    /// Keeps parameter `name` within [lo, hi] (either may be infinite).
    #[must_use]
    pub fn bounds(mut self, name: &str, lo: f64, hi: f64) -> Self {
        if let Some(k) = self.parameter_index(name) {
            if lo.is_nan() || hi.is_nan() || lo >= hi {
                self.fail(format!(
                    "the bounds of `{name}` must satisfy lo < hi, not [{lo}, {hi}]"
                ));
            }
            self.bounds[k] = (lo, hi);
        }
        self
    }

    /// The timing (see [`Timing`]; path generation defaults to
    /// [`Timing::Free`], function generation to the pairs' inputs).
    #[must_use]
    pub fn timing(mut self, timing: Timing) -> Self {
        self.timing = timing;
        self
    }

    /// Prescribed timing: the driver value of each target.
    #[must_use]
    pub fn prescribed(self, driver_values: &[f64]) -> Self {
        self.timing(Timing::Prescribed(driver_values.to_vec()))
    }

    /// Initial driver values for [`Timing::Free`], one per target.
    #[must_use]
    pub fn driver_guesses(mut self, values: &[f64]) -> Self {
        self.guesses = Some(values.to_vec());
        self
    }

    /// The linear inequality Σ c_k p_k ≤ `bound` over named parameters.
    #[must_use]
    pub fn at_most(mut self, terms: &[(&str, f64)], bound: f64) -> Self {
        let terms: Vec<(usize, f64)> = terms
            .iter()
            .filter_map(|(n, c)| self.parameter_index(n).map(|k| (k, *c)))
            .collect();
        self.linear.push((terms, bound));
        self
    }

    /// Grashof's condition with the link `crank` the shortest, so that it
    /// turns fully, kept `margin` away from its boundary: s + l ≤ p + q −
    /// margin for the lengths (`crank`, `coupler`, `rocker`, `ground`), as
    /// the three inequalities crank + x ≤ (sum of the other two) − margin
    /// for x each of the others (which together also make the crank the
    /// shortest). On the boundary (margin 0) the linkage folds flat once a
    /// turn, at a change point, so a margin of a few per cent of the
    /// lengths keeps it a clean crank.
    #[must_use]
    pub fn grashof_crank(
        self,
        crank: &str,
        coupler: &str,
        rocker: &str,
        ground: &str,
        margin: f64,
    ) -> Self {
        self.at_most(
            &[(crank, 1.0), (coupler, 1.0), (rocker, -1.0), (ground, -1.0)],
            -margin,
        )
        .at_most(
            &[(crank, 1.0), (rocker, 1.0), (coupler, -1.0), (ground, -1.0)],
            -margin,
        )
        .at_most(
            &[(crank, 1.0), (ground, 1.0), (coupler, -1.0), (rocker, -1.0)],
            -margin,
        )
    }

    /// The assembly modes of the closed-form blocks, in the order of the
    /// mechanism's `BLOCKS` (default: those of the start pose).
    #[must_use]
    pub fn modes(mut self, modes: &[Mode]) -> Self {
        self.modes = Some(modes.iter().map(|m| m.sign()).collect());
        self
    }

    /// The analysis options (tolerance, conditioning threshold).
    #[must_use]
    pub fn options(mut self, options: &Options) -> Self {
        self.options = *options;
        self
    }

    /// The most residual evaluations of one minimisation, per unknown
    /// (default 200).
    #[must_use]
    pub fn patience(mut self, patience: usize) -> Self {
        self.patience = patience.max(1);
        self
    }

    /// Runs the synthesis from the design given.
    ///
    /// # Errors
    /// [`Error::InvalidGeometry`] for a name that is not a point,
    /// unknown or parameter, targets of the wrong size, or timing values
    /// of the wrong count; [`Error::InvalidOption`] for non-finite
    /// targets; the error of the analysis when the starting design cannot
    /// be assembled at a target.
    pub fn run(self) -> Result<Synthesized<M>, Error> {
        if let Some(e) = self.problem {
            return Err(e);
        }
        let n = self.targets.len().checked_div(self.dim).unwrap_or(0);
        if n == 0 {
            return Err(Error::InvalidGeometry {
                what: "synthesis",
                detail: "there are no targets".into(),
            });
        }
        if self.targets.iter().any(|t| !t.is_finite()) {
            return Err(Error::InvalidOption {
                name: "targets",
                value: f64::NAN,
                requirement: "must be finite",
            });
        }
        let count_ok = match &self.timing {
            Timing::Free => self.guesses.as_ref().is_none_or(|g| g.len() == n),
            Timing::Prescribed(v) | Timing::Relative(v) => v.len() == n,
        };
        if !count_ok {
            return Err(Error::InvalidGeometry {
                what: "synthesis",
                detail: format!("the timing needs one driver value per target ({n})"),
            });
        }
        let mut state = self.design.step_state(&self.options)?;
        if let Some(modes) = &self.modes {
            let slots = M::step_modes(&mut state);
            if modes.len() != slots.len() {
                return Err(Error::InvalidGeometry {
                    what: "synthesis",
                    detail: format!(
                        "{} assembly modes given; the mechanism has {} closed-form blocks",
                        modes.len(),
                        slots.len()
                    ),
                });
            }
            slots.copy_from_slice(modes);
        }
        // The modes of the start pose (when not given).
        let zeros = M::Coords::default();
        self.design
            .step_carried(&self.start, &zeros, &zeros, &mut state)?;
        let phi0 = self.start.get(self.driver).unwrap_or(0.0);
        let timing_unknowns: Vec<f64> = match &self.timing {
            Timing::Free => self
                .guesses
                .clone()
                .or_else(|| self.nearest_on_path(n))
                .unwrap_or_else(|| {
                    let span = if self.driver_kind == Kind::Angle {
                        TAU
                    } else {
                        1.0
                    };
                    #[allow(clippy::cast_precision_loss)]
                    (0..n).map(|j| phi0 + span * j as f64 / n as f64).collect()
                }),
            Timing::Prescribed(_) => Vec::new(),
            Timing::Relative(_) => vec![phi0],
        };
        let scale = self
            .varied
            .iter()
            .map(|&k| self.design.parameter(k).abs())
            .fold(0.0f64, f64::max)
            .max(1e-300);
        let mut problem = Problem {
            s: &self,
            n,
            x: Vec::new(),
            weight: 1.0 / scale.max(1.0),
            reject: f64::INFINITY,
            poses: RefCell::new(vec![self.start; n]),
            modes: M::step_modes(&mut state).to_vec(),
            evaluations: Cell::new(0),
            jacobians: Cell::new(0),
            rejected: Cell::new(0),
        };
        // x: the varied parameters in their bounded variables, then the
        // timing unknowns.
        let mut x: Vec<f64> = self
            .varied
            .iter()
            .map(|&k| to_free(self.design.parameter(k), self.bounds[k]))
            .collect();
        x.extend(&timing_unknowns);
        problem.x = x;
        let r0 = problem.evaluate(&problem.x.clone(), false)?;
        problem.reject = 10.0 * norm(&r0.0) + 1.0;
        let mut termination = String::new();
        for _round in 0..7 {
            let lm = LevenbergMarquardt::new().with_patience(self.patience);
            let (solved, report) = lm.minimize(problem);
            problem = solved;
            termination = format!("{:?}", report.termination);
            if problem.violation() <= 1e-10 * scale || self.linear.is_empty() {
                break;
            }
            problem.weight *= 100.0;
        }
        let x = problem.x.clone();
        let (design, values) = problem.design_at(&x);
        let (res, _) = problem.evaluate(&x, false)?;
        let e = problem.errors(&res);
        let full_turn = (self.driver_kind == Kind::Angle).then(|| {
            let mut first = problem.poses.borrow()[0];
            first.set(self.driver, values[0]);
            let sweep = SweepBuilder::new(
                &design,
                Driver::<M, crate::sweep::Angle>::__new(
                    self.driver,
                    M::COORDINATES[self.driver].name,
                ),
                &first,
            )
            .turn()
            .options(&self.options)
            .run();
            sweep.stop.is_none()
        });
        Ok(Synthesized {
            design,
            driver_values: values,
            sum_squares: e.0,
            max_error: e.1,
            evaluations: problem.evaluations.get(),
            jacobians: problem.jacobians.get(),
            rejected: problem.rejected.get(),
            constraints_met: problem.violation() <= 1e-10 * scale,
            full_turn,
            termination,
        })
    }
}

impl<M: Sensitive + Clone> Synthesis<M> {
    /// For free timing with a point and an angle driver: each target's
    /// initial driver value, that of the sample of the starting design's
    /// path (one turn each way from the start, 360 steps, in the start's
    /// modes) nearest the target. `None` when the path has no sample.
    fn nearest_on_path(&self, n: usize) -> Option<Vec<f64>> {
        let Output::Point(k) = self.output else {
            return None;
        };
        if self.driver_kind != Kind::Angle {
            return None;
        }
        let handle =
            Driver::<M, crate::sweep::Angle>::__new(self.driver, M::COORDINATES[self.driver].name);
        let phi0 = self.start.get(self.driver)?;
        let mut samples = Vec::new();
        for to in [phi0 + TAU, phi0 - TAU] {
            let sweep = SweepBuilder::new(&self.design, handle, &self.start)
                .to(to)
                .steps(360)
                .options(&self.options)
                .run();
            let stopped = sweep.stop.is_some();
            samples.extend(sweep.samples.iter().filter_map(|x| {
                x.motion
                    .points()
                    .get(k)
                    .map(|p| (x.at, p.position().to_vec()))
            }));
            if !stopped {
                break;
            }
        }
        if samples.is_empty() {
            return None;
        }
        let d = self.dim;
        Some(
            (0..n)
                .map(|j| {
                    let t = &self.targets[j * d..(j + 1) * d];
                    let dist = |r: &[f64]| -> f64 {
                        r.iter().zip(t).map(|(a, b)| (a - b) * (a - b)).sum()
                    };
                    samples
                        .iter()
                        .min_by(|a, b| dist(&a.1).total_cmp(&dist(&b.1)))
                        .map_or(phi0, |s| s.0)
                })
                .collect(),
        )
    }
}

/// The bounded parameter p for the free variable x.
fn from_free(x: f64, (lo, hi): (f64, f64)) -> (f64, f64) {
    match (lo.is_finite(), hi.is_finite()) {
        (true, true) => (
            lo + (hi - lo) * 0.5 * (1.0 + (x).sin()),
            (hi - lo) * 0.5 * (x).cos(),
        ),
        (true, false) => {
            let r = (x * x + 1.0).sqrt();
            (lo - 1.0 + r, x / r)
        }
        (false, true) => {
            let r = (x * x + 1.0).sqrt();
            (hi + 1.0 - r, -x / r)
        }
        (false, false) => (x, 1.0),
    }
}

/// The free variable x of the bounded parameter p (p clamped into the
/// bounds).
fn to_free(p: f64, (lo, hi): (f64, f64)) -> f64 {
    match (lo.is_finite(), hi.is_finite()) {
        (true, true) => {
            let t = (2.0 * (p - lo) / (hi - lo) - 1.0).clamp(-1.0, 1.0);
            (t).asin()
        }
        (true, false) => {
            let r = (p - lo + 1.0).max(1.0);
            (r * r - 1.0).sqrt()
        }
        (false, true) => {
            let r = (hi + 1.0 - p).max(1.0);
            -(r * r - 1.0).sqrt()
        }
        (false, false) => p,
    }
}

fn norm(v: &[f64]) -> f64 {
    crate::math::sqrt(v.iter().map(|x| x * x).sum())
}

/// An angle difference in (−π, π].
fn wrapped(d: f64) -> f64 {
    PI - (PI - d).rem_euclid(TAU)
}

/// The least-squares problem handed to the solver.
struct Problem<'s, M: Sensitive> {
    s: &'s Synthesis<M>,
    n: usize,
    x: Vec<f64>,
    /// The weight of the inequality residuals.
    weight: f64,
    /// The size of the residual vector returned for a design that cannot
    /// be assembled (larger than any the solver has accepted).
    reject: f64,
    /// The last pose of each target (the guess of the next analysis).
    poses: RefCell<Vec<M::Coords>>,
    /// The assembly modes (as the step state holds them).
    modes: Vec<f64>,
    evaluations: Cell<usize>,
    jacobians: Cell<usize>,
    rejected: Cell<usize>,
}

impl<M: Sensitive + Clone> Problem<'_, M> {
    /// The design and driver values at x.
    fn design_at(&self, x: &[f64]) -> (M, Vec<f64>) {
        let s = self.s;
        let mut design = s.design.clone();
        for (i, &k) in s.varied.iter().enumerate() {
            design.set_parameter(k, from_free(x[i], s.bounds[k]).0);
        }
        let t = &x[s.varied.len()..];
        let values = match &s.timing {
            Timing::Free => t.to_vec(),
            Timing::Prescribed(v) => v.clone(),
            Timing::Relative(v) => v.iter().map(|d| t[0] + d).collect(),
        };
        (design, values)
    }

    /// The largest violation of a linear inequality.
    fn violation(&self) -> f64 {
        let (design, _) = self.design_at(&self.x);
        self.s
            .linear
            .iter()
            .map(|(terms, h)| {
                terms
                    .iter()
                    .map(|&(k, c)| c * design.parameter(k))
                    .sum::<f64>()
                    - h
            })
            .fold(0.0f64, f64::max)
    }

    /// E and the largest error from the residuals (the inequality
    /// residuals left out).
    fn errors(&self, res: &[f64]) -> (f64, f64) {
        let d = self.s.dim;
        let fit = &res[..self.n * d];
        let e = fit.iter().map(|r| r * r).sum();
        let worst = fit.chunks(d).map(norm).fold(0.0f64, f64::max);
        (e, worst)
    }

    /// The residuals at x and, if `jacobian`, the Jacobian (row-major,
    /// residuals × unknowns).
    fn evaluate(&self, x: &[f64], jacobian: bool) -> Result<(Vec<f64>, Vec<f64>), Error> {
        let s = self.s;
        let (n, d, nv) = (self.n, s.dim, s.varied.len());
        let nx = x.len();
        let (design, values) = self.design_at(x);
        let np = M::PARAMETERS.len();
        let nrows = n * d + s.linear.len();
        let mut res = vec![0.0; nrows];
        let mut jac = if jacobian {
            vec![0.0; nrows * nx]
        } else {
            Vec::new()
        };
        let mut rates = M::Coords::default();
        rates.set(s.driver, 1.0);
        let zeros = M::Coords::default();
        let ncoord = M::COORDINATES.len();
        let mut dq = vec![0.0; np * ncoord];
        let mut dr = vec![0.0; np * M::POINTS * M::POINT_DIM];
        let dpdx: Vec<f64> = s
            .varied
            .iter()
            .enumerate()
            .map(|(i, &k)| from_free(x[i], s.bounds[k]).1)
            .collect();
        // A fresh state for the design (its scaling and the sines and
        // cosines of its parameters), in the modes of the synthesis.
        let mut fresh = design.step_state(&s.options)?;
        M::step_modes(&mut fresh).copy_from_slice(&self.modes);
        let mut poses = self.poses.borrow_mut();
        for j in 0..n {
            let mut pose = poses[j];
            pose.set(s.driver, values[j]);
            let mut state = fresh.clone();
            let motion = design.step_carried(&pose, &rates, &zeros, &mut state)?;
            poses[j] = *motion.q();
            if jacobian {
                design.position_sensitivities_into(&motion, &mut dq, &mut dr)?;
            }
            // ∂(output)/∂φ_j and ∂(output)/∂p_k per component.
            for c in 0..d {
                let row = j * d + c;
                let (value, rate) = match s.output {
                    Output::Point(i) => {
                        let p = &motion.points()[i];
                        (p.position()[c], p.velocity()[c])
                    }
                    Output::Coordinate(i, _) => (
                        motion.q().get(i).unwrap_or(f64::NAN),
                        motion.qd().get(i).unwrap_or(f64::NAN),
                    ),
                };
                let target = s.targets[row];
                res[row] = match s.output {
                    Output::Coordinate(_, Kind::Angle) => wrapped(value - target),
                    _ => value - target,
                };
                if !jacobian {
                    continue;
                }
                let jr = &mut jac[row * nx..(row + 1) * nx];
                for (i, &k) in s.varied.iter().enumerate() {
                    let dp = match s.output {
                        Output::Point(pi) => dr[(k * M::POINTS + pi) * M::POINT_DIM + c],
                        Output::Coordinate(ci, _) => dq[k * ncoord + ci],
                    };
                    jr[i] = dp * dpdx[i];
                }
                match &s.timing {
                    Timing::Free => jr[nv + j] = rate,
                    Timing::Relative(_) => jr[nv] = rate,
                    Timing::Prescribed(_) => {}
                }
            }
        }
        for (l, (terms, h)) in s.linear.iter().enumerate() {
            let row = n * d + l;
            let g = terms
                .iter()
                .map(|&(k, c)| c * design.parameter(k))
                .sum::<f64>()
                - h;
            if g > 0.0 {
                res[row] = self.weight * g;
                if jacobian {
                    for &(k, c) in terms {
                        if let Some(i) = s.varied.iter().position(|&v| v == k) {
                            jac[row * nx + i] += self.weight * c * dpdx[i];
                        }
                    }
                }
            }
        }
        if res.iter().chain(&jac).any(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                input: crate::Input::Computed,
                name: "synthesis residual",
                value: f64::NAN,
            });
        }
        Ok((res, jac))
    }

    fn rows(&self) -> usize {
        self.n * self.s.dim + self.s.linear.len()
    }
}

impl<M: Sensitive + Clone> LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, M> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.x = x.iter().copied().collect();
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_column_slice(&self.x)
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.evaluations.set(self.evaluations.get() + 1);
        let rows = self.rows();
        match self.evaluate(&self.x, false) {
            Ok((r, _)) => Some(DVector::from_vec(r)),
            // A design that does not assemble: a residual larger than any
            // accepted, so that the step is rejected.
            #[allow(clippy::cast_precision_loss)]
            Err(_) => {
                self.rejected.set(self.rejected.get() + 1);
                Some(DVector::from_element(
                    rows,
                    self.reject / (rows as f64).sqrt(),
                ))
            }
        }
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        self.jacobians.set(self.jacobians.get() + 1);
        let (_, j) = self.evaluate(&self.x, true).ok()?;
        Some(DMatrix::from_row_slice(self.rows(), self.x.len(), &j))
    }
}
