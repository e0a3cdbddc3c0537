//! A program that reads the time ([`Leaf::Time`]) takes it after the
//! parameters, and one that does not takes the parameters alone.

#![allow(clippy::unwrap_used, missing_docs)]

use kinematics_compiler::ir::{Func, Graph, Leaf};
use kinematics_jit::{Inputs, Program};

#[test]
fn the_time_is_read_after_the_parameters_where_a_stage_reads_it() {
    // Stage 0: p0 sin(t) + q0; stage 1: p0 q0 (no time).
    let mut g = Graph::new();
    let (p, q, t) = (
        g.leaf(Leaf::Param(0)),
        g.leaf(Leaf::Q(0)),
        g.leaf(Leaf::Time),
    );
    let s = g.call(Func::Sin, t);
    let ps = g.mul(p, s);
    let timed = g.sum(ps, q);
    let plain = g.mul(p, q);
    let (q0, trig) = ([0.5], [0.5f64.cos(), 0.5f64.sin()]);
    let inputs = |params: &'static [f64]| Inputs {
        params,
        q: &q0,
        qd: &[0.0],
        qdd: &[0.0],
        trig: &trig,
    };
    let both = Program::new(&g, 1, 1, &[&[timed], &[plain]]).unwrap();
    assert!(both.reads_time() && both.stage_reads_time(0) && !both.stage_reads_time(1));
    let mut out = [0.0];
    both.eval(0, &inputs(&[2.0, 0.3]), &mut out).unwrap();
    assert_eq!(out[0], 2.0 * 0.3f64.sin() + 0.5);
    // The parameters alone are the wrong length for it.
    let e = both.eval(0, &inputs(&[2.0]), &mut out).unwrap_err();
    assert_eq!((e.array, e.expected, e.found), ("params", 2, 1));
    let plain_only = Program::new(&g, 1, 1, &[&[plain]]).unwrap();
    assert!(!plain_only.reads_time());
    plain_only.eval(0, &inputs(&[2.0]), &mut out).unwrap();
    assert_eq!(out[0], 1.0);
}

/// A sum with a negated term is evaluated as a subtraction, bit for bit
/// the sum for every input but a NaN (x + (−z) and x − z are one IEEE
/// operation): on either side of the sum, both terms negated, with the
/// negation also read elsewhere (a root of its own, a product) or read by
/// sums alone, signed zeros and infinities included.
#[test]
fn sums_of_negations_equal_the_sums_bit_for_bit() {
    use kinematics_compiler::ir::Node;
    let mut g = Graph::new();
    let (x, z) = (g.leaf(Leaf::Q(0)), g.leaf(Leaf::Qd(0)));
    let nz = g.intern(Node::Neg(z));
    let right = g.intern(Node::Add(x, nz));
    let left = g.intern(Node::Add(nz, x));
    let product = g.intern(Node::Mul(nz, x));
    let nx = g.intern(Node::Neg(x));
    // −x read by a sum alone: never evaluated as a value of its own.
    let only = g.intern(Node::Add(z, nx));
    // Both terms negated, one of them read by sums alone.
    let both = g.intern(Node::Add(nz, nx));
    let stages: [&[_]; 4] = [
        &[right, left, only],
        &[right, nz, product],
        &[left, only],
        &[both],
    ];
    let p = Program::new(&g, 0, 1, &stages).unwrap();
    let cases = [
        (0.75, 0.25),
        (0.0, 0.0),
        (-0.0, 0.0),
        (0.0, -0.0),
        (1e300, -1e300),
        (f64::INFINITY, 1.0),
        (2.5, f64::INFINITY),
        (-3.0, 1e-320),
    ];
    for (xv, zv) in cases {
        let (q, qd) = ([xv], [zv]);
        let inputs = Inputs {
            params: &[],
            q: &q,
            qd: &qd,
            qdd: &[0.0],
            trig: &[xv.cos(), xv.sin()],
        };
        let want: [&[f64]; 4] = [
            &[xv + (-zv), (-zv) + xv, zv + (-xv)],
            &[xv + (-zv), -zv, (-zv) * xv],
            &[(-zv) + xv, zv + (-xv)],
            &[(-zv) + (-xv)],
        ];
        for (k, w) in want.iter().enumerate() {
            let mut out = vec![f64::NAN; w.len()];
            p.eval(k, &inputs, &mut out).unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&out), bits(w), "stage {k} at x = {xv}, z = {zv}");
        }
    }
}

/// A sum or a product with a constant first is evaluated with the
/// constant second (the x86-64 back end then reads it from memory within
/// the instruction), bit for bit the same number: with the constant on
/// either side, both operands constant, the constant read again by a
/// quotient and a difference (which do not commute and keep their order),
/// signed zeros, infinities and a subnormal included.
#[test]
fn sums_and_products_with_a_constant_first_are_the_same_numbers() {
    use kinematics_compiler::ir::Node;
    let mut g = Graph::new();
    let x = g.leaf(Leaf::Q(0));
    let c = g.constant(0.3);
    let k = g.constant(-2.5);
    let stages: [Vec<_>; 2] = [
        vec![
            g.intern(Node::Mul(c, x)),
            g.intern(Node::Mul(x, c)),
            g.intern(Node::Add(c, x)),
            g.intern(Node::Add(x, k)),
            g.intern(Node::Mul(c, k)),
        ],
        vec![
            g.intern(Node::Div(c, x)),
            g.intern(Node::Div(x, c)),
            g.intern(Node::Add(k, x)),
        ],
    ];
    let p = Program::new(&g, 0, 1, &[&stages[0], &stages[1]]).unwrap();
    for xv in [0.75, -0.0, 0.0, 1e300, f64::INFINITY, -3.0, 1e-320] {
        let q = [xv];
        let inputs = Inputs {
            params: &[],
            q: &q,
            qd: &[0.0],
            qdd: &[0.0],
            trig: &[xv.cos(), xv.sin()],
        };
        let want: [&[f64]; 2] = [
            &[0.3 * xv, xv * 0.3, 0.3 + xv, xv + -2.5, 0.3 * -2.5],
            &[0.3 / xv, xv / 0.3, -2.5 + xv],
        ];
        for (s, w) in want.iter().enumerate() {
            let mut out = vec![f64::NAN; w.len()];
            p.eval(s, &inputs, &mut out).unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&out), bits(w), "stage {s} at x = {xv}");
        }
    }
}
