//! Generated derivatives against finite differences, for seeded random
//! dimensions and configurations of a four-bar, a slider-crank, a Watt six-bar
//! (two loops) and a 5R five-bar (two drivers).
//!
//! Each random mechanism is built from a random configuration: the joint
//! angles are drawn first and the closing dimensions computed from them, so
//! every sample is assemblable. Samples too close to a singular
//! configuration (relative pivot of Φ_u below 0.1) are redrawn, since finite
//! differences lose accuracy there.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]
// The test mechanisms' parameters are described in the struct docs.
#![allow(missing_docs)]

use kinematics_core::Mechanism;
use kinematics_examples::{
    FiveBar, FiveBarCoords, FourBar, FourBarCoords, SliderCrank, SliderCrankCoords, Watt,
    WattCoords,
};
use kinematics_tests::{assemble_back, check_jacobian, check_motion, regular, Rng};

const SAMPLES: usize = 60;

/// Checks one sample: Jacobian, velocities and accelerations against finite
/// differences at the pose assembled near `exact`. Returns `false`, checking
/// nothing, when the sample is too close to a singular configuration and
/// must be redrawn.
fn verify<M: Mechanism>(
    m: &M,
    exact: &M::Coords,
    rates: &[f64],
    accels: &[f64],
    rng: &mut Rng,
) -> bool {
    if !regular(m, exact) {
        return false;
    }
    let pose = assemble_back(m, exact, rng);
    check_jacobian(m, &pose, 1e-6);
    check_motion(m, &pose, rates, accels, 1e-6);
    true
}

/// Driver rates in ±20 rad/s and accelerations in ±50 rad/s².
fn driver_motion<const N: usize>(rng: &mut Rng) -> ([f64; N], [f64; N]) {
    let rates = std::array::from_fn(|_| rng.range(-20.0, 20.0));
    let accels = std::array::from_fn(|_| rng.range(-50.0, 50.0));
    (rates, accels)
}

#[test]
fn four_bar() {
    let mut rng = Rng::new(0x4BA2);
    let mut done = 0;
    while done < SAMPLES {
        let (a, phi, b, th3) = (
            rng.range(0.02, 0.1),
            rng.angle(),
            rng.range(0.05, 0.2),
            rng.angle(),
        );
        let d = rng.range(0.05, 0.2);
        let c_pt = (
            a * phi.cos() + b * th3.cos() - d,
            a * phi.sin() + b * th3.sin(),
        );
        let (c, th4) = (c_pt.0.hypot(c_pt.1), c_pt.1.atan2(c_pt.0));
        let m = FourBar {
            a,
            b,
            c,
            d,
            p: rng.range(0.0, 0.1),
            beta: rng.angle(),
        };
        let exact = FourBarCoords { phi, th3, th4 };
        let (rates, accels) = driver_motion::<1>(&mut rng);
        if verify(&m, &exact, &rates, &accels, &mut rng) {
            done += 1;
        }
    }
}

#[test]
fn slider_crank() {
    let mut rng = Rng::new(0x51DE);
    let mut done = 0;
    while done < SAMPLES {
        let (a, phi, b, th) = (
            rng.range(0.02, 0.1),
            rng.angle(),
            rng.range(0.1, 0.4),
            rng.angle(),
        );
        let e = a * phi.sin() + b * th.sin();
        let x = a * phi.cos() + b * th.cos();
        let m = SliderCrank { a, b, e };
        let exact = SliderCrankCoords { phi, th, x };
        let (rates, accels) = driver_motion::<1>(&mut rng);
        if verify(&m, &exact, &rates, &accels, &mut rng) {
            done += 1;
        }
    }
}

#[test]
fn watt_six_bar_two_loops() {
    let mut rng = Rng::new(0x6BA2);
    let mut done = 0;
    while done < SAMPLES {
        let (a, phi, b, th3, d) = (
            rng.range(0.02, 0.1),
            rng.angle(),
            rng.range(0.05, 0.2),
            rng.angle(),
            rng.range(0.05, 0.2),
        );
        let cx = a * phi.cos() + b * th3.cos() - d;
        let cy = a * phi.sin() + b * th3.sin();
        let (c, th4) = (cx.hypot(cy), cy.atan2(cx));
        let (e, gamma, f, th5, g, th6) = (
            rng.range(0.03, 0.15),
            rng.angle(),
            rng.range(0.05, 0.2),
            rng.angle(),
            rng.range(0.05, 0.2),
            rng.angle(),
        );
        let fx = d + e * (th4 + gamma).cos() + f * th5.cos();
        let fy = e * (th4 + gamma).sin() + f * th5.sin();
        let (gx, gy) = (fx - g * th6.cos(), fy - g * th6.sin());
        let m = Watt {
            a,
            b,
            c,
            d,
            e,
            gamma,
            f,
            g,
            gx,
            gy,
        };
        let exact = WattCoords {
            phi,
            th3,
            th4,
            th5,
            th6,
        };
        let (rates, accels) = driver_motion::<1>(&mut rng);
        if verify(&m, &exact, &rates, &accels, &mut rng) {
            done += 1;
        }
    }
}

#[test]
fn five_bar_two_drivers() {
    let mut rng = Rng::new(0x5BA2);
    let mut done = 0;
    while done < SAMPLES {
        let (a, phi1, b, th2) = (
            rng.range(0.02, 0.1),
            rng.angle(),
            rng.range(0.05, 0.2),
            rng.angle(),
        );
        let (c, th3, d, phi2) = (
            rng.range(0.05, 0.2),
            rng.angle(),
            rng.range(0.02, 0.1),
            rng.angle(),
        );
        let ex = a * phi1.cos() + b * th2.cos() - c * th3.cos() - d * phi2.cos();
        let ey = a * phi1.sin() + b * th2.sin() - c * th3.sin() - d * phi2.sin();
        let m = FiveBar { a, b, c, d, ex, ey };
        let exact = FiveBarCoords {
            phi1,
            phi2,
            th2,
            th3,
        };
        let (rates, accels) = driver_motion::<2>(&mut rng);
        if verify(&m, &exact, &rates, &accels, &mut rng) {
            done += 1;
        }
    }
}

#[test]
fn closed_form_four_bar_agrees_with_newton() {
    // Freudenstein's closed form for θ4 (tangent half-angle substitution)
    // gives both assembly branches; the Newton solution, continued from step
    // to step over a full turn, must equal one of them at every step.
    let m = FourBar::CRANK_ROCKER;
    let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    for k in 0..36 {
        let phi = f64::from(k) * 10f64.to_radians();
        pose.phi = phi;
        pose = m.assemble(&pose).expect("assembles");
        // k1 = d/a, k2 = d/c, k3 = (a² − b² + c² + d²)/(2ac);
        // A cos… form: A t² + B t + C = 0 with t = tan(θ4/2), where
        // A = cos φ − k1 − k2 cos φ + k3, B = −2 sin φ,
        // C = k1 − (k2 + 1) cos φ + k3.
        let (a, b, c, d) = (m.a, m.b, m.c, m.d);
        let k1 = d / a;
        let k2 = d / c;
        let k3 = (a * a - b * b + c * c + d * d) / (2.0 * a * c);
        let aa = phi.cos() - k1 - k2 * phi.cos() + k3;
        let bb = -2.0 * phi.sin();
        let cc = k1 - (k2 + 1.0) * phi.cos() + k3;
        let disc = (bb * bb - 4.0 * aa * cc).sqrt();
        let candidates =
            [(-bb + disc) / (2.0 * aa), (-bb - disc) / (2.0 * aa)].map(|t: f64| 2.0 * t.atan());
        let wrap = |x: f64| {
            (x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
        };
        let best = candidates
            .iter()
            .map(|t| wrap(t - pose.th4).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            best < 1e-10,
            "φ = {phi}: θ4 = {} vs closed form {candidates:?}",
            pose.th4
        );
    }
}

#[test]
fn slider_crank_against_closed_form_derivatives() {
    // Zero offset, λ = a/b, constant ω. With S = √(1 − λ² sin²φ):
    //   x   = a cos φ + b S
    //   x'  = −aω (sin φ + λ sin 2φ / (2S))
    //   x'' = −aω² (cos φ + λ cos 2φ / S + λ³ sin² 2φ / (4 S³))
    // (differentiating x(φ(t)) twice by hand).
    let (a, b, w) = (0.1, 0.2, 6.0);
    let lam = a / b;
    let m = SliderCrank { a, b, e: 0.0 };
    let mut pose = m
        .assemble(&SliderCrankCoords {
            phi: 0.0,
            th: 0.1,
            x: 0.3,
        })
        .expect("assembles");
    for k in 0..72 {
        let phi = f64::from(k) * 5f64.to_radians();
        pose.phi = phi;
        pose = m.assemble(&pose).expect("assembles");
        let s = m.analyze(&pose, w, 0.0).expect("analysis");
        let sq = (1.0 - lam * lam * phi.sin().powi(2)).sqrt();
        let x = a * phi.cos() + b * sq;
        let v = -a * w * (phi.sin() + lam * (2.0 * phi).sin() / (2.0 * sq));
        let acc = -a
            * w
            * w
            * (phi.cos()
                + lam * (2.0 * phi).cos() / sq
                + lam.powi(3) * (2.0 * phi).sin().powi(2) / (4.0 * sq.powi(3)));
        assert!((pose.x - x).abs() < 1e-12, "x at {phi}");
        assert!((s.qd.x - v).abs() < 1e-11, "v at {phi}: {} vs {v}", s.qd.x);
        assert!(
            (s.qdd.x - acc).abs() < 1e-10,
            "a at {phi}: {} vs {acc}",
            s.qdd.x
        );
    }
}

/// A simulation's steps (3600 per turn, each from the previous pose) take
/// Newton's common path with sines and cosines carried between iterates; the
/// motion must agree with a separate analysis at the same pose, which
/// evaluates every sine and cosine afresh, and the pose with a separate
/// assembly (polished to round-off) within the bound that the tolerance and
/// the conditioning give: |δu| ≤ tolerance / conditioning.
#[test]
fn small_steps_agree_with_assemble_then_analyze() {
    use kinematics_examples::{Rssr, RssrCoords};
    let close = |what: &str, k: usize, x: f64, y: f64| {
        assert!(
            (x - y).abs() <= 1e-13 * (1.0 + y.abs()),
            "{what} at step {k}: {x} vs {y}"
        );
    };
    let bounded = |what: &str, k: usize, x: f64, y: f64, conditioning: f64| {
        let bound = 1e-12 / conditioning + 1e-15 * (1.0 + y.abs());
        assert!(
            (x - y).abs() <= bound,
            "{what} at step {k}: {x} vs {y} (bound {bound:e})"
        );
    };
    let turn =
        |k: usize| f64::from(u32::try_from(k).expect("small")) * std::f64::consts::TAU / 3600.0;
    let m = FourBar::CRANK_ROCKER;
    let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    for k in 0..3600 {
        pose.phi = turn(k);
        let fused = m.step(&pose, 10.0, 2.0).expect("step");
        let solved = m.assemble(&pose).expect("assembles");
        bounded("th3", k, fused.q.th3, solved.th3, fused.conditioning);
        bounded("th4", k, fused.q.th4, solved.th4, fused.conditioning);
        let exact = m.analyze(&fused.q, 10.0, 2.0).expect("analysis");
        close("th3'", k, fused.qd.th3, exact.qd.th3);
        close("th4''", k, fused.qdd.th4, exact.qdd.th4);
        for (p, e) in fused.points.iter().zip(&exact.points) {
            for (u, v) in p.position.iter().zip(&e.position) {
                close("point position", k, *u, *v);
            }
            for (u, v) in p.acceleration.iter().zip(&e.acceleration) {
                close("point acceleration", k, *u, *v);
            }
        }
        pose = fused.q;
    }
    // The six-bar's second loop starts at E = D + e (cos, sin)(θ4 + γ): the
    // sine and cosine of an offset angle are carried between iterates too.
    let w = Watt {
        gamma: 0.3,
        ..Watt::EXAMPLE
    };
    let mut pose = w.assemble(&Watt::EXAMPLE_GUESS).expect("assembles");
    for k in 0..3600 {
        pose.phi = turn(k);
        let fused = w.step(&pose, 10.0, 2.0).expect("step");
        let solved = w.assemble(&pose).expect("assembles");
        bounded("th5", k, fused.q.th5, solved.th5, fused.conditioning);
        let exact = w.analyze(&fused.q, 10.0, 2.0).expect("analysis");
        close("th6'", k, fused.qd.th6, exact.qd.th6);
        close("th5''", k, fused.qdd.th5, exact.qdd.th5);
        for (p, e) in fused.points.iter().zip(&exact.points) {
            for (u, v) in p.acceleration.iter().zip(&e.acceleration) {
                close("point acceleration", k, *u, *v);
            }
        }
        pose = fused.q;
    }
    let r = Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d: 0.315,
    };
    let mut pose = RssrCoords { phi: 0.0, psi: 1.2 };
    for k in 0..3600 {
        pose.phi = turn(k);
        let fused = r.step(&pose, 25.0, 3.0).expect("step");
        let solved = r.assemble(&pose).expect("assembles");
        bounded("psi", k, fused.q.psi, solved.psi, fused.conditioning);
        let exact = r.analyze(&fused.q, 25.0, 3.0).expect("analysis");
        close("psi'", k, fused.qd.psi, exact.qd.psi);
        close("psi''", k, fused.qdd.psi, exact.qdd.psi);
        pose = fused.q;
    }
}

#[test]
fn fused_step_equals_assemble_then_analyze() {
    use kinematics_core::MotionState;
    use kinematics_examples::{Rssr, RssrCoords, SixAxisArm, SixAxisArmCoords};
    fn same<S: MotionState>(a: &S, b: &S) {
        use kinematics_core::{Coordinates, PointState};
        for j in 0.. {
            let (Some(x), Some(y)) = (a.qdd().get(j), b.qdd().get(j)) else {
                break;
            };
            let (xd, yd) = (a.qd().get(j).expect("q'"), b.qd().get(j).expect("q'"));
            let (xq, yq) = (a.q().get(j).expect("q"), b.q().get(j).expect("q"));
            assert!(
                (x - y).abs() + (xd - yd).abs() + (xq - yq).abs() < 1e-9,
                "coordinate {j}"
            );
        }
        for (p, q) in a.points().iter().zip(b.points()) {
            for (u, v) in p.acceleration().iter().zip(q.acceleration()) {
                assert!((u - v).abs() < 1e-9);
            }
        }
        for (f, g) in a.frames().iter().zip(b.frames()) {
            assert!((f.angular_acceleration - g.angular_acceleration).norm() < 1e-9);
        }
    }
    let m = FourBar::CRANK_ROCKER;
    let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    for k in 0..72 {
        pose.phi = f64::from(k) * 5f64.to_radians();
        let fused = m.step(&pose, 10.0, 2.0).expect("step");
        pose = m.assemble(&pose).expect("assembles");
        same(&fused, &m.analyze(&pose, 10.0, 2.0).expect("analysis"));
    }
    let (w, start) = (Watt::EXAMPLE, Watt::EXAMPLE_GUESS);
    let fused = w.step(&start, 10.0, 2.0).expect("step");
    same(
        &fused,
        &w.analyze(&w.assemble(&start).expect("assembles"), 10.0, 2.0)
            .expect("analysis"),
    );
    let r = Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d: 0.315,
    };
    let start = RssrCoords { phi: 0.3, psi: 1.2 };
    let fused = r.step(&start, 25.0, 3.0).expect("step");
    same(
        &fused,
        &r.analyze(&r.assemble(&start).expect("assembles"), 25.0, 3.0)
            .expect("analysis"),
    );
    let arm = SixAxisArm {
        d1: 0.4,
        a2: 0.45,
        a3: 0.4,
        d5: 0.08,
        d6: 0.1,
    };
    let q = SixAxisArmCoords {
        q1: 0.1,
        q2: -0.4,
        q3: 0.9,
        q4: 0.2,
        q5: -0.6,
        q6: 0.3,
    };
    let (rates, accels) = (
        [1.0, 0.5, -0.5, 1.0, 0.7, -1.0],
        [0.3, 0.1, -0.2, 0.0, 0.4, 0.2],
    );
    same(
        &arm.step(&q, rates, accels).expect("step"),
        &arm.analyze(&q, rates, accels).expect("analysis"),
    );
    // Failures are reported the same way.
    let short = FourBar {
        a: 0.04,
        b: 0.02,
        c: 0.02,
        d: 0.2,
        p: 0.0,
        beta: 0.0,
    };
    let start = FourBarCoords {
        phi: 0.0,
        th3: 0.5,
        th4: 2.0,
    };
    assert_eq!(
        std::mem::discriminant(&short.step(&start, 1.0, 0.0).expect_err("cannot close")),
        std::mem::discriminant(&short.assemble(&start).expect_err("cannot close"))
    );
}

/// A stepping handle carries the sines and cosines of each solved pose to
/// the next step (refreshed every 64): over a full turn its poses are those
/// of `step` within the tolerance's bound, and its motion is that of a
/// separate analysis at the same pose, which evaluates every sine and cosine
/// afresh, to 1e-13: the carried values do not drift.
#[test]
fn a_stepper_follows_step_over_a_turn() {
    use kinematics_core::Options;
    use kinematics_examples::{Rssr, RssrCoords};
    let close = |what: &str, k: usize, x: f64, y: f64, tol: f64| {
        assert!(
            (x - y).abs() <= tol * (1.0 + y.abs()),
            "{what} at step {k}: {x} vs {y}"
        );
    };
    let turn =
        |k: usize| f64::from(u32::try_from(k).expect("small")) * std::f64::consts::TAU / 3600.0;
    let m = FourBar::CRANK_ROCKER;
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    for k in 0..3600 {
        pose.phi = turn(k);
        let s = stepper.step(&pose, 10.0, 2.0).expect("steps");
        let plain = m.step(&pose, 10.0, 2.0).expect("steps");
        close("th3", k, s.q.th3, plain.q.th3, 2e-12 / s.conditioning);
        let exact = m.analyze(&s.q, 10.0, 2.0).expect("analysis");
        close("th3'", k, s.qd.th3, exact.qd.th3, 1e-13);
        close("th4''", k, s.qdd.th4, exact.qdd.th4, 1e-13);
        for (p, e) in s.points.iter().zip(&exact.points) {
            for (u, v) in p.acceleration.iter().zip(&e.acceleration) {
                close("point acceleration", k, *u, *v, 1e-13);
            }
        }
        pose = s.q;
    }
    // The six-bar's offset angle θ4 + γ is carried too; the RSSR has one
    // unknown; the slider-crank a length.
    let w = Watt {
        gamma: 0.3,
        ..Watt::EXAMPLE
    };
    let mut stepper = w.stepper(&Options::DEFAULT).expect("a stepper");
    let mut pose = w.assemble(&Watt::EXAMPLE_GUESS).expect("assembles");
    for k in 0..3600 {
        pose.phi = turn(k);
        let s = stepper.step(&pose, 10.0, 2.0).expect("steps");
        let exact = w.analyze(&s.q, 10.0, 2.0).expect("analysis");
        close("th5''", k, s.qdd.th5, exact.qdd.th5, 1e-13);
        close("th6'", k, s.qd.th6, exact.qd.th6, 1e-13);
        pose = s.q;
    }
    let r = Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d: 0.315,
    };
    let mut stepper = r.stepper(&Options::DEFAULT).expect("a stepper");
    let mut pose = RssrCoords { phi: 0.0, psi: 1.2 };
    for k in 0..3600 {
        pose.phi = turn(k);
        let s = stepper.step(&pose, 25.0, 3.0).expect("steps");
        let exact = r.analyze(&s.q, 25.0, 3.0).expect("analysis");
        // ψ'' divides by Φ_ψ: the two routes' rounding (closed-form sines
        // and cosines against those of ψ) grows as the conditioning falls
        // (to 0.195 near step 560, where the difference is 1.2e-13).
        close("psi''", k, s.qdd.psi, exact.qdd.psi, 1e-13 / s.conditioning);
        pose = s.q;
    }
    let sc = SliderCrank {
        a: 0.1,
        b: 0.25,
        e: 0.01,
    };
    let mut stepper = sc.stepper(&Options::DEFAULT).expect("a stepper");
    let mut pose = sc
        .assemble(&SliderCrankCoords {
            phi: 0.0,
            th: 0.0,
            x: 0.35,
        })
        .expect("assembles");
    for k in 0..3600 {
        pose.phi = turn(k);
        let s = stepper.step(&pose, 6.0, 0.0).expect("steps");
        let exact = sc.analyze(&s.q, 6.0, 0.0).expect("analysis");
        close("x''", k, s.qdd.x, exact.qdd.x, 1e-13);
        pose = s.q;
    }
}
