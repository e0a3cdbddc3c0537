//! The starts of a search: seeded designs drawn inside the bounds until
//! one is feasible at its starting driver values, and those values.

use core::f64::consts::TAU;
use std::vec::Vec;

#[cfg(doc)]
use super::design::Synthesis;
use super::design::{Output, Timing};
use super::search::Search;
use super::subject::{Solved, Subject};

/// SplitMix64 (Steele, Lea and Flood, OOPSLA 2014): a small generator
/// whose stream is fixed by its seed, so that a search is reproducible.
#[derive(Debug, Clone)]
pub(super) struct Draws(u64);

impl Draws {
    /// The stream of start `k` of the search seeded `seed` (each start's
    /// own, so that the starts do not depend on the order they run in).
    pub(super) fn new(seed: u64, k: u64) -> Self {
        let mut d = Draws(seed ^ k.wrapping_mul(0xD1B5_4A32_D192_ED03));
        d.next();
        d
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    #[allow(clippy::cast_precision_loss)]
    pub(super) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let u = (self.next() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
}

/// A starting design: the design, its pose at the first target, its
/// assembly modes and its starting driver values.
pub(super) type Drawn<M> = (M, <M as Subject>::Pose, Vec<f64>, Vec<f64>);

impl<M> Search<M>
where
    M: Subject + Send + Sync,
    M::Pose: Send + Sync,
{
    /// The feasible starting design of start `k` as [`Search::run`] draws
    /// it (see the type's documentation), with its starting driver values
    /// at the targets: a sampler of feasible designs, for another method
    /// started from the same designs. `None` when none was found in the
    /// tries allowed.
    #[must_use]
    pub fn starting_design(&self, k: usize) -> Option<(M, Vec<f64>)> {
        if self.problem.problem.is_some() || !self.undrawable().is_empty() {
            return None;
        }
        let mut draws = Draws::new(self.seed, k as u64);
        self.draw(k, &mut draws)
            .map(|(m, _, _, values)| (m, values))
    }

    /// The starting driver values of start `k` from `phi0`.
    pub(super) fn starting_values(&self, k: usize, phi0: f64) -> Vec<f64> {
        let p = &self.problem;
        let n = p.targets.len() / p.dim.max(1);
        match &p.timing {
            Timing::Prescribed(v) => v.clone(),
            Timing::Relative(d) => d.iter().map(|d| phi0 + d).collect(),
            Timing::Free => {
                if let Some(g) = &p.guesses {
                    return g.clone();
                }
                let span = if p.driver_is_angle() { TAU } else { 1.0 };
                // Even starts: evenly spaced; odd: spaced as the targets
                // are along their closed polygon (a point moving at a
                // uniform speed).
                let point_dim = match p.output {
                    Output::Point(_) | Output::Motion(..) => p.shape.point_dim,
                    Output::Coordinate(..) => 1,
                };
                let t = |j: usize| &p.targets[(j % n) * p.dim..(j % n) * p.dim + point_dim];
                let step = |j: usize| -> f64 {
                    if k % 2 == 1 {
                        t(j).iter()
                            .zip(t(j + 1))
                            .map(|(a, b)| (b - a) * (b - a))
                            .sum::<f64>()
                            .sqrt()
                    } else {
                        1.0
                    }
                };
                let total: f64 = (0..n).map(step).sum();
                let total = if total > 0.0 { total } else { 1.0 };
                let mut at = phi0;
                (0..n)
                    .map(|j| {
                        let here = at;
                        at += span * step(j) / total;
                        here
                    })
                    .collect()
            }
        }
    }

    /// A feasible starting design of start `k`: the design, its pose at
    /// the first target, its assembly modes and its starting driver
    /// values.
    pub(super) fn draw(&self, k: usize, draws: &mut Draws) -> Option<Drawn<M>> {
        let p = &self.problem;
        let slots = {
            let mut state = p.design.state(&p.options).ok()?;
            M::modes(&mut state).len()
        };
        let combinations = if slots < 16 { 1usize << slots } else { 1 << 16 };
        let mut solved = Solved::for_shape(&p.shape);
        for _ in 0..self.tries {
            let mut design = p.design.clone();
            for &k in &p.varied {
                let (lo, hi) = self
                    .sampling
                    .iter()
                    .find(|s| s.0 == k)
                    .map_or(p.bounds[k], |s| (s.1, s.2));
                design.set_parameter_at(k, draws.uniform(lo, hi));
            }
            let meets = p.linear.iter().all(|(terms, h)| {
                terms
                    .iter()
                    .map(|&(k, c)| c * design.parameter_at(k))
                    .sum::<f64>()
                    <= *h
            });
            if !meets {
                continue;
            }
            let phi0 = if p.driver_is_angle() {
                draws.uniform(0.0, TAU)
            } else {
                M::coordinate(&p.start, p.driver)
            };
            let values = self.starting_values(k, phi0);
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let first = draws.uniform(0.0, combinations as f64) as usize;
            if let Some(drawn) = self.assembled(design, values, (first, None), &mut solved) {
                return Some(drawn);
            }
        }
        None
    }

    /// `design` at the driver values `values` in the first set of
    /// assembly modes that assembles at every one with the transmission
    /// angles within bounds (those given to [`Synthesis::modes`], else
    /// `prefer` and then the combinations from `first` on): the design,
    /// its pose at the first value, the modes and the values.
    pub(super) fn assembled(
        &self,
        design: M,
        values: Vec<f64>,
        (first, prefer): (usize, Option<Vec<f64>>),
        solved: &mut Solved,
    ) -> Option<Drawn<M>> {
        let p = &self.problem;
        let fresh = design.state(&p.options).ok()?;
        let slots = {
            let mut state = fresh.clone();
            M::modes(&mut state).len()
        };
        let combinations = if slots < 16 { 1usize << slots } else { 1 << 16 };
        let tried: Vec<Vec<f64>> = match &p.modes {
            Some(m) => std::vec![m.clone()],
            None => prefer
                .into_iter()
                .chain((0..combinations.min(64)).map(|c| {
                    let c = (first + c) % combinations;
                    (0..slots)
                        .map(|b| if (c >> b) & 1 == 0 { 1.0 } else { -1.0 })
                        .collect()
                }))
                .collect(),
        };
        for modes in tried {
            let mut state = fresh.clone();
            M::modes(&mut state).copy_from_slice(&modes);
            let mut pose = p.start.clone();
            let mut first_pose = None;
            let assembled = values.iter().all(|&v| {
                M::set_coordinate(&mut pose, p.driver, v);
                let ok = design
                    .solve(&mut pose, p.driver, &mut state, false, solved)
                    .is_ok()
                    && self
                        .cycle
                        .transmission_holds(&solved.positions, p.shape.point_dim);
                if ok && first_pose.is_none() {
                    first_pose = Some(pose.clone());
                }
                ok
            });
            if let (true, Some(pose)) = (assembled, first_pose) {
                return Some((design, pose, modes, values));
            }
        }
        None
    }
}
