//! The slow path of the stepping iterator: change points (det Φ_u changing
//! sign, conditioning falling to zero and rising again) located and
//! crossed or stopped at, limit positions located by bisection, and the
//! failures that end a sweep.

use alloc::vec::Vec;
use core::borrow::Borrow;

use super::drive::Drive;
use super::engine::Engine;
use super::handles::{ChangePoints, Wrap};
use super::iter::{Candidate, SweepIter};
use super::sample::{Solved, StopReason};
use crate::error::Error;
use crate::mechanism::{Kind, Role};

impl<M: Engine, D: Drive<M>, S: Solved<M>> SweepIter<'_, M, D, S> {
    /// A new sample `s` near a possible change point, or after a held one.
    #[cold]
    #[inline(never)]
    pub(super) fn unusual(&mut self, s: S) {
        let Some((h_at, c1, h_det_sign)) = self.head().map(|h| (h.at, h.conditioning, h.det_sign))
        else {
            self.k += 1;
            self.push_head(&s);
            self.out.push_back(Ok(s));
            return;
        };
        let c2 = s.conditioning();
        if h_det_sign * s.det_sign() < 0.0 {
            // det Φ_u changed sign between the newest sample and `s`.
            let at = h_at + (s.at() - h_at) * c1 / (c1 + c2);
            self.release();
            return self.change_point(at, h_at, s.at());
        }
        if self.held.is_some() {
            // Does the conditioning dip to zero in a V around the held
            // sample?
            if let Some((a, c0)) = self.back(1).map(|p| (p.at, p.conditioning)) {
                if let Some(t) = v_zero(c0, c1, c2) {
                    let at = if t > 0.0 {
                        h_at + t * (s.at() - h_at)
                    } else {
                        h_at + t * (h_at - a)
                    };
                    // A held sample already at round-off is on the point.
                    let on_it = c1 < 1e-3 * c0.min(c2);
                    if on_it || self.singular_at(at, c1) {
                        if t > 0.0 {
                            self.release();
                            return self.change_point(at, h_at, s.at());
                        }
                        // The held sample is past the point: dropped,
                        // never handed out, and forgotten.
                        self.held = None;
                        self.history[self.newest & 3].clear();
                        self.newest = self.newest.wrapping_sub(1) & 3;
                        return self.change_point(at, a, h_at);
                    }
                }
                if let Some(at) = self.jumped(&s, (a, c0), (h_at, c1)) {
                    self.release();
                    return self.change_point(at, h_at, s.at());
                }
            }
            self.release();
        }
        // `s` accepted; held back if the conditioning was falling fast.
        self.k += 1;
        let fast = self.falling;
        self.push_head(&s);
        if fast {
            // Kept past the next step, which may overwrite what the state
            // holds of it.
            self.held = self.state.as_mut().map(|state| s.keep(state));
        } else {
            let s = self.wrapped(s);
            self.out.push_back(Ok(s));
        }
    }

    /// Whether `s`, after the held sample (at `h_at`, conditioning `c1`,
    /// the one before it at `a`, `c0`), left the branch: the line through
    /// the two conditionings meets zero less than two steps past the held
    /// sample, and `s` is off the pose extrapolated from the last three
    /// (Lagrange's parabola) by more than half the change of the last
    /// step, in the largest unknown. On a smooth branch the parabola is
    /// off by the step cubed; a jump of the order of the step is a
    /// change of branch, as at a parallelogram's fold midway between two
    /// samples, where a closed form in its mode passes from one branch to
    /// the other with no dip of the conditioning at a sample and no change
    /// of the sign of det Φ_u. Returns where the line meets zero.
    fn jumped(&self, s: &S, (a, c0): (f64, f64), (h_at, c1): (f64, f64)) -> Option<f64> {
        if !(c1 < c0 && h_at != a) {
            return None;
        }
        let t = c1 / (c0 - c1);
        if t >= 2.0 {
            return None;
        }
        // The last poses by reference (no copy: this runs at every sample
        // held back).
        let (last, before) = (self.back(0)?, self.back(1)?);
        let (three, two);
        let known: &[(f64, &M::Pose)] = match self.back(2) {
            Some(c) => {
                three = [(c.at, &c.q), (before.at, &before.q), (last.at, &last.q)];
                &three
            }
            None => {
                two = [(before.at, &before.q), (last.at, &last.q)];
                &two
            }
        };
        let (last, before) = (&last.q, &before.q);
        let predicted = extrapolated(self.m, known, s.at());
        let mut q = self.m.zero_pose();
        if !s.record(self.state.as_ref(), &mut q, None) {
            return None;
        }
        let (mut change, mut off, mut size) = (0.0f64, 0.0f64, 0.0f64);
        for j in self.m.drivers()..self.m.coordinates().len() {
            change = change.max((M::get(last, j) - M::get(before, j)).abs());
            off = off.max((M::get(&q, j) - M::get(&predicted, j)).abs());
            size = size.max(M::get(&q, j).abs());
        }
        // Above round-off too, where the unknowns barely move.
        let jumped = off > 0.5 * change && off > 1e-9 * (1.0 + size);
        // Where the line meets zero, between the held sample and `s`.
        let (lo, hi) = (h_at.min(s.at()), h_at.max(s.at()));
        jumped.then(|| (h_at + t * (h_at - a)).clamp(lo, hi))
    }

    /// Sample `k` failed with `e`.
    #[cold]
    pub(super) fn failed(&mut self, k: usize, e: Error) {
        let at = self.grid.at(k);
        match e {
            Error::CannotAssemble { unknowns, .. } => self.no_solution(k, at, unknowns),
            Error::Singular { .. } if self.change_points != ChangePoints::Stop => {
                // Exactly at a change point: this sample is left out, and
                // the branch chosen at the next.
                self.release();
                self.cross(at, k + 1);
            }
            e @ Error::Singular { .. } => {
                // A change point met exactly, if the conditioning rises
                // again past it as it fell before it (a V); else a
                // singular position.
                self.release();
                let before = self.head().map(|h| (h.at, h.conditioning));
                let after = self.probe(k + 1);
                let reason = match (before, after) {
                    (Some((from, c0)), Some((to, c2))) if c2 < 2.0 * c0 && c0 < 2.0 * c2 => {
                        StopReason::ChangePoint { from, to }
                    }
                    _ => StopReason::from_error(e),
                };
                self.finish(at, reason);
            }
            e => {
                self.release();
                self.finish(at, StopReason::from_error(e));
            }
        }
    }

    /// Grid sample `k` solved from the pose extrapolated from the accepted
    /// samples, with a fresh state: its value and conditioning.
    fn probe(&mut self, k: usize) -> Option<(f64, f64)> {
        if k >= self.grid.count {
            return None;
        }
        let target = self.grid.at(k);
        let guess = extrapolated(self.m, &self.known(), target);
        let mut state = self.m.state(&self.options).ok()?;
        let s = self.solve(k, &guess, &mut state).ok()?;
        Some((s.at(), s.conditioning()))
    }

    /// A change point at `at`, between the accepted sample at `from` and
    /// the value `next`.
    fn change_point(&mut self, at: f64, from: f64, next: f64) {
        if self.change_points == ChangePoints::Stop {
            self.finish(at, StopReason::ChangePoint { from, to: next });
            return;
        }
        let k = self.grid_index_after(at);
        self.cross(at, k);
    }

    /// The first grid index whose value is past `at` in the direction of
    /// the sweep.
    fn grid_index_after(&self, at: f64) -> usize {
        let forward = self.grid.to >= self.grid.from;
        (0..self.grid.count)
            .find(|&k| {
                let v = self.grid.at(k);
                if forward { v > at } else { v < at }
            })
            .unwrap_or(self.grid.count)
    }

    /// The accepted poses before a change point, oldest first: (value,
    /// pose).
    fn known(&self) -> Vec<(f64, M::Pose)> {
        (0..=2)
            .rev()
            .filter_map(|n| self.back(n).map(|h| (h.at, h.q.clone())))
            .collect()
    }

    /// Continues past the change point at `at` from grid index `k` (or
    /// the next that assembles) on the branch `self.change_points` names.
    fn cross(&mut self, at: f64, k: usize) {
        let known = self.known();
        let Ok(mut probe) = self.m.state(&self.options) else {
            self.done = true;
            return;
        };
        let modes = M::modes(&mut probe).len();
        let mut q = self.m.zero_pose();
        for k in k..(k + 3).min(self.grid.count) {
            let target = self.grid.at(k);
            let guess = extrapolated(self.m, &known, target);
            // Every combination of assembly modes (one, from the guess, for
            // Newton–Raphson), each from a fresh state, ranked by distance
            // from the extrapolated pose.
            let mut best: [Option<Candidate<M, S>>; 2] = [None, None];
            for combo in 0..1usize << modes {
                let Ok(mut state) = self.m.state(&self.options) else {
                    continue;
                };
                for (i, m) in M::modes(&mut state).iter_mut().enumerate() {
                    *m = if combo >> i & 1 == 1 { -1.0 } else { 1.0 };
                }
                let Ok(s) = self.solve(k, &guess, &mut state) else {
                    continue;
                };
                s.record(Some(&state), &mut q, None);
                let d = distance(self.m, &guess, &q);
                let entry = Some((d, s, state));
                if best[0].as_ref().is_none_or(|b| d < b.0) {
                    best[1] = best[0].take();
                    best[0] = entry;
                } else if best[1].as_ref().is_none_or(|b| d < b.0) {
                    best[1] = entry;
                }
            }
            if best[0].is_none() {
                // Still at the point: the next grid value.
                continue;
            }
            let chosen = match self.change_points {
                ChangePoints::Switch => best[1].take(),
                _ => best[0].take(),
            };
            let Some((_, s, state)) = chosen else {
                let reason = StopReason::Invalid(Error::InvalidOption {
                    name: "change_points",
                    value: f64::NAN,
                    requirement: "must be `Smooth` or `Stop` here: `Switch` needs the block that \
                                  meets the other branch solved in closed form (see the \
                                  mechanism's BLOCKS), where both branches are at hand",
                });
                self.finish(at, reason);
                return;
            };
            self.passed.push(at);
            self.state = Some(state);
            self.forget();
            self.push_head(&s);
            let s = self.wrapped(s);
            self.out.push_back(Ok(s));
            self.k = k + 1;
            return;
        }
        let from = known.last().map_or(at, |p| p.0);
        let to = self.grid.at(k.min(self.grid.count.saturating_sub(1)));
        self.finish(at, StopReason::ChangePoint { from, to });
    }

    /// No real solution at grid sample `k` (value `at`): a limit position,
    /// or a change point where the two solutions touch and round-off makes
    /// them vanish over a tiny interval.
    fn no_solution(&mut self, k: usize, at: f64, unknowns: &'static str) {
        let Some((h_at, pose)) = self.head().map(|h| (h.at, h.q.clone())) else {
            self.finish(at, StopReason::LimitPosition { unknowns });
            return;
        };
        let mut guess = pose.clone();
        let mut assembles = |it: &mut Self, v: f64| {
            guess.clone_from(&pose);
            it.drive.drive(v, &mut guess, &mut it.rates, &mut it.accels);
            it.m.assembles(&guess, &it.options)
        };
        // The last value that assembles, by bisection.
        let (mut good, mut bad) = (h_at, at);
        for _ in 0..200 {
            let mid = good + 0.5 * (bad - good);
            if mid == good || mid == bad {
                break;
            }
            if assembles(self, mid) {
                good = mid;
            } else {
                bad = mid;
            }
        }
        // A change point: the mechanism assembles again within a step, the
        // gap no wider than round-off makes it (1e-6 of the scale).
        if k + 1 < self.grid.count {
            let next = self.grid.at(k + 1);
            if assembles(self, next) {
                let (mut lo, mut hi) = (at, next);
                for _ in 0..200 {
                    let mid = lo + 0.5 * (hi - lo);
                    if mid == lo || mid == hi {
                        break;
                    }
                    if assembles(self, mid) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                let scale = 1.0 + good.abs().max(hi.abs());
                if (hi - good).abs() <= 1e-6 * scale {
                    self.release();
                    return self.change_point(0.5 * (good + hi), h_at, next);
                }
            }
        }
        self.release();
        self.finish(good, StopReason::LimitPosition { unknowns });
    }
}

/// The pose at `target` extrapolated from the `known` poses (up to three:
/// quadratic in the sweep variable), unknowns only.
fn extrapolated<E: Engine, Q: Borrow<E::Pose>>(m: &E, known: &[(f64, Q)], target: f64) -> E::Pose {
    let Some(last) = known.last() else {
        return m.zero_pose();
    };
    let mut guess = last.1.borrow().clone();
    for j in m.drivers()..m.coordinates().len() {
        // Lagrange's polynomial through the known poses.
        let mut value = 0.0;
        for (i, (ai, qi)) in known.iter().enumerate() {
            let mut w = 1.0;
            for (l, (al, _)) in known.iter().enumerate() {
                if l != i {
                    w *= (target - al) / (ai - al);
                }
            }
            value += w * E::get(qi.borrow(), j);
        }
        if value.is_finite() {
            E::set(&mut guess, j, value);
        }
    }
    guess
}

impl<M: Engine, D: Drive<M>, S: Solved<M>> SweepIter<'_, M, D, S> {
    /// Whether Φ_u is singular at `at` (where the conditioning, `c` at the
    /// nearest sample, extrapolates to zero): its conditioning there below
    /// a tenth of `c`, or a singular Jacobian. Tells a change point
    /// from a sharp but regular minimum of the conditioning.
    #[cold]
    fn singular_at(&mut self, at: f64, c: f64) -> bool {
        let known = self.known();
        let mut guess = extrapolated(self.m, &known, at);
        self.drive
            .drive(at, &mut guess, &mut self.rates, &mut self.accels);
        let Ok(mut state) = self.m.state(&self.options) else {
            return false;
        };
        match S::solve(self.m, at, &guess, &self.rates, &self.accels, &mut state) {
            Ok(s) => s.conditioning() < 0.1 * c,
            Err(Error::Singular { .. } | Error::CannotAssemble { .. }) => true,
            Err(_) => false,
        }
    }
}

/// Where a V-shaped dip of the conditioning c₀, c₁, c₂ (three equally
/// spaced samples, c₁ the least) reaches zero, as a fraction of a step
/// from the middle sample, if it is V-shaped: the two samples on one side
/// and the line through them meeting zero between the middle sample and
/// the one on the other side, where that line's mirror image passes
/// within 20 % of it. A minimum of a smooth curve sharper than the steps
/// can look so too; the sweep then checks the conditioning at the point.
#[inline]
fn v_zero(c0: f64, c1: f64, c2: f64) -> Option<f64> {
    if !(c1 < c0 && c1 < c2 && c0.min(c2) < 0.5) {
        return None;
    }
    // The point beyond the middle sample (towards c₂), from c₀ and c₁.
    let slope = c0 - c1;
    let t = c1 / slope;
    if t > 0.0 && t < 1.0 {
        let mirrored = slope * (1.0 - t);
        if (mirrored - c2).abs() <= 0.2 * c2 {
            return Some(t);
        }
    }
    // Before it (towards c₀), from c₂ and c₁.
    let slope = c2 - c1;
    let t = c1 / slope;
    if t > 0.0 && t < 1.0 {
        let mirrored = slope * (1.0 - t);
        if (mirrored - c0).abs() <= 0.2 * c0 {
            return Some(-t);
        }
    }
    None
}

/// The distance between two poses: unknown angles compared modulo 2π,
/// lengths as they are.
fn distance<E: Engine>(m: &E, a: &E::Pose, b: &E::Pose) -> f64 {
    let mut d = 0.0;
    for (j, c) in m.coordinates().iter().enumerate() {
        if c.role == Role::Driver {
            continue;
        }
        let (x, y) = (E::get(a, j), E::get(b, j));
        let e = if c.kind == Kind::Angle {
            Wrap::Signed.apply(y - x)
        } else {
            y - x
        };
        d += e * e;
    }
    d
}
