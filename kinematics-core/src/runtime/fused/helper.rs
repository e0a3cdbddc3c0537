//! The helper the fused machine code calls back for what is not an
//! expression: a closed form's branches and the turn of its angles, a
//! driver's cosine and sine computed afresh, the closing check and the
//! factorisation of the scaled diagonal blocks.

use kinematics_jit::Helper;

use super::{
    BLOCK, DRIVER_TRIG, FACTOR, INCONSISTENT, NO_SOLUTION, NOT_CLOSED, PartPlan, Plan, SINGULAR,
    WRONG_BRANCH,
};
use crate::closed;
use crate::solve::Lu;

/// What the helper works with besides the buffer.
pub(super) struct Context<'a> {
    pub(super) plan: &'a Plan,
}

impl Helper for Context<'_> {
    fn call(&mut self, f: &mut [f64], argument: u64) -> i64 {
        let plan = self.plan;
        let status = match argument {
            FACTOR => plan.factor(f),
            i if i >= BLOCK => usize::try_from(i - BLOCK)
                .ok()
                .and_then(|i| plan.parts.get(i))
                .and_then(|part| plan.block(f, part)),
            i if i >= DRIVER_TRIG => usize::try_from(i - DRIVER_TRIG)
                .ok()
                .map(|j| plan.driver_trig(f, j)),
            _ => None,
        };
        status.unwrap_or(INCONSISTENT)
    }
}

impl Plan {
    /// Driver j's cosine and sine computed afresh (the table's
    /// [`crate::math::table::sin_cos`], as [`closed::carried_sin_cos`]
    /// computes them beyond its series), written and carried.
    fn driver_trig(&self, f: &mut [f64], j: usize) -> i64 {
        let x = f[self.layout.q + j];
        let (s, c) = crate::math::table::sin_cos(x);
        let at = self.carry + 3 * j;
        f[at..at + 3].copy_from_slice(&[c, s, x]);
        let t = self.layout.trig + 2 * j;
        f[t] = c;
        f[t + 1] = s;
        0
    }

    /// Block `part` by its closed form from the coefficients in the
    /// buffer, in its mode (NaN: the guess's, then kept); each angle the
    /// representative nearest its guess, from the carried values.
    fn block(&self, f: &mut [f64], part: &PartPlan) -> Option<i64> {
        let (q, trig, carry) = (self.layout.q, self.layout.trig, self.carry);
        let carried_of = |j: usize| [f[carry + 3 * j], f[carry + 3 * j + 1], f[carry + 3 * j + 2]];
        let guesses = [f[q + part.coords[0]], f[q + part.coords[1]]];
        let mut mode = part.mode.map_or(f64::NAN, |slot| f[self.modes + slot]);
        let trig_of =
            |slot: usize| closed::guess_trig(&carried_of(part.coords[slot]), guesses[slot]);
        let solved = super::super::closed::solve(
            &part.form,
            &f[self.coef..self.coef + 12],
            &mut mode,
            trig_of,
            guesses[1],
        );
        let Ok(x) = solved else {
            return Some(NO_SOLUTION);
        };
        if let Some(slot) = part.mode {
            f[self.modes + slot] = mode;
        }
        // The angles first (cosine and sine each), then the lengths.
        let angles = part.form.angles();
        for slot in 0..part.count {
            let j = part.coords[slot];
            if slot < angles {
                let (mut c, mut s) = (x[2 * slot], x[2 * slot + 1]);
                let at = carry + 3 * j;
                let mut carried = [f[at], f[at + 1], f[at + 2]];
                f[q + j] = closed::near_carried(&mut c, &mut s, guesses[slot], &mut carried);
                f[trig + 2 * j] = c;
                f[trig + 2 * j + 1] = s;
                f[at..at + 3].copy_from_slice(&carried);
            } else {
                f[q + j] = x[angles + slot];
            }
        }
        Some(0)
    }

    /// 0 when the weighted residual is within the closing bound, else
    /// [`NOT_CLOSED`] (also for NaN).
    fn closing(&self, f: &[f64]) -> i64 {
        let within = f[self.closing] <= f[self.bound];
        if within { 0 } else { NOT_CLOSED }
    }

    /// The closing check, then each diagonal block of the scaled Φ_u
    /// factored, its conditioning judged and its inverse written (column
    /// j the solution for the j-th unit vector: for blocks of one or two
    /// unknowns, the very values the factorisation holds), and the sign
    /// of det Φ_u against the branch asked for.
    fn factor(&self, f: &mut [f64]) -> Option<i64> {
        let closing = self.closing(f);
        if closing != 0 {
            return Some(closing);
        }
        let threshold = f[self.threshold];
        let length = f[self.layout.params + self.np - 1];
        let mut conditioning = f64::INFINITY;
        let mut sign = if self.odd { -1.0 } else { 1.0 };
        for b in &self.blocks {
            // The scaled entry: Φ_u's times 1/S of its row, and times L
            // for a length's column.
            let entry = |f: &[f64], e: &(usize, usize, bool)| {
                let x = f[e.0] * f[e.1];
                if e.2 { x * length } else { x }
            };
            macro_rules! factored {
                ($n:literal) => {{
                    let mut a = [[0.0; $n]; $n];
                    for (row, entries) in a.iter_mut().zip(b.entries.chunks_exact($n)) {
                        for (x, e) in row.iter_mut().zip(entries) {
                            *x = entry(f, e);
                        }
                    }
                    let Ok(l) = Lu::<$n>::factor(&a, threshold) else {
                        return Some(SINGULAR);
                    };
                    let Ok(c) = l.check(threshold) else {
                        return Some(SINGULAR);
                    };
                    for j in 0..$n {
                        let mut unit = [0.0; $n];
                        unit[j] = 1.0;
                        for (i, v) in l.solve(&unit).into_iter().enumerate() {
                            f[b.inverse + i * $n + j] = v;
                        }
                    }
                    (c, l.det_sign())
                }};
            }
            let (c, s) = match b.n {
                1 => factored!(1),
                2 => factored!(2),
                3 => factored!(3),
                4 => factored!(4),
                _ => return None,
            };
            if c < conditioning {
                conditioning = c;
            }
            sign *= s;
        }
        if self.nu == 0 {
            conditioning = 1.0;
        }
        let wanted = f[self.branch];
        if wanted != 0.0 && sign != wanted {
            return Some(WRONG_BRANCH);
        }
        f[self.conditioning] = conditioning;
        f[self.sign] = sign;
        Some(0)
    }
}
