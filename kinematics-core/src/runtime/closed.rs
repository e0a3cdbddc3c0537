//! Closed-form assembly of run-time models: block by block in solve
//! order, each block with a closed form solved exactly by the form of
//! [`crate::closed`] that a generated mechanism calls (its coefficients
//! from the block's machine-code stage), each other block by
//! Newton–Raphson on that block alone; the assembly modes, and every
//! assembly at given drivers.

use alloc::vec;
use alloc::vec::Vec;

use kinematics_compiler::ClosedForm;
use kinematics_jit::Program;

use super::Model;
use super::solve::{Work, det_sign};
use crate::closed::{self, Mode};
use crate::error::Error;
use crate::names::Name;
use crate::options::{Branch, Options};
use crate::solve::{CLOSED, POLISH};

/// A block's closed form as the run-time assembly reads it: each
/// coefficient's place in the list its stage evaluates (the compiler's
/// [`ClosedForm::places`]).
pub(super) type Form = ClosedForm<usize>;

/// The form `form` solved by [`crate::closed`] from the coefficients `k`
/// (read at the places `form` holds), in the mode `*mode` (NaN: the mode
/// nearest the guess, whose unknowns' cosines and sines `trig_of(slot)`
/// gives, and whose second unknown is `length`, then stored): the cosine
/// and sine of each angle, then each length, in the form's order of its
/// unknowns.
///
/// # Errors
/// As the form in [`crate::closed`]: a negative discriminant past a
/// limit position, NaN where the form is degenerate.
///
/// Every form is homogeneous in its coefficients (Σ coefficient ·
/// monomial = 0), so its solutions do not change when all of them are
/// multiplied by one number: where the form is degenerate as given (its
/// squares overflow or underflow, a mechanism drawn in units 10^±100 of
/// its size), it is solved again with the coefficients brought near 1 by
/// a power of two, which is exact.
pub(super) fn solve(
    form: &Form,
    k: &[f64],
    mode: &mut f64,
    trig_of: impl Fn(usize) -> [f64; 2],
    length: f64,
) -> Result<[f64; 4], f64> {
    let values = form.map(|at| k.get(at).copied().unwrap_or(f64::NAN));
    match solve_values(values, mode, &trig_of, length) {
        Err(e) if e.is_nan() => {
            let largest = values
                .coefficients()
                .iter()
                .fold(0.0f64, |m, c| m.max(c.abs()));
            match unit_scale(largest) {
                Some(scale) => solve_values(values.map(|c| c * scale), mode, &trig_of, length),
                None => Err(e),
            }
        }
        other => other,
    }
}

/// The power of two that brings `largest` (a positive, finite, normal
/// number) into [1, 2); `None` for another.
fn unit_scale(largest: f64) -> Option<f64> {
    if !(largest.is_finite() && largest >= f64::MIN_POSITIVE) {
        return None;
    }
    let exponent = i64::try_from((largest.to_bits() >> 52) & 0x7ff).ok()? - 1023;
    let biased = u64::try_from(1023 - exponent).ok()?;
    (1..2047)
        .contains(&biased)
        .then(|| f64::from_bits(biased << 52))
}

/// [`solve`] of the form with its coefficients' values.
fn solve_values(
    values: ClosedForm<f64>,
    mode: &mut f64,
    trig_of: &impl Fn(usize) -> [f64; 2],
    length: f64,
) -> Result<[f64; 4], f64> {
    match values {
        ClosedForm::Angle { a, b, c } => {
            closed::angle(a, b, c, mode, || trig_of(0)).map(|[cs, sn]| [cs, sn, 0.0, 0.0])
        }
        ClosedForm::Linear { a, c } => closed::linear(a, c).map(|l| [l, 0.0, 0.0, 0.0]),
        ClosedForm::CircleCircle { k, p, q } => closed::circle_circle(k, p, q, mode, || {
            let ([c0, s0], [c1, s1]) = (trig_of(0), trig_of(1));
            [c0, s0, c1, s1]
        }),
        ClosedForm::CircleLine { k, p, v } => {
            closed::circle_line(k, p, v, mode, || trig_of(0)).map(|[cs, sn, l]| [cs, sn, l, 0.0])
        }
        ClosedForm::Slide { k, p, w } => {
            closed::slide(k, p, w, mode, || [length, 0.0]).map(|[cs, sn, l]| [cs, sn, l, 0.0])
        }
        ClosedForm::LineLine { k, v0, v1 } => {
            closed::line_line(k, v0, v1).map(|[a, b]| [a, b, 0.0, 0.0])
        }
    }
}

/// One diagonal block as the run-time assembly solves it.
#[derive(Clone, Debug)]
pub(super) struct Part {
    /// Its closed form, or `None` for Newton–Raphson.
    pub(super) form: Option<Form>,
    /// Its equations.
    pub(super) rows: Vec<usize>,
    /// Its unknowns (0-based among the unknowns), in the order of the
    /// form's results.
    pub(super) cols: Vec<usize>,
    /// Its unknowns' names, joined by ", " (for the errors).
    pub(super) names: Name,
}

/// How a block-by-block assembly ended, short of an error.
pub(super) enum Assembled {
    /// Every block solved and the pose at round-off (or polished there).
    Closed,
    /// A closed form was degenerate at this pose, or the pose does not
    /// close: the caller solves the whole system by Newton–Raphson.
    Degenerate,
}

impl Model {
    /// The number of blocks with two assembly modes (2^k assemblies).
    #[must_use]
    pub fn mode_count(&self) -> usize {
        self.parts
            .iter()
            .filter(|p| p.form.as_ref().is_some_and(Form::has_modes))
            .count()
    }

    /// Whether every block has a closed form (the guess of a pose then
    /// names its branch only).
    pub(super) fn all_closed(&self) -> bool {
        self.parts.iter().all(|p| p.form.is_some())
    }

    /// Whether some block has a closed form: then a model assembles block
    /// by block, as a generated mechanism does.
    pub(super) fn closed_path(&self) -> bool {
        self.parts.iter().any(|p| p.form.is_some())
    }

    /// Assembles q block by block in solve order from the guess q, in
    /// `modes` (one sign per two-mode block; NaN: the mode the guess lies
    /// in, then stored). The scaling must be that of q's drivers
    /// ([`Model::scaling`]). With `strict`, a Newton block that does not
    /// converge is an error; without, it hands over to Newton–Raphson on
    /// the whole system ([`Assembled::Degenerate`]).
    pub(super) fn assemble_blocks(
        &self,
        q: &mut [f64],
        w: &mut Work,
        modes: &mut [f64],
        options: &Options,
        strict: bool,
    ) -> Result<Assembled, Error> {
        let nd = self.drivers;
        w.guess.copy_from_slice(q);
        let mut mode = 0;
        for (i, part) in self.parts.iter().enumerate() {
            let Some(form) = part.form else {
                match self.solve_part(q, w, options, (&part.rows, &part.cols), true) {
                    Ok(()) => continue,
                    Err(e) if strict => return Err(e),
                    Err(_) => return Ok(Assembled::Degenerate),
                }
            };
            let n = self.program.outputs(Program::block(i));
            self.eval(
                Program::block(i),
                &w.params,
                q,
                &w.zeros,
                &w.zeros,
                &w.trig,
                &mut w.coef[..n],
            );
            let mut none = f64::NAN;
            let sign = if form.has_modes() {
                mode += 1;
                &mut modes[mode - 1]
            } else {
                &mut none
            };
            let guess = &w.guess;
            let trig_of = |c: usize| {
                let (s, c) = guess[nd + part.cols[c]].sin_cos();
                [c, s]
            };
            let length = part.cols.get(1).map_or(f64::NAN, |&c| guess[nd + c]);
            let solved = solve(&form, &w.coef, sign, trig_of, length);
            let x = match solved {
                Ok(x) => x,
                Err(disc) if disc < 0.0 => {
                    return Err(Error::CannotAssemble {
                        unknowns: part.names,
                        discriminant: disc,
                        drivers: self.configuration(&q[..nd]),
                    });
                }
                Err(_) => return Ok(Assembled::Degenerate),
            };
            // The angles first (cosine and sine each), then the lengths.
            let angles = form.angles();
            for (slot, &col) in part.cols.iter().enumerate() {
                let j = nd + col;
                if slot < angles {
                    let (mut c, mut s) = (x[2 * slot], x[2 * slot + 1]);
                    q[j] = closed::near(&mut c, &mut s, w.guess[j]);
                    w.trig[2 * j] = c;
                    w.trig[2 * j + 1] = s;
                } else {
                    q[j] = x[angles + slot];
                }
            }
        }
        // The pose's residual: at round-off it is returned; within the
        // tolerance it is polished by Newton–Raphson from itself (in the
        // same modes); beyond it, or NaN, it is not trusted. The blocks
        // left the cosines and sines of their angles, exactly as solved.
        self.newton_stage(q, w);
        let r = w.phi.iter().zip(&w.weights).fold(0.0f64, |m, (p, s)| {
            let r = (p * s).abs();
            if r > m || r.is_nan() { r } else { m }
        });
        let limit = options.tolerance.min(1e-12);
        let bound = (POLISH * options.tolerance).max(CLOSED);
        if r <= bound.min(limit) {
            Ok(Assembled::Closed)
        } else if r <= limit {
            self.solve_part(q, w, options, (&self.all, &self.all), false)?;
            Ok(Assembled::Closed)
        } else {
            Ok(Assembled::Degenerate)
        }
    }

    /// Assembles q from the guess q: block by block where a block has a
    /// closed form (in `modes`, NaN: from the guess), else by
    /// Newton–Raphson on the whole system; a degenerate closed form hands
    /// over to Newton–Raphson on the whole system from the guess (the
    /// modes then NaN again).
    ///
    /// With [`Options::branch`] asking for a sign of det Φ_u, a solution on
    /// the other branch is assembled again in the other combinations of
    /// modes (the first that gives the branch asked for is kept, for up to
    /// 16 two-mode blocks), as a generated mechanism does: for closed-form
    /// blocks the branch is a choice; without them it is
    /// [`Error::WrongBranch`].
    pub(super) fn assemble_into(
        &self,
        q: &mut [f64],
        w: &mut Work,
        modes: &mut [f64],
        options: &Options,
        strict: bool,
    ) -> Result<(), Error> {
        self.assemble_any(q, w, modes, options, strict)?;
        let wanted = match options.branch {
            Branch::Any => return Ok(()),
            Branch::Positive => 1.0,
            Branch::Negative => -1.0,
        };
        let nu = self.unknowns();
        if det_sign(w, nu) == wanted {
            return Ok(());
        }
        let k = modes.len();
        if self.closed_path() && (1..=16).contains(&k) && !modes.iter().any(|m| m.is_nan()) {
            let (base, guess) = (modes.to_vec(), w.guess.clone());
            let mut trial = base.clone();
            for flips in 1..1usize << k {
                for (j, (t, b)) in trial.iter_mut().zip(&base).enumerate() {
                    *t = if flips >> j & 1 == 1 { -b } else { *b };
                }
                q.copy_from_slice(&guess);
                if self.assemble_any(q, w, &mut trial, options, strict).is_ok()
                    && det_sign(w, nu) == wanted
                {
                    modes.copy_from_slice(&trial);
                    return Ok(());
                }
            }
        }
        Err(Error::WrongBranch {
            configuration: self.configuration(q),
        })
    }

    /// [`Model::assemble_into`] on whichever branch it lands.
    fn assemble_any(
        &self,
        q: &mut [f64],
        w: &mut Work,
        modes: &mut [f64],
        options: &Options,
        strict: bool,
    ) -> Result<(), Error> {
        self.scaling(q, w, options);
        if self.closed_path() {
            if let Assembled::Closed = self.assemble_blocks(q, w, modes, options, strict)? {
                return Ok(());
            }
            modes.fill(f64::NAN);
            q.copy_from_slice(&w.guess);
            self.program.trig(q, &mut w.trig, 0);
        }
        self.solve_part(q, w, options, (&self.all, &self.all), false)
    }

    /// Assembles at the drivers of `start` in the assembly modes `modes`
    /// (one per block with two modes, in solve order: see
    /// [`Model::blocks`]): each closed-form block exactly, with no guess;
    /// each other block by Newton–Raphson from the values of its unknowns
    /// in `start`, which is all of `start` read besides the drivers.
    /// Unknown angles of closed-form blocks are returned near their
    /// values in `start` (to a multiple of 2π).
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `modes` has
    /// [`Model::mode_count`] entries; [`Error::CannotAssemble`] when the
    /// links cannot close a closed-form block there (past a limit
    /// position); when a Newton block does not converge, its error; as
    /// [`Model::assemble`] otherwise.
    pub fn assemble_in(&self, start: &[f64], modes: &[Mode]) -> Result<Vec<f64>, Error> {
        let options = Options::DEFAULT;
        self.validate()?;
        self.length("modes", self.mode_count(), modes.len())?;
        self.check_pose(start)?;
        let mut q = start.to_vec();
        let mut signs: Vec<f64> = modes.iter().map(|m| m.sign()).collect();
        let mut w = self.work();
        self.assemble_into(&mut q, &mut w, &mut signs, &options, true)?;
        self.factor(&q, &mut w, &options, true)?;
        Ok(q)
    }

    /// Every assembly at the drivers of `start`, lazily: for each
    /// combination of modes (combination i has block j in
    /// [`Mode::Minus`] where bit j of i is set, as a generated
    /// mechanism's `assemble_all` orders them), the modes and the
    /// assembly in them, as [`Model::assemble_in`]. Nothing is assembled
    /// until asked for.
    ///
    /// ```
    /// use kinematics_core::closed::Mode;
    /// use kinematics_core::runtime::Model;
    /// let mut m = Model::compile(
    ///     "struct FourBar {
    ///          params   { a, b, c, d }
    ///          drivers  { phi }
    ///          unknowns { th3, th4 }
    ///          loops    { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
    ///      }",
    /// )?;
    /// m.set_values(&[0.04, 0.12, 0.10, 0.11])?;
    /// let all: Vec<_> = m.assemble_all(&[0.5, 0.0, 0.0]).collect();
    /// assert_eq!(all.len(), 2); // the open and the crossed assembly
    /// assert_eq!(all[1].0, [Mode::Minus]);
    /// for (_, pose) in &all {
    ///     let q = pose.as_ref().expect("assembles");
    ///     assert!(m.residual(q)?.iter().all(|r| r.abs() < 1e-15));
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn assemble_all<'m>(
        &'m self,
        start: &[f64],
    ) -> impl Iterator<Item = (Vec<Mode>, Result<Vec<f64>, Error>)> + 'm + use<'m> {
        let start = start.to_vec();
        let k = self.mode_count();
        let mut next = Some(vec![Mode::Plus; k]);
        core::iter::from_fn(move || {
            let modes = next.take()?;
            // The next combination: a binary counter over the blocks.
            let mut following = modes.clone();
            let mut carried = false;
            for m in &mut following {
                if *m == Mode::Plus {
                    *m = Mode::Minus;
                    carried = true;
                    break;
                }
                *m = Mode::Plus;
            }
            next = carried.then_some(following);
            let pose = self.assemble_in(&start, &modes);
            Some((modes, pose))
        })
    }
}
