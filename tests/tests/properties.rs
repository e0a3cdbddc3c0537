//! Property tests across the pipeline: random planar four-bars,
//! slider-cranks and six-bars, RSSR linkages and spatial serial chains.
//! For each: the loops close, the Jacobian equals central differences of
//! the residual, velocities equal differences of assembled positions and
//! accelerations differences of velocities, and where a closed form exists
//! the Newton solution agrees with it.
//!
//! The seed is fixed, so CI runs the same cases every time; the number of
//! cases comes from `PROPTEST_CASES` (64 by default). A long run:
//! `PROPTEST_CASES=100000 cargo test --release -p kinematics-tests --test properties`.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]

use std::f64::consts::PI;

use kinematics_core::nalgebra::Vector3;
use kinematics_core::Coordinates;
use kinematics_examples::{
    FourBar, FourBarCoords, Rssr, RssrCoords, SixAxisArm, SixAxisArmCoords, SliderCrank,
    SliderCrankCoords, Watt, WattCoords,
};
use kinematics_tests::{check_jacobian, check_motion, regular};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

fn config() -> ProptestConfig {
    let cases: u32 = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(64);
    ProptestConfig {
        rng_seed: RngSeed::Fixed(0x5EED_C0DE),
        failure_persistence: None,
        // Samples too near a singular configuration are redrawn.
        max_global_rejects: cases.saturating_mul(4).max(1024),
        ..ProptestConfig::with_cases(cases)
    }
}

/// Assembles from `exact` with the unknowns offset by `offsets` and checks
/// that Newton returns to `exact` (the branch follows the guess).
fn assemble_near<M: kinematics_core::Mechanism>(
    m: &M,
    exact: &M::Coords,
    offsets: &[f64],
) -> Result<M::Coords, TestCaseError> {
    let mut guess = *exact;
    for (k, o) in offsets.iter().enumerate().take(M::UNKNOWNS) {
        let j = M::DRIVERS + k;
        let v = exact.get(j).expect("coordinate");
        guess.set(j, v + o * v.abs().max(1.0));
    }
    let pose = m
        .assemble_with(&guess, &kinematics_core::Options::DEFAULT)
        .map_err(|e| TestCaseError::fail(format!("did not assemble: {e}")))?;
    for j in 0..M::DRIVERS + M::UNKNOWNS {
        let (a, b) = (pose.get(j).expect("q"), exact.get(j).expect("q"));
        prop_assert!((a - b).abs() < 1e-9, "coordinate {j}: {a} vs {b}");
    }
    let mut r = vec![0.0; M::EQUATIONS];
    m.residual_into(&pose, &mut r);
    prop_assert!(r.iter().all(|v| v.abs() < 1e-10), "residual {r:?}");
    Ok(pose)
}

/// Relative agreement with the (fourth-order) finite differences.
const FD_TOL: f64 = 1e-6;

fn angle() -> impl Strategy<Value = f64> {
    -PI..PI
}

fn offsets(n: usize) -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(-0.01..0.01f64, n)
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn four_bars(
        a in 0.02..0.1f64, phi in angle(), b in 0.05..0.2f64, th3 in angle(), d in 0.05..0.2f64,
        w in -20.0..20.0f64, al in -50.0..50.0f64, off in offsets(2),
    ) {
        let (cx, cy) = (a * phi.cos() + b * th3.cos() - d, a * phi.sin() + b * th3.sin());
        let (c, th4) = (cx.hypot(cy), cy.atan2(cx));
        let m = FourBar { a, b, c, d, p: 0.05, beta: 0.3 };
        let exact = FourBarCoords { phi, th3, th4 };
        // Non-degenerate: a rocker of a millimetre makes rates so large that
        // differences lose their digits.
        prop_assume!(c > 0.02);
        // Transmission angle μ = θ3 − θ4 at least about 11.5° from a toggle
        // (det Φ_u = b c sin μ); nearer, rates grow without bound and finite
        // differences lose the digits the comparison needs.
        prop_assume!((th3 - th4).sin().abs() > 0.2);
        prop_assume!(regular(&m, &exact));
        let pose = assemble_near(&m, &exact, &off)?;
        check_jacobian(&m, &pose, FD_TOL);
        check_motion(&m, &pose, &[w], &[al], FD_TOL);
        // Freudenstein: t = tan(θ4/2) solves A t² + B t + C = 0.
        let (k1, k2, k3) = (d / a, d / c, (a * a - b * b + c * c + d * d) / (2.0 * a * c));
        let ca = phi.cos() - k1 - k2 * phi.cos() + k3;
        let cb = -2.0 * phi.sin();
        let cc = k1 - (k2 + 1.0) * phi.cos() + k3;
        let t = (pose.th4 / 2.0).tan();
        prop_assert!((ca * t * t + cb * t + cc).abs() < 1e-8 * (1.0 + t * t) * (ca.abs() + cb.abs() + cc.abs()));
    }

    #[test]
    fn slider_cranks(
        a in 0.02..0.1f64, phi in angle(), ratio in 1.5..5.0f64, w in -20.0..20.0f64,
    ) {
        let b = a * ratio;
        // Zero offset: x = a cos φ + √(b² − a² sin²φ), the branch with x > a cos φ.
        let s = (b * b - (a * phi.sin()).powi(2)).sqrt();
        let x = a * phi.cos() + s;
        let th = (-(a * phi.sin()) / b).asin();
        let m = SliderCrank { a, b, e: 0.0 };
        let exact = SliderCrankCoords { phi, th, x };
        let pose = assemble_near(&m, &exact, &[0.005, 0.005])?;
        let motion = m.analyze(&pose, w, 0.0).expect("analysis");
        let v = -a * w * (phi.sin() + a * phi.sin() * phi.cos() / s);
        prop_assert!((motion.qd.x - v).abs() < 1e-10 * (1.0 + v.abs()));
        check_motion(&m, &pose, &[w], &[0.0], FD_TOL);
    }

    #[test]
    fn watt_six_bars(
        a in 0.02..0.1f64, phi in angle(), b in 0.05..0.2f64, th3 in angle(), d in 0.05..0.2f64,
        e in 0.03..0.15f64, gamma in angle(), f in 0.05..0.2f64, th5 in angle(),
        g in 0.05..0.2f64, th6 in angle(), w in -20.0..20.0f64, off in offsets(4),
    ) {
        let (cx, cy) = (a * phi.cos() + b * th3.cos() - d, a * phi.sin() + b * th3.sin());
        let (c, th4) = (cx.hypot(cy), cy.atan2(cx));
        let fx = d + e * (th4 + gamma).cos() + f * th5.cos();
        let fy = e * (th4 + gamma).sin() + f * th5.sin();
        let m = Watt { a, b, c, d, e, gamma, f, g, gx: fx - g * th6.cos(), gy: fy - g * th6.sin() };
        let exact = WattCoords { phi, th3, th4, th5, th6 };
        prop_assume!(c > 0.02);
        // Both dyads away from their toggle positions (see `four_bars`).
        prop_assume!((th3 - th4).sin().abs() > 0.2 && (th5 - th6).sin().abs() > 0.2);
        prop_assume!(regular(&m, &exact));
        let pose = assemble_near(&m, &exact, &off)?;
        check_jacobian(&m, &pose, FD_TOL);
        check_motion(&m, &pose, &[w], &[1.0], FD_TOL);
    }

    #[test]
    fn rssr_linkages(
        a in 0.05..0.15f64, c in 0.1..0.3f64, d in 0.2..0.4f64, phi in angle(), psi in angle(),
        w in -20.0..20.0f64, al in -50.0..50.0f64, off in offsets(1),
    ) {
        let pa = Vector3::new(-a * phi.cos(), 0.0, a * phi.sin());
        let pb = Vector3::new(-d - c * psi.cos(), c * psi.sin(), 0.0);
        let m = Rssr { a, b: (pb - pa).norm(), c, d };
        let exact = RssrCoords { phi, psi };
        // Non-degenerate: with a coupler of millimetres the two mirror
        // assemblies (ψ and −ψ) lie within the guess perturbation.
        prop_assume!(m.b > 0.05);
        // Away from the dead points: ∂Φ/∂ψ = (B − A)·∂B/∂ψ / |B − A| lies
        // in [−c, c] and vanishes there (a 1×1 Jacobian has no relative
        // pivot to judge by).
        let mut j = [0.0];
        kinematics_core::Mechanism::jacobian_into(&m, &exact, &mut j);
        prop_assume!(j[0].abs() > 0.2 * c);
        let pose = assemble_near(&m, &exact, &off)?;
        check_jacobian(&m, &pose, FD_TOL);
        check_motion(&m, &pose, &[w], &[al], FD_TOL);
    }

    #[test]
    fn six_axis_arms(
        d1 in 0.2..0.6f64, a2 in 0.2..0.6f64, a3 in 0.2..0.6f64, d5 in 0.0..0.2f64, d6 in 0.05..0.2f64,
        q in proptest::array::uniform6(angle()),
        qd in proptest::array::uniform6(-3.0..3.0f64),
        qdd in proptest::array::uniform6(-5.0..5.0f64),
    ) {
        let m = SixAxisArm { d1, a2, a3, d5, d6 };
        let start = SixAxisArmCoords { q1: q[0], q2: q[1], q3: q[2], q4: q[3], q5: q[4], q6: q[5] };
        let pose = m.assemble(&start).expect("an open chain always assembles");
        // Points, frame origins, ω against differences of R, α against
        // differences of ω.
        check_motion(&m, &pose, &qd, &qdd, FD_TOL);
    }
}
