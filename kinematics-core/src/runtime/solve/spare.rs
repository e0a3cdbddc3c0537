//! Spare work arrays: a model keeps the [`Work`]s its steppers and
//! one-off calls gave back, and the other arrays of its steppers, and
//! lends them again reset in place, so that a short sweep or a single
//! assembly does not allocate and free a few dozen small arrays each
//! time.

use alloc::vec::Vec;

use super::Work;
use crate::runtime::Motion;

/// A stepper's arrays besides its [`Work`]: its motion, pose, modes and
/// fused buffer (empty without fused code), as it gives them back.
#[derive(Default)]
pub(in crate::runtime) struct Arrays {
    pub(in crate::runtime) motion: Motion,
    pub(in crate::runtime) q: Vec<f64>,
    pub(in crate::runtime) modes: Vec<f64>,
    pub(in crate::runtime) f: Vec<f64>,
}

impl Work {
    /// Every array as the model makes it afresh (`Model::fresh_work`),
    /// the parameters `values`; `false`, and nothing reset, where the
    /// work is not whole (an array of the wrong length: the parameters'
    /// count differs, or a solve was left midway, its arrays taken).
    fn reset(&mut self, values: &[f64]) -> bool {
        let nu = self.phi.len();
        let p = &self.space;
        let whole = self.params.len() == values.len()
            && [
                &p.u, &p.phi, &p.row, &p.weights, &p.start, &p.step, &p.origin,
            ]
            .iter()
            .all(|v| v.len() == nu);
        if !whole {
            return false;
        }
        self.params.copy_from_slice(values);
        for v in [
            &mut self.phi,
            &mut self.jac,
            &mut self.newton,
            &mut self.zeros,
            &mut self.lu,
            &mut self.sub,
            &mut self.col,
            &mut self.unit,
            &mut self.sums,
            &mut self.rhs,
            &mut self.out,
            &mut self.trig,
            &mut self.guess,
            &mut self.coef,
        ] {
            v.fill(0.0);
        }
        self.rows.fill(1.0);
        self.weights.fill(1.0);
        self.perm.fill(0);
        self.sub_perm.fill(0);
        let p = &mut self.space;
        for v in [
            &mut p.u,
            &mut p.phi,
            &mut p.row,
            &mut p.weights,
            &mut p.start,
            &mut p.step,
            &mut p.origin,
        ] {
            v.fill(0.0);
        }
        self.closing = false;
        self.scaling_kept = false;
        true
    }
}

/// A few [`Work`]s of a model kept for its next steppers and one-off
/// calls: a `Work` is a few dozen small arrays, whose allocation and
/// release cost more than a short sweep's steps; one taken from here is
/// reset in place (`Model::work`). A clone of the model starts with
/// none.
#[derive(Default)]
pub(in crate::runtime) struct Spare {
    works: std::sync::Mutex<Vec<Work>>,
    arrays: std::sync::Mutex<Vec<Arrays>>,
    /// The storage of a sweep's poses, which the run-time engine lends
    /// (`Engine::zero_pose`) and takes back (`Engine::recycle`).
    poses: std::sync::Mutex<Vec<Vec<f64>>>,
}

impl Spare {
    /// A spare [`Work`] reset for the parameters `values`, or else
    /// `fresh()`; given back when the loan is dropped.
    pub(in crate::runtime) fn lend(
        &self,
        values: &[f64],
        fresh: impl FnOnce() -> Work,
    ) -> Pooled<'_> {
        let spare = lock(&self.works)
            .pop()
            .and_then(|mut w| w.reset(values).then_some(w));
        let work = spare.unwrap_or_else(fresh);
        Pooled { work, spare: self }
    }

    /// A stepper's spare arrays, as given back (the stepper reshapes
    /// them), or empty ones.
    pub(in crate::runtime) fn arrays(&self) -> Arrays {
        lock(&self.arrays).pop().unwrap_or_default()
    }

    /// A pose of `n` zeros, in spare storage where there is some.
    pub(in crate::runtime) fn pose(&self, n: usize) -> Vec<f64> {
        let mut v = lock(&self.poses).pop().unwrap_or_default();
        v.clear();
        v.resize(n, 0.0);
        v
    }

    /// Keeps a sweep's poses' storage for the next (not where a panic
    /// drops the sweep).
    pub(in crate::runtime) fn give_poses(&self, poses: impl Iterator<Item = Vec<f64>>) {
        if std::thread::panicking() {
            return;
        }
        let mut pool = lock(&self.poses);
        for v in poses {
            if pool.len() < POSES {
                pool.push(v);
            }
        }
    }

    /// How many steppers' arrays are kept.
    #[cfg(test)]
    pub(in crate::runtime) fn spare_arrays(&self) -> usize {
        lock(&self.arrays).len()
    }

    /// Keeps a stepper's arrays for the next (not where a panic drops
    /// the stepper).
    pub(in crate::runtime) fn give_back(&self, arrays: Arrays) {
        if std::thread::panicking() {
            return;
        }
        let mut pool = lock(&self.arrays);
        if pool.len() < SPARE {
            pool.push(arrays);
        }
    }
}

/// The spares behind `m` (a lock no holder can poison: nothing under it
/// panics).
fn lock<T>(m: &std::sync::Mutex<Vec<T>>) -> std::sync::MutexGuard<'_, Vec<T>> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Clone for Spare {
    fn clone(&self) -> Self {
        Spare::default()
    }
}

/// How many spare [`Work`]s, and steppers' arrays, a model keeps.
const SPARE: usize = 4;

/// How many poses' storage a model keeps: four sweeps' (each uses 11).
const POSES: usize = 44;

/// A [`Work`] lent by `Model::work`, given back to the model's spares
/// when dropped (not where a panic drops it).
pub(in crate::runtime) struct Pooled<'m> {
    work: Work,
    spare: &'m Spare,
}

impl core::ops::Deref for Pooled<'_> {
    type Target = Work;
    #[inline(always)]
    fn deref(&self) -> &Work {
        &self.work
    }
}

impl core::ops::DerefMut for Pooled<'_> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut Work {
        &mut self.work
    }
}

impl Drop for Pooled<'_> {
    fn drop(&mut self) {
        // A work dropped by a panic may be left midway through a solve:
        // not given back.
        if std::thread::panicking() {
            return;
        }
        let mut pool = lock(&self.spare.works);
        if pool.len() < SPARE {
            // (An empty `Work` left behind: no allocation.)
            pool.push(core::mem::take(&mut self.work));
        }
    }
}

#[cfg(test)]
mod tests {
    use alloc::format;
    use alloc::vec;

    use crate::Options;
    use crate::runtime::Model;

    /// Every array of a `Work` as text, to compare two.
    fn arrays(w: &super::Work) -> alloc::string::String {
        let p = &w.space;
        format!(
            "{:?}",
            (
                (&w.params, &w.phi, &w.jac, &w.newton, &w.rows, &w.weights),
                (&w.zeros, &w.lu, &w.perm, w.closing, &w.sub, &w.sub_perm),
                (&w.col, &w.unit, &w.sums, &w.rhs, &w.out, &w.trig),
                (&w.guess, &w.coef, w.scaling_kept),
                (
                    &p.u, &p.phi, &p.row, &p.weights, &p.start, &p.step, &p.origin
                ),
            )
        )
    }

    /// A model with a block solved by Newton–Raphson (a slider in the
    /// guide x = h + k y², driven through a rod) steps, which writes its
    /// work's arrays; the work it gave back, lent again, is as a fresh
    /// one, for its new parameter values too.
    #[test]
    fn a_spare_work_is_lent_as_a_fresh_one() {
        let text = "struct Curved {
            params   { a, b, h, k }
            drivers  { phi }
            unknowns { th, y }
            points   { C = vec2(h + k * y * y, y); }
            loops    { polar(a, phi) + polar(b, th) == vec2(h + k * y * y, y); }
        }";
        let mut m = Model::compile(text)
            .expect("compiles")
            .with_values(&[0.1, 0.3, 0.15, 0.5])
            .expect("values");
        let spares = |m: &Model| super::lock(&m.spare.works).len();
        {
            let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
            let mut q = vec![0.0, 1.2, 0.28];
            for k in 0..12 {
                q[0] = f64::from(k) * 0.1;
                let s = stepper.step(&q, &[1.0], &[0.0]).expect("a step");
                q.copy_from_slice(&s.q);
            }
            let mut positions = vec![0.0; 2];
            stepper.positions(&mut positions).expect("positions");
        }
        // The stepper gave its work back; lent again, it is taken.
        assert_eq!(spares(&m), 1);
        m.set_values(&[0.1, 0.3, 0.16, 0.5]).expect("values");
        let (lent, fresh) = (m.work(), m.fresh_work());
        assert_eq!(spares(&m), 0);
        assert!(arrays(&fresh).contains("0.16"));
        assert_eq!(arrays(&lent), arrays(&fresh));
        drop(lent);
        assert_eq!(spares(&m), 1);
        // A work left midway through a solve (its arrays taken) is not
        // lent again: a fresh one is made.
        let mut broken = m.work();
        drop(core::mem::take(&mut broken.space));
        drop(broken);
        let again = m.work();
        assert_eq!(arrays(&again), arrays(&m.fresh_work()));
    }

    /// A sweep gives its poses' storage back when dropped, and the next
    /// sweep of the model, which takes it, gives the numbers of a sweep
    /// of a clone (which has no spares), bit for bit.
    #[test]
    fn a_sweep_gives_back_its_poses() {
        let m = crate::runtime::test_models::crank_rocker();
        let start = m.assemble(&[0.3, 0.5, 1.5]).expect("assembles");
        let poses = |m: &Model| {
            let mut bits = vec![];
            let end = m
                .sweep("phi", &start)
                .expect("a sweep")
                .turns(1.0)
                .steps(36)
                .for_each_pose(|at, q, r| {
                    bits.extend([at].iter().chain(q).chain(r).map(|x| x.to_bits()));
                });
            assert!(end.stop.is_none());
            bits
        };
        // With rates and accelerations too.
        let motion = |m: &Model| {
            let s = m
                .sweep("phi", &start)
                .expect("a sweep")
                .turns(1.0)
                .steps(36)
                .rate(10.0)
                .acceleration(-3.0)
                .run();
            assert!(s.stop.is_none());
            format!("{:?}", s.samples)
        };
        let fresh = m.clone();
        let (first, moving) = (poses(&m), motion(&m));
        let kept = super::lock(&m.spare.poses).len();
        assert_eq!(kept, 11);
        assert_eq!(poses(&m), first);
        assert_eq!(motion(&m), moving);
        assert_eq!((poses(&fresh), motion(&fresh)), (first, moving));
        assert_eq!(super::lock(&m.spare.poses).len(), kept);
    }
}
