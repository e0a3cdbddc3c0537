//! The fused pose's closing check, through a stepper's own buffer.

use crate::Options;
use crate::runtime::Model;

const FOUR_BAR: &str = "
pub struct FourBar {
    params { a, b, c, d }
    drivers  { phi }
    unknowns { th3, th4 }
    points {
        B = polar(a, phi);
        D = vec2(d, 0.0);
        C = D + polar(c, th4);
    }
    loops { B + polar(b, th3) == C; }
}";

#[test]
fn a_pose_that_does_not_close_within_the_bound_leaves_the_fused_code() {
    let m = Model::compile(FOUR_BAR)
        .expect("the four-bar compiles")
        .with_values(&[0.04, 0.12, 0.10, 0.11])
        .expect("its values");
    let start = m
        .assemble_all(&[0.3, 1.0, 1.5])
        .find_map(|(_, p)| p.ok())
        .expect("an assembly");
    let mut stepper = m.stepper(&Options::default()).expect("a stepper");
    let mut q = start.clone();
    q[0] += 0.01;
    // Within the bound the machine code takes the pose, and again.
    assert!(stepper.fused_pose_within(&q, None));
    assert!(stepper.fused_pose_within(&q, None));
    // With a bound no residual meets (not even zero), it refuses it; the
    // stepper's pose is then the general path's, the same pose.
    assert!(!stepper.fused_pose_within(&q, Some(-1.0)));
    let fused = stepper.pose(&q).expect("the general path").to_vec();
    let mut fresh = m.stepper(&Options::default()).expect("a stepper");
    let general = fresh.pose(&q).expect("a pose");
    for (x, y) in fused.iter().zip(general) {
        assert!((x - y).abs() <= 1e-14, "{fused:?} against {general:?}");
    }
}

/// Values i of lane `l` of an interleaved array.
fn lane(v: &[f64], l: usize) -> std::vec::Vec<u64> {
    v.iter().skip(l).step_by(2).map(|x| x.to_bits()).collect()
}

fn interleave(a: &[f64], b: &[f64]) -> std::vec::Vec<f64> {
    a.iter().zip(b).flat_map(|(x, y)| [*x, *y]).collect()
}

#[test]
fn a_step_in_lanes_is_each_designs_step_bit_for_bit() {
    let text = "
    pub struct FourBar {
        params { a, b, c, d }
        drivers  { phi }
        unknowns { th3, th4 }
        points {
            B = polar(a, phi);
            C = vec2(d, 0.0) + polar(c, th4);
            P = B + polar(b / 2.0, th3 + 0.3);
        }
        loops { B + polar(b, th3) == C; }
    }";
    let model = Model::compile(text).expect("the four-bar compiles");
    let designs = [[0.04, 0.12, 0.10, 0.11], [0.045, 0.125, 0.095, 0.11]];
    let models = designs.map(|v| model.with_values(&v).expect("its values"));
    let plan = model.fused.as_deref().expect("a fused plan");
    let step = plan.lanes_step().expect("the step has a form in lanes");
    let o = Options::default();
    let mut steppers = [
        models[0].stepper(&o).expect("a stepper"),
        models[1].stepper(&o).expect("a stepper"),
    ];
    // Each design's first step alone (its modes, its carried values).
    let (rates, accelerations) = ([[7.0], [-3.0]], [[2.0], [0.5]]);
    for (l, (m, s)) in models.iter().zip(&mut steppers).enumerate() {
        let start = m
            .assemble_all(&[0.3, 1.0, 1.5])
            .find_map(|(_, p)| p.ok())
            .expect("an assembly");
        s.step_flat(&start, &rates[l], &accelerations[l])
            .expect("a step");
        assert!(s.is_fused());
    }
    // Then twelve steps in lanes (no refresh of the carried values falls
    // among them), each against the same step of each design alone.
    for k in 0..12 {
        let next = |s: &crate::runtime::Stepper<'_>, l: usize| {
            let mut q = s.q.clone();
            q[0] += if l == 0 { 0.01 } else { -0.012 };
            q
        };
        let q_next = [next(&steppers[0], 0), next(&steppers[1], 1)];
        let [s0, s1] = &steppers;
        let (Some(r0), Some(r1)) = (s0.fused.as_ref(), s1.fused.as_ref()) else {
            panic!("fused steppers");
        };
        let mut f = interleave(&r0.f, &r1.f);
        let mut modes = interleave(&s0.modes, &s1.modes);
        let mut q = interleave(&s0.q, &s1.q);
        let status = plan.step(
            &step,
            &mut f,
            [
                &interleave(&q_next[0], &q_next[1]),
                &interleave(&rates[0], &rates[1]),
                &interleave(&accelerations[0], &accelerations[1]),
            ],
            &mut modes,
            &mut q,
        );
        assert_eq!(status, 0, "step {k}: both designs on the common path");
        for (l, s) in steppers.iter_mut().enumerate() {
            s.step_flat(&q_next[l], &rates[l], &accelerations[l])
                .expect("a step");
            let run = s.fused.as_ref().expect("fused");
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<std::vec::Vec<_>>();
            assert_eq!(
                lane(&f, l),
                bits(&run.f),
                "step {k}, design {l}: the buffer"
            );
            assert_eq!(lane(&q, l), bits(&s.q), "step {k}, design {l}: the pose");
            assert_eq!(
                lane(&modes, l),
                bits(&s.modes),
                "step {k}, design {l}: the modes"
            );
        }
    }
}
