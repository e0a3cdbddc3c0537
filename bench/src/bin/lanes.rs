//! What two vector lanes buy on this processor: the stages of a run-time
//! program evaluated for two designs in one call
//! (`Program::for_model_in_lanes`) against the scalar program called
//! once per design, on the four-bar and the Strider leg of the examples.
//! Per stage: the velocities' right-hand side (−Φ_d d'), the
//! accelerations' (−Φ_d d'' − γ), every point's and frame's position,
//! velocity and acceleration, Φ with Φ_u, and the term scales. The lanes
//! are checked to equal the scalar results bit for bit first.
//!
//! Each round times, in turn, 10 000 pairs of scalar calls and 10 000
//! calls in lanes (thread CPU time, interleaved, 21 rounds): ns per
//! design, the median and range, and the ratio lanes ÷ scalar per round
//! (median and range).
//!
//! ```text
//! cargo run --release -p kinematics-bench --bin lanes
//! ```
//!
//! With `count` it runs 10 000 of each, untimed, for an instruction count
//! (`valgrind --tool=callgrind`): `scalar_calls` and `lane_calls` are
//! each 10 000 pairs of designs; `count four-bar 2` (a mechanism, a stage
//! by its place in the list above, from 0) counts that one alone.

#![allow(clippy::expect_used, missing_docs)]

use std::hint::black_box;

use kinematics_bench::{spread, thread_cpu_ns};
use kinematics_jit::{Inputs, Program};

const CALLS: usize = 10_000;
const ROUNDS: usize = 21;

/// One mechanism's inputs for two designs, interleaved and apart.
struct Case {
    name: &'static str,
    one: Program,
    two: Program,
    /// Interleaved: parameters, q, q', q'', trig.
    lanes: [Vec<f64>; 5],
    /// Design l's arrays alone.
    alone: [[Vec<f64>; 5]; 2],
}

fn case(name: &'static str, file: &str, params: &[f64], other: &[f64], q: &[f64]) -> Case {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/mechanisms/");
    let text = std::fs::read_to_string(format!("{root}{file}")).expect("the definition");
    let model = kinematics_compiler::compile_str(&text).expect("compiles");
    let one = Program::for_model(&model).expect("the scalar program");
    let two = Program::for_model_in_lanes(&model).expect("the program in lanes");
    let n = q.len();
    // The second design: other parameters, the pose shifted a little.
    let q2: Vec<f64> = q.iter().map(|x| x + 0.01).collect();
    let with_length = |p: &[f64]| {
        let mut v = p.to_vec();
        v.push(1.0);
        v
    };
    let designs = [
        [with_length(params), q.to_vec(), vec![1.0; n], vec![0.5; n]],
        [with_length(other), q2, vec![1.2; n], vec![0.4; n]],
    ];
    let alone = designs.clone().map(|[p, q, qd, qdd]| {
        let mut t = vec![0.0; 2 * n];
        one.trig(&q, &mut t, 0);
        [p, q, qd, qdd, t]
    });
    let interleave = |k: usize| -> Vec<f64> {
        alone[0][k]
            .iter()
            .zip(&alone[1][k])
            .flat_map(|(a, b)| [*a, *b])
            .collect()
    };
    let lanes = [
        interleave(0),
        interleave(1),
        interleave(2),
        interleave(3),
        interleave(4),
    ];
    Case {
        name,
        one,
        two,
        lanes,
        alone,
    }
}

fn inputs(a: &[Vec<f64>; 5]) -> Inputs<'_> {
    Inputs {
        params: &a[0],
        q: &a[1],
        qd: &a[2],
        qdd: &a[3],
        trig: &a[4],
    }
}

const STAGES: [(&str, usize); 5] = [
    ("velocity rhs", Program::VELOCITY),
    ("acceleration rhs", Program::ACCELERATION),
    ("outputs", Program::OUTPUTS),
    ("Φ and Φ_u", Program::NEWTON),
    ("term scales", Program::SCALES),
];

#[inline(never)]
fn scalar_calls(c: &Case, stage: usize, out: &mut [f64]) {
    let (a, b) = (inputs(&c.alone[0]), inputs(&c.alone[1]));
    for _ in 0..CALLS {
        c.one
            .eval(stage, black_box(&a), out)
            .expect("the scalar stage");
        c.one
            .eval(stage, black_box(&b), out)
            .expect("the scalar stage");
        black_box(&out);
    }
}

#[inline(never)]
fn lane_calls(c: &Case, stage: usize, out: &mut [f64]) {
    let both = inputs(&c.lanes);
    for _ in 0..CALLS {
        c.two
            .eval(stage, black_box(&both), out)
            .expect("the stage in lanes");
        black_box(&out);
    }
}

fn main() {
    use std::f64::consts::{FRAC_PI_4, PI};
    let args: Vec<String> = std::env::args().collect();
    let count = args.get(1).is_some_and(|a| a == "count");
    // `count` with a mechanism and a stage: that one alone.
    let only = |name: &str, k: usize| {
        args.get(2).is_none_or(|a| a == name) && args.get(3).is_none_or(|a| a.parse() == Ok(k))
    };
    let cases = [
        case(
            "four-bar",
            "four_bar.mech",
            &[0.04, 0.12, 0.10, 0.11, 0.06, 0.5],
            &[0.05, 0.13, 0.09, 0.12, 0.05, 0.4],
            &[0.3, 1.2, 1.8],
        ),
        case(
            "Strider",
            "strider.mech",
            &[2.0, FRAC_PI_4, 1.8, 2.6, 1.4, PI + 0.2, 2.5, 1.8],
            &[2.1, 0.8, 1.7, 2.5, 1.5, PI + 0.1, 2.4, 1.9],
            &[0.3, 2.9, 1.9, 0.2, 1.2, -1.9, -2.1, -1.0, -2.0],
        ),
    ];
    for c in &cases {
        for (i, (what, stage)) in STAGES.into_iter().enumerate() {
            if !only(c.name, i) {
                continue;
            }
            let k = c.one.outputs(stage);
            let (mut one, mut two) = (vec![0.0; k], vec![0.0; 2 * k]);
            c.two
                .eval(stage, &inputs(&c.lanes), &mut two)
                .expect("lanes");
            for l in 0..2 {
                c.one
                    .eval(stage, &inputs(&c.alone[l]), &mut one)
                    .expect("scalar");
                let lane: Vec<f64> = two.iter().skip(l).step_by(2).copied().collect();
                assert!(
                    one.iter()
                        .zip(&lane)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "{} {what}: lane {l} differs",
                    c.name
                );
            }
            if count {
                scalar_calls(c, stage, &mut one);
                lane_calls(c, stage, &mut two);
                continue;
            }
            let (mut s, mut v, mut r) = (Vec::new(), Vec::new(), Vec::new());
            for _ in 0..ROUNDS {
                let t0 = thread_cpu_ns();
                scalar_calls(c, stage, &mut one);
                let t1 = thread_cpu_ns();
                lane_calls(c, stage, &mut two);
                let t2 = thread_cpu_ns();
                let designs = (2 * CALLS) as f64;
                s.push((t1 - t0) / designs);
                v.push((t2 - t1) / designs);
                r.push((t2 - t1) / (t1 - t0));
            }
            let ((sm, s0, s1), (vm, v0, v1), (rm, r0, r1)) =
                (spread(&mut s), spread(&mut v), spread(&mut r));
            println!(
                "{:9} {what:17} ({k:3} roots): scalar {sm:6.1} ns ({s0:.1}–{s1:.1}), \
                 lanes {vm:6.1} ns ({v0:.1}–{v1:.1}) a design: lanes ÷ scalar {rm:.2} \
                 ({r0:.2}–{r1:.2})",
                c.name
            );
        }
    }
}
