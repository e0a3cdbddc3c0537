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
