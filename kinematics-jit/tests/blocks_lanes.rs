//! The factorisation of small blocks and the block solve in lanes against
//! the scalar function on each design: where both designs pass every
//! check each lane's buffer is the scalar buffer bit for bit (the
//! inverses, the conditioning, the sign, the unknowns); where either
//! design fails one (a singular block, the other branch, an unknown not
//! finite) the call returns that check's status, as the design alone
//! does.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use kinematics_compiler::ir::{Graph, Leaf};
use kinematics_jit::{Function, Fused, Helper, Layout, Op, SmallBlock, SolveBlock, SolveRow};

/// Eight parameters at 0–7 (a 2 × 2 block's entries, a 1 × 1 block's,
/// three right-hand sides), two coordinates from 8, and from 20: the row
/// scales (20–22), the column scales (23–25), the known entries (26–27),
/// the threshold (30), the branch asked (31), the conditioning and sign
/// written (32–33), the inverses (40–43, 44), the unknowns (50–52).
const LAYOUT: Layout = Layout {
    params: 0,
    q: 8,
    qd: 10,
    qdd: 12,
    trig: 14,
    len: 64,
};

const SINGULAR: i64 = 3;
const WRONG_BRANCH: i64 = 4;
const NOT_FINITE: i64 = 5;

/// Never called: neither op calls the helper.
struct NoHelper;

impl Helper for NoHelper {
    fn call(&mut self, _: &mut [f64], _: u64) -> i64 {
        panic!("the helper was called")
    }
}

/// The block [[p₀, p₁], [p₂, p₃]] (rows scaled by f₂₀, f₂₁, columns by
/// f₂₃, f₂₄) and the block [p₄] (by f₂₂ and f₂₅) factored; then
/// x₂ = p₇ f₂₂ / (p₄ f₂₂ f₂₅) · f₂₅ and x₀, x₁ from the first block with
/// the known terms f₂₆ x₂ and f₂₇ x₂, written at 50–52.
fn ops(g: &mut Graph, odd: bool) -> Vec<Op> {
    let p: Vec<_> = (0..8).map(|i| g.leaf(Leaf::Param(i))).collect();
    vec![
        Op::FactorSmall {
            blocks: vec![
                SmallBlock {
                    entries: vec![
                        (p[0], 20, Some(23)),
                        (p[1], 20, Some(24)),
                        (p[2], 21, Some(23)),
                        (p[3], 21, Some(24)),
                    ],
                    inverse: 40,
                },
                SmallBlock {
                    entries: vec![(p[4], 22, Some(25))],
                    inverse: 44,
                },
            ],
            threshold: 30,
            branch: 31,
            odd,
            conditioning: 32,
            sign: 33,
            singular: SINGULAR,
            wrong_branch: WRONG_BRANCH,
        },
        Op::Solve {
            rhs: vec![p[5], p[6], p[7]],
            blocks: vec![
                SolveBlock {
                    rows: vec![SolveRow {
                        rhs: 2,
                        scale: 22,
                        known: vec![],
                    }],
                    inverse: 44,
                    cols: vec![(2, Some(25))],
                },
                SolveBlock {
                    rows: vec![
                        SolveRow {
                            rhs: 0,
                            scale: 20,
                            known: vec![(26, 2)],
                        },
                        SolveRow {
                            rhs: 1,
                            scale: 21,
                            known: vec![(27, 2)],
                        },
                    ],
                    inverse: 40,
                    cols: vec![(0, Some(23)), (1, None)],
                },
            ],
            to: 50,
            finite: Some(NOT_FINITE),
        },
    ]
}

/// A design's buffer: the parameters `p`, the scales, the known entries,
/// the threshold 1e-10 and the branch asked.
fn buffer(p: [f64; 8], branch: f64) -> Vec<f64> {
    let mut f = vec![0.0; 64];
    f[..8].copy_from_slice(&p);
    f[20..28].copy_from_slice(&[0.5, 2.0, 1.5, 4.0, 0.25, 3.0, 0.7, -1.3]);
    (f[30], f[31]) = (1e-10, branch);
    f
}

struct Pair {
    scalar: Fused,
    lanes: Fused,
}

impl Pair {
    fn new(odd: bool) -> Self {
        let mut g = Graph::new();
        let ops = ops(&mut g, odd);
        let f = [Function {
            ops: &ops,
            preset: &[],
        }];
        Self {
            scalar: Fused::new(&g, 8, 2, LAYOUT, &f).expect("scalar"),
            lanes: Fused::new_in_lanes(&g, 8, 2, LAYOUT, &f, 77).expect("in lanes"),
        }
    }

    /// Both designs alone and in lanes: the statuses (alone, alone,
    /// lanes), each lane's buffer compared with its design's where the
    /// lanes passed.
    fn run(&self, f: [Vec<f64>; 2]) -> (i64, i64, i64) {
        let mut both: Vec<f64> = f[0].iter().zip(&f[1]).flat_map(|(x, y)| [*x, *y]).collect();
        let status = self.lanes.call(0, &mut both, &mut NoHelper);
        let mut alone = [0; 2];
        for (l, f) in f.into_iter().enumerate() {
            let mut fl = f;
            alone[l] = self.scalar.call(0, &mut fl, &mut NoHelper);
            if status == 0 {
                let lane: Vec<u64> = both
                    .iter()
                    .skip(l)
                    .step_by(2)
                    .map(|x| x.to_bits())
                    .collect();
                let own: Vec<u64> = fl.iter().map(|x| x.to_bits()).collect();
                assert_eq!(lane, own, "lane {l}'s buffer");
            }
        }
        (alone[0], alone[1], status)
    }
}

/// A regular design of round t, shifted by `l`: det of the first block
/// of either sign as t goes.
fn design(t: f64, l: f64) -> [f64; 8] {
    [
        1.0 + 0.5 * (t + l).sin(),
        0.3 * (2.0 * t).cos() - l,
        0.4 + 0.1 * t.cos(),
        -0.8 + 1.9 * (0.7 * t + l).sin(),
        0.6 + 0.2 * (t - l).cos(),
        t.sin() + l,
        (1.3 * t).cos(),
        0.5 - 0.1 * t,
    ]
}

#[test]
fn both_designs_factored_and_solved_as_each_alone() {
    for odd in [false, true] {
        let pair = Pair::new(odd);
        let mut signs = [0, 0];
        for k in 0..60 {
            let t = f64::from(k) * 0.29;
            let f = [buffer(design(t, 0.0), 0.0), buffer(design(t, 0.4), 0.0)];
            assert_eq!(pair.run(f.clone()), (0, 0, 0), "round {k}");
            // The sign written is the branch each design is on: asking
            // for it passes, in either lane.
            let mut one = f[0].clone();
            pair.scalar.call(0, &mut one, &mut NoHelper);
            let sign = one[33];
            signs[usize::from(sign > 0.0)] += 1;
            let asked = [buffer(design(t, 0.0), sign), f[1].clone()];
            assert_eq!(pair.run(asked), (0, 0, 0), "round {k}, asked");
        }
        assert!(signs[0] > 0 && signs[1] > 0, "both branches met: {signs:?}");
    }
}

#[test]
fn a_design_failing_a_check_fails_the_pair_with_its_status() {
    let pair = Pair::new(false);
    let good = || buffer(design(0.3, 0.0), 0.0);
    // The first block singular in lane 1 (p₀ p₃ = p₁ p₂).
    let mut p = design(0.3, 0.4);
    p[3] = p[1] * p[2] / p[0];
    let singular = buffer([p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]], 0.0);
    let (_, one, both) = pair.run([good(), singular]);
    assert_eq!((one, both), (SINGULAR, SINGULAR));
    // The 1 × 1 block at the threshold in lane 0.
    let mut p = design(0.3, 0.0);
    p[4] = 1e-10 / (1.5 * 3.0);
    assert_eq!(pair.run([buffer(p, 0.0), good()]), (SINGULAR, 0, SINGULAR));
    // The other branch asked for in lane 0.
    let mut f = good();
    pair.scalar.call(0, &mut f, &mut NoHelper);
    let other = buffer(design(0.3, 0.0), -f[33]);
    assert_eq!(pair.run([other, good()]), (WRONG_BRANCH, 0, WRONG_BRANCH));
    // A right-hand side infinite in lane 1: an unknown not finite.
    let mut p = design(0.3, 0.4);
    p[7] = f64::INFINITY;
    assert_eq!(
        pair.run([good(), buffer(p, 0.0)]),
        (0, NOT_FINITE, NOT_FINITE)
    );
}
