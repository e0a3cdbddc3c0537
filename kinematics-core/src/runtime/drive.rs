//! The loop of a run-time sweep: each sample assembled from the last
//! (the closed forms in their carried modes, the Newton blocks from the
//! parabola through the last three samples) and analysed, the stop at a
//! limit position found by bisection, the branch chosen past a change
//! point, and the sinks the samples are handed to.

use alloc::collections::VecDeque;

use super::fused::copy_small;
use super::sweep::SweepEnd;
use super::{Flat, Model, Motion};
use crate::error::Error;
use crate::mechanism::Kind;
use crate::names::Name;
use crate::options::Options;
use crate::sweep::{ChangePoints, Stop, StopReason};

/// A sample remembered for the prediction of the next pose, the test for
/// a change of branch and the bisection of a limit position.
pub(super) struct Recent {
    pub(super) at: f64,
    pub(super) q: Vec<f64>,
    pub(super) conditioning: f64,
    pub(super) det_sign: f64,
}

/// The last three samples, oldest first (their vectors reused as the
/// sweep moves on: no allocation per sample).
struct History(VecDeque<Recent>);

impl History {
    fn len(&self) -> usize {
        self.0.len()
    }
    /// The k-th sample from the end (1: the last).
    fn last(&self, k: usize) -> &Recent {
        &self.0[self.0.len() - k]
    }
    fn push(&mut self, at: f64, pose: &[f64], conditioning: f64, det_sign: f64) {
        // The oldest sample's vector, once there are three.
        let mut q = if self.0.len() == 3 {
            self.0.pop_front().map(|r| r.q).unwrap_or_default()
        } else {
            Vec::with_capacity(pose.len())
        };
        q.resize(pose.len(), 0.0);
        copy_small(&mut q, pose);
        self.0.push_back(Recent {
            at,
            q,
            conditioning,
            det_sign,
        });
    }
}

/// The samples at the values `ats` of the swept variable, the drivers,
/// their rates and their accelerations at each set by `set(at, d, d',
/// d'')`; from the pose `start`, each handed to `emit` as it is solved.
/// Each sample is assembled (the closed forms in the modes of the start,
/// carried; the Newton blocks from the parabola through the last three
/// samples) and analysed; the sweep stops at a limit position (by
/// bisection), where two branches meet, and at any error.
pub(super) fn drive_each(
    m: &Model,
    (variable, _kind, first): (Name, Kind, f64),
    start: &[f64],
    (options, change_points): (&Options, ChangePoints),
    ats: Result<Vec<f64>, Error>,
    mut set: impl FnMut(f64, &mut [f64], &mut [f64], &mut [f64]),
    mut sink: impl Sink,
) -> SweepEnd {
    let mut end = SweepEnd {
        stop: None,
        change_points: Vec::new(),
    };
    let stop = |at: f64, reason: StopReason| Stop {
        variable,
        at,
        reason,
    };
    let nd = m.drivers;
    let mut rates = vec![0.0; nd];
    let mut accelerations = vec![0.0; nd];
    let checked = ats.and_then(|ats| {
        options.validate()?;
        m.validate()?;
        m.check_inputs(start, &rates, &accelerations)?;
        Ok(ats)
    });
    let ats = match checked {
        Ok(a) => a,
        Err(e) => {
            end.stop = Some(stop(first, StopReason::from_error(e)));
            return end;
        }
    };
    // The steps through a stepper (the model's fused code where it has
    // one); the limit and change-point searches with arrays of their own.
    let mut stepper = match m.stepper(options) {
        Ok(s) => s,
        Err(e) => {
            end.stop = Some(stop(first, StopReason::from_error(e)));
            return end;
        }
    };
    let mut w = m.work();
    let mut q = start.to_vec();
    let mut predicted = q.clone();
    let mut history = History(VecDeque::with_capacity(3));
    // A sample left out because Φ_u is singular exactly there (a change
    // point met on the grid), its value: the branch is chosen at the next.
    let mut crossing: Option<f64> = None;
    for (i, &at) in ats.iter().enumerate() {
        predict(&history, at, nd, &mut q);
        set(at, &mut q[..nd], &mut rates, &mut accelerations);
        predicted.copy_from_slice(&q);
        // The assembly modes of the closed-form blocks: the start's, then
        // carried from sample to sample by the stepper.
        match stepper.advance(&q, &rates, &accelerations) {
            Ok(()) => {}
            Err(e @ Error::Singular { .. }) if history.len() > 0 && crossing.is_none() => {
                if change_points != ChangePoints::Stop {
                    // Exactly at a change point: this sample is left out,
                    // and the branch chosen at the next.
                    crossing = Some(at);
                    continue;
                }
                // A change point met exactly, if the conditioning rises
                // again past it as it fell before it (a V); else a
                // singular position.
                let last = history.last(1);
                let (from, before) = (last.at, last.conditioning);
                let modes = stepper.signs_mut().to_vec();
                let after = ats.get(i + 1).and_then(|&next| {
                    let mut probe = q.clone();
                    predict(&history, next, nd, &mut probe);
                    let (mut r, mut a) = (vec![0.0; nd], vec![0.0; nd]);
                    set(next, &mut probe[..nd], &mut r, &mut a);
                    let mut trial = modes.clone();
                    m.assemble_into(&mut probe, &mut w, &mut trial, options, false)
                        .ok()?;
                    let motion = m.analyze_at(&probe, &r, &a, &mut w, options, false).ok()?;
                    Some((next, motion.conditioning))
                });
                let reason = match after {
                    Some((to, c2)) if c2 < 2.0 * before && before < 2.0 * c2 => {
                        StopReason::ChangePoint { from, to }
                    }
                    _ => StopReason::from_error(e),
                };
                end.stop = Some(stop(at, reason));
                return end;
            }
            Err(Error::CannotAssemble { unknowns, .. }) if history.len() > 0 => {
                // A limit position between the last sample and this
                // value: the last value that assembles, by bisection.
                let modes = stepper.signs_mut().to_vec();
                let limit = limit(m, history.last(1), at, &modes, options, &mut set, &mut w);
                end.stop = Some(stop(limit, StopReason::LimitPosition { unknowns }));
                return end;
            }
            Err(e) => {
                end.stop = Some(stop(at, StopReason::from_error(e)));
                return end;
            }
        }
        // The pose, its conditioning and its branch, kept before the
        // tests of a change of branch.
        let (conditioning, det_sign) = {
            let new = stepper.flat();
            copy_small(&mut q, new.q);
            (new.conditioning, new.det_sign)
        };
        let mut chosen: Option<Motion> = None;
        if history.len() > 0 {
            let last = history.last(1);
            let at_fold = folded(&history, &q, &predicted, nd);
            let crossed = crossing.take();
            if crossed.is_some() || at_fold.is_some() || last.det_sign != det_sign {
                // Two branches met between the samples (at the sample left
                // out, where one was).
                let estimate = crossed.or(at_fold).map_or(0.5 * (last.at + at), |x| {
                    x.clamp(last.at.min(at), last.at.max(at))
                });
                let branch = (change_points != ChangePoints::Stop)
                    .then(|| {
                        let rates = (&rates[..], &accelerations[..]);
                        past(
                            m,
                            &predicted,
                            stepper.signs_mut(),
                            rates,
                            options,
                            change_points,
                            &mut w,
                        )
                    })
                    .flatten();
                let Some(motion) = branch else {
                    end.stop = Some(stop(
                        estimate,
                        StopReason::ChangePoint {
                            from: last.at,
                            to: at,
                        },
                    ));
                    return end;
                };
                chosen = Some(motion);
                end.change_points.push(estimate);
            }
        }
        match &chosen {
            Some(motion) => {
                q.copy_from_slice(&motion.q);
                history.push(at, &motion.q, motion.conditioning, motion.det_sign);
                sink.motion(at, motion);
            }
            None => {
                history.push(at, &q, conditioning, det_sign);
                sink.stepped(at, &mut stepper);
            }
        }
    }
    end
}

/// What a sweep hands its samples to: a step's (read from the stepper,
/// as a [`Motion`] or flat arrays) or a motion chosen past a change point.
pub(super) trait Sink {
    fn stepped(&mut self, at: f64, stepper: &mut super::Stepper<'_>);
    fn motion(&mut self, at: f64, motion: &Motion);
}

/// Hands each sample to a callback as a [`Motion`].
pub(super) struct Motions<F>(pub(super) F);

impl<F: FnMut(f64, &Motion)> Sink for Motions<F> {
    fn stepped(&mut self, at: f64, stepper: &mut super::Stepper<'_>) {
        (self.0)(at, stepper.motion_now());
    }
    fn motion(&mut self, at: f64, motion: &Motion) {
        (self.0)(at, motion);
    }
}

/// Hands each sample to a callback as flat arrays (a motion chosen past a
/// change point through arrays of its own).
pub(super) struct Flats<'m, F> {
    f: F,
    m: &'m Model,
    outputs: Vec<f64>,
}

impl<'m, F> Flats<'m, F> {
    pub(super) fn new(m: &'m Model, f: F) -> Self {
        Flats {
            f,
            m,
            outputs: Vec::new(),
        }
    }
}

impl<F: FnMut(f64, &Flat<'_>)> Sink for Flats<'_, F> {
    fn stepped(&mut self, at: f64, stepper: &mut super::Stepper<'_>) {
        (self.f)(at, &stepper.flat());
    }
    fn motion(&mut self, at: f64, motion: &Motion) {
        self.m.flatten_outputs(motion, &mut self.outputs);
        (self.f)(
            at,
            &Flat {
                q: &motion.q,
                qd: &motion.qd,
                qdd: &motion.qdd,
                outputs: &self.outputs,
                conditioning: motion.conditioning,
                det_sign: motion.det_sign,
                residual: motion.residual,
            },
        );
    }
}

/// The pose past a change point on the branch `change_points` asks for:
/// every combination of the closed forms' modes is assembled from the
/// extrapolated pose `predicted` (for up to 16 two-mode blocks); `Smooth`
/// takes the assembly nearest it, `Switch` the nearest of the others.
/// `modes` is set to the chosen combination. `None` where there is no
/// choice to make (no two-mode block, or no assembly but one).
fn past(
    m: &Model,
    predicted: &[f64],
    modes: &mut [f64],
    (rates, accelerations): (&[f64], &[f64]),
    options: &Options,
    change_points: ChangePoints,
    w: &mut super::solve::Work,
) -> Option<Motion> {
    let k = modes.len();
    if !(1..=16).contains(&k) || !m.closed_path() {
        return None;
    }
    let nd = m.drivers;
    let mut candidates: Vec<(f64, Vec<f64>, Vec<f64>)> = Vec::new();
    for combination in 0..1usize << k {
        let mut trial: Vec<f64> = (0..k)
            .map(|j| if combination >> j & 1 == 1 { -1.0 } else { 1.0 })
            .collect();
        let mut q = predicted.to_vec();
        if m.assemble_into(&mut q, w, &mut trial, options, true)
            .is_err()
        {
            continue;
        }
        // The distance from the extrapolated pose, angles and lengths
        // alike (as the generated sweep measures it).
        let d = q[nd..]
            .iter()
            .zip(&predicted[nd..])
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>();
        let same = candidates.iter().any(|(_, c, _)| {
            c.iter()
                .zip(&q)
                .all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs()))
        });
        if !same {
            candidates.push((d, q, trial));
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let chosen = match change_points {
        ChangePoints::Smooth => candidates.first(),
        ChangePoints::Switch => candidates.get(1),
        ChangePoints::Stop => None,
    }?;
    if candidates.len() < 2 {
        return None;
    }
    let (_, q, trial) = chosen;
    modes.copy_from_slice(trial);
    m.analyze_at(q, rates, accelerations, w, options, false)
        .ok()
}

/// The last value of the swept variable between the sample `last`, which
/// assembles, and `failed`, which does not (a closed-form block has no
/// real solution there), in the modes `modes`: by bisection, to the
/// resolution of `f64`.
pub(super) fn limit(
    m: &Model,
    last: &Recent,
    failed: f64,
    modes: &[f64],
    options: &Options,
    set: &mut impl FnMut(f64, &mut [f64], &mut [f64], &mut [f64]),
    w: &mut super::solve::Work,
) -> f64 {
    let nd = m.drivers;
    let (mut good, mut bad) = (last.at, failed);
    let mut q = last.q.clone();
    let (mut rates, mut accelerations) = (vec![0.0; nd], vec![0.0; nd]);
    let mut trial_modes = modes.to_vec();
    for _ in 0..200 {
        let mid = 0.5 * (good + bad);
        if mid == good || mid == bad {
            break;
        }
        q.copy_from_slice(&last.q);
        set(mid, &mut q[..nd], &mut rates, &mut accelerations);
        trial_modes.copy_from_slice(modes);
        match m.assemble_into(&mut q, w, &mut trial_modes, options, false) {
            Ok(()) => good = mid,
            Err(_) => bad = mid,
        }
    }
    good
}

/// Whether two branches met between the last sample and `new`, solved
/// from the guess `predicted`: the conditioning of the last two samples
/// falls (by the line through them) to zero less than two steps past the
/// last, the last is below 0.5 (a regular pose is of order one), and the
/// new pose is off the prediction by more than half the last step's
/// change (on a smooth branch the parabola through three samples is off
/// by the step cubed: a jump of the order of the step is a change of
/// branch, as at a parallelogram's fold, where a closed form in its mode
/// passes from one branch to the other). Returns where the line meets
/// zero.
fn folded(history: &History, new: &[f64], predicted: &[f64], drivers: usize) -> Option<f64> {
    if history.len() < 2 {
        return None;
    }
    let (a, b) = (history.last(2), history.last(1));
    let (ca, cb) = (a.conditioning, b.conditioning);
    let step = b.at - a.at;
    if !(cb < ca && cb < 0.5 && step != 0.0) {
        return None;
    }
    // The line through (a, ca) and (b, cb) meets zero at b + t·step.
    let t = cb / (ca - cb);
    let largest = |x: &mut dyn Iterator<Item = f64>| x.fold(0.0f64, f64::max);
    let change = largest(
        &mut a.q[drivers..]
            .iter()
            .zip(&b.q[drivers..])
            .map(|(x, y)| (x - y).abs()),
    );
    let off = largest(
        &mut new[drivers..]
            .iter()
            .zip(&predicted[drivers..])
            .map(|(x, y)| (x - y).abs()),
    );
    (t < 2.0 && off > 0.5 * change).then_some(b.at + t * step)
}

/// The guess of the unknowns at `at` (written into `q` past the
/// `drivers`): the parabola through the last three samples, the line
/// through the last two, or the last pose.
fn predict(history: &History, at: f64, drivers: usize, q: &mut [f64]) {
    let n = history.len();
    let last = |k: usize| history.last(k);
    match n {
        0 => {}
        1 => q[drivers..].copy_from_slice(&last(1).q[drivers..]),
        _ => {
            // The interpolating polynomial in Lagrange's form: its weights
            // depend on the sample values alone, computed once for every
            // coordinate.
            let (a, b) = (last(2), last(1));
            let (xa, xb) = (a.at, b.at);
            let (wa, wb, wc, c) = match (n >= 3).then(|| last(3)) {
                Some(c) => {
                    let xc = c.at;
                    (
                        (at - xb) * (at - xc) / ((xa - xb) * (xa - xc)),
                        (at - xa) * (at - xc) / ((xb - xa) * (xb - xc)),
                        (at - xa) * (at - xb) / ((xc - xa) * (xc - xb)),
                        Some(c),
                    )
                }
                None => ((at - xb) / (xa - xb), (at - xa) / (xb - xa), 0.0, None),
            };
            for (j, qj) in q.iter_mut().enumerate().skip(drivers) {
                let yb = b.q[j];
                let mut y = wa * a.q[j] + wb * yb;
                if let Some(c) = c {
                    y += wc * c.q[j];
                }
                *qj = if y.is_finite() { y } else { yb };
            }
        }
    }
}
