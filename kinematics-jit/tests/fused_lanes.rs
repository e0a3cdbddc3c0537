//! Fused functions in lanes against the scalar function on each design:
//! the common path (imports, a carried cosine, a guarded computation,
//! stores, the scaled maximum, a bound, exports) gives each lane the
//! scalar buffer and ports bit for bit; where either design leaves the
//! common path or fails a check, the call's status says so.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use kinematics_compiler::ir::{Func, Graph, Leaf, Node};
use kinematics_jit::{Compare, Function, Fused, Helper, Inst, Layout, Op, Port, Val};

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

const SERIES: kinematics_jit::Series = kinematics_jit::Series {
    step: 0.0625,
    sin: [1.0 / 6.0, 1.0 / 120.0, 1.0 / 5040.0, 1.0 / 362_880.0],
    vers: [
        0.5,
        1.0 / 24.0,
        1.0 / 720.0,
        1.0 / 40_320.0,
        1.0 / 3_628_800.0,
    ],
};

const LEFT: i64 = 77;
const NOT_FINITE: i64 = 5;
const TOO_FAR: i64 = 9;

/// The scalar helper: never called on the common path; off it, it writes
/// what a fall-back would (a fresh cosine and sine; q₁ = −1).
struct Fallback(u32);

impl Helper for Fallback {
    fn call(&mut self, f: &mut [f64], argument: u64) -> i64 {
        self.0 += 1;
        if argument == 3 {
            let x = f[2];
            (f[20], f[21], f[22], f[8], f[9]) = (x.cos(), x.sin(), x, x.cos(), x.sin());
        } else {
            f[3] = -1.0;
        }
        0
    }
}

/// q₀ and q₁ from input 0; q₀'s carried cosine and sine; q₁ = √(p₀ − p₁
/// cos q₀) where that is ≥ 0 (else the helper); then p₀ q₁ cos q₀ + sin q₀,
/// q₁ / p₁ and exp(q₁) stored at 30–32 (checked finite), the scaled
/// maximum of (q₁ − 1, p₁ sin q₀) by the scales at 40–41 at 33, at most
/// the bound at 34; q₀, q₁ to output 0.
fn ops(g: &mut Graph) -> Vec<Op> {
    let (p0, p1) = (g.leaf(Leaf::Param(0)), g.leaf(Leaf::Param(1)));
    let (q0, q1) = (g.leaf(Leaf::Q(0)), g.leaf(Leaf::Q(1)));
    let c0 = g.intern(Node::Call(Func::Cos, q0));
    let s0 = g.intern(Node::Call(Func::Sin, q0));
    let pq = g.intern(Node::Mul(p0, q1));
    let pqc = g.intern(Node::Mul(pq, c0));
    let a = g.intern(Node::Add(pqc, s0));
    let d = g.intern(Node::Div(q1, p1));
    let e = g.intern(Node::Call(Func::Exp, q1));
    let one = g.constant(1.0);
    let m1 = g.intern(Node::Neg(one));
    let r0 = g.intern(Node::Add(q1, m1));
    let r1 = g.intern(Node::Mul(p1, s0));
    let code = vec![
        Inst::Root(p0),
        Inst::Root(p1),
        Inst::Root(c0),
        Inst::Mul(Val(1), Val(2)),
        Inst::Sub(Val(0), Val(3)),
        Inst::Const(0.0),
        Inst::Compare(Compare::GreaterOrEqual, Val(4), Val(5)),
        Inst::Sqrt(Val(4)),
        Inst::Const(1.0),
        Inst::Dot(vec![(Val(7), Val(8)), (Val(5), Val(0))]),
        Inst::Compare(Compare::Less, Val(9), Val(0)),
        Inst::And(Val(6), Val(10)),
        Inst::Select(Val(11), Val(9), Val(5)),
        // A choice that differs between the lanes while the guard holds
        // in both: p₀ where p₀ < 3, else p₁ (written at 14).
        Inst::Const(3.0),
        Inst::Compare(Compare::Less, Val(0), Val(13)),
        Inst::Select(Val(14), Val(0), Val(1)),
    ];
    vec![
        Op::Import {
            from: Port::Input(0),
            to: 2,
            len: 2,
            finite: Some(NOT_FINITE),
        },
        Op::CarriedTrig {
            value: 2,
            carried: 20,
            to: 8,
            fresh: 3,
            series: SERIES,
        },
        Op::Guarded {
            code,
            ok: Val(11),
            fast: vec![(3, Val(12)), (13, Val(9)), (14, Val(15))],
            slow: vec![],
            helper: 21,
            keep: vec![3],
        },
        Op::Store {
            roots: vec![a, d, e],
            at: vec![30, 31, 32],
            finite: Some(NOT_FINITE),
        },
        Op::MaxScaled {
            roots: vec![r0, r1],
            scales: 40,
            at: 33,
        },
        Op::AtMost {
            at: 33,
            bound: 34,
            status: TOO_FAR,
        },
        Op::Export {
            to: 0,
            from: 2,
            len: 2,
        },
    ]
}

/// A design's buffer: parameters p, q₀ carried from `x0`, the scales and
/// the bound.
fn buffer(p: [f64; 2], x0: f64, bound: f64) -> Vec<f64> {
    let mut f = vec![0.0; 48];
    (f[0], f[1]) = (p[0], p[1]);
    (f[20], f[21], f[22]) = (x0.cos(), x0.sin(), x0);
    (f[40], f[41], f[34]) = (0.5, 2.0, bound);
    f
}

fn interleave(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).flat_map(|(x, y)| [*x, *y]).collect()
}

fn lane(v: &[f64], l: usize) -> Vec<f64> {
    v.iter().skip(l).step_by(2).copied().collect()
}

struct Pair {
    scalar: Fused,
    lanes: Fused,
}

impl Pair {
    fn new() -> Self {
        let mut g = Graph::new();
        let ops = ops(&mut g);
        let f = [Function {
            ops: &ops,
            preset: &[],
        }];
        Self {
            scalar: Fused::new(&g, 2, 2, LAYOUT, &f).expect("scalar"),
            lanes: Fused::new_in_lanes(&g, 2, 2, LAYOUT, &f, LEFT).expect("lanes"),
        }
    }

    /// Both designs alone and in lanes, from the buffers `f` and the
    /// inputs `q`: the statuses (alone, alone, lanes), with the buffers
    /// and exports compared where the lanes succeeded.
    fn run(&self, f: [Vec<f64>; 2], q: [[f64; 2]; 2]) -> (i64, i64, i64) {
        let mut both = interleave(&f[0], &f[1]);
        let input = interleave(&q[0], &q[1]);
        let mut out = vec![f64::NAN; 4];
        let status = self
            .lanes
            .call_ports(0, &mut both, &mut Fallback(0), [&input], [&mut out]);
        let mut alone = [0; 2];
        for l in 0..2 {
            let mut fl = f[l].clone();
            let mut ol = vec![f64::NAN; 2];
            let mut h = Fallback(0);
            alone[l] = self
                .scalar
                .call_ports(0, &mut fl, &mut h, [&q[l]], [&mut ol]);
            if status == 0 {
                assert_eq!(h.0, 0, "lane {l}: the common path calls no helper");
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&lane(&both, l)), bits(&fl), "lane {l}'s buffer");
                assert_eq!(bits(&lane(&out, l)), bits(&ol), "lane {l}'s export");
            }
        }
        (alone[0], alone[1], status)
    }
}

#[test]
fn the_common_path_in_lanes_is_each_designs_bit_for_bit() {
    let pair = Pair::new();
    assert_eq!(pair.lanes.len(), 96);
    for k in 0..40 {
        let t = f64::from(k) * 0.37;
        // p₀ ≥ 2 > p₁: 0 < p₀ − p₁ cos q₀ < p₀², the guard holds.
        let p = |l: f64| [2.5 + 0.5 * t.sin() + l, 0.5 + 0.3 * (t + l).cos()];
        let x = |l: f64| 0.2 * t + l;
        let f = [buffer(p(0.0), x(0.0), 10.0), buffer(p(1.0), x(1.0), 10.0)];
        let q = [[x(0.0) + 0.05, 0.4], [x(1.0) - 0.03, 0.1]];
        assert_eq!(pair.run(f, q), (0, 0, 0), "round {k}");
    }
    // The choice at 14 differs between the lanes: p₀ of lane 0 below 3,
    // of lane 1 above (checked against each design alone by `run`).
    let f = [buffer([2.5, 0.5], 0.2, 10.0), buffer([3.5, 0.7], 1.2, 10.0)];
    assert_eq!(pair.run(f, [[0.25, 0.4], [1.22, 0.1]]), (0, 0, 0));
}

#[test]
fn a_design_off_the_common_path_or_failing_a_check_stops_the_pair() {
    let pair = Pair::new();
    let good = || buffer([2.0, 0.5], 0.3, 10.0);
    let q = [0.32, 0.4];
    // The driver moved beyond the series' step in lane 1: left.
    assert_eq!(
        pair.run([good(), good()], [q, [0.5, 0.4]]),
        (0, 0, LEFT),
        "the scalar code takes it through the helper"
    );
    // The guard fails in lane 0 (p₀ < p₁ cos q₀): left.
    let low = buffer([0.1, 0.5], 0.3, 10.0);
    assert_eq!(pair.run([low, good()], [q, q]).2, LEFT);
    // A coordinate not finite in lane 1: the import's status.
    assert_eq!(
        pair.run([good(), good()], [q, [f64::NAN, 0.4]]).2,
        NOT_FINITE
    );
    // exp(q₁) infinite in lane 0 (p₀ huge): the store's status, as alone.
    let huge = buffer([1e6, 0.5], 0.3, 1e300);
    assert_eq!(
        pair.run([huge, good()], [q, q]),
        (NOT_FINITE, 0, NOT_FINITE)
    );
    // The scaled maximum above the bound in lane 1 only: the bound's
    // status, as lane 1 alone.
    let tight = buffer([2.0, 0.5], 0.3, 1e-3);
    assert_eq!(pair.run([good(), tight], [q, q]), (0, TOO_FAR, TOO_FAR));
}

#[test]
fn ops_with_no_form_in_lanes_are_refused() {
    let g = Graph::new();
    // A call of the helper: the common path in lanes calls none.
    let ops = [Op::Call(1)];
    let e = Fused::new_in_lanes(
        &g,
        2,
        2,
        LAYOUT,
        &[Function {
            ops: &ops,
            preset: &[],
        }],
        LEFT,
    )
    .expect_err("no form in lanes");
    assert!(e.to_string().contains("no form in lanes"), "{e}");
    // Arrays of one design are refused by the call (−1, nothing run).
    let pair = Pair::new();
    let mut f = vec![0.0; 48];
    let mut out = vec![0.0; 4];
    assert_eq!(
        pair.lanes
            .call_ports(0, &mut f, &mut Fallback(0), [&[0.0; 4][..]], [&mut out]),
        -1
    );
}
