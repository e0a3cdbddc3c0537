//! The chapter's Examples 4.1 and 4.2, against the printed answers.
//!
//! The book prints three decimals and, in several places, truncates rather
//! than rounds (72.2357° is printed 72.235) or carries rounded intermediate
//! values into later steps. A printed value is taken as reproduced when the
//! computed one is within one unit of its last decimal. Where a printed value
//! is further off, the test shows with an independent check (central finite
//! differences of assembled positions) that the computed value is the right
//! one.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]

use kinematics_core::Mechanism;
use kinematics_examples::{RRtrRrt, RTrr};
use kinematics_tests::{check_motion, pose_at};

/// |computed − printed| within one unit of the printed value's last decimal.
fn book(name: &str, computed: f64, printed: f64, decimals: i32) {
    let unit = 10f64.powi(-decimals);
    assert!(
        (computed - printed).abs() < unit,
        "{name}: computed {computed:.6}, book {printed}"
    );
}

/// Velocity and acceleration of a point by finite differences of its
/// assembled positions at φ ± h and φ, for constant driver speed ω:
/// v = ω dr/dφ, a = ω² d²r/dφ².
fn fd_point<M: Mechanism>(m: &M, pose: &M::Coords, omega: f64, k: usize) -> ([f64; 2], [f64; 2]) {
    let h = 1e-4;
    let at = |t: f64| {
        let p = pose_at(m, pose, &[1.0], &[0.0], t);
        let mut r = vec![0.0; M::POINTS * 2];
        m.point_positions_into(&p, &mut r);
        kinematics_core::nalgebra::Vector2::new(r[2 * k], r[2 * k + 1])
    };
    let (rp, r0, rm) = (at(h), at(0.0), at(-h));
    let v = (rp - rm) / (2.0 * h) * omega;
    let a = (rp - 2.0 * r0 + rm) / (h * h) * omega * omega;
    ([v.x, v.y], [a.x, a.y])
}

#[test]
fn example_4_1_r_trr() {
    let m = RTrr::EXAMPLE_4_1;
    // Rough guess: angles to the nearest 10°, B about 0.35 m along the crank.
    let pose = m.assemble(&RTrr::example_4_1_guess()).expect("assembles");
    // The book turns 30 rev/min into ω = 3.141 rad/s and uses that value in
    // every numerical step (Eq. 4.79, 4.81); so does this test.
    #[allow(clippy::approx_constant)] // deliberately the book's rounded value
    let omega = 3.141;
    let s = m.analyze(&pose, omega, 0.0).expect("analysis");
    let b = s.point_b();
    book("x_B", b.position.x, 0.256, 3);
    book("y_B", b.position.y, 0.256, 3);
    book("v_Bx", b.velocity.x, -0.999, 3);
    book("v_By", b.velocity.y, 0.609, 3);
    book("|v_B|", b.speed(), 1.171, 3);
    book("a_Bx", b.acceleration.x, -1.802, 3);
    book("|a_B|", b.acceleration.norm(), 4.620, 3);
    book("phi3 (deg)", pose.phi3.to_degrees(), 58.633, 3);
    book("omega3", s.qd.phi3, 3.903, 3);
    book("alpha3", s.qdd.phi3, -2.252, 3);

    // a_By: the book prints −4.255 m/s², the value for the stated 30 rev/min
    // (ω = π exactly); the rest of the example computes with the rounded
    // ω = 3.141, which gives −4.2534. Finite differences of the assembled
    // positions of B confirm both: −4.2534 at ω = 3.141, −4.255 at ω = π.
    let (fd_v, fd_a) = fd_point(&m, &pose, omega, 0);
    assert!((b.velocity.x - fd_v[0]).abs() < 1e-6 && (b.velocity.y - fd_v[1]).abs() < 1e-6);
    assert!(
        (b.acceleration.y - fd_a[1]).abs() < 1e-5,
        "{} vs {}",
        b.acceleration.y,
        fd_a[1]
    );
    assert!(
        (fd_a[1] - -4.255).abs() > 1e-3,
        "the printed a_By is off by more than rounding"
    );
    let exact = m
        .analyze(&pose, std::f64::consts::PI, 0.0)
        .expect("analysis");
    book("a_By at ω = π", exact.point_b().acceleration.y, -4.255, 3);

    // Closed form: B lies on the crank line, so φ3 = atan2(y_B, x_B − AC).
    let phi3 = b.position.y.atan2(b.position.x - 0.1);
    assert!((phi3 - pose.phi3).abs() < 1e-12);
    check_motion(&m, &pose, &[omega], &[0.0], 1e-6);
}

#[test]
fn example_4_2_r_rtr_rrt() {
    let m = RRtrRrt::EXAMPLE_4_2;
    // Rough guess, angles to the nearest 10°.
    let pose = m
        .assemble(&RRtrRrt::example_4_2_guess())
        .expect("assembles");
    let omega = 4.712;
    let s = m.analyze(&pose, omega, 0.0).expect("analysis");
    let (d, e) = (s.point_d(), s.point_e());
    book("phi3 (deg)", pose.phi3.to_degrees(), 72.235, 3);
    book("omega3", s.qd.phi3, 1.807, 3);
    book("alpha3", s.qdd.phi3, 1.020, 3);
    book("x_D", d.position.x, -0.023, 3);
    book("y_D", d.position.y, -0.071, 3);
    book("v_Dx", d.velocity.x, 0.129, 3);
    book("v_Dy", d.velocity.y, -0.041, 3);
    // |v_D| is printed from the rounded components: √(0.129² + 0.041²) = 0.1354.
    book("|v_D|", d.speed(), 0.135, 3);
    book("a_Dx", d.acceleration.x, 0.147, 3);
    book("a_Dy", d.acceleration.y, 0.210, 3);
    book("|a_D|", d.acceleration.norm(), 0.256, 3);
    book("x_E", e.position.x, 0.164, 3);
    book("v_E", e.velocity.x, 0.113, 3);
    book("a_E", e.acceleration.x, 0.217, 3);
    book("phi4 (deg)", pose.phi4.to_degrees(), 20.923, 3);
    book("omega4", s.qd.phi4, 0.221, 3);
    book("alpha4", s.qdd.phi4, -1.105, 3);
    // E stays on the x axis and D on the circle of radius CD about C.
    assert!(e.position.y.abs() < 1e-15 && e.velocity.y.abs() < 1e-15);
    assert!((d.position.norm() - 0.075).abs() < 1e-12);
    // x_D < 0: the branch the book selects.
    assert!(d.position.x < 0.0);
    // Independent check of every velocity and acceleration.
    let (fd_v, fd_a) = fd_point(&m, &pose, omega, 1);
    assert!((d.velocity.x - fd_v[0]).abs() < 1e-6 && (d.acceleration.x - fd_a[0]).abs() < 1e-5);
    check_motion(&m, &pose, &[omega], &[0.0], 1e-6);
}

/// A planar vector as the toolkit's 3-D one.
fn v3(x: f64, y: f64) -> kinematics_core::nalgebra::Vector3<f64> {
    kinematics_core::nalgebra::Vector3::new(x, y, 0.0)
}

#[test]
fn example_4_1_relative_motion_of_the_slider() {
    use kinematics_core::rigid::{relative_motion, FrameMotion};
    // Block 2 slides along link 1 (the crank through A) at B: its motion is
    // that of the point B₁ of link 1 under it (transport), plus the slide
    // s' and s'' along the crank (relative), plus Coriolis 2ω₁ × v_rel.
    let m = RTrr::EXAMPLE_4_1;
    let pose = m.assemble(&RTrr::example_4_1_guess()).expect("assembles");
    #[allow(clippy::approx_constant)] // the book's rounded ω
    let omega = 3.141;
    let s = m.analyze(&pose, omega, 0.0).expect("analysis");
    let e = v3(pose.phi.cos(), pose.phi.sin());
    let link1 = FrameMotion {
        angular_velocity: kinematics_core::nalgebra::Vector3::z() * omega,
        ..FrameMotion::default()
    };
    let b = s.point_b();
    let r = relative_motion(
        &link1,
        &v3(b.position.x, b.position.y),
        &(e * s.qd.s),
        &(e * s.qdd.s),
    );
    book("v_B1x", r.transport_velocity.x, -0.804, 3);
    book("v_B1y", r.transport_velocity.y, 0.804, 3);
    book("v_B21x", r.relative_velocity.x, -0.195, 3);
    book("v_B21y", r.relative_velocity.y, -0.195, 3);
    book("a_B1x", r.transport_acceleration.x, -2.528, 3);
    book("a_B1y", r.transport_acceleration.y, -2.528, 3);
    book("a_B21 Coriolis x", r.coriolis.x, 1.226, 3);
    book("a_B21 Coriolis y", r.coriolis.y, -1.226, 3);
    // Printed to one decimal, −0.5 i − 0.5 j (with a_By = −4.255, the value
    // for ω = π; with ω = 3.141 the y component is −0.4994).
    book("a_B21 relative x", r.relative_acceleration.x, -0.5, 1);
    book("a_B21 relative y", r.relative_acceleration.y, -0.5, 1);
    // ω₂ = ω₁ (the block turns with the crank): ω₂₃ = ω₁ − ω₃, α₂₃ = −α₃.
    book("omega23", omega - s.qd.phi3, -0.762, 3);
    book("alpha23", -s.qdd.phi3, 2.252, 3);
    // The parts add up to the motion of B found by the analysis.
    assert!((r.velocity - v3(b.velocity.x, b.velocity.y)).norm() < 1e-12);
    assert!((r.acceleration - v3(b.acceleration.x, b.acceleration.y)).norm() < 1e-12);
}

#[test]
fn example_4_2_relative_motion_of_the_slider() {
    use kinematics_core::nalgebra::Vector3;
    use kinematics_core::rigid::{relative_motion, FrameMotion};
    // Block 2, pinned to the crank at B, slides along link 3 (turning about
    // C at the origin): B₂ = B₃ (the point of link 3 under it) + the slide
    // s', s'' along CB + Coriolis 2ω₃ × v_rel.
    let m = RRtrRrt::EXAMPLE_4_2;
    let pose = m
        .assemble(&RRtrRrt::example_4_2_guess())
        .expect("assembles");
    let omega = 4.712;
    let s = m.analyze(&pose, omega, 0.0).expect("analysis");
    let b = s.point_b();
    book("v_B2x", b.velocity.x, -0.333, 3);
    book("v_B2y", b.velocity.y, 0.333, 3);
    book("a_B2x", b.acceleration.x, -1.569, 3);
    book("a_B2y", b.acceleration.y, -1.569, 3);
    let e = v3(pose.phi3.cos(), pose.phi3.sin());
    let link3 = FrameMotion {
        angular_velocity: Vector3::z() * s.qd.phi3,
        angular_acceleration: Vector3::z() * s.qdd.phi3,
        ..FrameMotion::default()
    };
    let r = relative_motion(
        &link3,
        &v3(b.position.x, b.position.y),
        &(e * s.qd.s),
        &(e * s.qdd.s),
    );
    // ω₂ = ω₃: relative to the crank, ω₂₁ = ω₃ − ω₁ and α₂₁ = α₃.
    book("omega21", s.qd.phi3 - omega, -2.905, 3);
    book("alpha21", s.qdd.phi3, 1.020, 3);
    book("v_B3x", r.transport_velocity.x, -0.398, 3);
    book("v_B3y", r.transport_velocity.y, 0.127, 3);
    book("a_B3x", r.transport_acceleration.x, -0.456, 3);
    book("a_B3y", r.transport_acceleration.y, -0.649, 3);
    book("v_B23x", r.relative_velocity.x, 0.065, 3);
    book("v_B23y", r.relative_velocity.y, 0.205, 3);
    book("a_B23 Coriolis x", r.coriolis.x, -0.742, 3);
    book("a_B23 Coriolis y", r.coriolis.y, 0.237, 3);
    assert!((r.acceleration - v3(b.acceleration.x, b.acceleration.y)).norm() < 1e-12);
    // The relative acceleration is printed −0.5 i − 0.5 j: a copy of Example
    // 4.1's. The book's own numbers give a_B2 − a_B3 − a^c =
    // (−1.569 + 0.456 + 0.742) i + (−1.569 + 0.649 − 0.237) j
    // = −0.371 i − 1.157 j, and a slide along link 3 must be parallel to CB,
    // at φ3 = 72.2°, which (−0.5, −0.5), at 225°, is not.
    let from_printed = (-1.569f64 + 0.456 + 0.742, -1.569f64 + 0.649 - 0.237);
    book(
        "a_B23 relative x",
        r.relative_acceleration.x,
        from_printed.0,
        2,
    );
    book(
        "a_B23 relative y",
        r.relative_acceleration.y,
        from_printed.1,
        2,
    );
    assert!(r.relative_acceleration.cross(&e).norm() < 1e-12, "along CB");
    assert!((r.relative_acceleration - v3(-0.5, -0.5)).norm() > 0.5);
}
