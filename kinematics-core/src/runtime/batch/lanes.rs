//! A batch of positions only, two designs per instruction: the designs
//! taken in pairs, each pair's poses by the pose's machine code in vector
//! lanes (both designs' buffers interleaved), its samples those of each
//! design's sweep of poses.
//!
//! Each design keeps its own stepper, which takes the first pose, the
//! poses at which the unknowns' carried cosines and sines are refreshed
//! (every 64), as its sweep would, and the poses where a design leaves
//! the common path (an unknown turning by more than 1/32 rad in a step,
//! which the scalar pose hands to the library's closed form); between
//! them the pair poses in lanes (the drivers' carried cosines and sines
//! refreshed every 16 poses as the helper refreshes them), each lane the
//! scalar pose's computation for its design, operation for operation,
//! from the previous pose (the guesses matter to a closed form only for
//! the turn of its angles, which both carry). Where a design fails a
//! check (no pose ahead: a limit position; a value not finite), both
//! designs of the pair are swept alone from their start, as the batch
//! sweeps any design: so every design's samples, stop and record are its
//! sweep's, bit for bit.

use alloc::vec;

use super::{Batch, Early, From, Keep, keep};
use crate::runtime::{Model, Stepper};

/// Value i of lane `l` (0 or 1) of an interleaved array, for each i.
#[inline]
pub(super) fn lane(v: &[f64], l: usize, out: &mut [f64]) {
    let second = l == 1;
    for (o, pair) in out.iter_mut().zip(v.chunks_exact(2)) {
        *o = if second { pair[1] } else { pair[0] };
    }
}

/// The two arrays interleaved into `out` (a's values at even entries).
pub(super) fn interleave(a: &[f64], b: &[f64], out: &mut [f64]) {
    for (pair, (x, y)) in out.chunks_exact_mut(2).zip(a.iter().zip(b)) {
        pair[0] = *x;
        pair[1] = *y;
    }
}

/// Whether the stepper's last pose came from its fused code, its buffer
/// holding that pose, with a scaling that every pose shares.
fn fused(stepper: &Stepper<'_>) -> bool {
    stepper
        .fused
        .as_ref()
        .is_some_and(|run| run.positions && run.scaled)
}

/// How each design of a pair ended: its samples, and why it ended early.
type PairEnds = [(usize, Option<Early>); 2];

impl Keep<'_> {
    /// Keeps lane `l`'s pose and points' positions as the next row, read
    /// from the interleaved pose `q` and positions `r` (each slot's few
    /// values gathered, the rest not copied).
    #[inline(always)]
    fn put_lane(&mut self, q: &[f64], r: &[f64], l: usize) {
        let row = self.row;
        if row >= self.rows {
            return;
        }
        for s in self.slots {
            let from = if matches!(s.from, From::Positions) {
                r
            } else {
                q
            };
            let mut v = [0.0; 3];
            let width = s.width.min(3);
            for (i, x) in v.iter_mut().enumerate().take(width) {
                *x = from.get(2 * (s.at + i) + l).copied().unwrap_or(f64::NAN);
            }
            keep(self.out, s, row, self.reduce, &v[..width], 0);
        }
        self.row = row + 1;
    }
}

impl Batch<'_> {
    /// The positions (designs × samples) of steps from which a model's
    /// batches compile its step in lanes ([`Batch::in_lanes`]), counted
    /// over the batches that could have paired (a loop of small batches
    /// compiles it too): about where the time saved pays for the
    /// compilation (2.4 ms for the four-bar and 11 ms for the Strider
    /// leg, saving 14 and 41 ns a position, on the machine of the
    /// library's benchmarks).
    pub const LANES_FROM_STEPS: usize = 200_000;

    /// [`Batch::LANES_FROM_STEPS`] for a batch of positions only (1.3 and
    /// 5.2 ms, saving 24 and 72 ns a position).
    pub const LANES_FROM_POSES: usize = 60_000;

    /// Whether this batch can run its designs in pairs in vector lanes
    /// ([`Batch::in_lanes`]): swept in steps of at most 1/16 (the largest
    /// the carried cosine and sine of the driver are rotated by), lanes
    /// not turned off, and a model with parameters, a scaling that every
    /// pose shares, and a pose (positions only) or step with a form in
    /// lanes (every block's closed form in its fused code, a pose of at
    /// most 16 blocks, no Newton block). Compiles that form at the first
    /// call for the model: every later batch of the model (and of its
    /// clones) then runs in pairs whatever its size, unless told not to.
    #[must_use]
    pub fn in_pairs(&self) -> bool {
        self.lanes != Some(false) && self.pairable() && self.lanes_form()
    }

    /// Whether a run of `count` designs goes in pairs: where it can
    /// ([`Batch::in_pairs`]), asked to, or else with the code in lanes
    /// compiled already or enough positions, this batch's and those of
    /// the model's earlier batches that could have paired, to pay for
    /// compiling it.
    pub(super) fn pairs_for(&self, count: usize) -> bool {
        let Some(plan) = self.model.fused.as_deref() else {
            return false;
        };
        match self.lanes {
            Some(false) => false,
            Some(true) => self.in_pairs(),
            None => {
                if !self.pairable() {
                    return false;
                }
                let from = if self.poses {
                    Self::LANES_FROM_POSES
                } else {
                    Self::LANES_FROM_STEPS
                };
                let paid = plan.lanes_compiled(self.poses)
                    || plan.batched(self.poses, count.saturating_mul(self.samples)) >= from;
                paid && self.lanes_form()
            }
        }
    }

    /// Whether the model's pose (positions only) or step has a form in
    /// lanes, compiled at the first call.
    fn lanes_form(&self) -> bool {
        self.model.fused.as_deref().is_some_and(|plan| {
            if self.poses {
                plan.lanes_pose().is_some()
            } else {
                plan.lanes_step().is_some()
            }
        })
    }

    /// The conditions of [`Batch::in_pairs`] but the code in lanes.
    fn pairable(&self) -> bool {
        let Some(s) = self.sweep.as_ref() else {
            return false;
        };
        let step_within = self
            .sweep_of(self.model, s)
            .and_then(|b| b.grid())
            .is_ok_and(|g| g.count < 2 || (g.at(1) - g.at(0)).abs() <= crate::closed::CARRIED_STEP);
        step_within && !self.model.params.is_empty() && self.model.fixed_scaling
    }

    /// Designs `values[0]` and `values[1]` with the models `models`, their
    /// records written into `outs`: in lanes where both take the common
    /// path to the end of the sweep, else each swept alone.
    pub(super) fn pair(
        &self,
        models: [&mut Model; 2],
        values: [&[f64]; 2],
        outs: [&mut [f64]; 2],
    ) -> [(usize, Option<Early>); 2] {
        let [m0, m1] = models;
        let [o0, o1] = outs;
        let set = m0.set_values(values[0]).is_ok() && m1.set_values(values[1]).is_ok();
        if set {
            let ends = if self.poses {
                self.lanes_pair([m0, m1], [&mut *o0, &mut *o1])
                    .map(|(ends, _)| ends)
            } else {
                self.steps_pair([m0, m1], [&mut *o0, &mut *o1])
                    .map(|(ends, _)| ends)
            };
            if let Some(ends) = ends {
                return ends;
            }
        }
        // Alone, each from its start; what the pair wrote is cleared.
        o0.fill(f64::NAN);
        o1.fill(f64::NAN);
        [
            self.design(m0, values[0], o0),
            self.design(m1, values[1], o1),
        ]
    }

    /// The pair's sweeps in lanes, with the number of poses taken by each
    /// design's stepper where a design left the common path; `None` where
    /// a design failed a check (the records then partly written).
    fn lanes_pair(&self, models: [&Model; 2], outs: [&mut [f64]; 2]) -> Option<(PairEnds, usize)> {
        let m = models[0];
        let s = self.sweep.as_ref()?;
        // A start the sweep would refuse (its values are checked before
        // the first value of the driver is set).
        m.check_pose(&self.start).ok()?;
        let plan = m.fused.as_deref()?;
        let code = plan.lanes_pose()?;
        // The grid of each design's sweep (the same start and settings).
        let grid = self.sweep_of(m, s).ok()?.grid().ok()?;
        let (n, j) = (m.coordinates.len(), s.driver);
        let mut steppers = [
            models[0].stepper(&self.options).ok()?,
            models[1].stepper(&self.options).ok()?,
        ];
        let [out0, out1] = outs;
        let mut keeps = [out0, out1].map(|out| self.keep(m, out));
        let mut r = vec![0.0; m.points.len() * m.point_dim];
        let (positions, count) = plan.positions_at();
        let mut q = self.start.clone();
        // The first pose, each design's own (which sets its modes).
        q[j] = grid.at(0);
        for (stepper, keep) in steppers.iter_mut().zip(keeps.iter_mut()) {
            stepper.pose(&q).ok()?;
            if !fused(stepper) {
                return None;
            }
            stepper.positions(&mut r).ok()?;
            keep.put_pose(&stepper.q, &r);
        }
        let len = plan.layout().len;
        let modes = steppers[0].modes.len();
        let (mut f, mut q2, mut modes2) =
            (vec![0.0; 2 * len], vec![0.0; 2 * n], vec![0.0; 2 * modes]);
        let mut start = vec![0.0; 2 * n];
        let mut one = vec![0.0; n];
        let mut joined = false;
        let mut alone = 0;
        for k in 1..grid.count {
            let at = grid.at(k);
            let due = steppers[0]
                .fused
                .as_ref()
                .map_or(0, |run| run.steps.wrapping_add(1));
            // The pose in lanes, unless the unknowns' carried values are
            // due to be refreshed (every 64 poses); the drivers' (every
            // 16) are refreshed here, as the helper would.
            if due % 64 != 0 {
                if !joined {
                    let [a, b] = &steppers;
                    interleave(&a.fused.as_ref()?.f, &b.fused.as_ref()?.f, &mut f);
                    interleave(&a.q, &b.q, &mut q2);
                    interleave(&a.modes, &b.modes, &mut modes2);
                    joined = true;
                }
                start.copy_from_slice(&q2);
                start[2 * j] = at;
                start[2 * j + 1] = at;
                if due % 16 == 0 {
                    // The drivers' carried values, as a stepper's refresh
                    // and the helper leave them.
                    for l in 0..2 {
                        plan.refresh_drivers_in_lane(&mut f, &start, l);
                    }
                }
                let status = plan.pose(&code, &mut f, &start, &mut modes2, &mut q2);
                if status == 0 {
                    for (l, (stepper, keep)) in
                        steppers.iter_mut().zip(keeps.iter_mut()).enumerate()
                    {
                        if let Some(run) = stepper.fused.as_mut() {
                            run.steps = run.steps.wrapping_add(1);
                        }
                        let at = 2 * positions;
                        keep.put_lane(&q2, f.get(at..at + 2 * count).unwrap_or(&[]), l);
                    }
                    continue;
                }
                if !crate::runtime::fused::Plan::left_lanes(status) {
                    return None;
                }
                alone += 1;
            }
            // Each design's stepper takes the pose: the refresh, or a
            // design off the common path (a fast turn of an unknown, which
            // the scalar pose takes through the library's closed form).
            // What the code in lanes wrote for this pose leaves the same
            // pose to compute: the values carried to it, rotated by zero.
            for (l, (stepper, keep)) in steppers.iter_mut().zip(keeps.iter_mut()).enumerate() {
                if joined {
                    let run = stepper.fused.as_mut()?;
                    lane(&f, l, &mut run.f);
                    lane(&q2, l, &mut stepper.q);
                    lane(&modes2, l, &mut stepper.modes);
                }
                one.copy_from_slice(&stepper.q);
                one[j] = at;
                stepper.pose(&one).ok()?;
                if !fused(stepper) {
                    return None;
                }
                stepper.positions(&mut r).ok()?;
                keep.put_pose(&stepper.q, &r);
            }
            joined = false;
        }
        Some(([(keeps[0].row, None), (keeps[1].row, None)], alone))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Options;
    use crate::runtime::{BatchSweep, Output};
    use crate::sweep::ChangePoints;

    use crate::runtime::test_models::crank_rocker;

    /// A turn of the crank in 360 steps, stopping at a change point.
    fn turn() -> BatchSweep {
        BatchSweep {
            driver: 0,
            from: None,
            to: None,
            turns: Some(1.0),
            steps: 360,
            change_points: ChangePoints::Stop,
        }
    }

    /// Pairs of crank-rockers run to their end in lanes; the longer the
    /// crank, the faster the rocker swings near its extremes, and a pair
    /// of the longest takes some poses by each design's stepper (more
    /// than 1/32 rad a step) and goes on in lanes, to the same numbers as
    /// design by design.
    #[test]
    fn pairs_finish_in_lanes_with_poses_off_the_common_path() {
        let m = crank_rocker();
        let start = m.assemble(&[0.0, 0.5, 1.5]).expect("assembles");
        let sweep = turn();
        let batch = |lanes: bool| {
            Batch::new(
                &m,
                &start,
                &[1.0],
                &[0.0],
                Some(sweep.clone()),
                &[Output::Position(1)],
                &Options::DEFAULT,
            )
            .expect("a batch")
            .positions_only()
            .expect("positions only")
            .in_lanes(lanes)
        };
        let paired = batch(true);
        assert!(paired.in_pairs());
        let mut most = 0;
        for crank in [0.03, 0.05, 0.07, 0.085, 0.088] {
            let (mut m0, mut m1) = (m.clone(), m.clone());
            m0.set_values(&[crank, 0.12, 0.10, 0.11]).expect("values");
            m1.set_values(&[crank - 0.001, 0.12, 0.10, 0.11])
                .expect("values");
            let record = paired.record();
            let mut out = vec![f64::NAN; 2 * record];
            let (o0, o1) = out.split_at_mut(record);
            let (ends, alone) = paired
                .lanes_pair([&m0, &m1], [o0, o1])
                .unwrap_or_else(|| panic!("crank {crank}: the pair finishes in lanes"));
            assert_eq!(ends.map(|e| e.0), [360, 360]);
            most = most.max(alone);
            // Design by design, the same numbers.
            let designs = [crank, 0.12, 0.10, 0.11, crank - 0.001, 0.12, 0.10, 0.11];
            let each = batch(false).run(&designs);
            assert!(
                out.iter()
                    .zip(&each.values)
                    .all(|(x, y)| x.to_bits() == y.to_bits())
            );
        }
        assert!(most > 0, "no pose left the common path");
    }

    /// A batch that is not told compiles its code in lanes only once the
    /// model's batches that could pair have run enough positions (one
    /// large batch, or many small ones), and then uses it for any size;
    /// told, it uses it or not whatever the size.
    #[test]
    fn a_small_batch_does_not_compile_the_code_in_lanes() {
        let start = crank_rocker()
            .assemble(&[0.0, 0.5, 1.5])
            .expect("assembles");
        let sweep = turn();
        fn batch<'m>(m: &'m Model, start: &[f64], sweep: &BatchSweep, poses: bool) -> Batch<'m> {
            let b = Batch::new(
                m,
                start,
                &[1.0],
                &[0.0],
                Some(sweep.clone()),
                &[Output::Position(1)],
                &Options::DEFAULT,
            )
            .expect("a batch");
            if poses {
                b.positions_only().expect("positions only")
            } else {
                b
            }
        }
        for (poses, from) in [
            (false, Batch::LANES_FROM_STEPS),
            (true, Batch::LANES_FROM_POSES),
        ] {
            // Models of their own: each compiles its code in lanes once.
            let [m, n, o] = [crank_rocker(), crank_rocker(), crank_rocker()];
            let compiled = |m: &Model| {
                m.fused
                    .as_deref()
                    .is_some_and(|plan| plan.lanes_compiled(poses))
            };
            let b = batch(&m, &start, &sweep, poses);
            let samples = b.rows();
            // The designs whose positions pay for the compilation.
            let enough = from.div_ceil(samples);
            assert!(!b.pairs_for(enough / 2) && !compiled(&m), "poses {poses}");
            let designs = [0.04, 0.12, 0.10, 0.11].repeat(4);
            assert!(b.run(&designs).samples.iter().all(|&k| k == samples));
            assert!(!compiled(&m));
            assert!(!b.clone().in_lanes(false).pairs_for(enough) && !compiled(&m));
            // The rest of the positions: the small batches have paid.
            assert!(b.pairs_for(enough - enough / 2 - 4) && compiled(&m));
            assert!(b.pairs_for(1));
            assert!(!b.clone().in_lanes(false).pairs_for(enough));
            // One batch large enough pays alone.
            let c = batch(&n, &start, &sweep, poses);
            assert!(!c.pairs_for(enough - 1) && !compiled(&n));
            let d = batch(&o, &start, &sweep, poses);
            assert!(d.pairs_for(enough) && compiled(&o));
            // Told to, a small batch compiles it.
            let e = batch(&n, &start, &sweep, poses).in_lanes(true);
            assert!(e.pairs_for(1) && compiled(&n));
        }
    }
}
