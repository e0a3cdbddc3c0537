//! Spatial mechanisms against the lecture notes' worked examples, and
//! generated derivatives against finite differences for random spatial
//! chains and RSSR linkages.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]
// The test mechanisms' parameters are described in the struct docs.
#![allow(missing_docs)]

use std::f64::consts::PI;

use kinematics_core::mechanism;
use kinematics_core::nalgebra::Vector3;
use kinematics_core::rigid::{no_spin_angular_acceleration, no_spin_angular_velocity};
use kinematics_examples::{
    Crane, CraneCoords, RobotArm, RobotArmCoords, Rssr, RssrCoords, SatelliteDish,
    SatelliteDishCoords, SixAxisArm, SixAxisArmCoords, SpatialSlider, SpatialSliderCoords,
};
use kinematics_tests::{check_jacobian, check_motion, Rng};

fn close3(a: &Vector3<f64>, b: &Vector3<f64>, tol: f64) -> bool {
    (a - b).abs().max() <= tol
}

fn rpm(n: f64) -> f64 {
    n * PI / 30.0
}

/// The RSSR of Example 7.3. The statement gives A₀B₀ = d = 315 mm, but the
/// printed solution computes with d = 0.314 m (it writes "−0.314" in its
/// vector b): ψ = 88.42° at φ = 60° and ψ = 70.64° at φ = 0 follow from
/// d = 314 mm, while d = 315 mm gives 88.66° and 70.97°. The printed
/// answers are therefore checked with d = 314 mm.
fn rssr(d: f64) -> Rssr {
    Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d,
    }
}

#[test]
fn example_7_3_rssr_output_and_coupler_velocity() {
    let given = rssr(0.315)
        .assemble(&RssrCoords {
            phi: PI / 3.0,
            psi: 1.5,
        })
        .expect("assembles");
    assert!(
        (given.psi.to_degrees() - 88.656).abs() < 1e-3,
        "{}",
        given.psi.to_degrees()
    );
    let m = rssr(0.314);
    let pose = m
        .assemble(&RssrCoords {
            phi: PI / 3.0,
            psi: 1.5,
        })
        .expect("assembles");
    assert!(
        (pose.psi.to_degrees() - 88.42).abs() < 5e-3,
        "ψ = {}",
        pose.psi.to_degrees()
    );
    // Closed form (58): cos ψ = (b² − a² − c² − d² + 2ad cos φ) / (2c(d − a cos φ)).
    let (a, b, c, d) = (m.a, m.b, m.c, m.d);
    let cos_psi = (b * b - a * a - c * c - d * d + 2.0 * a * d * (PI / 3.0).cos())
        / (2.0 * c * (d - a * (PI / 3.0).cos()));
    assert!((pose.psi.cos() - cos_psi).abs() < 1e-12);
    let w1 = rpm(240.0);
    let s = m.analyze(&pose, w1, 0.0).expect("analysis");
    // ω_o = 10.7 rad/s, and the closed form (56):
    // ω_o/ω₁ = a sin φ (d + c cos ψ) / (c sin ψ (d − a cos φ)).
    assert!((s.qd.psi - 10.7).abs() < 0.05, "ω_o = {}", s.qd.psi);
    let (sp, cp) = pose.psi.sin_cos();
    let ratio = a * (PI / 3.0).sin() * (d + c * cp) / (c * sp * (d - a * (PI / 3.0).cos()));
    assert!((s.qd.psi - ratio * w1).abs() < 1e-10);
    // Coupler with no spin about AB: Ω = b × v_BA / b².
    let (pa, pb) = (s.point_a(), s.point_b());
    let omega =
        no_spin_angular_velocity(&(pb.position - pa.position), &(pb.velocity - pa.velocity))
            .expect("b ≠ 0");
    // |Ω| = 3.61 rad/s (the notes' first method, |v_BA|/b): confirmed.
    assert!((omega.norm() - 3.61).abs() < 5e-3, "|Ω| = {}", omega.norm());
    // The printed components (−2.239, −2.685, −1.013), |Ω| = 3.64: ω_y and
    // ω_z follow from the notes' rounded ω_o = 10.7 and ω₁ = 25.1 (the same
    // formula with those inputs gives −2.685 and −1.013, within 0.02 of the
    // exact −2.682 and −0.995), but ω_x = −2.239 does not (those inputs give
    // −2.193); that slip is why its |Ω| disagrees with the 3.61 of the first
    // method.
    assert!((omega.y - -2.685).abs() < 5e-3, "ω_y = {}", omega.y);
    assert!((omega.z - -1.013).abs() < 0.02 && (omega.x - -2.239).abs() > 0.03);
    // Ω is perpendicular to AB and carries B around A.
    let bb = pb.position - pa.position;
    assert!(omega.dot(&bb).abs() < 1e-12);
    assert!(close3(
        &omega.cross(&bb),
        &(pb.velocity - pa.velocity),
        1e-12
    ));
    check_motion(&m, &pose, &[w1], &[0.0], 1e-6);
}

#[test]
fn example_7_3_rssr_accelerations_at_phi_zero() {
    let m = rssr(0.314);
    let pose = m
        .assemble(&RssrCoords { phi: 0.0, psi: 1.2 })
        .expect("assembles");
    assert!(
        (pose.psi.to_degrees() - 70.64).abs() < 5e-3,
        "ψ = {}",
        pose.psi.to_degrees()
    );
    let (w1, a1) = (rpm(1200.0), rpm(3000.0));
    let s = m.analyze(&pose, w1, a1).expect("analysis");
    let (pa, pb) = (s.point_a(), s.point_b());
    // a_A = 1611i + 32.05k m/s².
    assert!(close3(
        &pa.acceleration,
        &Vector3::new(1611.0, 0.0, 32.05),
        0.5
    ));
    // ω_o = 0 at φ = 0 (the ratio (56) has sin φ as a factor).
    assert!(s.qd.psi.abs() < 1e-12);
    let bb = pb.position - pa.position;
    let omega = no_spin_angular_velocity(&bb, &(pb.velocity - pa.velocity)).expect("b ≠ 0");
    let alpha =
        no_spin_angular_acceleration(&bb, &(pb.acceleration - pa.acceleration)).expect("b ≠ 0");
    // ω_c = −21.2i − 26.13j: confirmed.
    assert!(
        close3(&omega, &Vector3::new(-21.2, -26.13, 0.0), 0.05),
        "{omega:?}"
    );
    // α_o: the notes print 12.607 in one line and −12 607 rad/s² in the
    // next; in the sense in which they define ω_o (v_B = −ω_o k × c, the
    // sense in which ψ increases here) it is positive. Its size, 12 607,
    // and the coupler's α_c = −53i − 65.3j − 4497k agree with the exact
    // values to 0.2 %, the rounding of the printed intermediate figures
    // (1611, 335, 0.240, 0.0842) from which they were solved.
    assert!(s.qdd.psi > 0.0);
    assert!(
        (s.qdd.psi - 12_607.0).abs() / 12_607.0 < 2e-3,
        "α_o = {}",
        s.qdd.psi
    );
    for (got, printed) in alpha.iter().zip([-53.0, -65.3, -4497.0]) {
        assert!((got - printed).abs() <= 2e-3 * 4497.0, "α_c = {alpha:?}");
    }
    assert!(alpha.dot(&bb).abs() < 1e-9 * alpha.norm());
    check_motion(&m, &pose, &[w1], &[a1], 1e-6);
}

#[test]
fn example_7_2_spatial_crank_and_slider() {
    let m = SpatialSlider {
        a: 50.0,
        b: 175.0,
        h: 75.0,
    };
    let pose = m
        .assemble(&SpatialSliderCoords {
            phi: PI / 2.0,
            y: 140.0,
        })
        .expect("assembles");
    // B = 150j + 75k and v_A = −500k mm/s at φ = 90°.
    assert!((pose.y - 150.0).abs() < 1e-9);
    let s = m.analyze(&pose, 10.0, 0.0).expect("analysis");
    assert!(close3(
        &s.point_a().velocity,
        &Vector3::new(0.0, 0.0, -500.0),
        1e-9
    ));
    // The slider moves at −250 mm/s, toward P: confirmed.
    assert!((s.qd.y - -250.0).abs() < 1e-9, "v_B = {}", s.qd.y);
    // The coupler with no spin about its own axis AB: Ω = b × v_BA / b².
    let (pa, pb) = (s.point_a(), s.point_b());
    let b = pb.position - pa.position;
    let v_ba = pb.velocity - pa.velocity;
    let omega = no_spin_angular_velocity(&b, &v_ba).expect("b ≠ 0");
    assert!(close3(&omega.cross(&b), &v_ba, 1e-9) && omega.dot(&b).abs() < 1e-9);
    // To 1e-10: Newton–Raphson stops at |Φ|/S ≤ 1e-12, which leaves y
    // within about 5e-10 mm of 150.
    assert!(close3(
        &omega,
        &(Vector3::new(93_750.0, 25_000.0, 12_500.0) / 30_625.0),
        1e-10
    ));
    // The notes instead take the collar's condition Ω · R = 0 with
    // R = 50i − 75k; their equations 51–54 then give v_B = −250 mm/s and
    // Ω = (2.31, 3.08, 1.54) rad/s. The printed Ω = (57.7, 76.9, 38.5) is
    // 25 times that and violates their own equation 53
    // (150 ω_x + 50 ω_y = 500).
    let r = Vector3::new(50.0, 0.0, -75.0);
    let w = Vector3::new(1.5, 2.0, 1.0) * (500.0 / 325.0);
    // |v_BA| ≈ 290 mm/s, from the pose within about 5e-10 mm.
    assert!(close3(&w.cross(&b), &v_ba, 1e-7) && w.dot(&r).abs() < 1e-9);
    assert!(close3(&w, &Vector3::new(2.31, 3.08, 1.54), 5e-3));
    assert!((150.0 * 57.7 + 50.0 * 76.9 - 500.0_f64).abs() > 1000.0);
    check_motion(&m, &pose, &[10.0], &[0.0], 1e-6);
}

#[test]
fn example_7_4_satellite_dish_from_its_frames() {
    let m = SatelliteDish { r: 1.4 };
    let pose = m
        .assemble(&SatelliteDishCoords {
            phi: 0.0,
            th: 25f64.to_radians(),
        })
        .expect("assembles");
    // ω₁ = 6, ω̇₁ = 3 about z; ω₂ = 2, ω̇₂ = 1.5 about the mount's x axis.
    let s = m.analyze(&pose, [6.0, 2.0], [3.0, 1.5]).expect("analysis");
    let dish = s.frame_dish();
    assert!(close3(
        &dish.angular_velocity,
        &Vector3::new(2.0, 0.0, 6.0),
        1e-12
    ));
    assert!(close3(
        &dish.angular_acceleration,
        &Vector3::new(1.5, 12.0, 3.0),
        1e-12
    ));
    // v_A = (−7.6, −1.18, 2.54) m/s, a_A = (10.4, −51.6, −0.46) m/s².
    let a = s.point_a();
    assert!(
        close3(&a.velocity, &Vector3::new(-7.6, -1.18, 2.54), 0.05),
        "{:?}",
        a.velocity
    );
    assert!(
        close3(&a.acceleration, &Vector3::new(10.4, -51.6, -0.46), 0.05),
        "{:?}",
        a.acceleration
    );
    // The frame's own point helper agrees with the point of the model.
    let local = Vector3::new(0.0, 1.4, 0.0);
    assert!(close3(
        &dish.point(&local).acceleration,
        &a.acceleration,
        1e-12
    ));
    check_motion(&m, &pose, &[6.0, 2.0], &[3.0, 1.5], 1e-6);
}

#[test]
fn practical_exercise_2_crane() {
    // Cab ω₁ = 0.30 rad/s about the vertical z axis, boom raised at
    // ω₂ = 0.50 rad/s relative to the cab, both constant; l = 12 m at 30°.
    let m = Crane { l: 12.0 };
    let pose = m
        .assemble(&CraneCoords {
            phi: 0.0,
            th: PI / 6.0,
        })
        .expect("assembles");
    let s = m
        .analyze(&pose, [0.30, 0.50], [0.0, 0.0])
        .expect("analysis");
    // By hand: ω = ω₁k + ω₂(−j) = (0, −0.5, 0.3); α = ω₁k × ω₂(−j) =
    // (0.15, 0, 0); r = 12(cos 30°, 0, sin 30°); v = ω × r; a = α × r + ω × v.
    let boom = s.frame_boom();
    let w = Vector3::new(0.0, -0.5, 0.3);
    let al = Vector3::new(0.15, 0.0, 0.0);
    let r = Vector3::new(12.0 * (PI / 6.0).cos(), 0.0, 6.0);
    let v = w.cross(&r);
    let acc = al.cross(&r) + w.cross(&v);
    assert!(close3(&boom.angular_velocity, &w, 1e-12));
    assert!(close3(&boom.angular_acceleration, &al, 1e-12));
    let tip = s.point_p();
    assert!(close3(&tip.velocity, &v, 1e-12) && close3(&tip.acceleration, &acc, 1e-12));
    // Numerically: v = (−3.00, 3.12, 5.20) m/s, a = (−3.53, −1.80, −1.50) m/s².
    assert!(close3(
        &tip.velocity,
        &Vector3::new(-3.0, 3.118, 5.196),
        1e-3
    ));
    assert!(close3(
        &tip.acceleration,
        &Vector3::new(-3.533, -1.8, -1.5),
        1e-3
    ));
    check_motion(&m, &pose, &[0.30, 0.50], &[0.0, 0.0], 1e-6);
}

#[test]
fn robot_arm_worked_problem() {
    let m = RobotArm {
        l1: 1.2,
        l2: 0.6,
        l3: 0.2,
        alpha: PI / 3.0,
    };
    let pose = m
        .assemble(&RobotArmCoords {
            q1: 0.0,
            q4: 0.0,
            q5: 0.0,
        })
        .expect("assembles");
    let s = m
        .analyze(&pose, [1.0, 1.0, 1.0], [0.0, 0.0, 0.0])
        .expect("analysis");
    // ω_arm = −ω₄E₁ + ω₅ sin α E₂ + (ω₁ − ω₅ cos α)E₃.
    let arm = s.frame_arm();
    assert!(close3(
        &arm.angular_velocity,
        &Vector3::new(-1.0, (PI / 3.0).sin(), 0.5),
        1e-12
    ));
    // α_arm = −ω₁ω₅ sin α E₁ − (ω₄ω₅ cos α + ω₁ω₄)E₂ − ω₄ω₅ sin α E₃: confirmed.
    let (sa, ca) = (PI / 3.0).sin_cos();
    assert!(close3(
        &arm.angular_acceleration,
        &Vector3::new(-sa, -(ca + 1.0), -sa),
        1e-12
    ));
    // v_B = (−1.12, −0.20, −0.69) m/s: confirmed.
    let b = s.point_b();
    assert!(
        close3(&b.velocity, &Vector3::new(-1.12, -0.20, -0.69), 5e-3),
        "{:?}",
        b.velocity
    );
    // The worked problem's a^A = 2ω₁ω₄L₂ cos α E₁ − (ω₁²L₁ cos α + ω₄²L₂ sin α
    // + ω₁²L₂ sin α)E₂ + ω₄²L₂ cos α E₃ = (0.6, −1.639, 0.3): confirmed.
    let a_a = Vector3::new(2.0 * 0.6 * ca, -(1.2 * ca + 0.6 * sa + 0.6 * sa), 0.6 * ca);
    assert!(close3(&s.point_a().acceleration, &a_a, 1e-12));
    // Its final expression for a^B has ω₁²L₃ cos α in the E₂ term where the
    // a^A it substitutes has ω₁²L₁ cos α; with that slip corrected it gives
    // (0.4, −1.986, 0.5), the computed value, which finite differences of
    // the positions confirm (check_motion below).
    let d = Vector3::new(
        -0.2 * sa * sa - (0.2 - 0.2 * ca) * (1.0 - ca),
        -0.2 * sa,
        -(0.2 - 0.2 * ca),
    );
    let corrected = d + Vector3::new(
        2.0 * 0.6 * ca,
        -(0.2 * sa + 1.2 * ca + 0.6 * sa + 0.6 * sa),
        0.2 * ca + 0.2 + 0.6 * ca,
    );
    assert!(
        close3(&b.acceleration, &corrected, 1e-12),
        "{:?}",
        b.acceleration
    );
    let as_printed = corrected + Vector3::new(0.0, (1.2 - 0.2) * ca, 0.0);
    assert!((b.acceleration - as_printed).norm() > 0.4);
    check_motion(&m, &pose, &[1.0, 1.0, 1.0], &[0.0, 0.0, 0.0], 1e-6);
}

mechanism! {
    /// The screw joint of tutorial question 2: Pⁱ = T₆(A, B, C, θ, k) Pʲ.
    pub struct ScrewJoint {
        params { a, b, c, lead, px, py, pz }
        drivers { th }
        unknowns { }
        points { P = t6(a, b, c, th, lead) * vec3(px, py, pz); }
    }
}

mechanism! {
    /// The notes' cylindrical joint s_jl(B, ψ) = T₇(A, B, 0) T₂(0, 0, 0, ψ):
    /// slide s and turn ψ about the joint's y axis.
    pub struct Cylindrical {
        params { a, px, py, pz }
        drivers { s, psi }
        unknowns { }
        frames { body = t7(a, s, 0.0) * t2(0.0, 0.0, 0.0, psi); }
        points { P = body * vec3(px, py, pz); }
    }
}

#[test]
fn screw_and_cylindrical_joints() {
    // Pʲ = (0, 2, 0), θ = 180°, A = 2, B = −3, C = 2, k = 0.125: the point
    // turns to (0, −2, 0) and the joint advances k/2 along z:
    // Pⁱ = (2, −5, 2.0625).
    let m = ScrewJoint {
        a: 2.0,
        b: -3.0,
        c: 2.0,
        lead: 0.125,
        px: 0.0,
        py: 2.0,
        pz: 0.0,
    };
    let pose = m.assemble(&ScrewJointCoords { th: PI }).expect("assembles");
    let s = m.analyze(&pose, 2.0, 0.0).expect("analysis");
    assert!(close3(
        &s.point_p().position,
        &Vector3::new(2.0, -5.0, 2.0625),
        1e-14
    ));
    // Turning at θ' = 2 rad/s: v = θ' k × (P − axis) + θ' k/2π along z.
    let v = Vector3::new(0.0, 0.0, 2.0).cross(&Vector3::new(0.0, -2.0, 0.0))
        + Vector3::new(0.0, 0.0, 2.0 * 0.125 / (2.0 * PI));
    assert!(close3(&s.point_p().velocity, &v, 1e-14));
    check_motion(&m, &pose, &[2.0], &[0.5], 1e-6);

    // Cylindrical: P at (1, 0, 0) in the body goes to (A + cos ψ, s, −sin ψ);
    // by hand v = (−sin ψ ψ', s', −cos ψ ψ').
    let m = Cylindrical {
        a: 0.5,
        px: 1.0,
        py: 0.0,
        pz: 0.0,
    };
    let pose = m
        .assemble(&CylindricalCoords { s: 0.3, psi: 0.7 })
        .expect("assembles");
    let s = m.analyze(&pose, [0.2, 1.5], [0.0, 0.0]).expect("analysis");
    let p = s.point_p();
    assert!(close3(
        &p.position,
        &Vector3::new(0.5 + 0.7f64.cos(), 0.3, -(0.7f64.sin())),
        1e-14
    ));
    assert!(close3(
        &p.velocity,
        &Vector3::new(-(0.7f64.sin()) * 1.5, 0.2, -(0.7f64.cos()) * 1.5),
        1e-14
    ));
    assert!(close3(
        &s.frame_body().angular_velocity,
        &Vector3::new(0.0, 1.5, 0.0),
        1e-14
    ));
    check_motion(&m, &pose, &[0.2, 1.5], &[0.3, -0.7], 1e-6);
}

#[test]
fn random_six_axis_arms_against_finite_differences() {
    let mut rng = Rng::new(0x6A);
    for _ in 0..40 {
        let m = SixAxisArm {
            d1: rng.range(0.2, 0.6),
            a2: rng.range(0.2, 0.6),
            a3: rng.range(0.2, 0.6),
            d5: rng.range(0.0, 0.2),
            d6: rng.range(0.05, 0.2),
        };
        let q: [f64; 6] = std::array::from_fn(|_| rng.angle());
        let start = SixAxisArmCoords::from(q);
        let pose = m.assemble(&start).expect("an open chain always assembles");
        let rates: [f64; 6] = std::array::from_fn(|_| rng.range(-3.0, 3.0));
        let accels: [f64; 6] = std::array::from_fn(|_| rng.range(-5.0, 5.0));
        // Point, frame origins, ω (against differences of R) and α.
        check_motion(&m, &pose, &rates, &accels, 1e-6);
    }
}

#[test]
fn random_rssr_linkages_against_finite_differences() {
    let mut rng = Rng::new(0x2552);
    let mut done = 0;
    while done < 40 {
        let (a, c, d) = (
            rng.range(0.05, 0.15),
            rng.range(0.1, 0.3),
            rng.range(0.2, 0.4),
        );
        let (phi, psi) = (rng.angle(), rng.angle());
        let pa = Vector3::new(-a * phi.cos(), 0.0, a * phi.sin());
        let pb = Vector3::new(-d - c * psi.cos(), c * psi.sin(), 0.0);
        let b = (pb - pa).norm();
        let m = Rssr { a, b, c, d };
        let exact = RssrCoords { phi, psi };
        // Skip samples near a dead point (v_B ⟂ AB makes ψ ill-determined).
        let mut j = [0.0];
        kinematics_core::Mechanism::jacobian_into(&m, &exact, &mut j);
        if j[0].abs() < 0.2 * c {
            continue;
        }
        let start = RssrCoords {
            phi,
            psi: psi + rng.range(-0.01, 0.01),
        };
        let pose = m.assemble(&start).expect("assembles");
        assert!((pose.psi - psi).abs() < 1e-9);
        check_jacobian(&m, &pose, 1e-6);
        check_motion(
            &m,
            &pose,
            &[rng.range(-20.0, 20.0)],
            &[rng.range(-50.0, 50.0)],
            1e-6,
        );
        done += 1;
    }
}

mechanism! {
    /// A pan–tilt head with a telescoping arm that follows a target moving
    /// along a line: one spatial loop, three scalar equations, three
    /// unknowns (pan ψ about z, tilt θ about the panned x axis, reach s).
    pub struct PanTilt {
        params   { d, h }
        drivers  { y }
        unknowns { psi, th, s }
        frames   { arm = rot_z(psi) * rot_x(th); }
        points   { T = arm * vec3(0.0, s, 0.0); }
        loops    { arm * vec3(0.0, s, 0.0) == vec3(d, y, h); }
    }
}

#[test]
fn a_spatial_loop_is_three_equations() {
    // Counted as two before: this model was rejected with "2 scalar
    // equations for 3 unknowns".
    let m = PanTilt { d: 0.4, h: 0.3 };
    let y = 0.5;
    let pose = m
        .assemble(&PanTiltCoords {
            y,
            psi: -0.5,
            th: 0.4,
            s: 0.6,
        })
        .expect("assembles");
    // The closed form: s = |target|, the arm's direction (−sin ψ cos θ,
    // cos ψ cos θ, sin θ) along the target.
    let r = (0.4f64 * 0.4 + y * y + 0.3 * 0.3).sqrt();
    assert!((pose.s - r).abs() < 1e-14);
    assert!((pose.th - (0.3 / r).asin()).abs() < 1e-14);
    assert!((pose.psi - (-0.4f64).atan2(y)).abs() < 1e-14);
    check_motion(&m, &pose, &[0.7], &[-0.2], 1e-6);
}

/// Frames and points along a chain against finite differences (ω against
/// differences of R, α of ω, velocities of positions, accelerations of
/// velocities):
/// * `arm`, joints with constant offsets: ω, α, the origin's and the point
///   Q's motion all along the chain (ȯ = Σ ωₖ × sₘ);
/// * `chained`, turned about z, x and the screw axis (1, 1, 1)/√3, whose
///   slide k q3 moves the origin: ω, α and P along the chain, the origin's
///   motion by differentiating its expression;
/// * `moving`, about an axis that turns with q1: everything by
///   differentiating R.
#[test]
fn frames_along_a_chain_and_about_a_moving_axis_match_finite_differences() {
    mechanism! {
        pub struct Gimbal {
            params { l, k }
            drivers { q1, q2, q3 }
            unknowns { }
            frames {
                arm = t3(0.0, 0.0, l, q1) * t2(l, 0.0, 0.0, q2) * t1(0.0, l, 0.0, q3);
                chained = rot_z(q1) * translation(vec3(l, 0.0, 0.0)) * rot_x(q2)
                    * screw(vec3(1.0, 1.0, 1.0), q3, k * q3);
                moving = rot(vec3(cos(q1), sin(q1), 0.5), q2 * q3);
            }
            points {
                P = chained * vec3(0.1, l, 0.2);
                Q = arm * vec3(0.1, 0.2, 0.3);
            }
        }
    }
    let m = Gimbal { l: 0.3, k: 0.05 };
    let mut rng = Rng::new(0x61_3B);
    for _ in 0..20 {
        let q: [f64; 3] = std::array::from_fn(|_| rng.range(-3.0, 3.0));
        let rates: [f64; 3] = std::array::from_fn(|_| rng.range(-2.0, 2.0));
        let accels: [f64; 3] = std::array::from_fn(|_| rng.range(-5.0, 5.0));
        let pose = GimbalCoords::from(q);
        check_motion(&m, &pose, &rates, &accels, 1e-7);
    }
}
