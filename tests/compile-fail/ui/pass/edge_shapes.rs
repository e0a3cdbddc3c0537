use kinematics_core::mechanism;

mechanism! {
    /// Open chain: drivers and points, no unknowns.
    pub struct TwoLinkArm {
        params   { l1, l2 }
        drivers  { q1, q2 }
        unknowns { }
        points {
            E = polar(l1, q1);
            T = E + polar(l2, q1 + q2);
        }
    }
}

mechanism! {
    /// No drivers: a structure whose shape is solved for.
    pub struct Triangle {
        params   { a, b, c }
        drivers  { }
        unknowns { x, y }
        constraints {
            powi(x, 2) + powi(y, 2) == powi(b, 2);
            powi(x - c, 2) + powi(y, 2) == powi(a, 2);
        }
    }
}

mechanism! {
    /// Raw identifiers, a driver deliberately unused, consistent joints.
    pub struct r#Odd {
        params   { r#type, b, c, d }
        drivers  { phi, #[allow(unused)] spare }
        unknowns { r#th3, th4 }
        points { r#B = polar(r#type, phi); }
        loops { r#B + polar(b, r#th3) == vec2(d, 0.0) + polar(c, th4); }
        joints { R: 4, passive: 0 }
    }
}

mechanism! {
    /// Two drivers, five revolutes: F = 3(5 − 5 − 1) + 5 = 2.
    pub struct FiveBar {
        params { a, b, c, d, e }
        drivers  { phi1, phi2 }
        unknowns { th2, th3 }
        loops { polar(a, phi1) + polar(b, th2) == vec2(e, 0.0) + polar(d, phi2) + polar(c, th3); }
        joints { links: 5, R: 5 }
    }
}

fn main() {
    let arm = TwoLinkArm { l1: 1.0, l2: 1.0 };
    let pose = arm.assemble(&TwoLinkArmCoords { q1: 0.0, q2: std::f64::consts::FRAC_PI_2 }).unwrap();
    let m = arm.analyze(&pose, [1.0, 0.0], [0.0, 0.0]).unwrap();
    // Tip at (1, 1) turning about the origin at 1 rad/s: v = (−1, 1).
    assert!((m.point_t().velocity.x + 1.0).abs() < 1e-12 && (m.point_t().velocity.y - 1.0).abs() < 1e-12);

    let t = Triangle { a: 4.0, b: 3.0, c: 5.0 };
    let p = t.assemble(&TriangleCoords { x: 1.0, y: 2.0 }).unwrap();
    assert!((p.x - 1.8).abs() < 1e-12 && (p.y - 2.4).abs() < 1e-12);
    assert!(t.analyze(&p, [], []).is_ok());

    let o = Odd { r#type: 0.04, b: 0.12, c: 0.10, d: 0.11 };
    let p = o.assemble(&OddCoords { phi: 0.0, spare: 0.0, r#th3: 1.0, th4: 1.6 }).unwrap();
    assert!(o.analyze(&p, [10.0, 0.0], [0.0, 0.0]).unwrap().point_b().speed() > 0.0);

    let _ = FiveBar { a: 1.0, b: 2.0, c: 2.0, d: 1.0, e: 1.5 };
}
