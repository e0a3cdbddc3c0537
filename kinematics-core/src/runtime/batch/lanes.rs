//! A batch of positions only, two designs per instruction: the designs
//! taken in pairs, each pair's poses by the pose's machine code in vector
//! lanes (both designs' buffers interleaved), its samples those of each
//! design's sweep of poses.
//!
//! Each design keeps its own stepper, which takes the first pose and the
//! poses at which the unknowns' carried cosines and sines are refreshed
//! (every 64), as its sweep would, and those where a design leaves the
//! common path (an unknown turning fast); between them the pair steps in
//! lanes (the driver's carried cosine and sine refreshed every 16 as the
//! helper refreshes them), each lane
//! the scalar pose's computation for its design, operation for operation,
//! from the previous pose (the guesses matter to a closed form only for
//! the turn of its angles, which both carry). Where a design leaves the
//! common path (a limit position ahead, a pose off the closed forms'
//! guards, a value not finite), both designs of the pair are swept alone
//! from their start, as the batch sweeps any design: so every design's
//! samples, stop and record are its sweep's.

use alloc::vec;
use alloc::vec::Vec;

use super::{Batch, Early, From, Keep, keep};
use crate::runtime::{Model, Stepper};

/// Value i of lane `l` (0 or 1) of an interleaved array, for each i.
#[inline]
fn lane(v: &[f64], l: usize, out: &mut [f64]) {
    let second = l == 1;
    for (o, pair) in out.iter_mut().zip(v.chunks_exact(2)) {
        *o = if second { pair[1] } else { pair[0] };
    }
}

/// The two arrays interleaved into `out` (a's values at even entries).
fn interleave(a: &[f64], b: &[f64], out: &mut [f64]) {
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
    /// Whether this batch runs its designs in pairs in vector lanes
    /// ([`Batch::in_lanes`]): positions only, swept, lanes not turned off,
    /// and a model with parameters whose pose has a form in lanes (its
    /// closed forms in its fused code). Compiles that form at the first
    /// call for the model.
    #[must_use]
    pub fn in_pairs(&self) -> bool {
        self.poses
            && self.lanes
            && self.sweep.is_some()
            && !self.model.params.is_empty()
            && self
                .model
                .fused
                .as_deref()
                .is_some_and(|plan| plan.lanes_pose().is_some())
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
        if set && let Some(ends) = self.lanes_pair([m0, m1], [&mut *o0, &mut *o1]) {
            return ends;
        }
        // Alone, each from its start; what the pair wrote is cleared.
        o0.fill(f64::NAN);
        o1.fill(f64::NAN);
        [
            self.design(m0, values[0], o0),
            self.design(m1, values[1], o1),
        ]
    }

    /// The pair's sweeps in lanes; `None` where a design left the common
    /// path (the records then partly written).
    fn lanes_pair(
        &self,
        models: [&Model; 2],
        outs: [&mut [f64]; 2],
    ) -> Option<[(usize, Option<Early>); 2]> {
        let m = models[0];
        let s = self.sweep.as_ref()?;
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
        let mut keeps = [out0, out1].map(|out| Keep {
            model: m,
            slots: &self.slots,
            out,
            row: 0,
            rows: self.samples,
            reduce: self.reduce,
            scratch: Vec::new(),
        });
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
                    plan.carry_driver_in_lanes(&mut f, j, at);
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
        Some([(keeps[0].row, None), (keeps[1].row, None)])
    }
}
