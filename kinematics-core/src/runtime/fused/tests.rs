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
