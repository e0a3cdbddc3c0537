//! A stepper's arrays given back to its model when it is dropped, for
//! the model's next stepper (`Model::stepper` reshapes them): its motion,
//! pose, modes and fused buffer, as its [`super::Work`] is.

use super::Stepper;
use crate::runtime::solve::Arrays;

impl Drop for Stepper<'_> {
    /// Gives the stepper's arrays back to its model, for the next stepper.
    fn drop(&mut self) {
        let f = self
            .fused
            .as_mut()
            .map(|run| core::mem::take(&mut run.f))
            .unwrap_or_default();
        self.m.spare.give_back(Arrays {
            motion: core::mem::take(&mut self.motion),
            q: core::mem::take(&mut self.q),
            modes: core::mem::take(&mut self.modes),
            f,
        });
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use crate::Options;
    use crate::runtime::Stepper;

    /// Every value a stepper starts from, as bits (NaN compared too).
    fn state(s: &Stepper<'_>) -> Vec<u64> {
        let m = &s.motion;
        let f = s.fused.as_ref().map_or(&[][..], |r| &r.f[..]);
        [&m.q, &m.qd, &m.qdd, &s.q, &s.modes, f]
            .iter()
            .flat_map(|v| v.iter().map(|x| x.to_bits()))
            .chain([m.conditioning, m.det_sign, m.residual].map(f64::to_bits))
            .collect()
    }

    /// A stepper that has stepped gives its arrays back; the next stepper
    /// of the model, made from them, starts as one made afresh (by a
    /// clone, which has no spares), its fused buffer bit for bit, for new
    /// parameter values too.
    #[test]
    fn a_stepper_from_spare_arrays_is_a_fresh_one() {
        let mut m = crate::runtime::test_models::crank_rocker();
        let given = {
            let mut s = m.stepper(&Options::DEFAULT).expect("a stepper");
            assert!(s.is_fused());
            let mut q = vec![0.0, 0.5, 1.5];
            for k in 0..40 {
                q[0] = f64::from(k) * 0.05;
                let step = s.step(&q, &[10.0], &[0.0]).expect("a step");
                q.copy_from_slice(&step.q);
            }
            (s.motion.q.as_ptr(), s.fused.as_ref().map(|r| r.f.as_ptr()))
        };
        assert_eq!(m.spare.spare_arrays(), 1);
        m.set_values(&[0.045, 0.12, 0.10, 0.11]).expect("values");
        let fresh = m.clone();
        let (reused, made) = (
            m.stepper(&Options::DEFAULT).expect("a stepper"),
            fresh.stepper(&Options::DEFAULT).expect("a stepper"),
        );
        // The arrays given back are the ones reused.
        assert_eq!(m.spare.spare_arrays(), 0);
        let taken = (
            reused.motion.q.as_ptr(),
            reused.fused.as_ref().map(|r| r.f.as_ptr()),
        );
        assert_eq!(taken, given);
        assert!(reused.is_fused() && !state(&made).is_empty());
        assert_eq!(state(&reused), state(&made));
        assert_eq!(reused.motion.points, made.motion.points);
        assert_eq!(reused.motion.frames, made.motion.frames);
    }
}
