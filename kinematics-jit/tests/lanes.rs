//! Two designs per call in vector lanes: every stage of every example
//! definition, and a graph calling every function the code knows, give in
//! each lane the scalar program's numbers for that design, bit for bit (a
//! NaN where the scalar's is NaN, its sign aside), whether the arrays lie
//! on 16-byte boundaries or not.

#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use kinematics_compiler::ir::{Func, Graph, Leaf};
use kinematics_jit::{Inputs, Program};

/// The definitions of `examples/mechanisms`.
const EXAMPLES: [(&str, &str); 15] = [
    (
        "crane",
        include_str!("../../examples/mechanisms/crane.mech"),
    ),
    (
        "five_bar",
        include_str!("../../examples/mechanisms/five_bar.mech"),
    ),
    (
        "four_bar",
        include_str!("../../examples/mechanisms/four_bar.mech"),
    ),
    (
        "gas_engine",
        include_str!("../../examples/mechanisms/gas_engine.mech"),
    ),
    (
        "placed_four_bar",
        include_str!("../../examples/mechanisms/placed_four_bar.mech"),
    ),
    (
        "r_rtr_rrt",
        include_str!("../../examples/mechanisms/r_rtr_rrt.mech"),
    ),
    (
        "r_trr",
        include_str!("../../examples/mechanisms/r_trr.mech"),
    ),
    (
        "robot_arm",
        include_str!("../../examples/mechanisms/robot_arm.mech"),
    ),
    ("rssr", include_str!("../../examples/mechanisms/rssr.mech")),
    (
        "satellite_dish",
        include_str!("../../examples/mechanisms/satellite_dish.mech"),
    ),
    (
        "six_axis_arm",
        include_str!("../../examples/mechanisms/six_axis_arm.mech"),
    ),
    (
        "slider_crank",
        include_str!("../../examples/mechanisms/slider_crank.mech"),
    ),
    (
        "spatial_slider",
        include_str!("../../examples/mechanisms/spatial_slider.mech"),
    ),
    (
        "strider",
        include_str!("../../examples/mechanisms/strider.mech"),
    ),
    ("watt", include_str!("../../examples/mechanisms/watt.mech")),
];

/// A reproducible value in [lo, hi): a linear congruential sequence.
struct Draw(u64);

impl Draw {
    fn next(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        #[allow(clippy::cast_precision_loss)]
        let u = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
}

/// Lane `lane` of an interleaved array.
fn lane(v: &[f64], lane: usize) -> Vec<f64> {
    v.iter().skip(lane).step_by(2).copied().collect()
}

/// Every stage of `one` and `two` (the same graph, scalar and in lanes)
/// on two drawn designs and poses: each lane equals the scalar result of
/// its design, bit for bit (NaN where the scalar's is NaN).
fn compare(
    name: &str,
    one: &Program,
    two: &Program,
    params: usize,
    coords: usize,
    draw: &mut Draw,
) {
    compare_with(name, (one, two), (params, coords), draw, None);
}

/// [`compare`], the first parameter of lane 0 `special` where one is
/// given; every second round the arrays are read and written 8 bytes past
/// a 16-byte boundary (the lanes' vectors unaligned).
fn compare_with(
    name: &str,
    (one, two): (&Program, &Program),
    (params, coords): (usize, usize),
    draw: &mut Draw,
    special: Option<f64>,
) {
    assert_eq!((one.lanes(), two.lanes()), (1, 2));
    for round in 0..4 {
        let skew = round % 2;
        // Each array one value longer than the call reads, taken from
        // its value `skew` on.
        let n = |k: usize, draw: &mut Draw, lo: f64, hi: f64| -> Vec<f64> {
            (0..=2 * k).map(|_| draw.next(lo, hi)).collect()
        };
        let mut p = n(params, draw, 0.2, 2.0);
        if let Some(x) = special {
            p[skew] = x;
        }
        let (q, qd, qdd) = (
            n(coords, draw, -3.0, 3.0),
            n(coords, draw, -5.0, 5.0),
            n(coords, draw, -50.0, 50.0),
        );
        let (p, q, qd, qdd) = (
            &p[skew..skew + 2 * params],
            &q[skew..skew + 2 * coords],
            &qd[skew..skew + 2 * coords],
            &qdd[skew..skew + 2 * coords],
        );
        let mut trig_buffer = vec![0.0; 4 * coords + 1];
        two.trig(q, &mut trig_buffer[skew..skew + 4 * coords], 0);
        let trig = &trig_buffer[skew..skew + 4 * coords];
        let inputs = Inputs {
            params: p,
            q,
            qd,
            qdd,
            trig,
        };
        for stage in 0..one.stages() {
            let k = one.outputs(stage);
            let mut out = vec![0.0; 2 * k + 1];
            two.eval(stage, &inputs, &mut out[skew..skew + 2 * k])
                .unwrap();
            let both = &out[skew..skew + 2 * k];
            for l in 0..2 {
                let (pl, ql, qdl, qddl) = (lane(p, l), lane(q, l), lane(qd, l), lane(qdd, l));
                let mut tl = vec![0.0; 2 * coords];
                one.trig(&ql, &mut tl, 0);
                assert_eq!(
                    tl,
                    lane(trig, l),
                    "{name}: the cosines and sines of lane {l}"
                );
                let alone_inputs = Inputs {
                    params: &pl,
                    q: &ql,
                    qd: &qdl,
                    qdd: &qddl,
                    trig: &tl,
                };
                let mut alone = vec![0.0; k];
                one.eval(stage, &alone_inputs, &mut alone).unwrap();
                let got = lane(both, l);
                for (r, (a, b)) in alone.iter().zip(&got).enumerate() {
                    assert!(
                        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                        "{name}, stage {stage}, root {r}, lane {l}: {a:e} alone, {b:e} in lanes"
                    );
                }
            }
        }
    }
}

#[test]
fn every_stage_of_every_example_is_the_scalar_programs_in_each_lane() {
    let mut draw = Draw(7);
    for (name, text) in EXAMPLES {
        let model =
            kinematics_compiler::compile_str(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        let one = Program::for_model(&model).unwrap();
        let two = Program::for_model_in_lanes(&model).unwrap();
        let params = model.parameters().len() + 1;
        let params = params + usize::from(one.reads_time());
        compare(
            name,
            &one,
            &two,
            params,
            model.coordinates().len(),
            &mut draw,
        );
    }
}

#[test]
fn every_function_and_power_is_the_scalar_programs_in_each_lane() {
    // One root per function of p0 q0 + p1 (finite or not: ln of a
    // negative number, asin beyond 1), atan2, |x|, √, powers of every
    // sign, a negation, a constant, the time and a rate and acceleration.
    let mut g = Graph::new();
    let (p0, p1, q0, qd0, qdd0, t) = (
        g.leaf(Leaf::Param(0)),
        g.leaf(Leaf::Param(1)),
        g.leaf(Leaf::Q(0)),
        g.leaf(Leaf::Qd(0)),
        g.leaf(Leaf::Qdd(0)),
        g.leaf(Leaf::Time),
    );
    let pq = g.mul(p0, q0);
    let x = g.sum(pq, p1);
    let mut roots = Vec::new();
    for f in [
        Func::Sin,
        Func::Cos,
        Func::Tan,
        Func::Asin,
        Func::Acos,
        Func::Exp,
        Func::Ln,
        Func::Sqrt,
        Func::Abs,
    ] {
        roots.push(g.call(f, x));
    }
    roots.push(g.atan2(x, p1));
    for n in [-3, -1, 0, 1, 2, 5] {
        roots.push(g.powi(x, n));
    }
    roots.push(g.neg(x));
    roots.push(g.constant(0.1));
    let tq = g.mul(t, qd0);
    roots.push(g.sum(tq, qdd0));
    let sq = g.call(Func::Sin, q0);
    roots.push(g.div(sq, x));
    let one = Program::new(&g, 2, 1, &[&roots]).unwrap();
    let two = Program::new_in_lanes(&g, 2, 1, &[&roots]).unwrap();
    assert!(one.reads_time() && two.reads_time());
    let mut draw = Draw(11);
    for _ in 0..20 {
        compare("functions", &one, &two, 3, 1, &mut draw);
    }
    // p0 = 0, ±0, ±∞, NaN or huge in one lane: x = p1 exactly, or
    // infinite, or NaN there; ln, negative powers and quotients then give
    // infinities and NaN in that lane, finite numbers in the other.
    for special in [0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY, f64::NAN, 1e300] {
        compare_with("functions", (&one, &two), (3, 1), &mut draw, Some(special));
    }
}

#[test]
fn arrays_of_the_wrong_length_are_refused_in_lanes() {
    let model = kinematics_compiler::compile_str(EXAMPLES[2].1).unwrap();
    let two = Program::for_model_in_lanes(&model).unwrap();
    let (np, nc) = (model.parameters().len() + 1, model.coordinates().len());
    let (p, q, trig) = (vec![1.0; 2 * np], vec![0.1; 2 * nc], vec![0.0; 4 * nc]);
    let mut out = vec![0.0; 2 * two.outputs(Program::OUTPUTS)];
    // One design's parameters, not two.
    let inputs = Inputs {
        params: &p[..np],
        q: &q,
        qd: &q,
        qdd: &q,
        trig: &trig,
    };
    let e = two.eval(Program::OUTPUTS, &inputs, &mut out).unwrap_err();
    assert_eq!((e.array, e.expected, e.found), ("params", 2 * np, np));
    // One design's outputs.
    let inputs = Inputs {
        params: &p,
        q: &q,
        qd: &q,
        qdd: &q,
        trig: &trig,
    };
    let half = out.len() / 2;
    let e = two
        .eval(Program::OUTPUTS, &inputs, &mut out[..half])
        .unwrap_err();
    assert_eq!((e.array, e.expected, e.found), ("out", 2 * half, half));
}
