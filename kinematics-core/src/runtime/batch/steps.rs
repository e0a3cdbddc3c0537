//! A batch of full steps (positions, velocities and accelerations), two
//! designs per instruction: the designs taken in pairs, each design's
//! sweep the one sweep driver's ([`SweepIter`]), the pair's steps on the
//! common path taken by the step's machine code in vector lanes.
//!
//! Each design's iterator predicts its next pose and sets its drivers
//! ([`SweepIter::step_inputs`]); the step in lanes solves both (the
//! buffer interleaved, value i of design l at 2i + l); each iterator then
//! takes its design's outcome ([`SweepIter::conclude_common`]) as it takes
//! its own steps. So each design's samples, stop and record are its
//! sweep's, bit for bit: each lane computes what the scalar step computes
//! for its design, operation for operation.
//!
//! While the pair steps in lanes, the interleaved buffer is the designs'
//! state; each stepper gets back, per sample, only what its sweep and the
//! record read (the pose and rates, the judged values, the outputs kept),
//! and the whole buffer where it goes on alone. A design steps alone at a
//! sample where the step leaves the common path in either lane (a fast
//! turn of an unknown, which the scalar step hands to the library's
//! closed form) or refreshes the unknowns' carried cosines and sines
//! (every 64 steps), and goes on alone from a sample off its sweep's
//! common path (a change of branch ahead, a limit) to its end. Where a
//! check fails in lanes (a value not finite, a singular block, the other
//! branch), both take that step alone too, from what the code in lanes
//! left: the values it carried to the step, which the step alone rotates
//! by zero (the same numbers), as a design's stepper takes a step from
//! what its own code left where a check failed.

use alloc::vec;
use alloc::vec::Vec;

use super::lanes::{interleave, lane};
use super::{Batch, Early, Keep, keep};
use crate::runtime::drive::{Held, Sink, Stepped, rest, start};
use crate::runtime::stepper::FlatAt;
use crate::runtime::{Model, Stepper};
use crate::sweep::{Engine, Stop, SweepDrive, SweepIter};

/// A design's sweep as a batch of steps drives it.
type Iter<'e, 'm> = SweepIter<'e, Stepped<'m>, SweepDrive, Held>;

/// How each design of a pair ended: its samples, and why it ended early;
/// and the samples the pair took in lanes.
type PairEnds = ([(usize, Option<Early>); 2], usize);

/// The steppers of both designs' sweeps.
fn steppers<'a, 'm>(its: &'a mut [Iter<'_, 'm>; 2]) -> Option<[&'a mut Stepper<'m>; 2]> {
    let [a, b] = its;
    Some([a.state_mut()?, b.state_mut()?])
}

/// Hands the sample `s` of a design's sweep to its record.
#[inline(always)]
fn put(s: Held, stepper: Option<&mut Stepper<'_>>, mut keep: &mut Keep<'_>) {
    match (s, stepper) {
        (Held::Current { at, .. }, Some(stepper)) => keep.stepped(at, stepper),
        (Held::Kept { at, motion }, _) => keep.motion(at, &motion),
        (Held::Current { .. }, None) => {}
    }
}

/// The items of a design's sweep off its common path, handed to its
/// record until its next sample is on it again (or it ended); its stop.
fn until_common(it: &mut Iter<'_, '_>, keep: &mut Keep<'_>, stop: &mut Option<Stop>) {
    while it.next_common().is_none() {
        match it.next() {
            None => return,
            Some(Ok(s)) => put(s, it.state_mut(), keep),
            Some(Err(s)) => *stop = Some(s),
        }
    }
}

/// The interleaved state of a pair stepping in lanes: the buffer, the
/// modes and the poses, and the steps' inputs.
struct Joined {
    f: Vec<f64>,
    modes: Vec<f64>,
    q: Vec<f64>,
    start: Vec<f64>,
    rates: Vec<f64>,
    accelerations: Vec<f64>,
    /// Whether `f`, `modes` and `q` hold the steppers' state (else each
    /// stepper holds its own).
    held: bool,
}

impl Joined {
    /// The steppers' state interleaved, where it is not already.
    fn join(&mut self, steppers: [&Stepper<'_>; 2]) -> Option<()> {
        if !self.held {
            let [a, b] = steppers;
            interleave(&a.fused.as_ref()?.f, &b.fused.as_ref()?.f, &mut self.f);
            interleave(&a.modes, &b.modes, &mut self.modes);
            interleave(&a.q, &b.q, &mut self.q);
            self.held = true;
        }
        Some(())
    }

    /// Each stepper given back its whole state, where the pair holds it.
    fn part(&mut self, steppers: [&mut Stepper<'_>; 2]) {
        if !self.held {
            return;
        }
        for (l, s) in steppers.into_iter().enumerate() {
            if let Some(run) = s.fused.as_mut() {
                lane(&self.f, l, &mut run.f);
            }
            lane(&self.modes, l, &mut s.modes);
            lane(&self.q, l, &mut s.q);
        }
        self.held = false;
    }
}

impl Batch<'_> {
    /// The pair's sweeps of full steps, in lanes where both designs are on
    /// their common path, with the number of samples taken in lanes;
    /// `None` where the pair cannot step in lanes (a sweep that does not
    /// start, a model without the step in lanes; the records then perhaps
    /// partly written, and each design is swept alone).
    pub(super) fn steps_pair(
        &self,
        models: [&Model; 2],
        outs: [&mut [f64]; 2],
    ) -> Option<PairEnds> {
        let m = models[0];
        let s = self.sweep.as_ref()?;
        let plan = m.fused.as_deref()?;
        let code = plan.lanes_step()?;
        let builder = |model| {
            self.sweep_of(model, s).ok().map(|b| {
                b.rate(self.rates[s.driver])
                    .acceleration(self.accelerations[s.driver])
                    .change_points(s.change_points)
            })
        };
        let builders = [builder(models[0])?, builder(models[1])?];
        let engines = [Stepped::new(models[0]), Stepped::new(models[1])];
        let setups = [builders[0].setup(), builders[1].setup()];
        let [(g0, d0), (g1, d1)] = [builders[0].parts(), builders[1].parts()];
        let mut its: [Iter<'_, '_>; 2] = [
            start::<SweepDrive, Held>(&engines[0], &setups[0], g0, d0).ok()?,
            start::<SweepDrive, Held>(&engines[1], &setups[1], g1, d1).ok()?,
        ];
        let [out0, out1] = outs;
        let mut keeps = [out0, out1].map(|out| self.keep(m, out));
        let mut stops = [None, None];
        // Each design's first sample (its modes, its carried values), and
        // any others off the common path.
        for ((it, keep), stop) in its.iter_mut().zip(&mut keeps).zip(&mut stops) {
            until_common(it, keep, stop);
        }
        // What each sample of a step in lanes gives back to the steppers:
        // what their sweeps read (the outputs kept are read in lanes).
        let (flat, copies) = Self::layout_of(its[0].state_mut()?, engines[0].newton_guess())?;
        let (n, nd) = (m.coordinates.len(), m.drivers);
        let [conditioning, sign, _] = plan.results_at();
        let len = plan.layout().len;
        let mut in_lanes = 0;
        let mut joined = Joined {
            f: vec![0.0; 2 * len],
            modes: vec![0.0; 2 * its[0].state_mut()?.modes.len()],
            q: vec![0.0; 2 * n],
            start: vec![0.0; 2 * n],
            rates: vec![0.0; 2 * nd],
            accelerations: vec![0.0; 2 * nd],
            held: false,
        };
        while let (Some((k, at)), Some((k1, at1))) = (its[0].next_common(), its[1].next_common()) {
            if k != k1 || at.to_bits() != at1.to_bits() {
                break;
            }
            // The steps each stepper has taken (the same while the pair
            // steps together), which time the refreshes.
            let [a, b] = &mut its;
            let steps = match (a.state_mut(), b.state_mut()) {
                (Some(a), Some(b)) => match (a.fused.as_ref(), b.fused.as_ref()) {
                    (Some(a), Some(b)) if a.steps == b.steps => a.steps,
                    _ => break,
                },
                _ => break,
            };
            let due = steps.wrapping_add(1);
            for (l, it) in its.iter_mut().enumerate() {
                let [guess, rates, accelerations] = it.step_inputs(at);
                let into = |to: &mut [f64], from: &[f64]| {
                    for (pair, x) in to.chunks_exact_mut(2).zip(from) {
                        if let Some(slot) = pair.get_mut(l) {
                            *slot = *x;
                        }
                    }
                };
                into(&mut joined.start, guess);
                into(&mut joined.rates, rates);
                into(&mut joined.accelerations, accelerations);
            }
            // The unknowns' carried values are refreshed by the helper
            // (every 64 steps): each design alone then.
            if due % 64 != 0 {
                joined.join(steppers(&mut its)?.map(|s| &*s))?;
                if due % 16 == 0 {
                    // The drivers' carried values, as a stepper's refresh
                    // and the helper leave them.
                    for l in 0..2 {
                        plan.refresh_drivers_in_lane(&mut joined.f, &joined.start, l);
                    }
                }
                let status = plan.step(
                    &code,
                    &mut joined.f,
                    [&joined.start, &joined.rates, &joined.accelerations],
                    &mut joined.modes,
                    &mut joined.q,
                );
                if status == 0 {
                    let read = |i: usize| joined.f.get(i).copied().unwrap_or(f64::NAN);
                    let (c, s) = (2 * conditioning, 2 * sign);
                    let judged = [(read(c), read(s)), (read(c + 1), read(s + 1))];
                    let common = its[0].passes(judged[0].1) && its[1].passes(judged[1].1);
                    if !common {
                        // A sample off the common path: each design takes
                        // it with its whole state, then goes on alone.
                        joined.part(steppers(&mut its)?);
                    }
                    for (l, (it, keep)) in its.iter_mut().zip(&mut keeps).enumerate() {
                        let stepper = it.state_mut()?;
                        if common && let Some(run) = stepper.fused.as_mut() {
                            for &o in &copies {
                                if let (Some(x), Some(v)) =
                                    (run.f.get_mut(o), joined.f.get(2 * o + l))
                                {
                                    *x = *v;
                                }
                            }
                        }
                        stepper.stepped_in_lanes();
                        match it.conclude_common(k, at, Ok(judged[l])) {
                            Some(Held::Current { .. }) if common => {
                                keep.put_fused_lane(&joined.f, &flat, l);
                            }
                            Some(sample) => put(sample, it.state_mut(), keep),
                            None => {}
                        }
                    }
                    in_lanes += 1;
                    if common {
                        continue;
                    }
                    break;
                }
                // Left the common path, or a check failed in a lane: each
                // design takes the step alone, from what the code in
                // lanes left (the values it carried rotated by zero, the
                // same numbers), as its stepper takes it from its own.
            }
            joined.part(steppers(&mut its)?);
            // Each design's own step of this sample.
            let mut off = false;
            for (it, keep) in its.iter_mut().zip(&mut keeps) {
                match it.step_prepared(k, at) {
                    Some(sample) => put(sample, it.state_mut(), keep),
                    None => off = true,
                }
            }
            if off {
                break;
            }
        }
        joined.part(steppers(&mut its)?);
        // Each design to its end alone.
        let mut ends = [(0, None), (0, None)];
        for (((it, keep), stop), end) in its.iter_mut().zip(&mut keeps).zip(stops).zip(&mut ends) {
            let mut sink = &mut *keep;
            let last = rest(it, &mut sink);
            *end = (keep.row, stop.or(last).map(Early::Stopped));
        }
        Some((ends, in_lanes))
    }

    /// Where a fused step of `stepper` leaves its results (`None` for a
    /// stepper without fused code), and the offsets
    /// of the buffer a design's sweep reads of a sample: the pose, and its
    /// rates where the predictor reads them (Newton blocks).
    fn layout_of(stepper: &Stepper<'_>, newton: bool) -> Option<(FlatAt, Vec<usize>)> {
        let at = stepper.fused_layout()?;
        let end = if newton { at.qdd } else { at.qd };
        Some((at, (at.q..end).collect()))
    }
}

impl Keep<'_> {
    /// Keeps lane `l`'s sample of the interleaved buffer `f` of a step in
    /// lanes, laid out as `at` says, as the next row: each slot's few
    /// values gathered (as [`Keep::put_fused`] reads them alone).
    #[inline(always)]
    fn put_fused_lane(&mut self, f: &[f64], at: &FlatAt, l: usize) {
        let row = self.row;
        if row >= self.rows {
            return;
        }
        for s in self.slots {
            let Some(first) = s.in_buffer(at) else {
                continue;
            };
            let read = |i: usize| f.get(2 * (first + i) + l).copied().unwrap_or(f64::NAN);
            if s.width <= 3 {
                // A coordinate, the conditioning, a point's vector.
                let mut v = [0.0; 3];
                for (i, x) in v.iter_mut().enumerate().take(s.width) {
                    *x = read(i);
                }
                keep(self.out, s, row, self.reduce, &v[..s.width], 0);
            } else {
                self.scratch.clear();
                self.scratch.extend((0..s.width).map(read));
                keep(self.out, s, row, self.reduce, &self.scratch, 0);
            }
        }
        self.row = row + 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Options;
    use crate::runtime::{BatchSweep, Output};
    use crate::sweep::ChangePoints;

    use crate::runtime::test_models::crank_rocker;

    /// Pairs of crank-rockers step in lanes through two turns (the
    /// carried values refreshed many times, the unknowns' by each design
    /// alone), the longer cranks' fast-swinging rockers taking some steps
    /// alone; every record bit for bit the batch's design by design.
    #[test]
    fn pairs_step_in_lanes_to_the_numbers_of_each_design_alone() {
        let m = crank_rocker();
        let start = m.assemble(&[0.0, 0.5, 1.5]).expect("assembles");
        let sweep = BatchSweep {
            driver: 0,
            from: None,
            to: None,
            turns: Some(2.0),
            steps: 720,
            change_points: ChangePoints::Stop,
        };
        let batch = |lanes: bool| {
            Batch::new(
                &m,
                &start,
                &[10.0],
                &[3.0],
                Some(sweep.clone()),
                &[
                    Output::Rate(2),
                    Output::Acceleration(1),
                    Output::PointAcceleration(1),
                    Output::Conditioning,
                ],
                &Options::DEFAULT,
            )
            .expect("a batch")
            .in_lanes(lanes)
        };
        let paired = batch(true);
        assert!(paired.in_pairs() && !batch(false).in_pairs());
        for crank in [0.03, 0.05, 0.07, 0.085, 0.088] {
            let (mut m0, mut m1) = (m.clone(), m.clone());
            m0.set_values(&[crank, 0.12, 0.10, 0.11]).expect("values");
            m1.set_values(&[crank - 0.001, 0.12, 0.10, 0.11])
                .expect("values");
            let record = paired.record();
            let mut out = vec![f64::NAN; 2 * record];
            let (o0, o1) = out.split_at_mut(record);
            let (ends, in_lanes) = paired
                .steps_pair([&m0, &m1], [o0, o1])
                .unwrap_or_else(|| panic!("crank {crank}: the pair runs"));
            assert_eq!(ends.clone().map(|e| e.0), [720, 720]);
            assert!(ends.iter().all(|e| e.1.is_none()));
            // Most samples in lanes; each 64th step and the fast swings
            // alone.
            assert!(in_lanes > 600, "crank {crank}: {in_lanes} samples in lanes");
            let designs = [crank, 0.12, 0.10, 0.11, crank - 0.001, 0.12, 0.10, 0.11];
            let each = batch(false).run(&designs);
            for (i, (x, y)) in out.iter().zip(&each.values).enumerate() {
                assert!(
                    x.to_bits() == y.to_bits(),
                    "crank {crank}, value {i}: {x} in lanes, {y} alone"
                );
            }
        }
    }
}
