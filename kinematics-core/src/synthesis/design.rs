//! The synthesis problem as posed (targets, timing, free parameters and
//! bounds) and its solution by Levenberg–Marquardt from a starting design.

use core::cell::{Cell, RefCell};
use core::f64::consts::TAU;
use std::format;
use std::string::String;
use std::vec;
use std::vec::Vec;

use levenberg_marquardt::LevenbergMarquardt;

use crate::closed::Mode;
use crate::error::Error;
use crate::mechanism::{Kind, Role};
use crate::options::Options;

use super::problem::{Problem, norm, to_free};
use super::subject::{DriverOf, Shape, Solved, Subject};

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
pub(super) enum Output {
    /// A point (index), all its components.
    Point(usize),
    /// A coordinate (index), an angle or a length.
    Coordinate(usize, Kind),
    /// A body's pose: a point (index), all its components, and an angle
    /// coordinate (index) whose difference is weighed by a length.
    Motion(usize, usize, f64),
}

/// A dimensional synthesis problem, set up with [`Synthesis::path`] or
/// [`Synthesis::function`] and solved with [`Synthesis::run`].
#[derive(Debug, Clone)]
pub struct Synthesis<M: Subject> {
    pub(super) design: M,
    pub(super) shape: Shape,
    pub(super) start: M::Pose,
    pub(super) driver: usize,
    driver_kind: Kind,
    pub(super) output: Output,
    pub(super) dim: usize,
    pub(super) targets: Vec<f64>,
    pub(super) varied: Vec<usize>,
    pub(super) bounds: Vec<(f64, f64)>,
    pub(super) timing: Timing,
    pub(super) guesses: Option<Vec<f64>>,
    /// w_j per target (none: all 1).
    pub(super) weights: Option<Vec<f64>>,
    pub(super) linear: Vec<(Vec<(usize, f64)>, f64)>,
    /// Whether free driver values must increase through the targets.
    pub(super) ordered: bool,
    /// With `ordered` and an angle driver, the most φ_N − φ₁ (2π).
    pub(super) order_span: f64,
    pub(super) modes: Option<Vec<f64>>,
    pub(super) options: Options,
    pub(super) patience: usize,
    pub(super) problem: Option<Error>,
}

/// The result of a synthesis.
#[derive(Debug, Clone)]
pub struct Synthesized<M> {
    /// The design found (the varied parameters changed, the others as
    /// given).
    pub design: M,
    /// The driver value at each target.
    pub driver_values: Vec<f64>,
    /// E = Σ_j w_j |output_j − target_j|² (angle differences in (−π, π],
    /// weighed by the length given in motion generation; w_j the
    /// weights, 1 unless given).
    pub sum_squares: f64,
    /// |output_j − target_j| at each target (not weighted).
    pub target_errors: Vec<f64>,
    /// The largest of [`Self::target_errors`].
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
    /// scale), and with [`Synthesis::in_order`] the order of the driver
    /// values.
    pub constraints_met: bool,
    /// For an angle driver, whether the design sweeps a whole turn from the
    /// first target's pose in its assembly modes; `None` for a length
    /// driver.
    pub full_turn: Option<bool>,
    /// Why the last minimisation ended, as the solver reports it.
    pub termination: String,
}

impl<M: Subject> Synthesis<M> {
    /// Path generation: point `point` of `design` through `targets` (each
    /// with the point's number of components), driven by `driver` (a
    /// generated mechanism's handle, `FourBar::PHI`, or a run-time
    /// model's driver by name), with every parameter of the
    /// `sensitivities` section varied and free timing; `start` is a pose
    /// of `design` that fixes the assembly modes (and the guess of the
    /// unknowns for blocks solved by Newton–Raphson).
    pub fn path<T: AsRef<[f64]>>(
        design: &M,
        driver: impl DriverOf<M>,
        point: &str,
        targets: &[T],
        start: &M::Pose,
    ) -> Self {
        let mut s = Self::new(design, driver.driver_index(design), start);
        let dim = s.shape.point_dim;
        match s.shape.points.iter().position(|p| *p == point) {
            Some(i) => s.output = Output::Point(i),
            None => {
                let names = s.shape.points.join(", ");
                s.fail(format!(
                    "the mechanism has no point `{point}`; its points are {names}"
                ));
            }
        }
        s.dim = dim;
        for (j, t) in targets.iter().enumerate() {
            let t = t.as_ref();
            if t.len() != dim {
                s.fail(format!(
                    "target {j} has {} components; point `{point}` has {dim}",
                    t.len(),
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
    /// driver values prescribed as the pairs' first members; `driver` and
    /// `start` as for [`Synthesis::path`].
    pub fn function(
        design: &M,
        driver: impl DriverOf<M>,
        output: &str,
        pairs: &[(f64, f64)],
        start: &M::Pose,
    ) -> Self {
        let mut s = Self::new(design, driver.driver_index(design), start);
        let coordinates = &s.shape.coordinates;
        match coordinates
            .iter()
            .position(|c| c.name == output && c.role == Role::Unknown)
        {
            Some(i) => s.output = Output::Coordinate(i, coordinates[i].kind),
            None => {
                let names = coordinates
                    .iter()
                    .filter(|c| c.role == Role::Unknown)
                    .map(|c| c.name)
                    .collect::<Vec<_>>()
                    .join(", ");
                s.fail(format!(
                    "the mechanism has no unknown `{output}`; its unknowns are {names}"
                ));
            }
        }
        s.dim = 1;
        s.targets = pairs.iter().map(|p| p.1).collect();
        s.timing = Timing::Prescribed(pairs.iter().map(|p| p.0).collect());
        s
    }

    /// Motion generation: a body through poses, each the position of its
    /// point `point` and the value of its angle coordinate `angle` (an
    /// unknown or a driver of `design`: the coupler's θ3, say), with free
    /// timing as [`Synthesis::path`]. Each pose is `[x, y, θ]` (`[x, y, z,
    /// θ]` in space) and its error |r_j − t_j|² + (ℓ·Δθ_j)², Δθ_j in
    /// (−π, π], with ℓ = `length` the length that weighs an angle against a
    /// distance (the body's size, say).
    pub fn motion<T: AsRef<[f64]>>(
        design: &M,
        driver: impl DriverOf<M>,
        (point, angle): (&str, &str),
        poses: &[T],
        length: f64,
        start: &M::Pose,
    ) -> Self {
        let mut s = Self::path(design, driver, point, &[] as &[&[f64]], start);
        let Output::Point(p) = s.output else {
            return s;
        };
        match s
            .shape
            .coordinates
            .iter()
            .position(|c| c.name == angle && c.kind == Kind::Angle)
        {
            Some(i) => s.output = Output::Motion(p, i, length),
            None => {
                let names = s
                    .shape
                    .coordinates
                    .iter()
                    .filter(|c| c.kind == Kind::Angle)
                    .map(|c| c.name)
                    .collect::<Vec<_>>()
                    .join(", ");
                s.fail(format!(
                    "the mechanism has no angle coordinate `{angle}`; its angles are {names}"
                ));
            }
        }
        if !(length.is_finite() && length > 0.0) {
            s.fail(format!(
                "the length that weighs the angles must be positive and finite, not {length}"
            ));
        }
        let dim = s.shape.point_dim + 1;
        s.dim = dim;
        for (j, t) in poses.iter().enumerate() {
            let t = t.as_ref();
            if t.len() != dim {
                s.fail(format!(
                    "pose {j} has {} components; a pose of `{point}` and `{angle}` has {dim}",
                    t.len(),
                ));
            }
            s.targets.extend(t.iter().copied());
        }
        s
    }

    fn new(design: &M, driver: Result<usize, String>, start: &M::Pose) -> Self {
        let shape = design.shape();
        let n = shape.parameters.len();
        let index = driver.as_ref().map_or(0, |&i| i);
        let driver_kind = shape
            .coordinates
            .get(index)
            .map_or(Kind::Length, |c| c.kind);
        let mut s = Self {
            design: design.clone(),
            shape,
            start: start.clone(),
            driver: index,
            driver_kind,
            output: Output::Point(0),
            dim: 0,
            targets: Vec::new(),
            varied: (0..n).collect(),
            bounds: vec![(f64::NEG_INFINITY, f64::INFINITY); n],
            timing: Timing::Free,
            guesses: None,
            weights: None,
            linear: Vec::new(),
            ordered: false,
            order_span: TAU,
            modes: None,
            options: Options::DEFAULT,
            patience: 200,
            problem: None,
        };
        if let Err(detail) = driver {
            s.fail(detail);
        }
        s
    }

    /// Whether the driver is an angle.
    pub(super) fn driver_is_angle(&self) -> bool {
        self.driver_kind == Kind::Angle
    }

    pub(super) fn fail(&mut self, detail: String) {
        if self.problem.is_none() {
            self.problem = Some(Error::InvalidGeometry {
                what: "synthesis",
                detail,
            });
        }
    }

    fn parameter_index(&mut self, name: &str) -> Option<usize> {
        let k = self.shape.parameters.iter().position(|p| *p == name);
        if k.is_none() {
            let names = self.shape.parameters.join(", ");
            self.fail(format!(
                "`{name}` is not a parameter of the `sensitivities` section, which lists {names}"
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

    /// The weight w_j > 0 of each target: E = Σ_j w_j |output_j −
    /// target_j|² (default: every weight 1; leave a target out rather
    /// than weigh it 0).
    #[must_use]
    pub fn weights(mut self, weights: &[f64]) -> Self {
        if weights.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
            self.fail(format!(
                "the weights must be positive and finite, not {weights:?} (leave a target out rather than weigh it 0)"
            ));
        }
        self.weights = Some(weights.to_vec());
        self
    }

    /// With [`Timing::Free`], keeps the driver values in order through
    /// the targets: φ₁ ≤ φ₂ ≤ … ≤ φ_N, and for an angle driver
    /// φ_N ≤ φ₁ + 2π (the driver turns one way, less than a turn, as the
    /// targets are listed). Each is a penalty residual as the linear
    /// inequalities are ([`Synthesis::at_most`]); starting values out of
    /// order are sorted first.
    #[must_use]
    pub fn in_order(mut self) -> Self {
        self.ordered = true;
        self
    }

    /// [`Synthesis::in_order`] with φ_N ≤ φ₁ + `span` for an angle driver
    /// instead of a whole turn: less than 2π keeps the last target's crank
    /// angle short of the first's a turn later (a strict order modulo a
    /// turn, as some published benchmarks score it).
    #[must_use]
    pub fn in_order_within(mut self, span: f64) -> Self {
        if !(span.is_finite() && span > 0.0) {
            self.fail(format!(
                "the span of the order must be positive, not {span}"
            ));
        }
        self.ordered = true;
        self.order_span = span;
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

    /// The problem checked as posed, before any analysis: its number of
    /// targets and a state in its assembly modes.
    pub(super) fn checked(&self) -> Result<(usize, M::State), Error> {
        if let Some(e) = &self.problem {
            return Err(e.clone());
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
        if let Some(w) = self.weights.as_ref().filter(|w| w.len() != n) {
            return Err(Error::InvalidGeometry {
                what: "synthesis",
                detail: format!("{} weights given: one per target ({n})", w.len()),
            });
        }
        let mut state = self.design.state(&self.options)?;
        if let Some(modes) = &self.modes {
            let slots = M::modes(&mut state);
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
        Ok((n, state))
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
        let (n, mut state) = self.checked()?;
        // The modes of the start pose (when not given).
        let mut first = self.start.clone();
        let mut solved = Solved::for_shape(&self.shape);
        self.design
            .solve(&mut first, self.driver, &mut state, false, &mut solved)?;
        let phi0 = M::coordinate(&self.start, self.driver);
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
        let timing_unknowns = if self.ordered && self.timing == Timing::Free {
            let mut sorted = timing_unknowns;
            sorted.sort_by(f64::total_cmp);
            sorted
        } else {
            timing_unknowns
        };
        let scale = self
            .varied
            .iter()
            .map(|&k| self.design.parameter_at(k).abs())
            .fold(0.0f64, f64::max)
            .max(1e-300);
        let mut problem = Problem {
            s: &self,
            n,
            x: Vec::new(),
            weight: 1.0 / scale.max(1.0),
            reject: f64::INFINITY,
            poses: RefCell::new(vec![self.start.clone(); n]),
            solved: RefCell::new(vec![Solved::for_shape(&self.shape); n]),
            modes: M::modes(&mut state).to_vec(),
            evaluations: Cell::new(0),
            jacobians: Cell::new(0),
            rejected: Cell::new(0),
        };
        // x: the varied parameters in their bounded variables, then the
        // timing unknowns.
        let mut x: Vec<f64> = self
            .varied
            .iter()
            .map(|&k| to_free(self.design.parameter_at(k), self.bounds[k]))
            .collect();
        x.extend(&timing_unknowns);
        problem.x = x;
        let mut termination = String::new();
        for _round in 0..7 {
            // A design that cannot be assembled counts as a residual ten
            // times the round's first (whose penalties weigh more in each
            // round), so that no step to one is ever accepted.
            let r0 = problem.evaluate(&problem.x.clone(), false)?;
            problem.reject = 10.0 * norm(&r0.0) + 1.0;
            let lm = LevenbergMarquardt::new().with_patience(self.patience);
            let (solved, report) = lm.minimize(problem);
            problem = solved;
            termination = format!("{:?}", report.termination);
            if problem.violation() <= 1e-10 * scale || (self.linear.is_empty() && !self.ordered) {
                break;
            }
            problem.weight *= 100.0;
        }
        let x = problem.x.clone();
        let (design, values) = problem.design_at(&x);
        let (res, _) = problem.evaluate(&x, false)?;
        let e = problem.errors(&res);
        let full_turn = (self.driver_kind == Kind::Angle).then(|| {
            let mut first = problem.poses.borrow()[0].clone();
            M::set_coordinate(&mut first, self.driver, values[0]);
            design.turns(self.driver, &first, &self.options)
        });
        Ok(Synthesized {
            design,
            driver_values: values,
            sum_squares: e.0,
            max_error: e.2.iter().copied().fold(0.0, f64::max),
            target_errors: e.2,
            evaluations: problem.evaluations.get(),
            jacobians: problem.jacobians.get(),
            rejected: problem.rejected.get(),
            constraints_met: problem.violation() <= 1e-10 * scale,
            full_turn,
            termination,
        })
    }
}

impl<M: Subject> Synthesis<M> {
    /// For free timing with a point and an angle driver: each target's
    /// initial driver value, that of the sample of the starting design's
    /// path (one turn each way from the start, 360 steps, in the start's
    /// modes) nearest the target. `None` when the path has no sample.
    fn nearest_on_path(&self, n: usize) -> Option<Vec<f64>> {
        let (Output::Point(k) | Output::Motion(k, _, _)) = self.output else {
            return None;
        };
        if self.driver_kind != Kind::Angle {
            return None;
        }
        let phi0 = M::coordinate(&self.start, self.driver);
        let mut samples = Vec::new();
        for to in [phi0 + TAU, phi0 - TAU] {
            let (path, stopped) =
                self.design
                    .path(self.driver, &self.start, to, 360, &self.options);
            let at = k * self.shape.point_dim..(k + 1) * self.shape.point_dim;
            samples.extend(
                path.into_iter()
                    .map(|(phi, r)| (phi, r[at.clone()].to_vec())),
            );
            if !stopped {
                break;
            }
        }
        if samples.is_empty() {
            return None;
        }
        let (d, point_dim) = (self.dim, self.shape.point_dim);
        Some(
            (0..n)
                .map(|j| {
                    let t = &self.targets[j * d..j * d + point_dim];
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
