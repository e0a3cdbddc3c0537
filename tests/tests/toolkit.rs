//! The runtime toolkit against the lecture notes' and the chapter's worked
//! answers, and round-trip property tests of the inverse problems.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use kinematics_core::mechanism;
use kinematics_core::mobility::{mobility, JointKind, Space};
use kinematics_core::nalgebra::{Complex, Matrix3, Matrix4, Vector3};
use kinematics_core::rigid::{
    angular_velocity_chain, body_point_acceleration, body_point_velocity,
    derivative_in_moving_frame, relative_motion, FrameMotion,
};
use kinematics_core::transform::{
    axis_angle, rot, rot_x, rot_y, rot_z, rotation_between, rotation_operator, screw, screw_about,
    screw_joint, screw_parameters, t6, transform_point, translation, Axis, CompositeRotation,
    Plane,
};
use kinematics_examples::RTrr;
use kinematics_tests::Rng;

fn close3(a: &Vector3<f64>, b: &Vector3<f64>, tol: f64) -> bool {
    (a - b).abs().max() <= tol
}

#[test]
fn example_3_1_rotations_about_the_coordinate_axes() {
    // Eq. 32 with û = x, y, z reduces to the printed single-axis operators.
    for t in [0.3, -1.2, 2.9] {
        let (s, c) = f64::sin_cos(t);
        let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c);
        let ry = Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c);
        let rz = Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        assert!((rot(&Vector3::x(), t).expect("axis") - rx).norm() < 1e-15);
        assert!((rot(&Vector3::y(), t).expect("axis") - ry).norm() < 1e-15);
        assert!((rot(&Vector3::z(), t).expect("axis") - rz).norm() < 1e-15);
        assert_eq!((rot_x(t), rot_y(t), rot_z(t)), (rx, ry, rz));
    }
}

#[test]
fn example_3_2_composite_rotation_about_fixed_axes() {
    // α about z, then β about y, then γ about x, all fixed axes:
    // R = R_x(γ) R_y(β) R_z(α).
    let (a, b, g) = (0.4, -0.7, 1.1);
    let r = CompositeRotation::new()
        .about_fixed(Axis::Z, a)
        .about_fixed(Axis::Y, b)
        .about_fixed(Axis::X, g)
        .matrix();
    let (sa, ca) = f64::sin_cos(a);
    let (sb, cb) = f64::sin_cos(b);
    let (sg, cg) = f64::sin_cos(g);
    // The printed closed form, entry by entry, except (2,1): see below.
    let printed = Matrix3::new(
        cb * ca,
        -cb * sa,
        sb,
        ca * sb * sg + cg * sa,
        -sa * sb * sg + cg * ca,
        -sg * cb,
        -ca * sb * cg + sg * sa,
        sa * sb * cg + sg * ca,
        cg * cb,
    );
    assert!((r - printed).norm() < 1e-15);
    // The notes print r₂₁ = cα sγ + cγ sα, without the factor sβ; with it
    // dropped the matrix is no longer orthonormal (its first column is not a
    // unit vector), so the printed entry is a slip.
    let slip = ca * sg + cg * sa;
    let column = Vector3::new(cb * ca, slip, -ca * sb * cg + sg * sa);
    assert!((column.norm() - 1.0).abs() > 1e-2);
    // Rotations about the mobile axes compose in the reverse order.
    let mobile = CompositeRotation::new()
        .about_mobile(Axis::X, g)
        .about_mobile(Axis::Y, b)
        .about_mobile(Axis::Z, a)
        .matrix();
    assert!((mobile - r).norm() < 1e-15);
}

#[test]
fn example_3_3_translation() {
    let p = transform_point(
        &translation(&Vector3::new(-1.0, -2.0, 2.0)),
        &Vector3::new(1.0, 4.0, 2.0),
    );
    assert_eq!(p, Vector3::new(0.0, 2.0, 4.0));
}

#[test]
fn example_3_5_screw_through_the_origin() {
    let u = Vector3::new(0.0, FRAC_PI_4.cos(), FRAC_PI_4.cos());
    let s = screw(&u, FRAC_PI_4, 2f64.sqrt()).expect("screw");
    // The printed rotation part, to its three decimals.
    let printed = Matrix3::new(
        0.707, -0.500, 0.500, 0.500, 0.854, 0.146, -0.500, 0.146, 0.854,
    );
    let r: Matrix3<f64> = s.fixed_view::<3, 3>(0, 0).into();
    assert!((r - printed).abs().max() < 5e-4);
    // D = (0, 1, 1).
    assert!(close3(
        &s.fixed_view::<3, 1>(0, 3).into(),
        &Vector3::new(0.0, 1.0, 1.0),
        1e-15
    ));
    // The statement gives P₁ = (0, 1, 3), but the printed computation
    // multiplies (0, 1, 2); the printed answer (0.5, 2.146, 2.854) is that of
    // (0, 1, 2).
    let p2 = transform_point(&s, &Vector3::new(0.0, 1.0, 2.0));
    assert!(close3(&p2, &Vector3::new(0.5, 2.146, 2.854), 5e-4));
    let p3 = transform_point(&s, &Vector3::new(0.0, 1.0, 3.0));
    assert!(!close3(&p3, &Vector3::new(0.5, 2.146, 2.854), 0.1));
}

/// The printed screw matrix of Example 3.6, rounded to three decimals (two
/// for the translation column).
fn example_3_6_matrix() -> Matrix4<f64> {
    Matrix4::new(
        -0.748, 0.263, 0.612, -3.17, 0.608, -0.093, 0.788, 5.99, 0.263, 0.963, -0.092, 4.94, 0.0,
        0.0, 0.0, 1.0,
    )
}

#[test]
fn example_3_6_screw_parameters_within_the_rounding_of_the_printed_matrix() {
    let s = screw_parameters(&example_3_6_matrix()).expect("a screw");
    let at_yz = s.intersection(Plane::YZ).expect("crosses x = 0");
    // What the rounding of the printed entries can explain: perturb every
    // entry within half a unit of its last printed decimal and record the
    // range of each extracted quantity.
    let mut rng = Rng::new(36);
    let (mut lo, mut hi) = ([f64::INFINITY; 6], [f64::NEG_INFINITY; 6]);
    for _ in 0..4000 {
        let mut m = example_3_6_matrix();
        for i in 0..3 {
            for j in 0..3 {
                m[(i, j)] += rng.range(-5e-4, 5e-4);
            }
            m[(i, 3)] += rng.range(-5e-3, 5e-3);
        }
        let p = screw_parameters(&m).expect("a screw");
        let q = p.intersection(Plane::YZ).expect("crosses x = 0");
        let v = [
            p.angle.to_degrees(),
            p.axis.x,
            p.axis.y,
            p.axis.z,
            p.translation,
            q.y.max(q.z),
        ];
        for k in 0..6 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    let within = |k: usize, printed: f64, own_rounding: f64| {
        printed + own_rounding >= lo[k] && printed - own_rounding <= hi[k]
    };
    // θ ≈ 165° (printed to the degree), û ≈ (1/3, 2/3, 2/3): confirmed.
    assert!((s.angle.to_degrees() - 165.0).abs() < 0.5);
    assert!(within(0, 165.0, 0.5));
    assert!(within(1, 1.0 / 3.0, 5e-4) && within(2, 2.0 / 3.0, 5e-4) && within(3, 2.0 / 3.0, 5e-4));
    // The axis crosses the yz plane at about (0, 6, 6): confirmed.
    assert!(at_yz.x.abs() < 1e-12 && (at_yz.y - 6.0).abs() < 0.05 && (at_yz.z - 6.0).abs() < 0.1);
    // Δ: the printed 6.25 lies outside what the rounding explains (Δ = û·d
    // ranges over about 6.21 to 6.24; 6.23 from the printed matrix itself).
    println!("Δ = {}, rounding range {}..{}", s.translation, lo[4], hi[4]);
    assert!((s.translation - 6.23).abs() < 0.01, "Δ = {}", s.translation);
    assert!(!within(4, 6.25, 5e-3), "Δ range {}..{}", lo[4], hi[4]);
}

#[test]
fn example_3_6_rectangle_rotated_about_line_ef() {
    // E = (0, 2, 2) and EF along (1, 2, 4) (the notes' translation by
    // (0, −2, −2) and the direction numbers a = 1, b = 2, c = 4); a rotation
    // of 30° about EF, positive by the right-hand rule along E → F.
    let e = Vector3::new(0.0, 2.0, 2.0);
    let dir = Vector3::new(1.0, 2.0, 4.0);
    let f = e + dir;
    let m = screw_about(&dir, &e, PI / 6.0, 0.0).expect("axis");
    let u = dir.normalize();
    let corners = [
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(2.0, 0.0, 0.0),
        Vector3::new(2.0, 2.0, 0.0),
        Vector3::new(0.0, 2.0, 0.0),
    ];
    // Independent checks of a rotation by 30° about EF: E and F stay, each
    // corner keeps its foot on the axis and its distance to it, and its
    // radial vector turns by +30° about û.
    assert!(
        close3(&transform_point(&m, &e), &e, 1e-14) && close3(&transform_point(&m, &f), &f, 1e-14)
    );
    for p in corners {
        let q = transform_point(&m, &p);
        let (rp, rq) = (p - e - u * u.dot(&(p - e)), q - e - u * u.dot(&(q - e)));
        assert!((u.dot(&(p - e)) - u.dot(&(q - e))).abs() < 1e-14);
        assert!((rp.norm() - rq.norm()).abs() < 1e-14);
        let angle = rp.cross(&rq).dot(&u).atan2(rp.dot(&rq));
        assert!((angle - PI / 6.0).abs() < 1e-12);
    }
    // The notes' concatenated matrix (row-vector form) is not a rotation
    // about EF: it keeps E but moves F by more than a unit, because its
    // second alignment rotation turns the axis away from z instead of onto
    // it. Its printed corner coordinates are therefore not used here.
    let printed = Matrix4::new(
        0.9312, 0.1634, -0.3256, 0.0, -0.1743, 0.9846, -0.0044, 0.0, 0.3199, 0.0609, 0.9454, 0.0,
        -0.2913, -0.0909, 0.1179, 1.0,
    )
    .transpose();
    assert!(close3(&transform_point(&printed, &e), &e, 1e-3));
    assert!((transform_point(&printed, &f) - f).norm() > 1.0);
}

#[test]
fn tutorial_question_1_complex_rotation() {
    // A₁ = 0.707 + 0.707i turned by θ₁₂ = 165°: θ₁ = 45°, θ₂ = 210°.
    let a1 = Complex::new(0.707, 0.707);
    let a2 = rotation_operator(165f64.to_radians()) * a1;
    assert!((a1.arg().to_degrees() - 45.0).abs() < 1e-12);
    assert!(
        (a2.arg().to_degrees() - -150.0).abs() < 1e-9,
        "θ₂ = 210° = −150°"
    );
    let r = 0.707 * 2f64.sqrt();
    assert!(
        (a2 - Complex::new(
            r * (-150f64).to_radians().cos(),
            r * (-150f64).to_radians().sin()
        ))
        .norm()
            < 1e-12
    );
    let back = rotation_between(a1, a2).expect("non-zero");
    assert!((back.arg().to_degrees() - 165.0).abs() < 1e-9);
    assert!(rotation_between(Complex::new(0.0, 0.0), a2).is_err());
}

#[test]
fn tutorial_question_2_screw_joint() {
    // Pʲ = (0, 2, 0), θ = 180°, A = 2, B = −3, C = 2, lead k = 0.125: the
    // point turns to (0, −2, 0), then is offset by (2, −3, 2 + k·π/2π).
    let p = transform_point(&t6(2.0, -3.0, 2.0, PI, 0.125), &Vector3::new(0.0, 2.0, 0.0));
    assert!(close3(&p, &Vector3::new(2.0, -5.0, 2.0625), 1e-14));
    let joint = screw_joint(Axis::Z, &Vector3::new(2.0, -3.0, 2.0), PI, 0.125);
    assert!((joint - t6(2.0, -3.0, 2.0, PI, 0.125)).norm() < 1e-15);
}

mechanism! {
    /// Two sliders joined by a rigid link: A on the x axis, B on the y axis.
    pub struct TwoSliders {
        params {
            /// Link length AB (m).
            l
        }
        drivers {
            /// Position of slider A on the x axis (m).
            x_a
        }
        unknowns {
            /// Angle of AB (rad).
            th,
            /// Position of slider B on the y axis (m).
            y_b
        }
        points {
            /// Slider B.
            B = vec2(0.0, y_b);
        }
        loops { vec2(x_a, 0.0) + polar(l, th) == vec2(0.0, y_b); }
    }
}

#[test]
fn example_7_1_two_sliders() {
    // AB = 450 mm at θ = 30° from the slot: r_B/A = (−0.39, 0.225) m.
    let m = TwoSliders { l: 0.45 };
    let pose = m
        .assemble(&TwoSlidersCoords {
            x_a: 0.45 * 30f64.to_radians().cos(),
            th: 2.5,
            y_b: 0.2,
        })
        .expect("assembles");
    let s = m.analyze(&pose, 0.6, 1.2).expect("analysis");
    // ω = 2.67 rad/s, v_B = 1.04 m/s down, α = 17.69 rad/s², a_B = 8.5 m/s² down.
    assert!((s.qd.th - 2.67).abs() < 5e-3, "ω = {}", s.qd.th);
    assert!((s.qd.y_b - -1.04).abs() < 5e-3, "v_B = {}", s.qd.y_b);
    assert!((s.qdd.th - 17.69).abs() < 5e-2, "α = {}", s.qdd.th);
    assert!((s.qdd.y_b - -8.5).abs() < 5e-2, "a_B = {}", s.qdd.y_b);
    // The same from the rigid-body relations v_B = v_A + ω × r and
    // a_B = a_A + α × r + ω × (ω × r).
    let r = Vector3::new(-0.45 * 30f64.to_radians().cos(), 0.45 * 0.5, 0.0);
    let w = Vector3::new(0.0, 0.0, s.qd.th);
    let al = Vector3::new(0.0, 0.0, s.qdd.th);
    let vb = body_point_velocity(&Vector3::new(0.6, 0.0, 0.0), &w, &r);
    let ab = body_point_acceleration(&Vector3::new(1.2, 0.0, 0.0), &al, &w, &r);
    assert!(close3(&vb, &Vector3::new(0.0, s.qd.y_b, 0.0), 1e-12));
    assert!(close3(&ab, &Vector3::new(0.0, s.qdd.y_b, 0.0), 1e-12));
}

#[test]
fn example_7_4_satellite_dish() {
    // ω₁ = 6k (ω̇₁ = 3k) about the fixed z axis; ω₂ = 2i (ω̇₂ = 1.5i relative
    // to the turning frame); horn at 1.4 m, θ = 25°.
    let (w1, w2) = (Vector3::new(0.0, 0.0, 6.0), Vector3::new(2.0, 0.0, 0.0));
    let w = angular_velocity_chain(&[w1, w2]);
    let alpha = derivative_in_moving_frame(&Vector3::new(0.0, 0.0, 3.0), &Vector3::zeros(), &w1)
        + derivative_in_moving_frame(&Vector3::new(1.5, 0.0, 0.0), &w1, &w2);
    assert_eq!(alpha, Vector3::new(1.5, 12.0, 3.0));
    let t = 25f64.to_radians();
    let r = Vector3::new(0.0, 1.4 * t.cos(), 1.4 * t.sin());
    let v = body_point_velocity(&Vector3::zeros(), &w, &r);
    let a = body_point_acceleration(&Vector3::zeros(), &alpha, &w, &r);
    // Printed: v_A = (−7.6, −1.18, 2.54) m/s, a_A = (10.4, −51.6, −0.46) m/s².
    assert!(close3(&v, &Vector3::new(-7.6, -1.18, 2.54), 0.05), "{v:?}");
    assert!(close3(&a, &Vector3::new(10.4, -51.6, -0.46), 0.05), "{a:?}");
}

#[test]
fn chapter_example_4_1_coriolis_decomposition() {
    // Slider 2 moves along link 1 (turning at ω₁ = 3.141 rad/s): its
    // velocity relative to link 1 is v_B2 − v_B1, and the Coriolis term is
    // 2ω₁ × v_rel = 1.226i − 1.226j m/s².
    let m = RTrr::EXAMPLE_4_1;
    let pose = m.assemble(&RTrr::example_4_1_guess()).expect("assembles");
    #[allow(clippy::approx_constant)] // the book's rounded value
    let w1 = 3.141;
    let s = m.analyze(&pose, w1, 0.0).expect("analysis");
    let b = s.point_b();
    let r_ab = Vector3::new(b.position.x, b.position.y, 0.0);
    let link1 = FrameMotion {
        angular_velocity: Vector3::new(0.0, 0.0, w1),
        ..Default::default()
    };
    // On link 1, B moves with the slide rate s' along the crank direction.
    let e = r_ab.normalize();
    let v_rel = e * s.qd.s;
    let a_rel = e * s.qdd.s;
    let motion = relative_motion(&link1, &r_ab, &v_rel, &a_rel);
    assert!(
        close3(&motion.coriolis, &Vector3::new(1.226, -1.226, 0.0), 1e-3),
        "{:?}",
        motion.coriolis
    );
    // The parts add up to the absolute motion found by the analysis.
    let v_b = Vector3::new(b.velocity.x, b.velocity.y, 0.0);
    let a_b = Vector3::new(b.acceleration.x, b.acceleration.y, 0.0);
    assert!(close3(&motion.velocity, &v_b, 1e-12) && close3(&motion.acceleration, &a_b, 1e-12));
    // The book's transport terms: v_B1 = −0.804i + 0.804j, a_B1 = −2.528(i + j),
    // and the relative acceleration −0.5i − 0.5j.
    assert!(close3(
        &motion.transport_velocity,
        &Vector3::new(-0.804, 0.804, 0.0),
        1e-3
    ));
    assert!(close3(
        &motion.transport_acceleration,
        &Vector3::new(-2.528, -2.528, 0.0),
        1e-3
    ));
    assert!(close3(
        &motion.relative_acceleration,
        &Vector3::new(-0.5, -0.5, 0.0),
        1e-3
    ));
}

#[test]
fn mobility_of_the_slider_crank_and_the_swash_plate() {
    use JointKind::{P, R, S};
    let slider_crank = mobility(Space::Planar, 4, &[R, R, R, P]);
    assert_eq!((slider_crank.freedom, slider_crank.loops), (1, 1));
    // Swash plate (notes' Example 1.1): n = j = 4, Σf = 1 + 3 + 3 + 1, λ = 6.
    let swash = mobility(Space::Spatial, 4, &[R, S, S, R]).with_passive(
        "spin of link 3 about the axis through the sphere centre normal to the plate",
        1,
    );
    assert_eq!((swash.freedom, swash.effective(), swash.loops), (2, 1, 1));
    let report = swash.to_string();
    assert!(
        report.contains("F = 6(4 − 4 − 1) + 8 = 2") && report.contains("1 passive"),
        "{report}"
    );
}

#[test]
fn axis_angle_round_trip() {
    let mut rng = Rng::new(0xA715);
    for k in 0..20_000 {
        let axis = rng.vector3(-1.0, 1.0);
        if axis.norm() < 1e-3 {
            continue;
        }
        // Cover the whole range, with extra samples near 0 and π.
        let angle = match k % 4 {
            0 => rng.range(0.0, 1e-6),
            1 => PI - rng.range(0.0, 1e-6),
            _ => rng.range(0.0, PI),
        };
        let r = rot(&axis, angle).expect("axis");
        let aa = axis_angle(&r).expect("a rotation");
        assert!((aa.angle - angle).abs() < 1e-12, "θ {angle} → {}", aa.angle);
        // θû identifies the rotation (û is undefined at θ = 0, and ±û
        // coincide at θ = π).
        let want = axis.normalize() * angle;
        let got = aa.axis.into_inner() * aa.angle;
        let ok = (got - want).norm() < 1e-12 || (PI - angle < 1e-6 && (got + want).norm() < 1e-12);
        assert!(ok, "θû {want:?} → {got:?}");
        assert!((rot(&aa.axis, aa.angle).expect("axis") - r).norm() < 1e-12);
    }
}

#[test]
fn screw_parameters_round_trip() {
    let mut rng = Rng::new(0x5C2E);
    for _ in 0..20_000 {
        let axis = rng.vector3(-1.0, 1.0);
        if axis.norm() < 1e-3 {
            continue;
        }
        let u = axis.normalize();
        let p = rng.vector3(-5.0, 5.0);
        let nearest = p - u * u.dot(&p);
        let (angle, delta) = (rng.range(0.01, PI - 0.01), rng.range(-5.0, 5.0));
        let t = screw_about(&axis, &p, angle, delta).expect("axis");
        let s = screw_parameters(&t).expect("a screw");
        assert!((s.angle - angle).abs() < 1e-12);
        assert!((s.axis.into_inner() - u).norm() < 1e-12);
        assert!((s.translation - delta).abs() < 1e-12);
        assert!(
            (s.point - nearest).norm() < 1e-12 * (1.0 + nearest.norm()),
            "{:?} vs {nearest:?}",
            s.point
        );
        let back = screw_about(&s.axis, &s.point, s.angle, s.translation).expect("axis");
        assert!((back - t).norm() < 1e-12);
    }
}

#[test]
fn degenerate_inputs_are_errors() {
    assert!(rot(&Vector3::zeros(), 1.0).is_err());
    assert!(screw(&Vector3::new(f64::NAN, 0.0, 0.0), 1.0, 0.0).is_err());
    // A reflection is not a rotation.
    assert!(axis_angle(&Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0))).is_err());
    // A pure translation has its axis along the translation.
    let s = screw_parameters(&translation(&Vector3::new(0.0, 3.0, 4.0))).expect("a screw");
    assert_eq!((s.angle, s.translation), (0.0, 5.0));
    // An axis parallel to the plane never crosses it.
    let s = screw_parameters(&screw(&Vector3::y(), 1.0, 0.0).expect("axis")).expect("a screw");
    assert!(s.intersection(Plane::XZ).is_ok() && s.intersection(Plane::YZ).is_err());
    let _ = FRAC_PI_2;
}

/// Every toolkit function that returns a `Result` rejects a NaN or an
/// infinity in any of its inputs with a clear error, and never returns a
/// value holding one. (Before, `screw_parameters` of a NaN or infinite
/// translation, and `rot`, `screw`, `screw_about`, `rotation_between`,
/// `no_spin_angular_velocity` with a NaN argument returned `Ok` with NaN.)
#[test]
fn every_result_function_rejects_non_finite_inputs() {
    use kinematics_core::nalgebra::Complex;
    use kinematics_core::rigid::{
        angular_velocity_from_vectors, no_spin_angular_acceleration, no_spin_angular_velocity,
    };
    use kinematics_core::transform::{rotation_between, screw_about, Screw};
    use kinematics_core::Error;
    fn rejected<T: std::fmt::Debug>(what: &str, r: Result<T, Error>) {
        match r {
            Err(Error::InvalidGeometry { detail, .. }) => assert!(!detail.is_empty(), "{what}"),
            other => panic!("{what}: {other:?}"),
        }
    }
    let axis = Vector3::new(1.0, 2.0, 2.0);
    let p = Vector3::new(0.0, 6.0, 6.0);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let v = Vector3::new(0.3, bad, 1.0);
        rejected("rot θ", rot(&axis, bad));
        rejected("rot axis", rot(&v, 1.0));
        rejected("screw θ", screw(&axis, bad, 1.0));
        rejected("screw Δ", screw(&axis, 1.0, bad));
        rejected("screw axis", screw(&v, 1.0, 1.0));
        rejected("screw_about point", screw_about(&axis, &v, 1.0, 1.0));
        rejected("screw_about θ", screw_about(&axis, &p, bad, 1.0));
        rejected("screw_about Δ", screw_about(&axis, &p, 1.0, bad));
        rejected("screw_about axis", screw_about(&v, &p, 1.0, 1.0));
        rejected(
            "screw_parameters translation",
            screw_parameters(&translation(&v)),
        );
        rejected(
            "screw_parameters translation(∞, 0, 0)",
            screw_parameters(&translation(&Vector3::new(bad, 0.0, 0.0))),
        );
        let mut r = Matrix3::identity();
        r[(1, 2)] = bad;
        rejected("axis_angle", axis_angle(&r));
        let s = Screw {
            axis: Vector3::z_axis(),
            angle: 1.0,
            translation: 0.0,
            point: v,
        };
        rejected("Screw::intersection", s.intersection(Plane::XY));
        rejected(
            "rotation_between A₂",
            rotation_between(Complex::new(1.0, 0.0), Complex::new(bad, 0.0)),
        );
        rejected(
            "rotation_between A₁",
            rotation_between(Complex::new(bad, 0.0), Complex::new(1.0, 0.0)),
        );
        let b = Vector3::new(0.0, 0.0, 2.0);
        rejected(
            "no_spin_angular_velocity v",
            no_spin_angular_velocity(&b, &v),
        );
        rejected(
            "no_spin_angular_velocity b",
            no_spin_angular_velocity(&v, &b),
        );
        rejected(
            "no_spin_angular_acceleration a",
            no_spin_angular_acceleration(&b, &v),
        );
        let (a1, b1) = (Vector3::x(), Vector3::y());
        for (i, args) in [
            [v, b1, a1, a1],
            [a1, v, a1, a1],
            [a1, b1, v, a1],
            [a1, b1, a1, v],
        ]
        .iter()
        .enumerate()
        {
            rejected(
                &format!("angular_velocity_from_vectors argument {i}"),
                angular_velocity_from_vectors(&args[0], &args[1], &args[2], &args[3]),
            );
        }
    }
}

/// An axis is normalised after scaling by its largest component: tiny and
/// huge axes are valid (their norm underflowed or overflowed before).
#[test]
fn axes_of_any_finite_size_are_normalised() {
    for k in [1e-200, 1e-300, 1e200, 1e300] {
        let r = rot(&Vector3::new(k, 0.0, 0.0), 0.7).expect("a valid axis");
        assert!(
            (r - kinematics_core::transform::rot_x(0.7)).norm() < 1e-15,
            "{k:e}"
        );
        let s = screw(&Vector3::new(0.0, k, k), 0.7, 1.0).expect("a valid axis");
        let d = s.fixed_view::<3, 1>(0, 3).into_owned();
        let u = Vector3::new(0.0, 1.0, 1.0) / 2f64.sqrt();
        assert!((d - u).norm() < 1e-15, "{k:e}");
    }
}
