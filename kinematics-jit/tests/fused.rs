//! The ops of a fused function, each against values computed here by
//! hand: stores, calls and their statuses, the scaled maximum, the
//! finiteness checks, the block solve, the carried cosines and sines,
//! guarded computations, preset nodes, and the guards on the buffer and
//! the helper.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use kinematics_compiler::ir::{Func, Graph, Leaf, Node};
use kinematics_jit::{Function, Fused, Helper, Layout, Op, SolveBlock, SolveRow, HELPER_PANICKED};

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

/// Records its calls; returns `status` for argument 7, writes f[12] = 99
/// for argument 1, and panics for argument 13.
#[derive(Default)]
struct Recorder {
    calls: Vec<u64>,
    status: i64,
}

impl Helper for Recorder {
    fn call(&mut self, f: &mut [f64], argument: u64) -> i64 {
        self.calls.push(argument);
        match argument {
            1 => {
                f[12] = 99.0;
                0
            }
            7 => self.status,
            13 => panic!("the helper fails"),
            _ => {
                // A fresh cosine and sine of f[2], carried at 20–22.
                let x = f[2];
                f[20] = x.cos();
                f[21] = x.sin();
                f[22] = x;
                f[8] = x.cos();
                f[9] = x.sin();
                0
            }
        }
    }
}

fn one(g: &Graph, ops: &[Op]) -> Fused {
    Fused::new(g, 2, 2, LAYOUT, &[Function { ops, preset: &[] }]).expect("compiles")
}

#[test]
fn stores_calls_and_statuses() {
    let mut g = Graph::new();
    let a = g.leaf(Leaf::Param(0));
    let q = g.leaf(Leaf::Q(0));
    let cq = g.intern(Node::Call(Func::Cos, q));
    let prod = g.intern(Node::Mul(a, cq));
    let ops = [
        Op::Call(1),
        Op::Store {
            roots: vec![prod],
            at: vec![13],
            finite: Some(5),
        },
        Op::Call(7),
        Op::Store {
            roots: vec![a],
            at: vec![14],
            finite: None,
        },
    ];
    let code = one(&g, &ops);
    let mut f = vec![0.0; 48];
    f[0] = 3.0;
    f[8] = 0.5; // cos q₀, read from the array, not computed
    let mut h = Recorder::default();
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(h.calls, [1, 7]);
    assert_eq!((f[12], f[13], f[14]), (99.0, 1.5, 3.0));
    // A nonzero status stops the function there.
    let mut f = vec![0.0; 48];
    f[0] = 3.0;
    f[8] = 0.5;
    let mut h = Recorder {
        calls: Vec::new(),
        status: 42,
    };
    assert_eq!(code.call(0, &mut f, &mut h), 42);
    assert_eq!(f[14], 0.0);
    // A stored root that is not finite returns the store's status.
    f[0] = f64::INFINITY;
    h.status = 0;
    assert_eq!(code.call(0, &mut f, &mut h), 5);
    // A buffer of another length, or no such function: nothing runs.
    assert_eq!(code.call(0, &mut [0.0; 47], &mut h), -1);
    assert_eq!(code.call(1, &mut f, &mut h), -1);
}

#[test]
fn a_panicking_helper_is_a_status() {
    let g = Graph::new();
    let code = one(&g, &[Op::Call(13)]);
    let mut h = Recorder::default();
    assert_eq!(code.call(0, &mut [0.0; 48], &mut h), HELPER_PANICKED);
}

#[test]
fn scaled_maximum_and_finiteness() {
    let mut g = Graph::new();
    let x = g.leaf(Leaf::Q(0));
    let y = g.leaf(Leaf::Q(1));
    let ops = [
        Op::MaxScaled {
            roots: vec![x, y],
            scales: 12,
            at: 14,
        },
        Op::Finite {
            from: 4,
            len: 2,
            status: 9,
        },
    ];
    let code = one(&g, &ops);
    let mut h = Recorder::default();
    let mut f = vec![0.0; 48];
    (f[2], f[3], f[12], f[13]) = (-2.0, 1.0, 0.25, 4.0);
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(f[14], 4.0); // max(|−2·0.25|, |1·4|)
    f[3] = f64::NAN;
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert!(f[14].is_nan(), "a NaN product is the maximum");
    // First or last, with its sign bit set or not, a NaN stays the maximum.
    (f[2], f[3]) = (-f64::NAN, 1.0);
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert!(f[14].is_nan(), "a NaN before a number stays the maximum");
    // An infinite product is above every finite one; tiny ones are ordered.
    (f[2], f[3]) = (f64::NEG_INFINITY, 1.0);
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(f[14], f64::INFINITY);
    (f[2], f[3], f[12], f[13]) = (-4e-320, 1e-320, 1.0, 1.0);
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(f[14], 4e-320, "subnormal magnitudes compare as numbers");
    (f[2], f[3]) = (-0.0, 0.0);
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(f[14].to_bits(), 0, "+0 for zero residuals");
    f[5] = f64::NEG_INFINITY;
    assert_eq!(code.call(0, &mut f, &mut h), 9);
}

#[test]
fn block_solve_by_forward_substitution() {
    // Φ_u = [[2, 0], [1, 4]] as blocks [2] then [4] (row scales 1/2 and
    // 1/4 make each scaled block 1, inverse 1), right-hand side (6, 11),
    // the second unknown a length scaled by L = 10: x₀ = 3, then
    // x₁ = (11 − 1·3)/4 = 2, written ×10 as the length's column scale
    // asks (its scaled unknown is x₁ / L).
    let mut g = Graph::new();
    let r0 = g.leaf(Leaf::Param(0));
    let r1 = g.leaf(Leaf::Param(1));
    let ops = [Op::Solve {
        rhs: vec![r0, r1],
        blocks: vec![
            SolveBlock {
                rows: vec![SolveRow {
                    rhs: 0,
                    scale: 12,
                    known: vec![],
                }],
                inverse: 14,
                cols: vec![(0, None)],
            },
            SolveBlock {
                rows: vec![SolveRow {
                    rhs: 1,
                    scale: 13,
                    known: vec![(16, 0)],
                }],
                inverse: 15,
                cols: vec![(1, Some(17))],
            },
        ],
        to: 30,
        finite: Some(9),
    }];
    let code = one(&g, &ops);
    let mut f = vec![0.0; 48];
    (f[0], f[1]) = (6.0, 11.0);
    (f[12], f[13], f[14], f[15], f[16], f[17]) = (0.5, 0.25, 1.0, 1.0, 1.0, 10.0);
    let mut h = Recorder::default();
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!((f[30], f[31]), (3.0, 20.0));
    // An unknown that is not finite returns the op's status.
    f[1] = f64::INFINITY;
    assert_eq!(code.call(0, &mut f, &mut h), 9);
}

#[test]
fn carried_cosines_and_sines() {
    // After the op, q₀'s cosine and sine as later expressions use them
    // (from registers, not the buffer), times p₀: at 30–31.
    let mut g = Graph::new();
    let p = g.leaf(Leaf::Param(0));
    let q = g.leaf(Leaf::Q(0));
    let cq = g.intern(Node::Call(Func::Cos, q));
    let sq = g.intern(Node::Call(Func::Sin, q));
    let pc = g.intern(Node::Mul(p, cq));
    let ps = g.intern(Node::Mul(p, sq));
    let ops = [
        Op::CarriedTrig {
            value: 2,
            carried: 20,
            to: 8,
            fresh: 3,
            series: TAYLOR,
        },
        Op::Store {
            roots: vec![pc, ps],
            at: vec![30, 31],
            finite: None,
        },
    ];
    let code = one(&g, &ops);
    let used_after = |f: &[f64]| assert_eq!([f[30], f[31]], [2.0 * f[8], 2.0 * f[9]]);
    let mut h = Recorder::default();
    let mut f = vec![0.0; 48];
    f[0] = 2.0;
    (f[20], f[21], f[22]) = (f64::NAN, f64::NAN, f64::NAN);
    // Nothing carried: computed afresh by the helper.
    f[2] = 1.0;
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(h.calls, [3]);
    used_after(&f);
    // Then rotated in small steps, within 4e-15 of the library's.
    for k in 1..=16 {
        f[2] = 1.0 + 0.01 * f64::from(k);
        assert_eq!(code.call(0, &mut f, &mut h), 0);
        assert!((f[8] - f[2].cos()).abs() < 4e-15 && (f[9] - f[2].sin()).abs() < 4e-15);
        assert_eq!((f[20], f[21], f[22]), (f[8], f[9], f[2]));
        used_after(&f);
    }
    // Steps of 0.06, within 1/16 but past 1/32.
    for k in 1..=4 {
        f[2] = 1.16 + 0.06 * f64::from(k);
        assert_eq!(code.call(0, &mut f, &mut h), 0);
        assert!((f[8] - f[2].cos()).abs() < 4e-15 && (f[9] - f[2].sin()).abs() < 4e-15);
        used_after(&f);
    }
    assert_eq!(h.calls, [3], "no fresh computation within 1/16");
    // A jump beyond 1/16 is computed afresh.
    f[2] = 2.0;
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(h.calls, [3, 3]);
    used_after(&f);
}

/// sin Δ and 1 − cos Δ by their Taylor series to Δ⁹ and Δ¹⁰, for
/// |Δ| ≤ 1/16.
const TAYLOR: kinematics_jit::Series = kinematics_jit::Series {
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

#[test]
fn ports_are_read_and_written() {
    use kinematics_jit::Port;
    // q₀, q₁ from input 0, q'₀ from input 1, a mode through output 0 (read
    // into 12, written back from 12), and p₀ q₀ + q'₀ written to output 1.
    let mut g = Graph::new();
    let p = g.leaf(Leaf::Param(0));
    let q = g.leaf(Leaf::Q(0));
    let qd = g.leaf(Leaf::Qd(0));
    let pq = g.intern(Node::Mul(p, q));
    let sum = g.intern(Node::Add(pq, qd));
    let ops = [
        Op::Import {
            from: Port::Input(0),
            to: 2,
            len: 2,
            finite: Some(5),
        },
        Op::Import {
            from: Port::Input(1),
            to: 4,
            len: 1,
            finite: Some(5),
        },
        Op::Import {
            from: Port::Output(0),
            to: 12,
            len: 1,
            finite: None,
        },
        Op::Store {
            roots: vec![sum],
            at: vec![13],
            finite: None,
        },
        Op::Call(7),
        Op::Export {
            to: 0,
            from: 12,
            len: 1,
        },
        Op::Export {
            to: 1,
            from: 13,
            len: 1,
        },
    ];
    let code = one(&g, &ops);
    let mut h = Recorder::default();
    let mut f = vec![0.0; 48];
    f[0] = 3.0;
    let (mut mode, mut out) = ([f64::NAN], [0.0]);
    let run = |f: &mut [f64],
               q: &[f64],
               qd: &[f64],
               mode: &mut [f64],
               out: &mut [f64],
               h: &mut Recorder| { code.call_ports(0, f, h, [q, qd], [mode, out]) };
    assert_eq!(
        run(&mut f, &[2.0, 5.0], &[0.5], &mut mode, &mut out, &mut h),
        0
    );
    assert_eq!((f[2], f[3], f[4]), (2.0, 5.0, 0.5));
    assert!(f[12].is_nan() && mode[0].is_nan());
    assert_eq!(out, [6.5]); // 3·2 + 0.5
                            // A value not finite: the import's status, the outputs untouched.
    out = [-1.0];
    assert_eq!(
        run(
            &mut f,
            &[f64::INFINITY, 5.0],
            &[0.5],
            &mut mode,
            &mut out,
            &mut h
        ),
        5
    );
    assert_eq!(
        run(
            &mut f,
            &[2.0, 5.0],
            &[f64::NAN],
            &mut mode,
            &mut out,
            &mut h
        ),
        5
    );
    assert_eq!(out, [-1.0]);
    // A status before the exports leaves the outputs as they were too.
    h.status = 42;
    mode = [1.0];
    assert_eq!(
        run(&mut f, &[1.0, 5.0], &[0.5], &mut mode, &mut out, &mut h),
        42
    );
    assert_eq!((mode, out), ([1.0], [-1.0]));
    assert_eq!(f[12], 1.0, "the mode was read in");
    // A port shorter than the ops use, or missing: nothing runs.
    h.status = 0;
    f[13] = 0.0;
    assert_eq!(run(&mut f, &[1.0], &[0.5], &mut mode, &mut out, &mut h), -1);
    assert_eq!(
        run(&mut f, &[1.0, 5.0], &[], &mut mode, &mut out, &mut h),
        -1
    );
    assert_eq!(
        run(&mut f, &[1.0, 5.0], &[0.5], &mut mode, &mut [], &mut h),
        -1
    );
    assert_eq!(f[13], 0.0);
    assert_eq!(code.call(0, &mut f, &mut h), -1, "`call` has no ports");
    // Looked up with fewer ports than it uses, the function is not given.
    assert!(code.function::<1, 2>(0).is_none());
    assert!(code.function::<2, 1>(0).is_none());
    assert!(code.function::<2, 2>(0).is_some());
    assert!(code.function::<5, 2>(0).is_none(), "more ports than PORTS");
    assert!(code.function::<2, 2>(1).is_none(), "no second function");
    // Longer ports are read and written as far as the ops use them.
    let mut long = [0.0, 7.0];
    assert_eq!(
        run(
            &mut f,
            &[2.0, 5.0, 9.0],
            &[0.5, 1.0],
            &mut mode,
            &mut long,
            &mut h
        ),
        0
    );
    assert_eq!(long, [6.5, 7.0]);
}

#[test]
fn preset_nodes_are_read_not_computed() {
    let mut g = Graph::new();
    let a = g.leaf(Leaf::Param(0));
    let sa = g.intern(Node::Call(Func::Sin, a));
    let q = g.leaf(Leaf::Q(0));
    let r = g.intern(Node::Mul(sa, q));
    let prelude = [Op::Store {
        roots: vec![sa],
        at: vec![15],
        finite: None,
    }];
    let step = [Op::Store {
        roots: vec![r],
        at: vec![16],
        finite: None,
    }];
    let code = Fused::new(
        &g,
        2,
        2,
        LAYOUT,
        &[
            Function {
                ops: &prelude,
                preset: &[],
            },
            Function {
                ops: &step,
                preset: &[(sa, 15)],
            },
        ],
    )
    .expect("compiles");
    let mut h = Recorder::default();
    let mut f = vec![0.0; 48];
    (f[0], f[2]) = (0.5, 2.0);
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(f[15], 0.5f64.sin());
    // The step reads sin a from the buffer: changing a does not change it.
    f[0] = 1.5;
    assert_eq!(code.call(1, &mut f, &mut h), 0);
    assert_eq!(f[16], 0.5f64.sin() * 2.0);
}

#[test]
fn offsets_past_the_buffer_are_refused() {
    let mut g = Graph::new();
    let a = g.leaf(Leaf::Param(0));
    let ops = [Op::Store {
        roots: vec![a],
        at: vec![48],
        finite: None,
    }];
    assert!(Fused::new(
        &g,
        2,
        2,
        LAYOUT,
        &[Function {
            ops: &ops,
            preset: &[]
        }]
    )
    .is_err());
}

#[test]
fn small_blocks_factored_and_judged() {
    use kinematics_jit::SmallBlock;
    // Blocks [4] (row scale 1/2: scaled 2) and [[1, 2], [3, 4]] (row
    // scales 1, column 1 scaled by L = 1): det = −2, inverse
    // [[−2, 1], [1.5, −0.5]], row sums 3 and 2, conditioning 1/3; signs
    // +1 and −1.
    let mut g = Graph::new();
    let leaves: Vec<_> = (0..2).map(|j| g.leaf(Leaf::Param(j))).collect();
    let consts: Vec<_> = [1.0, 2.0, 3.0, 4.0]
        .iter()
        .map(|&v| g.constant(v))
        .collect();
    let ops = [
        Op::AtMost {
            at: 12,
            bound: 13,
            status: 8,
        },
        Op::FactorSmall {
            blocks: vec![
                SmallBlock {
                    entries: vec![(leaves[0], 14, None)],
                    inverse: 20,
                },
                SmallBlock {
                    entries: vec![
                        (consts[0], 15, None),
                        (consts[1], 15, Some(16)),
                        (consts[2], 15, None),
                        (consts[3], 15, Some(16)),
                    ],
                    inverse: 21,
                },
            ],
            threshold: 17,
            branch: 18,
            odd: false,
            conditioning: 30,
            sign: 31,
            singular: 3,
            wrong_branch: 4,
        },
    ];
    let code = one(&g, &ops);
    let mut h = Recorder::default();
    let setup = |a: f64, threshold: f64, branch: f64| {
        let mut f = vec![0.0; 48];
        f[0] = a;
        (f[12], f[13], f[14], f[15], f[16], f[17], f[18]) =
            (0.5, 1.0, 0.5, 1.0, 1.0, threshold, branch);
        f
    };
    let mut f = setup(4.0, 1e-10, 0.0);
    assert_eq!(code.call(0, &mut f, &mut h), 0);
    assert_eq!(f[20], 0.5);
    assert_eq!(f[21..25], [-2.0, 1.0, 1.5, -0.5]);
    assert!((f[30] - 1.0 / 3.0).abs() < 1e-16);
    assert_eq!(f[31], -1.0);
    // The branch asked for: the other sign fails.
    let mut f = setup(4.0, 1e-10, 1.0);
    assert_eq!(code.call(0, &mut f, &mut h), 4);
    // A singular 1 × 1 block, and conditioning at the threshold.
    let mut f = setup(0.0, 1e-10, 0.0);
    assert_eq!(code.call(0, &mut f, &mut h), 3);
    let mut f = setup(4.0, 0.4, 0.0);
    assert_eq!(code.call(0, &mut f, &mut h), 3);
    // Not within the bound (and NaN).
    let mut f = setup(4.0, 1e-10, 0.0);
    f[12] = 2.0;
    assert_eq!(code.call(0, &mut f, &mut h), 8);
    f[12] = f64::NAN;
    assert_eq!(code.call(0, &mut f, &mut h), 8);
}

#[test]
fn guarded_computation_fast_path_and_fall_back() {
    use kinematics_jit::{Compare, Inst, Val};
    // y = √p₀ where p₀ ≥ 0 (written at 13 and as cos q₀, at 8), else the
    // helper (argument 21), handed p₀ at 14, writes cos q₀ = −1. A later
    // store of cos q₀ reads the kept value, from either path.
    let mut g = Graph::new();
    let p0 = g.leaf(Leaf::Param(0));
    let p1 = g.leaf(Leaf::Param(1));
    let q0 = g.leaf(Leaf::Q(0));
    let c0 = g.intern(Node::Call(Func::Cos, q0));
    let code = vec![
        Inst::Root(p0),
        Inst::Const(0.0),
        Inst::Compare(Compare::GreaterOrEqual, Val(0), Val(1)),
        Inst::Sqrt(Val(0)),
        // p₀ · 0 + p₁ · 1 with the constant-0 term left out: p₁ even
        // where p₀ is not finite.
        Inst::Root(p1),
        Inst::Const(1.0),
        Inst::Dot(vec![(Val(0), Val(1)), (Val(4), Val(5))]),
        Inst::Select(Val(2), Val(3), Val(4)),
    ];
    let ops = [
        Op::Guarded {
            code,
            ok: Val(2),
            fast: vec![(8, Val(3)), (13, Val(3)), (15, Val(6)), (16, Val(7))],
            slow: vec![(14, Val(0))],
            helper: 21,
            keep: vec![8],
        },
        Op::Store {
            roots: vec![c0],
            at: vec![30],
            finite: None,
        },
    ];
    let fused = one(&g, &ops);
    struct Fallback(usize);
    impl Helper for Fallback {
        fn call(&mut self, f: &mut [f64], argument: u64) -> i64 {
            assert_eq!(argument, 21);
            self.0 += 1;
            f[8] = -1.0;
            0
        }
    }
    let mut h = Fallback(0);
    let mut f = vec![0.0; 48];
    (f[0], f[1], f[8], f[14]) = (6.25, 3.0, 7.0, 5.0);
    assert_eq!(fused.call(0, &mut f, &mut h), 0);
    assert_eq!(
        (f[8], f[13], f[15], f[16], f[30]),
        (2.5, 2.5, 3.0, 2.5, 2.5)
    );
    assert_eq!((h.0, f[14]), (0, 5.0), "the other path's writes not made");
    // p₀ < 0 (and NaN): the helper, the fast path's writes not made.
    for p in [-1.0, f64::NAN] {
        (f[0], f[13], f[15]) = (p, 0.0, 0.0);
        assert_eq!(fused.call(0, &mut f, &mut h), 0);
        assert_eq!((f[8], f[13], f[15], f[30]), (-1.0, 0.0, 0.0, -1.0));
        assert!(f[14].to_bits() == p.to_bits());
    }
    assert_eq!(h.0, 2);
}

#[test]
fn guarded_computations_that_do_not_type_are_refused() {
    use kinematics_jit::{Compare, Inst, Val};
    let g = Graph::new();
    let compiles = |code: Vec<Inst>, ok: u32, keep: Vec<usize>| {
        let ops = [Op::Guarded {
            code,
            ok: Val(ok),
            fast: vec![(13, Val(0))],
            slow: vec![],
            helper: 1,
            keep,
        }];
        Fused::new(
            &g,
            2,
            2,
            LAYOUT,
            &[Function {
                ops: &ops,
                preset: &[],
            }],
        )
        .is_ok()
    };
    let flag = || Inst::Compare(Compare::Less, Val(0), Val(0));
    assert!(compiles(vec![Inst::Const(1.0), flag()], 1, vec![13]));
    // The flag is a number; a number read as a flag; a value used before
    // it is defined; an offset kept that the fast path does not write.
    assert!(!compiles(vec![Inst::Const(1.0), flag()], 0, vec![]));
    assert!(!compiles(
        vec![
            Inst::Const(1.0),
            flag(),
            Inst::Select(Val(0), Val(0), Val(0))
        ],
        1,
        vec![]
    ));
    assert!(!compiles(
        vec![Inst::Const(1.0), Inst::Add(Val(0), Val(5)), flag()],
        2,
        vec![]
    ));
    assert!(!compiles(vec![Inst::Const(1.0), flag()], 1, vec![14]));
}

#[test]
fn a_value_the_helper_rewrites_is_read_again_after_the_call() {
    // f[12] = p₀ is stored, then read (exported) from a register; the
    // helper (argument 1) then writes 99 there, which the second export
    // must read from the buffer, not from the register.
    let mut g = Graph::new();
    let a = g.leaf(Leaf::Param(0));
    let ops = [
        Op::Store {
            roots: vec![a],
            at: vec![12],
            finite: None,
        },
        Op::Export {
            to: 0,
            from: 12,
            len: 1,
        },
        Op::Call(1),
        Op::Export {
            to: 1,
            from: 12,
            len: 1,
        },
    ];
    let code = one(&g, &ops);
    let mut h = Recorder::default();
    let mut f = vec![0.0; 48];
    f[0] = 2.5;
    let (mut before, mut after) = ([0.0], [0.0]);
    assert_eq!(
        code.call_ports(0, &mut f, &mut h, [], [&mut before, &mut after]),
        0
    );
    assert_eq!((before, after), ([2.5], [99.0]));
}

#[test]
fn consecutive_imports_are_checked_together_even_past_an_empty_one() {
    // Two imports with the same status, the second of no value, then one
    // with none: a NaN in the first port is still the status; the third
    // port is not checked.
    use kinematics_jit::Port;
    let g = Graph::new();
    let ops = [
        Op::Import {
            from: Port::Input(0),
            to: 12,
            len: 2,
            finite: Some(5),
        },
        Op::Import {
            from: Port::Input(1),
            to: 14,
            len: 0,
            finite: Some(5),
        },
        Op::Import {
            from: Port::Input(2),
            to: 15,
            len: 1,
            finite: None,
        },
    ];
    let code = one(&g, &ops);
    let mut h = Recorder::default();
    let mut f = vec![0.0; 48];
    let run = |f: &mut [f64], a: &[f64], c: &[f64], h: &mut Recorder| {
        code.call_ports::<3, 0>(0, f, h, [a, &[], c], [])
    };
    assert_eq!(run(&mut f, &[1.0, 2.0], &[f64::NAN], &mut h), 0);
    assert_eq!((f[12], f[13]), (1.0, 2.0));
    assert!(f[15].is_nan(), "the unchecked port is read as it is");
    assert_eq!(run(&mut f, &[1.0, f64::INFINITY], &[0.0], &mut h), 5);
    assert_eq!(run(&mut f, &[f64::NAN, 2.0], &[0.0], &mut h), 5);
}

/// A call entered after 256-bit code left the upper halves of the vector
/// registers in use computes the same values, to the bit, as one entered
/// with them clear (the library clears them before the machine code).
#[test]
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
fn a_call_after_256_bit_code_computes_the_same() {
    if !std::arch::is_x86_feature_detected!("avx") {
        return;
    }
    let mut g = Graph::new();
    let p = g.leaf(Leaf::Param(0));
    let q = g.leaf(Leaf::Q(0));
    let cq = g.intern(Node::Call(Func::Cos, q));
    let s = g.intern(Node::Add(p, cq));
    let r = g.intern(Node::Mul(s, s));
    let code = one(
        &g,
        &[Op::Store {
            roots: vec![s, r],
            at: vec![30, 31],
            finite: None,
        }],
    );
    let run = |dirty: bool| {
        let mut f = vec![0.0; 48];
        (f[0], f[2], f[8]) = (0.25, 1.0, 1.0_f64.cos());
        if dirty {
            // SAFETY: the host has AVX (checked above); writes ymm15 only.
            unsafe {
                core::arch::asm!(
                    "vpcmpeqd ymm15, ymm15, ymm15",
                    out("xmm15") _,
                    options(nomem, nostack)
                );
            }
        }
        let status = code.call(0, &mut f, &mut Recorder::default());
        (status, f[30].to_bits(), f[31].to_bits())
    };
    let clear = run(false);
    let s = 0.25 + 1.0_f64.cos();
    assert_eq!(clear, (0, s.to_bits(), (s * s).to_bits()));
    assert_eq!(run(true), clear);
}
