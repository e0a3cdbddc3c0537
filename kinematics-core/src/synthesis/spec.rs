//! A synthesis problem as data: what the `kinematics synthesize` command
//! reads from a TOML file and the Python package from keywords, turned
//! into a [`Search`] here, once for every front end.

use std::collections::BTreeMap;
use std::format;
use std::string::String;
use std::time::Duration;
use std::vec::Vec;

use crate::closed::Mode;
use crate::error::Error;
use crate::mechanism::Role;
use crate::units;

use super::design::{Synthesis, Timing};
use super::search::Search;
use super::subject::Subject;

/// A number, or a number with an angle's unit as text (`"40deg"`): an
/// angle in radians either way, a length as written.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(untagged))]
pub enum Amount {
    /// The number as written (radians for an angle).
    Number(f64),
    /// A number and a unit (`"30deg"`, `"0.5rev"`).
    Text(String),
}

impl From<f64> for Amount {
    fn from(x: f64) -> Self {
        Amount::Number(x)
    }
}

impl Amount {
    /// The value, angles in radians.
    ///
    /// # Errors
    /// [`Error::InvalidGeometry`] naming `what` for text that is not a
    /// number with an angle's unit, or a value that is not finite.
    pub fn value(&self, what: &str) -> Result<f64, Error> {
        let x = match self {
            Amount::Number(x) => *x,
            Amount::Text(t) => {
                units::read_parameter(t)
                    .map_err(|e| problem(format!("{what}: {e}")))?
                    .value
            }
        };
        if x.is_finite() {
            Ok(x)
        } else {
            Err(problem(format!("{what} must be finite, not {x}")))
        }
    }
}

/// What the mechanism is to do.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)
)]
pub enum Task {
    /// Path generation: `point` through the targets, each its position.
    Path {
        /// The point's name.
        point: String,
    },
    /// Motion generation: a body through poses, each `[x, y, θ]` of its
    /// point `point` and its angle coordinate `angle`; an angle's error
    /// weighed by `length` (see [`Synthesis::motion`]).
    Motion {
        /// The body's point.
        point: String,
        /// The body's angle coordinate.
        angle: String,
        /// The length that weighs an angle against a distance.
        length: f64,
    },
    /// Function generation: the unknown `output` against the driver, each
    /// target `[input, output]` (the timing prescribed by the inputs).
    Function {
        /// The output coordinate's name.
        output: String,
    },
}

/// How the driver values of the targets are found.
#[derive(Debug, Clone, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum TimingSpec {
    /// Every target's driver value an unknown.
    #[default]
    Free,
    /// The driver value of each target given.
    Prescribed(Vec<Amount>),
    /// Each target's driver value φ₀ + Δ_j, the increments given, φ₀ free.
    Relative(Vec<Amount>),
}

/// A linear inequality Σ c_k p_k ≤ bound over named parameters.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Inequality {
    /// c_k by parameter name.
    pub terms: BTreeMap<String, f64>,
    /// The bound.
    pub bound: f64,
}

/// Grashof's condition with `crank` the shortest link (see
/// [`Synthesis::grashof_crank`]).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Grashof {
    /// The crank's length parameter.
    pub crank: String,
    /// The coupler's.
    pub coupler: String,
    /// The rocker's.
    pub rocker: String,
    /// The ground link's.
    pub ground: String,
    /// The margin kept from the condition's boundary (a length).
    #[cfg_attr(feature = "serde", serde(default))]
    pub margin: f64,
}

/// A transmission angle kept within [min, 180° − min] (see
/// [`Search::transmission`]).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct TransmissionSpec {
    /// The input link's far end, the joint, the output link's far end.
    pub points: [String; 3],
    /// The smallest angle allowed.
    pub min: Amount,
}

/// A point kept inside a box (see [`Search::inside`]).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Region {
    /// The point.
    pub point: String,
    /// The box's lower corner.
    pub lo: Vec<f64>,
    /// Its upper corner.
    pub hi: Vec<f64>,
}

/// The budget and the seed of a search.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct SearchSpec {
    /// Starting designs (16).
    pub starts: usize,
    /// Refined to convergence (8).
    pub keep: usize,
    /// The seed (0).
    pub seed: u64,
    /// At most this many residual and Jacobian evaluations.
    pub evaluations: Option<usize>,
    /// At most this many seconds.
    pub seconds: Option<f64>,
    /// Designs drawn per start before it is given up (10 000).
    pub tries: Option<usize>,
    /// Residual evaluations per unknown of a refinement (200).
    pub patience: Option<usize>,
}

impl Default for SearchSpec {
    fn default() -> Self {
        SearchSpec {
            starts: 16,
            keep: 8,
            seed: 0,
            evaluations: None,
            seconds: None,
            tries: None,
            patience: None,
        }
    }
}

/// A synthesis problem as data, every name a string: the TOML file of
/// `kinematics synthesize`, the keywords of the Python package's
/// `synthesize`. [`Spec::search`] turns it into a [`Search`].
///
/// ```toml
/// mechanism = "four_bar.mech"   # read by the command, beside this file
/// driver = "phi"
/// task = { kind = "path", point = "P" }
/// targets = [[0.1, 0.05], [0.08, 0.09], [0.03, 0.1]]
/// timing = "free"
/// in_order = true
///
/// [vary]
/// a = [0.01, 0.1]
/// b = [0.01, 0.3]
///
/// [[transmission]]
/// points = ["B", "C", "D"]
/// min = "30deg"
///
/// [search]
/// starts = 32
/// seed = 7
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Spec {
    /// The definition's file, for the command (relative to the problem's
    /// file); not read here.
    #[cfg_attr(feature = "serde", serde(default))]
    pub mechanism: Option<String>,
    /// The driver's name.
    pub driver: String,
    /// The task.
    pub task: Task,
    /// The targets: positions, poses `[x, y, θ]` or pairs `[input,
    /// output]`, as the task has them.
    pub targets: Vec<Vec<Amount>>,
    /// w_j per target (default: all 1).
    #[cfg_attr(feature = "serde", serde(default))]
    pub weights: Option<Vec<f64>>,
    /// The timing (free by default; function generation takes its
    /// targets' inputs).
    #[cfg_attr(feature = "serde", serde(default))]
    pub timing: TimingSpec,
    /// With free timing, the driver values increase through the targets,
    /// less than a turn.
    #[cfg_attr(feature = "serde", serde(default))]
    pub in_order: bool,
    /// With `in_order`, the most φ_N − φ₁ (default a turn; see
    /// [`Synthesis::in_order_within`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub order_span: Option<Amount>,
    /// The assembly modes, `"+"` or `"-"` per closed-form block (default:
    /// each start's own).
    #[cfg_attr(feature = "serde", serde(default))]
    pub modes: Option<Vec<String>>,
    /// The parameters varied, each with its bounds `[lo, hi]`.
    pub vary: BTreeMap<String, [Amount; 2]>,
    /// Narrower ranges the starts are drawn from.
    #[cfg_attr(feature = "serde", serde(default))]
    pub sampling: BTreeMap<String, [Amount; 2]>,
    /// Values of parameters not varied.
    #[cfg_attr(feature = "serde", serde(default))]
    pub values: BTreeMap<String, Amount>,
    /// Guesses of the unknowns at the first target (for blocks solved
    /// by Newton–Raphson).
    #[cfg_attr(feature = "serde", serde(default))]
    pub start: BTreeMap<String, Amount>,
    /// Linear inequalities.
    #[cfg_attr(feature = "serde", serde(default))]
    pub at_most: Vec<Inequality>,
    /// Grashof's condition for a crank.
    #[cfg_attr(feature = "serde", serde(default))]
    pub grashof_crank: Option<Grashof>,
    /// Transmission angles.
    #[cfg_attr(feature = "serde", serde(default))]
    pub transmission: Vec<TransmissionSpec>,
    /// Regions.
    #[cfg_attr(feature = "serde", serde(default))]
    pub inside: Vec<Region>,
    /// Whether the driver must turn fully.
    #[cfg_attr(feature = "serde", serde(default))]
    pub full_turn: bool,
    /// The search's budget and seed.
    #[cfg_attr(feature = "serde", serde(default))]
    pub search: SearchSpec,
}

fn problem(detail: String) -> Error {
    Error::InvalidGeometry {
        what: "synthesis problem",
        detail,
    }
}

fn values(list: &[Amount], what: &str) -> Result<Vec<f64>, Error> {
    list.iter()
        .enumerate()
        .map(|(i, a)| a.value(&format!("{what} {i}")))
        .collect()
}

impl Spec {
    /// The search this problem poses for `design` (its parameters not
    /// varied as given, then those of [`Spec::values`]; parameters named
    /// here are those of its `sensitivities` section), from the pose
    /// `start` (a guess of the unknowns; those of [`Spec::start`]
    /// replace it).
    ///
    /// # Errors
    /// [`Error::InvalidGeometry`] for a name that is not the
    /// mechanism's, a mode other than `"+"`/`"-"`, a value that is not a
    /// number; then as [`Search::run`] when it runs.
    pub fn search<M>(&self, design: &M, start: &M::Pose) -> Result<Search<M>, Error>
    where
        M: Subject + Send + Sync,
        M::Pose: Send + Sync,
    {
        let s = self.synthesis(design, start)?;
        let mut search = s
            .search()
            .starts(self.search.starts)
            .keep(self.search.keep)
            .seed(self.search.seed);
        if let Some(n) = self.search.evaluations {
            search = search.evaluations(n);
        }
        if let Some(t) = self.search.seconds {
            let limit = Duration::try_from_secs_f64(t).ok().filter(|_| t > 0.0);
            let Some(limit) = limit else {
                return Err(problem(format!(
                    "search.seconds must be a positive number of seconds, not {t}"
                )));
            };
            search = search.time(limit);
        }
        if let Some(n) = self.search.tries {
            search = search.tries(n);
        }
        for (name, [lo, hi]) in &self.sampling {
            let what = format!("sampling.{name}");
            search = search.sampling(name, lo.value(&what)?, hi.value(&what)?);
        }
        for t in &self.transmission {
            let [a, j, b] = &t.points;
            search = search.transmission([a, j, b], t.min.value("transmission.min")?);
        }
        for r in &self.inside {
            search = search.inside(&r.point, &r.lo, &r.hi);
        }
        if self.full_turn {
            search = search.full_turn();
        }
        Ok(search)
    }

    /// The local problem this poses for `design` from `start`, as
    /// [`Spec::search`] reads it, without the search: a refinement of the
    /// design given ([`Synthesis::run`]); the search's settings, sampling,
    /// transmission angles, regions and full turn are not read.
    ///
    /// # Errors
    /// As [`Spec::search`].
    pub fn synthesis<M: Subject>(
        &self,
        design: &M,
        start: &M::Pose,
    ) -> Result<Synthesis<M>, Error> {
        let shape = design.shape();
        let coordinate = |name: &str, role: Option<Role>| {
            shape
                .coordinates
                .iter()
                .position(|c| c.name == name && role.is_none_or(|r| c.role == r))
        };
        let driver = coordinate(&self.driver, Some(Role::Driver)).ok_or_else(|| {
            let drivers: Vec<&str> = shape
                .coordinates
                .iter()
                .filter(|c| c.role == Role::Driver)
                .map(|c| c.name)
                .collect();
            problem(format!(
                "`{}` is not a driver of the mechanism; its drivers are {}",
                self.driver,
                drivers.join(", ")
            ))
        })?;
        let mut design = design.clone();
        for (name, v) in &self.values {
            let k = self.parameter(&shape.parameters, name, "values")?;
            design.set_parameter_at(k, v.value(&format!("values.{name}"))?);
        }
        let mut pose = start.clone();
        for (name, v) in &self.start {
            let i = coordinate(name, None).ok_or_else(|| {
                problem(format!(
                    "start: `{name}` is not a coordinate of the mechanism"
                ))
            })?;
            M::set_coordinate(&mut pose, i, v.value(&format!("start.{name}"))?);
        }
        let targets: Vec<Vec<f64>> = self
            .targets
            .iter()
            .enumerate()
            .map(|(j, t)| values(t, &format!("target {j}, component")))
            .collect::<Result<_, _>>()?;
        let with = |index| Ok::<_, String>(index);
        let mut s = match &self.task {
            Task::Path { point } => {
                Synthesis::path(&design, Named(with(driver)), point, &targets, &pose)
            }
            Task::Motion {
                point,
                angle,
                length,
            } => Synthesis::motion(
                &design,
                Named(with(driver)),
                (point, angle),
                &targets,
                *length,
                &pose,
            ),
            Task::Function { output } => {
                let pairs = targets
                    .iter()
                    .enumerate()
                    .map(|(j, t)| match t[..] {
                        [x, y] => Ok((x, y)),
                        _ => Err(problem(format!(
                            "target {j} of function generation must be [input, output], not {} numbers",
                            t.len()
                        ))),
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Synthesis::function(&design, Named(with(driver)), output, &pairs, &pose)
            }
        };
        let varied: Vec<&str> = self.vary.keys().map(String::as_str).collect();
        for name in &varied {
            self.parameter(&shape.parameters, name, "vary")?;
        }
        s = s.vary(&varied);
        for (name, [lo, hi]) in &self.vary {
            let what = format!("vary.{name}");
            s = s.bounds(name, lo.value(&what)?, hi.value(&what)?);
        }
        match &self.timing {
            TimingSpec::Free => {}
            TimingSpec::Prescribed(v) => {
                s = s.timing(Timing::Prescribed(values(v, "timing value")?));
            }
            TimingSpec::Relative(v) => {
                s = s.timing(Timing::Relative(values(v, "timing increment")?));
            }
        }
        let function = matches!(self.task, Task::Function { .. });
        if function && self.timing != TimingSpec::Free {
            return Err(problem(
                "function generation takes its timing from its targets' inputs: leave `timing` out"
                    .into(),
            ));
        }
        if self.in_order && (function || self.timing != TimingSpec::Free) {
            return Err(problem(
                "in_order orders free driver values: with prescribed or relative timing (or function generation) the order is given; leave it out"
                    .into(),
            ));
        }
        match (&self.in_order, &self.order_span) {
            (true, Some(span)) => s = s.in_order_within(span.value("order_span")?),
            (true, None) => s = s.in_order(),
            (false, Some(_)) => {
                return Err(problem(
                    "order_span is given without in_order = true".into(),
                ));
            }
            (false, None) => {}
        }
        if let Some(w) = &self.weights {
            s = s.weights(w);
        }
        if let Some(modes) = &self.modes {
            let modes = modes
                .iter()
                .map(|m| match m.as_str() {
                    "+" | "plus" => Ok(Mode::Plus),
                    "-" | "minus" => Ok(Mode::Minus),
                    other => Err(problem(format!(
                        "modes: `{other}` is not an assembly mode; write \"+\" or \"-\" per closed-form block"
                    ))),
                })
                .collect::<Result<Vec<_>, _>>()?;
            s = s.modes(&modes);
        }
        for (i, q) in self.at_most.iter().enumerate() {
            let terms: Vec<(&str, f64)> = q.terms.iter().map(|(n, c)| (n.as_str(), *c)).collect();
            for (n, _) in &terms {
                self.parameter(&shape.parameters, n, &format!("at_most {i}"))?;
            }
            s = s.at_most(&terms, q.bound);
        }
        if let Some(g) = &self.grashof_crank {
            for n in [&g.crank, &g.coupler, &g.rocker, &g.ground] {
                self.parameter(&shape.parameters, n, "grashof_crank")?;
            }
            s = s.grashof_crank(&g.crank, &g.coupler, &g.rocker, &g.ground, g.margin);
        }
        if let Some(p) = self.search.patience {
            s = s.patience(p);
        }
        Ok(s)
    }

    /// The index of parameter `name` among `parameters`, or an error
    /// naming the section `what`.
    fn parameter(&self, parameters: &[&str], name: &str, what: &str) -> Result<usize, Error> {
        parameters.iter().position(|p| *p == name).ok_or_else(|| {
            problem(format!(
                "{what}: `{name}` is not a parameter of the mechanism's `sensitivities` section, which lists {}",
                parameters.join(", ")
            ))
        })
    }
}

/// A driver already found by index.
struct Named(Result<usize, String>);

impl<M: Subject> super::subject::DriverOf<M> for Named {
    fn driver_index(&self, _: &M) -> Result<usize, String> {
        self.0.clone()
    }
}

impl core::fmt::Display for Task {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Task::Path { point } => write!(f, "path generation of {point}"),
            Task::Motion { point, angle, .. } => {
                write!(f, "motion generation of {point} and {angle}")
            }
            Task::Function { output } => write!(f, "function generation of {output}"),
        }
    }
}
