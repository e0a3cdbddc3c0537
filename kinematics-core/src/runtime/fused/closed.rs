//! The closed forms that the fused step solves in its machine code,
//! written as plain instructions ([`kinematics_jit::Inst`]) with a guard
//! and a fall-back to the helper ([`Op::Guarded`]): the code generator
//! knows arithmetic, comparisons and selections; the mathematics of a
//! dyad and of carrying an angle from step to step is written here, once,
//! as [`crate::closed`] computes it.
//!
//! Each form computes its angles' cosines and sines from its
//! coefficients, then each angle from its carried value (θ = θₚ + asin x
//! with x = cₚ s − sₚ c by its series, as [`crate::closed::near_carried`]
//! takes it). Where the form is regular and every angle is near its
//! carried value, the code writes each angle, its cosine and sine, and
//! carries them; anywhere else (the mode not set yet, past a limit
//! position, a rotation too large, a value not finite) it writes the
//! coefficients for the helper and calls it, which solves the block in
//! general.

use alloc::vec::Vec;

use kinematics_compiler::ClosedForm;
use kinematics_compiler::ir::Id;
use kinematics_jit::{Compare, Inst, Op, Val};

/// Where an angle lies in the buffer: its value (the guess on entry), its
/// cosine and sine, and its carried (cos, sin, angle).
#[derive(Clone, Copy, Debug)]
pub(super) struct AngleAt {
    /// The angle.
    pub(super) value: usize,
    /// Its cosine, then its sine.
    pub(super) trig: usize,
    /// The carried cosine, sine and angle.
    pub(super) carried: usize,
}

/// Where a form's values lie: its mode (±1, NaN: not set), where its
/// coefficients are written for the helper, and the helper's argument
/// for the general solution.
#[derive(Clone, Copy, Debug)]
pub(super) struct Slots {
    /// The mode.
    pub(super) mode: usize,
    /// The first coefficient written for the helper.
    pub(super) store: usize,
    /// The helper's argument.
    pub(super) general: u64,
}

/// The guarded op solving `form` (its coefficients nodes of the graph)
/// with its angles at `angles` (in the form's order of its unknowns), or
/// `None` for a form the machine code does not solve (then the helper
/// solves it at every step).
pub(super) fn op(form: &ClosedForm<Id>, angles: [AngleAt; 2], slots: Slots) -> Option<Op> {
    let mut code = Code::default();
    // Each coefficient's value, in the order of the form's list (which is
    // also where the helper reads them: `ClosedForm::places`).
    let given = form.map(|id| code.put(Inst::Root(id)));
    let (ok, solved) = match given {
        ClosedForm::CircleCircle { k, p, q } => {
            let sigma = code.put(Inst::Load(slots.mode));
            let (ok, [e0, e1]) = circle_circle(&mut code, [k, p[0], p[1], q[0], q[1]], sigma);
            (ok, Vec::from([(angles[0], e0), (angles[1], e1)]))
        }
        ClosedForm::Angle { a, b, c } => {
            let sigma = code.put(Inst::Load(slots.mode));
            let (cos, sin, ok) = angle(&mut code, [a, b, c], sigma);
            (ok, Vec::from([(angles[0], [cos, sin])]))
        }
        ClosedForm::Linear { .. }
        | ClosedForm::CircleLine { .. }
        | ClosedForm::Slide { .. }
        | ClosedForm::LineLine { .. } => return None,
    };
    Some(near_carried(
        code,
        ok,
        &solved,
        &given.coefficients(),
        slots,
    ))
}

/// The instructions of a guarded computation, as they are written.
#[derive(Default)]
struct Code(Vec<Inst>);

impl Code {
    /// Appends `inst`: the value it defines.
    fn put(&mut self, inst: Inst) -> Val {
        // The code of one form has well under 2³² instructions.
        let at = u32::try_from(self.0.len()).unwrap_or(u32::MAX);
        self.0.push(inst);
        Val(at)
    }

    fn constant(&mut self, x: f64) -> Val {
        self.put(Inst::Const(x))
    }

    fn add(&mut self, x: Val, y: Val) -> Val {
        self.put(Inst::Add(x, y))
    }

    fn sub(&mut self, x: Val, y: Val) -> Val {
        self.put(Inst::Sub(x, y))
    }

    fn mul(&mut self, x: Val, y: Val) -> Val {
        self.put(Inst::Mul(x, y))
    }

    fn abs(&mut self, x: Val) -> Val {
        self.put(Inst::Abs(x))
    }

    fn neg(&mut self, x: Val) -> Val {
        self.put(Inst::Neg(x))
    }

    /// x₀y₀ + x₁y₁, without the terms whose factor is the constant 0 (a
    /// dyad's P and Q are often diagonal), as the generated code,
    /// simplified by the compiler, computes it.
    fn dot(&mut self, x0: Val, y0: Val, x1: Val, y1: Val) -> Val {
        self.put(Inst::Dot(Vec::from([(x0, y0), (x1, y1)])))
    }

    fn compare(&mut self, how: Compare, x: Val, y: Val) -> Val {
        self.put(Inst::Compare(how, x, y))
    }

    fn and(&mut self, x: Val, y: Val) -> Val {
        self.put(Inst::And(x, y))
    }
}

/// (cos θ, sin θ) solving a cos θ + b sin θ + c = 0 in the mode σ, as
/// [`crate::closed::angle`] computes them: R² = a² + b², Δ = R² − c²
/// (0 within 8 ε of R² + c²), cos θ = (−a c − σ b √Δ)/R²,
/// sin θ = (−b c + σ a √Δ)/R²; and the flag Δ ≥ 0 and 0 < R² < ∞ and σ
/// not NaN.
fn angle(code: &mut Code, [a, b, c]: [Val; 3], sigma: Val) -> (Val, Val, Val) {
    let x0 = code.mul(a, a);
    let x1 = code.mul(b, b);
    let r2 = code.add(x0, x1);
    let cc = code.mul(c, c);
    let d = code.sub(r2, cc);
    let size = code.add(r2, cc);
    let eps8 = code.constant(8.0 * f64::EPSILON);
    let tol = code.mul(eps8, size);
    let ad = code.abs(d);
    let tiny = code.compare(Compare::LessOrEqual, ad, tol);
    let zero = code.constant(0.0);
    let disc = code.put(Inst::Select(tiny, zero, d));
    let inf = code.constant(f64::INFINITY);
    let ok_disc = code.compare(Compare::GreaterOrEqual, disc, zero);
    let ok_r2 = code.compare(Compare::Greater, r2, zero);
    let ok_fin = code.compare(Compare::Less, r2, inf);
    let same = code.compare(Compare::Equal, sigma, sigma);
    let ok = code.and(ok_disc, ok_r2);
    let ok = code.and(ok, ok_fin);
    let ok = code.and(ok, same);
    let one = code.constant(1.0);
    let inv = code.put(Inst::Div(one, r2));
    let sq = code.put(Inst::Sqrt(disc));
    let root = code.mul(sigma, sq);
    let na = code.neg(a);
    let x0 = code.mul(na, c);
    let x1 = code.mul(b, root);
    let x = code.sub(x0, x1);
    let cos = code.mul(x, inv);
    let nb = code.neg(b);
    let x0 = code.mul(nb, c);
    let x1 = code.mul(a, root);
    let x = code.add(x0, x1);
    let sin = code.mul(x, inv);
    (cos, sin, ok)
}

/// The RRR dyad k + P e₀ + Q e₁ = 0 (k, then P and Q row by row) in the
/// mode σ, as [`crate::closed::circle_circle`] solves it:
/// θ₀ from the [`angle`] equation a = 2 (Pᵀk)₀, b = 2 (Pᵀk)₁,
/// c = |k|² + p² − q² (|k + P e₀| = q); then e₁ = −Qᵀ(k + P e₀)
/// normalised by one Newton step from 1/q². The flag also asks q² > 0
/// and the normalisation off by at most 1e-8.
fn circle_circle(code: &mut Code, rows: [[Val; 2]; 5], sigma: Val) -> (Val, [[Val; 2]; 2]) {
    let [[k0, k1], [p00, p01], [p10, p11], [q00, q01], [q10, q11]] = rows;
    let p2 = code.dot(p00, p00, p10, p10);
    let q2 = code.dot(q00, q00, q10, q10);
    let two = code.constant(2.0);
    let x = code.dot(p00, k0, p10, k1);
    let a = code.mul(two, x);
    let x = code.dot(p01, k0, p11, k1);
    let b = code.mul(two, x);
    let x = code.dot(k0, k0, k1, k1);
    let x = code.add(x, p2);
    let c = code.sub(x, q2);
    let (c0, s0, ok) = angle(code, [a, b, c], sigma);
    let zero = code.constant(0.0);
    let ok_q2 = code.compare(Compare::Greater, q2, zero);
    let ok = code.and(ok, ok_q2);
    let x = code.dot(p00, c0, p01, s0);
    let w0 = code.add(k0, x);
    let x = code.dot(p10, c0, p11, s0);
    let w1 = code.add(k1, x);
    let x = code.dot(q00, w0, q10, w1);
    let ex = code.neg(x);
    let x = code.dot(q01, w0, q11, w1);
    let ey = code.neg(x);
    let m = code.dot(ex, ex, ey, ey);
    let one = code.constant(1.0);
    let r0 = code.put(Inst::Div(one, q2));
    let x = code.mul(m, r0);
    let x = code.mul(x, r0);
    let delta = code.sub(x, one);
    let adelta = code.abs(delta);
    let small = code.constant(1e-8);
    let ok_unit = code.compare(Compare::LessOrEqual, adelta, small);
    let ok = code.and(ok, ok_unit);
    let half = code.constant(0.5);
    let x = code.mul(half, r0);
    let x = code.mul(x, delta);
    let r = code.sub(r0, x);
    let c1 = code.mul(ex, r);
    let s1 = code.mul(ey, r);
    (ok, [[c0, s0], [c1, s1]])
}

/// The guarded op that takes each solved angle from its carried value,
/// θ = θₚ + asin x with x = cₚ s − sₚ c by its series, where the rotation
/// is small (cₚ c + sₚ s > 0, |x| ≤ 1/32) and θ within π of the guess:
/// where `ok` and these hold for every angle, each angle, its cosine and
/// sine are written and carried; otherwise the coefficients `given` are
/// written at `slots.store` and the helper is called with
/// `slots.general` (the guesses and carried values untouched).
fn near_carried(
    mut code: Code,
    mut ok: Val,
    solved: &[(AngleAt, [Val; 2])],
    given: &[Val],
    slots: Slots,
) -> Op {
    let mut fast = Vec::with_capacity(6 * solved.len());
    let mut keep = Vec::with_capacity(3 * solved.len());
    for &(at, [cv, sv]) in solved {
        let cp = code.put(Inst::Load(at.carried));
        let sp = code.put(Inst::Load(at.carried + 1));
        let tp = code.put(Inst::Load(at.carried + 2));
        let guess = code.put(Inst::Load(at.value));
        let x0 = code.mul(cp, sv);
        let x1 = code.mul(sp, cv);
        let x = code.sub(x0, x1);
        let y0 = code.mul(cp, cv);
        let y1 = code.mul(sp, sv);
        let y = code.add(y0, y1);
        let x2 = code.mul(x, x);
        // asin x = x + x³/6 + 3x⁵/40 + 5x⁷/112 + 35x⁹/1152 + 63x¹¹/2816.
        let mut t = code.constant(63.0 / 2816.0);
        for coefficient in [35.0 / 1152.0, 5.0 / 112.0, 3.0 / 40.0, 1.0 / 6.0] {
            let m = code.mul(x2, t);
            let k = code.constant(coefficient);
            t = code.add(m, k);
        }
        let series = code.mul(x2, t);
        let xs = code.mul(x, series);
        let asin = code.add(x, xs);
        let theta = code.add(tp, asin);
        let zero = code.constant(0.0);
        let ok_y = code.compare(Compare::Greater, y, zero);
        let ax = code.abs(x);
        let limit = code.constant(0.031_25);
        let ok_x = code.compare(Compare::LessOrEqual, ax, limit);
        let off = code.sub(theta, guess);
        let aoff = code.abs(off);
        let pi = code.constant(core::f64::consts::PI);
        let ok_ref = code.compare(Compare::LessOrEqual, aoff, pi);
        ok = code.and(ok, ok_y);
        ok = code.and(ok, ok_x);
        ok = code.and(ok, ok_ref);
        fast.extend([
            (at.value, theta),
            (at.trig, cv),
            (at.trig + 1, sv),
            (at.carried, cv),
            (at.carried + 1, sv),
            (at.carried + 2, theta),
        ]);
        keep.extend([at.value, at.trig, at.trig + 1]);
    }
    let slow = given
        .iter()
        .enumerate()
        .map(|(i, &v)| (slots.store + i, v))
        .collect();
    Op::Guarded {
        code: code.0,
        ok,
        fast,
        slow,
        helper: slots.general,
        keep,
    }
}

#[cfg(test)]
mod tests {
    //! Each form through the machine code, against its solution computed
    //! here by hand (the RRR dyad by its elimination, the angle equation
    //! by acos), with the fall-back to the helper where the mode is not
    //! set or there is no solution.
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use alloc::vec;
    use alloc::vec::Vec;

    use kinematics_compiler::ClosedForm;
    use kinematics_compiler::ir::{Func, Graph, Leaf, Node};
    use kinematics_jit::{Function, Fused, Helper, Layout, Op};

    use super::{AngleAt, Slots, op};

    /// Two parameters at 0–1, two coordinates at 2–3, rates 4–5,
    /// accelerations 6–7, cosines and sines 8–11, and scratch from 12.
    const LAYOUT: Layout = Layout {
        params: 0,
        q: 2,
        qd: 4,
        qdd: 6,
        trig: 8,
        len: 48,
    };

    /// The mode at 12, the coefficients for the helper from 34.
    fn slots(general: u64) -> Slots {
        Slots {
            mode: 12,
            store: 34,
            general,
        }
    }

    fn one(g: &Graph, ops: &[Op]) -> Fused {
        Fused::new(g, 2, 2, LAYOUT, &[Function { ops, preset: &[] }]).expect("compiles")
    }

    /// Records its calls and returns `status`.
    #[derive(Default)]
    struct Recorder {
        calls: Vec<u64>,
        status: i64,
    }

    impl Helper for Recorder {
        fn call(&mut self, _: &mut [f64], argument: u64) -> i64 {
            self.calls.push(argument);
            self.status
        }
    }

    #[test]
    fn rrr_dyad_in_machine_code() {
        // A four-bar a = 1, b = 2, c = 2.5, d = 3 at φ = 90°: with
        // k = (a cos φ − d, a sin φ), the loop k + b e₃ − c e₄ = 0; the
        // coefficients as parameters 0–1 and constants.
        let mut g = Graph::new();
        let k0 = g.leaf(Leaf::Param(0));
        let k1 = g.leaf(Leaf::Param(1));
        let (b, zero, minus_c) = (g.constant(2.0), g.constant(0.0), g.constant(-2.5));
        let form = ClosedForm::CircleCircle {
            k: [k0, k1],
            p: [[b, zero], [zero, b]],
            q: [[minus_c, zero], [zero, minus_c]],
        };
        let angles = [
            AngleAt {
                value: 2,
                trig: 8,
                carried: 20,
            },
            AngleAt {
                value: 3,
                trig: 10,
                carried: 23,
            },
        ];
        // After the dyad, its angles and their cosines and sines as later
        // expressions use them (from registers, not the buffer): copied to
        // 30–33.
        let q0 = g.leaf(Leaf::Q(0));
        let q1 = g.leaf(Leaf::Q(1));
        let c0 = g.intern(Node::Call(Func::Cos, q0));
        let s1 = g.intern(Node::Call(Func::Sin, q1));
        let ops = [
            op(&form, angles, slots(99)).expect("the machine code solves the dyad"),
            Op::Store {
                roots: vec![q0, c0, q1, s1],
                at: vec![30, 31, 32, 33],
                finite: None,
            },
        ];
        let code = one(&g, &ops);
        let used_after =
            |f: &[f64]| assert_eq!([f[30], f[31], f[32], f[33]], [f[2], f[8], f[3], f[11]]);
        /// The general solution's stand-in: records the call and the guesses
        /// and carried values it is handed (which the machine code must not
        /// have touched), and sets the mode to +1.
        struct General(usize, Vec<[f64; 8]>);
        impl Helper for General {
            fn call(&mut self, f: &mut [f64], argument: u64) -> i64 {
                assert_eq!(argument, 99);
                // The coefficients are in the buffer for it.
                assert_eq!(
                    f[34..44],
                    [f[0], f[1], 2.0, 0.0, 0.0, 2.0, -2.5, 0.0, 0.0, -2.5]
                );
                self.0 += 1;
                self.1
                    .push([f[2], f[3], f[20], f[21], f[22], f[23], f[24], f[25]]);
                f[12] = 1.0;
                0
            }
        }
        let (a, d) = (1.0f64, 3.0f64);
        let loop_of = |f: &[f64], phi: f64| {
            let (c3, s3, c4, s4) = (f[8], f[9], f[10], f[11]);
            let k = [a * phi.cos() - d, a * phi.sin()];
            (k[0] + 2.0 * c3 - 2.5 * c4, k[1] + 2.0 * s3 - 2.5 * s4)
        };
        let mut f = vec![0.0; 48];
        for (at, v) in [
            (20, f64::NAN),
            (21, f64::NAN),
            (22, f64::NAN),
            (23, f64::NAN),
            (24, f64::NAN),
            (25, f64::NAN),
        ] {
            f[at] = v;
        }
        f[12] = f64::NAN;
        let mut h = General(0, Vec::new());
        // Mode not set: the general solution, handed the guesses untouched.
        (f[0], f[1]) = (a * 1.5f64.cos() - d, a * 1.5f64.sin());
        (f[2], f[3]) = (1.0, 2.0);
        assert_eq!(code.call(0, &mut f, &mut h), 0);
        assert_eq!(h.0, 1);
        assert_eq!(h.1[0][..2], [1.0, 2.0]);
        assert!(h.1[0][2..].iter().all(|v| v.is_nan()));
        used_after(&f);
        // Then the carried angles of a solution near φ = 1.5 (computed here
        // by atan2) let the machine code take the next steps itself.
        let solve_exact = |phi: f64, sigma: f64| {
            // a cos θ₃ + b sin θ₃ + c = 0 from |k + b e₃| = c.
            let k = [a * phi.cos() - d, a * phi.sin()];
            let (aa, bb) = (2.0 * 2.0 * k[0], 2.0 * 2.0 * k[1]);
            let cc = k[0] * k[0] + k[1] * k[1] + 4.0 - 6.25;
            let r2 = aa * aa + bb * bb;
            let root = sigma * (r2 - cc * cc).sqrt();
            let (c3, s3) = ((-aa * cc - bb * root) / r2, (-bb * cc + aa * root) / r2);
            let (c4, s4) = ((k[0] + 2.0 * c3) / 2.5, (k[1] + 2.0 * s3) / 2.5);
            (s3.atan2(c3), s4.atan2(c4))
        };
        let (t3, t4) = solve_exact(1.5, 1.0);
        (f[20], f[21], f[22]) = (t3.cos(), t3.sin(), t3);
        (f[23], f[24], f[25]) = (t4.cos(), t4.sin(), t4);
        for step in 1..=20 {
            let phi = 1.5 + 0.01 * f64::from(step);
            (f[0], f[1]) = (a * phi.cos() - d, a * phi.sin());
            (f[2], f[3]) = (f[22], f[25]);
            assert_eq!(code.call(0, &mut f, &mut h), 0);
            let (r0, r1) = loop_of(&f, phi);
            assert!(
                r0.abs() < 1e-14 && r1.abs() < 1e-14,
                "{step}: {r0:e}, {r1:e}"
            );
            let (e3, e4) = solve_exact(phi, 1.0);
            assert!((f[2] - e3).abs() < 1e-13 && (f[3] - e4).abs() < 1e-13);
            assert_eq!((f[20], f[21], f[22]), (f[8], f[9], f[2]));
            used_after(&f);
        }
        assert_eq!(h.0, 1, "every step after the first in the machine code");
        // Past the limit (no real solution): the general solution decides,
        // from the guesses and carried values as they were.
        let before = [f[22], f[25], f[20], f[21], f[22], f[23], f[24], f[25]];
        (f[0], f[1]) = (-10.0, 0.0);
        (f[2], f[3]) = (f[22], f[25]);
        assert_eq!(code.call(0, &mut f, &mut h), 0);
        assert_eq!(h.0, 2);
        assert_eq!(h.1[1], before);
        used_after(&f);
    }

    #[test]
    fn angle_equation_in_machine_code() {
        // a cos θ + b sin θ + c = 0 with (a, b) = (3 cos t, 3 sin t), c = −2,
        // the coefficients as parameters 0–1 and a constant.
        let mut g = Graph::new();
        let a = g.leaf(Leaf::Param(0));
        let b = g.leaf(Leaf::Param(1));
        let c = g.constant(-2.0);
        let at = AngleAt {
            value: 2,
            trig: 8,
            carried: 20,
        };
        let form = ClosedForm::Angle { a, b, c };
        let ops = [op(&form, [at, at], slots(7)).expect("the machine code solves the equation")];
        let code = one(&g, &ops);
        let mut h = Recorder {
            calls: Vec::new(),
            status: 42,
        };
        // θ = t + acos(2/3) (mode +1 takes the root with the + sign).
        let exact = |t: f64| t + (2.0f64 / 3.0).acos();
        let mut f = vec![0.0; 48];
        let t0 = 0.2f64;
        let th = exact(t0);
        (f[20], f[21], f[22], f[12]) = (th.cos(), th.sin(), th, 1.0);
        for step in 1..=10 {
            let t = t0 + 0.01 * f64::from(step);
            (f[0], f[1], f[2]) = (3.0 * t.cos(), 3.0 * t.sin(), f[22]);
            assert_eq!(code.call(0, &mut f, &mut h), 0);
            let r = f[0] * f[8] + f[1] * f[9] - 2.0;
            assert!(r.abs() < 1e-15, "{step}: {r:e}");
            assert!((f[2] - exact(t)).abs() < 1e-14, "{step}");
        }
        assert!(h.calls.is_empty());
        assert_eq!(
            f[34..37],
            [0.0; 3],
            "the coefficients are written for the helper only"
        );
        // No real solution (|c| > R): the helper, with the guess untouched
        // and the coefficients in the buffer.
        (f[0], f[1], f[2]) = (1.0, 0.0, 5.0);
        assert_eq!(code.call(0, &mut f, &mut h), 42);
        assert_eq!(h.calls, [7]);
        assert_eq!(f[2], 5.0);
        assert_eq!(f[34..37], [1.0, 0.0, -2.0]);
    }
}
