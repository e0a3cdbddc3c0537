//! The global search: seeded feasible starting designs, each refined by
//! Levenberg–Marquardt with the exact Jacobian, the best refined to
//! convergence and checked over the whole cycle; the distinct optima
//! found, ranked.

use std::boxed::Box;
use std::format;
use std::time::{Duration, Instant};
use std::vec::Vec;

use crate::error::Error;

use super::cycle::{Cycle, Motion};
use super::design::{Synthesis, Synthesized, Timing};
pub use super::found::{Budget, Found, Optimum, Progress};
use super::starts::Draws;
use super::subject::{Solved, Subject};

type Report = Box<dyn FnMut(&Progress) + Send + Sync>;

/// A global search for the problem of a [`Synthesis`] (its mechanism,
/// task, varied parameters and their bounds, timing, linear inequalities,
/// order and assembly modes): multi-start Levenberg–Marquardt with the
/// exact Jacobian, from designs drawn inside the bounds.
///
/// 1. **Starts.** Each of [`Self::starts`] designs is drawn uniformly
///    inside the bounds (or the narrower [`Self::sampling`] ranges) until
///    one meets the linear inequalities and assembles at every starting
///    driver value in one set of assembly modes (those given to
///    [`Synthesis::modes`], else the first that does, from a random
///    one), with its transmission angles within bounds there. Starting
///    driver values with free timing: evenly spaced over a turn from a
///    random angle for even starts, spaced as the targets are along
///    their closed polygon for odd ones.
/// 2. **Screening.** Each start is refined briefly (20 residual
///    evaluations per unknown), on all cores with the `parallel` feature.
/// 3. **Refinement.** The [`Self::keep`] best are refined to convergence
///    in order of their E, two at a time, until a feasible one passes
///    through the targets (E ≤ 10⁻²⁴ · max(1, s²), s the largest
///    |component| of the targets) or two feasible ones end within 1 % of
///    each other.
/// 4. **Cycle.** Each is swept over its motion and checked (see
///    [`Optimum`]); optima whose E agree to 10⁻⁶ and whose parameters
///    agree to 10⁻⁶ of the design's scale are one.
///
/// Every start draws from its own stream, fixed by the seed and its
/// number, so a search is reproducible whatever the number of threads
/// (unless stopped by [`Self::time`]).
///
/// ```
/// use kinematics_core::{mechanism, synthesis::Synthesis};
///
/// mechanism! {
///     struct FourBar {
///         params { a, b, c, d }
///         drivers { phi }
///         unknowns { th3, th4 }
///         points { B = polar(a, phi); D = vec2(d, 0.0); C = D + polar(c, th4); }
///         loops { B + polar(b, th3) == C; }
///         sensitivities { a, b, c, d }
///     }
/// }
///
/// # fn main() -> Result<(), kinematics_core::Error> {
/// // Four positions of the rocker pin C of the design a = 1, b = 3,
/// // c = 2.5, d = 3.2, at crank angles the search is not told.
/// let truth = FourBar { a: 1.0, b: 3.0, c: 2.5, d: 3.2 };
/// let first = truth.assemble(&FourBarCoords { phi: 0.4, th3: 1.0, th4: 2.0 })?;
/// let targets: Vec<[f64; 2]> = [0.4, 1.5, 2.9, 4.4]
///     .iter()
///     .map(|&phi| {
///         let q = truth.assemble(&FourBarCoords { phi, ..first }).unwrap();
///         let c = truth.positions(&q).C;
///         [c.x, c.y]
///     })
///     .collect();
/// let guess = FourBar { a: 0.5, b: 2.0, c: 2.0, d: 3.2 };
/// let found = Synthesis::path(&guess, FourBar::PHI, "C", &targets, &first)
///     .vary(&["a", "b", "c"])
///     .bounds("a", 0.3, 2.0)
///     .bounds("b", 0.5, 5.0)
///     .bounds("c", 0.5, 5.0)
///     .grashof_crank("a", "b", "c", "d", 0.05)
///     .in_order()
///     .search()
///     .transmission(["B", "C", "D"], 40f64.to_radians())
///     .starts(32)
///     .seed(3)
///     .run()?;
/// let best = found.best().expect("a feasible design");
/// assert!(best.found.sum_squares < 1e-16);
/// assert!(best.min_transmission.unwrap() >= 40f64.to_radians());
/// assert_eq!(best.found.full_turn, Some(true));
/// # Ok(())
/// # }
/// ```
pub struct Search<M: Subject> {
    pub(super) problem: Synthesis<M>,
    pub(super) starts: usize,
    pub(super) keep: usize,
    pub(super) seed: u64,
    pub(super) tries: usize,
    pub(super) sampling: Vec<(usize, f64, f64)>,
    pub(super) evaluations: Option<usize>,
    pub(super) time: Option<Duration>,
    pub(super) cycle: Cycle,
    pub(super) progress: Option<Report>,
    /// Designs given to start from, with their driver values.
    pub(super) given: Vec<(M, Option<Vec<f64>>)>,
}

impl<M: Subject> core::fmt::Debug for Search<M> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Search")
            .field("starts", &self.starts)
            .field("keep", &self.keep)
            .field("seed", &self.seed)
            .finish_non_exhaustive()
    }
}

impl<M: Subject> Synthesis<M> {
    /// The global search for this problem ([`Search`]), from the seed 0.
    #[must_use]
    pub fn search(self) -> Search<M> {
        Search {
            problem: self,
            starts: 16,
            keep: 8,
            seed: 0,
            tries: 10_000,
            sampling: Vec::new(),
            evaluations: None,
            time: None,
            cycle: Cycle::default(),
            progress: None,
            given: Vec::new(),
        }
    }
}

/// A start after its screening: the refinement, its pose at the first
/// target and its assembly modes.
type Screened<M> = (Synthesized<M>, <M as Subject>::Pose, Vec<f64>);

impl<M> Search<M>
where
    M: Subject + Send + Sync,
    M::Pose: Send + Sync,
{
    /// The number of starting designs drawn (default 16; 0 with a design
    /// to start from, [`Self::also_from`], and no other).
    #[must_use]
    pub fn starts(mut self, n: usize) -> Self {
        self.starts = n;
        self
    }

    /// How many of the screened starts are refined to convergence
    /// (default 8).
    #[must_use]
    pub fn keep(mut self, n: usize) -> Self {
        self.keep = n.max(1);
        self
    }

    /// The seed of the starting designs (default 0).
    #[must_use]
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The most designs drawn for one start before it is given up
    /// (default 10 000).
    #[must_use]
    pub fn tries(mut self, n: usize) -> Self {
        self.tries = n.max(1);
        self
    }

    /// Draws parameter `name`'s starting values in [lo, hi] (inside its
    /// bounds) instead of over its bounds: links kept away from zero
    /// length, say.
    #[must_use]
    pub fn sampling(mut self, name: &str, lo: f64, hi: f64) -> Self {
        let s = &mut self.problem;
        match s.shape.parameters.iter().position(|p| *p == name) {
            Some(k) if lo.is_finite() && hi.is_finite() && lo < hi => {
                self.sampling.push((k, lo, hi));
            }
            Some(_) => s.fail(format!(
                "the sampling range of `{name}` must be finite with lo < hi, not [{lo}, {hi}]"
            )),
            None => s.fail(format!("`{name}` is not a parameter of the problem")),
        }
        self
    }

    /// Stops drawing and refining once `n` residual and Jacobian
    /// evaluations are spent (checked between groups of starts).
    #[must_use]
    pub fn evaluations(mut self, n: usize) -> Self {
        self.evaluations = Some(n);
        self
    }

    /// Stops drawing and refining after `limit` of wall time (checked
    /// between groups of starts; the result then depends on the
    /// machine).
    #[must_use]
    pub fn time(mut self, limit: Duration) -> Self {
        self.time = Some(limit);
        self
    }

    /// Keeps the transmission angle μ of a dyad within [μ_min, π − μ_min]
    /// over the motion: μ the angle at the joint `joint` between the
    /// links to `input` and to `output` (the coupler and the rocker of a
    /// four-bar: `["B", "C", "D"]` for coupler BC and rocker CD), by
    /// point name; checked at the starts' driver values and over the
    /// whole motion of the results.
    #[must_use]
    pub fn transmission(mut self, [input, joint, output]: [&str; 3], mu_min: f64) -> Self {
        let index = |p: &mut Synthesis<M>, n: &str| -> usize {
            let k = p.shape.points.iter().position(|q| *q == n);
            if k.is_none() {
                let names = p.shape.points.join(", ");
                p.fail(format!(
                    "the mechanism has no point `{n}`; its points are {names}"
                ));
            }
            k.unwrap_or(0)
        };
        let ids = [
            index(&mut self.problem, input),
            index(&mut self.problem, joint),
            index(&mut self.problem, output),
        ];
        if !(0.0..core::f64::consts::FRAC_PI_2).contains(&mu_min) {
            self.problem.fail(format!(
                "the smallest transmission angle must be in [0, π/2) rad, not {mu_min} (a number without a unit is in radians: write \"40deg\" in a problem file)"
            ));
        }
        self.cycle.transmission.push((ids, mu_min));
        self
    }

    /// Keeps point `point` inside the box [lo, hi] (per component) over
    /// the motion: a ground pivot inside a region of the frame, or a
    /// moving point inside the space it may sweep.
    #[must_use]
    pub fn inside(mut self, point: &str, lo: &[f64], hi: &[f64]) -> Self {
        let p = &mut self.problem;
        let dim = p.shape.point_dim;
        match p.shape.points.iter().position(|q| *q == point) {
            Some(_)
                if lo
                    .iter()
                    .zip(hi)
                    .any(|(l, h)| l.partial_cmp(h).is_none_or(core::cmp::Ordering::is_gt)) =>
            {
                p.fail(format!(
                "the region of `{point}` needs lo ≤ hi in every component, not {lo:?} and {hi:?}"
                ));
            }
            Some(k) if lo.len() == dim && hi.len() == dim => {
                self.cycle.regions.push((k, lo.to_vec(), hi.to_vec()));
            }
            Some(_) => p.fail(format!(
                "the region of `{point}` needs {dim} lower and {dim} upper bounds"
            )),
            None => {
                let names = p.shape.points.join(", ");
                p.fail(format!(
                    "the mechanism has no point `{point}`; its points are {names}"
                ));
            }
        }
        self
    }

    /// Requires of every feasible result that its angle driver turn
    /// fully (a crank, in its assembly modes).
    #[must_use]
    pub fn full_turn(mut self) -> Self {
        self.cycle.full_turn = true;
        self
    }

    /// Starts from `design` too (screened first, before the drawn
    /// starts, which it does not change), with its driver values at the
    /// targets `driver_values` (free or relative timing) or those a drawn
    /// start would take: an exact solution of fewer targets
    /// ([`exact`](super::exact)), or a design at hand.
    #[must_use]
    pub fn also_from(mut self, design: &M, driver_values: Option<&[f64]>) -> Self {
        self.given
            .push((design.clone(), driver_values.map(<[f64]>::to_vec)));
        self
    }

    /// Calls `report` after each group of starts screened and each
    /// design refined.
    #[must_use]
    pub fn progress(mut self, report: impl FnMut(&Progress) + Send + Sync + 'static) -> Self {
        self.progress = Some(Box::new(report));
        self
    }

    /// Runs the search.
    ///
    /// # Errors
    /// As [`Synthesis::run`] for the problem as posed;
    /// [`Error::InvalidGeometry`] for a varied parameter without finite
    /// bounds (the starts are drawn inside them).
    pub fn run(mut self) -> Result<Found<M>, Error> {
        if let Some(e) = self.problem.problem.take() {
            return Err(e);
        }
        let unbounded = self.undrawable();
        if !unbounded.is_empty() {
            return Err(Error::InvalidGeometry {
                what: "synthesis",
                detail: format!(
                    "the search draws its starting designs inside the bounds; give {} finite bounds (or a sampling range)",
                    unbounded.join(", ")
                ),
            });
        }
        // The problem as posed, checked once from the design given.
        let (n, _) = self.problem.checked()?;
        let shape = &self.problem.shape;
        for (i, (m, values)) in self.given.iter().enumerate() {
            let theirs = m.shape();
            if theirs.coordinates.len() != shape.coordinates.len()
                || theirs.points != shape.points
                || theirs.parameters != shape.parameters
            {
                return Err(Error::InvalidGeometry {
                    what: "synthesis",
                    detail: format!(
                        "the design given to start from ({i}) is not of the problem's mechanism"
                    ),
                });
            }
            if values.as_ref().is_some_and(|v| v.len() != n) {
                return Err(Error::InvalidGeometry {
                    what: "synthesis",
                    detail: format!(
                        "the design given to start from ({i}) needs one driver value per target ({n})"
                    ),
                });
            }
        }
        if self.given.len() + self.starts == 0 {
            return Err(Error::InvalidGeometry {
                what: "synthesis",
                detail: "a search needs a start: give starts ≥ 1 or a design to start from".into(),
            });
        }
        let began = Instant::now();
        let mut report = self.progress.take();
        let total = self.given.len() + self.starts;
        let mut progress = Progress {
            screened: 0,
            starts: total,
            refined: 0,
            keep: self.keep.min(total),
            best: f64::INFINITY,
            evaluations: 0,
        };
        let mut stopped_by = None;
        let mut screened: Vec<Screened<M>> = Vec::new();
        let mut undrawn = 0;
        // Groups of a fixed size, whatever the number of threads.
        const GROUP: usize = 8;
        let mut k = 0;
        while k < total {
            if let Some(why) = self.over_budget(began, progress.evaluations) {
                stopped_by = Some(why);
                break;
            }
            let group: Vec<usize> = (k..(k + GROUP).min(total)).collect();
            k += group.len();
            let this = &self;
            let results = map(&group, |&k| this.screen(k));
            for r in results {
                progress.screened += 1;
                match r {
                    Some((found, pose, modes)) => {
                        progress.evaluations += found.evaluations + found.jacobians;
                        progress.best = progress.best.min(found.sum_squares);
                        screened.push((found, pose, modes));
                    }
                    None => undrawn += 1,
                }
            }
            tell(&mut report, &progress);
        }
        screened.sort_by(|a, b| a.0.sum_squares.total_cmp(&b.0.sum_squares));
        screened.truncate(self.keep);
        let exact = 1e-24 * self.target_scale().powi(2).max(1.0);
        // Each refined design checked over its motion at once, so that
        // the search stops only at a feasible one.
        let mut checked: Vec<Optimum<M>> = Vec::new();
        'refine: for group in screened.chunks(2) {
            if let Some(why) = self.over_budget(began, progress.evaluations) {
                stopped_by = Some(why);
                break;
            }
            let this = &self;
            let results = map(group, |(s, pose, modes)| {
                let (r, pose, modes) = this.refine(s, pose, modes)?;
                Some(this.optimum(&r, &pose, &modes))
            });
            for o in results.into_iter().flatten() {
                let e = o.found.sum_squares;
                progress.evaluations += o.found.evaluations + o.found.jacobians;
                progress.refined += 1;
                progress.best = progress.best.min(e);
                let agrees = checked.iter().any(|q| {
                    q.feasible && (q.found.sum_squares - e).abs() <= 0.01 * q.found.sum_squares
                });
                let done = o.feasible && (e <= exact || agrees);
                checked.push(o);
                if done {
                    tell(&mut report, &progress);
                    break 'refine;
                }
            }
            tell(&mut report, &progress);
        }
        let scale = self.parameter_scale();
        let mut optima: Vec<Optimum<M>> = Vec::new();
        for o in checked {
            match optima
                .iter_mut()
                .find(|q| same(q, &o, scale, &self.problem))
            {
                Some(q) => {
                    q.reached_by += 1;
                    if (o.feasible, -o.found.sum_squares) > (q.feasible, -q.found.sum_squares) {
                        let reached_by = q.reached_by;
                        *q = o;
                        q.reached_by = reached_by;
                    }
                }
                None => optima.push(o),
            }
        }
        optima.sort_by(|a, b| {
            b.feasible
                .cmp(&a.feasible)
                .then(a.found.sum_squares.total_cmp(&b.found.sum_squares))
        });
        Ok(Found {
            optima,
            evaluations: progress.evaluations,
            starts: progress.screened - undrawn,
            undrawn,
            stopped_by,
        })
    }

    /// The varied parameters the starts cannot be drawn for: without
    /// finite bounds or a sampling range.
    pub(super) fn undrawable(&self) -> Vec<&'static str> {
        let p = &self.problem;
        p.varied
            .iter()
            .filter(|&&k| {
                let (lo, hi) = p.bounds[k];
                let drawable =
                    (lo.is_finite() && hi.is_finite()) || self.sampling.iter().any(|s| s.0 == k);
                !drawable
            })
            .map(|&k| p.shape.parameters[k])
            .collect()
    }

    fn over_budget(&self, began: Instant, evaluations: usize) -> Option<Budget> {
        if self.evaluations.is_some_and(|n| evaluations >= n) {
            Some(Budget::Evaluations)
        } else if self.time.is_some_and(|t| began.elapsed() >= t) {
            Some(Budget::Time)
        } else {
            None
        }
    }

    /// The largest |component| of the targets (1 for none).
    fn target_scale(&self) -> f64 {
        self.problem
            .targets
            .iter()
            .fold(0.0f64, |m, t| m.max(t.abs()))
            .max(f64::MIN_POSITIVE)
    }

    /// The largest |bound| of the varied parameters' finite bounds.
    fn parameter_scale(&self) -> f64 {
        let p = &self.problem;
        p.varied
            .iter()
            .flat_map(|&k| [p.bounds[k].0, p.bounds[k].1])
            .filter(|b| b.is_finite())
            .fold(1e-300f64, |m, b| m.max(b.abs()))
    }

    /// Start `k`: a feasible design drawn and briefly refined; `None`
    /// when none was drawn in the tries allowed or its refinement failed.
    fn screen(&self, k: usize) -> Option<Screened<M>> {
        let (design, pose, modes, values) = match self.given.get(k) {
            Some((design, values)) => {
                let p = &self.problem;
                let values = values
                    .clone()
                    .unwrap_or_else(|| self.starting_values(k, M::coordinate(&p.start, p.driver)));
                // The modes the problem's start pose is in, tried first.
                let mut solved = Solved::for_shape(&p.shape);
                let mut state = design.state(&p.options).ok()?;
                let mut pose = p.start.clone();
                M::set_coordinate(&mut pose, p.driver, *values.first()?);
                let prefer = design
                    .solve(&mut pose, p.driver, &mut state, false, &mut solved)
                    .ok()
                    .map(|()| M::modes(&mut state).to_vec());
                self.assembled(design.clone(), values, (0, prefer), &mut solved)?
            }
            None => {
                let k = k - self.given.len();
                let mut draws = Draws::new(self.seed, k as u64);
                self.draw(k, &mut draws)?
            }
        };
        let s = self
            .posed(design, pose.clone(), &modes, &values)
            .patience(20);
        let found = s.run().ok()?;
        Some((found, pose, modes))
    }

    /// Refines a screened start to convergence.
    fn refine(&self, s: &Synthesized<M>, pose: &M::Pose, modes: &[f64]) -> Option<Screened<M>> {
        let p = &self.problem;
        let mut pose = pose.clone();
        let mut state = s.design.state(&p.options).ok()?;
        M::modes(&mut state).copy_from_slice(modes);
        M::set_coordinate(&mut pose, p.driver, *s.driver_values.first()?);
        let mut solved = Solved::for_shape(&p.shape);
        s.design
            .solve(&mut pose, p.driver, &mut state, false, &mut solved)
            .ok()?;
        let posed = self.posed(s.design.clone(), pose.clone(), modes, &s.driver_values);
        let found = posed.patience(p.patience).run().ok()?;
        Some((found, pose, modes.to_vec()))
    }

    /// The problem from `design` at `pose` in `modes`, with the timing's
    /// unknowns starting at `values`.
    fn posed(&self, design: M, pose: M::Pose, modes: &[f64], values: &[f64]) -> Synthesis<M> {
        let mut s = self.problem.clone();
        s.design = design;
        s.start = pose;
        s.modes = Some(modes.to_vec());
        match &s.timing {
            Timing::Free => s.guesses = Some(values.to_vec()),
            Timing::Relative(d) => {
                if let (Some(v), Some(d)) = (values.first(), d.first()) {
                    M::set_coordinate(&mut s.start, s.driver, v - d);
                }
            }
            Timing::Prescribed(_) => {}
        }
        s
    }

    /// A refined design checked over its motion.
    fn optimum(&self, s: &Synthesized<M>, pose: &M::Pose, modes: &[f64]) -> Optimum<M> {
        let p = &self.problem;
        let motion = Motion {
            driver: p.driver,
            angle: p.driver_is_angle(),
            point_dim: p.shape.point_dim,
            options: &p.options,
            shape: &p.shape,
            ordered: p.ordered && p.timing == Timing::Free,
        };
        let verdict = motion.check(s, pose, modes, &self.cycle);
        let turns_ok = !self.cycle.full_turn || s.full_turn == Some(true);
        Optimum {
            feasible: s.constraints_met && verdict.one_branch && verdict.within && turns_ok,
            min_transmission: verdict.min_transmission,
            one_branch: verdict.one_branch,
            found: s.clone(),
            reached_by: 1,
            poses: verdict.poses,
        }
    }
}

/// Hands `p` to the progress report, if there is one.
fn tell(report: &mut Option<Report>, p: &Progress) {
    if let Some(report) = report.as_mut() {
        report(p);
    }
}

/// Whether two optima are one: E within 10⁻⁶ of each other (relative)
/// and every varied parameter within 10⁻⁶ of the parameters' scale.
fn same<M: Subject>(a: &Optimum<M>, b: &Optimum<M>, scale: f64, p: &Synthesis<M>) -> bool {
    let (ea, eb) = (a.found.sum_squares, b.found.sum_squares);
    let e_close = (ea - eb).abs() <= 1e-6 * ea.max(eb) + 1e-30 * scale * scale;
    e_close
        && p.varied.iter().all(|&k| {
            (a.found.design.parameter_at(k) - b.found.design.parameter_at(k)).abs() <= 1e-6 * scale
        })
}

/// `f` over `items`, on all cores with the `parallel` feature, the
/// results in the order of the items.
#[cfg(feature = "parallel")]
fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    items.par_iter().map(f).collect()
}

/// `f` over `items`, in order.
#[cfg(not(feature = "parallel"))]
fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    items.iter().map(f).collect()
}
