//! The constraints a search checks over the whole motion of a design, not
//! only at its targets: one branch from target to target, transmission
//! angles, regions.

use core::f64::consts::{FRAC_PI_2, PI, TAU};
use std::vec::Vec;

use crate::options::Options;

use super::design::Synthesized;
use super::subject::{Shape, Solved, Subject};

/// What is checked over the motion.
#[derive(Debug, Clone, Default)]
pub(super) struct Cycle {
    /// Dyads by point index (input end, joint, output end), each with its
    /// smallest transmission angle μ_min (rad).
    pub(super) transmission: Vec<([usize; 3], f64)>,
    /// Points that stay inside a box: (point, lower, upper).
    pub(super) regions: Vec<(usize, Vec<f64>, Vec<f64>)>,
    /// Whether a feasible design must turn fully.
    pub(super) full_turn: bool,
}

/// The transmission angle μ ∈ [0, π] at `joint` between the links to
/// `a` and to `b` (positions of `dim` components), or NaN where a link
/// has no length.
fn angle_at(a: &[f64], joint: &[f64], b: &[f64]) -> f64 {
    let u: Vec<f64> = a.iter().zip(joint).map(|(a, j)| a - j).collect();
    let v: Vec<f64> = b.iter().zip(joint).map(|(b, j)| b - j).collect();
    let dot: f64 = u.iter().zip(&v).map(|(u, v)| u * v).sum();
    let nu: f64 = u.iter().map(|x| x * x).sum::<f64>().sqrt();
    let nv: f64 = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if nu * nv > 0.0 {
        crate::math::acos((dot / (nu * nv)).clamp(-1.0, 1.0))
    } else {
        f64::NAN
    }
}

impl Cycle {
    /// The smallest folded transmission angle min(μ, π − μ) of the dyads
    /// at the point positions `r` (every point, `dim` components each);
    /// `None` with no dyad, NaN where a link has no length.
    fn folded_min(&self, r: &[f64], dim: usize) -> Option<f64> {
        let point = |k: usize| &r[k * dim..(k + 1) * dim];
        self.transmission
            .iter()
            .map(|([a, j, b], _)| {
                let mu = angle_at(point(*a), point(*j), point(*b));
                mu.min(PI - mu)
            })
            .reduce(|x, y| {
                if x.is_nan() || y.is_nan() {
                    f64::NAN
                } else {
                    x.min(y)
                }
            })
    }

    /// Whether every dyad's transmission angle is within [μ_min, π − μ_min]
    /// at the point positions `r`.
    pub(super) fn transmission_holds(&self, r: &[f64], dim: usize) -> bool {
        let point = |k: usize| &r[k * dim..(k + 1) * dim];
        self.transmission.iter().all(|([a, j, b], mu_min)| {
            let mu = angle_at(point(*a), point(*j), point(*b));
            mu >= *mu_min && mu <= PI - mu_min
        })
    }

    /// Whether every region holds at the point positions `r`.
    fn inside(&self, r: &[f64], dim: usize) -> bool {
        self.regions.iter().all(|(k, lo, hi)| {
            let p = &r[k * dim..(k + 1) * dim];
            p.iter()
                .zip(lo.iter().zip(hi))
                .all(|(x, (lo, hi))| x >= lo && x <= hi)
        })
    }
}

/// The motion of a design as the checks sweep it.
pub(super) struct Motion<'a> {
    pub(super) driver: usize,
    /// Whether the driver is an angle (a turn is 2π).
    pub(super) angle: bool,
    pub(super) point_dim: usize,
    pub(super) options: &'a Options,
    pub(super) shape: &'a Shape,
    /// Whether the driver values are in order through the targets (else
    /// an angle driver's values are taken within half a turn of the
    /// first's, the way round the motion is nearest).
    pub(super) ordered: bool,
}

/// The checks' verdict on a design.
#[derive(Debug, Clone)]
pub(super) struct Verdict<P> {
    /// The design's pose at each target, in its assembly modes (empty
    /// where one does not assemble).
    pub(super) poses: Vec<P>,
    /// The targets are reached from one another without a stop.
    pub(super) one_branch: bool,
    /// Every transmission angle and region holds over the motion.
    pub(super) within: bool,
    /// The smallest folded transmission angle over the motion.
    pub(super) min_transmission: Option<f64>,
}

impl Motion<'_> {
    /// Sweeps the design of `s` over its motion in `modes` (a turn when it
    /// turns fully, else from its first target's driver value to the
    /// smallest and to the largest of its targets') and checks it: `pose`
    /// is a guess of its unknowns at the first target.
    pub(super) fn check<M: Subject>(
        &self,
        s: &Synthesized<M>,
        pose: &M::Pose,
        modes: &[f64],
        cycle: &Cycle,
    ) -> Verdict<M::Pose> {
        let failed = Verdict {
            poses: Vec::new(),
            one_branch: false,
            within: false,
            min_transmission: None,
        };
        let Some(&first) = s.driver_values.first() else {
            return failed;
        };
        let near = |v: f64| first + (v - first + PI).rem_euclid(TAU) - PI;
        let values: Vec<f64> = if self.angle && !self.ordered {
            s.driver_values.iter().map(|&v| near(v)).collect()
        } else {
            s.driver_values.clone()
        };
        let design = &s.design;
        let Ok(mut state) = design.state(self.options) else {
            return failed;
        };
        M::modes(&mut state).copy_from_slice(modes);
        let mut pose = pose.clone();
        M::set_coordinate(&mut pose, self.driver, first);
        let mut solved = Solved::for_shape(self.shape);
        if design
            .solve(&mut pose, self.driver, &mut state, false, &mut solved)
            .is_err()
        {
            return failed;
        }
        let start = pose.clone();
        let mut poses = Vec::with_capacity(values.len());
        let mut at = pose.clone();
        let mut each = solved.clone();
        for &v in &values {
            M::set_coordinate(&mut at, self.driver, v);
            if design
                .solve(&mut at, self.driver, &mut state, false, &mut each)
                .is_err()
            {
                return failed;
            }
            poses.push(at.clone());
        }
        let pose = start;
        let lo = values.iter().copied().fold(first, f64::min);
        let hi = values.iter().copied().fold(first, f64::max);
        // About one sample a degree (200 over a length driver's span).
        let steps = |span: f64| -> usize {
            let per = if self.angle {
                180.0 / PI
            } else {
                200.0 / span.abs().max(1e-300)
            };
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let n = (span.abs() * per).ceil().min(1e6) as usize;
            n.max(8)
        };
        let mut samples = Vec::new();
        let mut one_branch = true;
        for to in [lo, hi] {
            if to != first {
                let (path, stopped) =
                    design.path(self.driver, &pose, to, steps(to - first), self.options);
                one_branch &= !stopped;
                samples.extend(path.into_iter().map(|x| x.1));
            }
        }
        if self.angle && s.full_turn == Some(true) {
            let (path, _) = design.path(self.driver, &pose, first + TAU, 360, self.options);
            samples.extend(path.into_iter().map(|x| x.1));
        }
        samples.push(solved.positions.clone());
        let d = self.point_dim;
        let within = samples
            .iter()
            .all(|r| cycle.transmission_holds(r, d) && cycle.inside(r, d));
        let min_transmission = samples
            .iter()
            .filter_map(|r| cycle.folded_min(r, d))
            .reduce(|a, b| {
                if a.is_nan() || b.is_nan() {
                    f64::NAN
                } else {
                    a.min(b)
                }
            })
            .map(|m| m.min(FRAC_PI_2));
        Verdict {
            poses,
            one_branch,
            within,
            min_transmission,
        }
    }
}
