//! Driving efforts against the exact closed form of a slider-crank's gas torque and Newton–Euler solves of an engine and a four-bar with gravity.

use super::*;
#[allow(unused_imports)]
use super::{descriptions::*, energy::*, reactions::*, sections::*};

mechanism! {
    /// A slider-crank engine: crank a, rod b, the rod's centre of mass at
    /// r3 from the crank pin, the crank's at half its length, the piston
    /// at C on the x axis.
    pub struct Engine {
        params   { a, b, r3 }
        drivers  { phi }
        unknowns { th, x }
        points {
            G2 = polar(a / 2.0, phi);
            B = polar(a, phi);
            G3 = polar(a, phi) + polar(r3, th);
            C = vec2(x, 0.0);
            O = vec2(0.0, 0.0);
        }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
    }
}

pub(crate) const A: f64 = 0.05;
pub(crate) const B: f64 = 0.2;
pub(crate) const R3: f64 = 0.07;
pub(crate) const M2: f64 = 1.1;
pub(crate) const J2: f64 = 4e-4;
pub(crate) const M3: f64 = 0.6;
pub(crate) const J3: f64 = 2.5e-3;
pub(crate) const M4: f64 = 0.45;
pub(crate) const G: f64 = 9.81;

pub(crate) fn close(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * (1.0 + b.abs()),
        "{what}: {a} against {b} (difference {:.2e})",
        (a - b).abs()
    );
}

/// The engine's motion at φ with rate ω and acceleration α, assembled on
/// the branch with the piston at x > 0.
pub(crate) fn engine_motion(m: &Engine, phi: f64, w: f64, al: f64) -> EngineMotion {
    let th = (-(A / B) * phi.sin()).asin();
    let guess = EngineCoords {
        phi,
        th,
        x: A * phi.cos() + B * th.cos(),
    };
    let pose = m.assemble(&guess).expect("assembles");
    m.analyze(&pose, w, al).expect("analyses")
}

/// With massless links and a gas force P on the piston toward the crank,
/// the crank torque is the exact textbook expression
/// T = −P a sin φ (1 + a cos φ / √(b² − a² sin² φ)), from the virtual work
/// T δφ = P δx with x = a cos φ + √(b² − a² sin² φ).
#[test]
fn the_gas_torque_of_a_slider_crank_is_the_exact_closed_form() -> Result<(), Error> {
    let m = Engine { a: A, b: B, r3: R3 };
    let p = 1800.0;
    let dynamics = Dynamics::builder()
        .force("C", move |_| [-p, 0.0, 0.0])
        .build::<Engine>()?;
    for k in 0..72 {
        let phi = TAU * f64::from(k) / 72.0 + 0.01;
        let motion = engine_motion(&m, phi, 120.0, 0.0);
        let forces = dynamics.inverse(&m, &motion)?;
        let (s, c) = phi.sin_cos();
        let exact = -p * A * s * (1.0 + A * c / (B * B - A * A * s * s).sqrt());
        close(forces.effort.phi, exact, 1e-12, "gas torque");
        assert_eq!((forces.effort.th, forces.effort.x), (0.0, 0.0));
        assert_eq!(forces.kinetic_energy, 0.0);
    }
    Ok(())
}

/// A force on the piston's coordinate x is the same load as the force at
/// C along x: with massless links, the exact gas torque again; and a
/// torque τ on the rocker of a massless four-bar needs, by virtual work,
/// the driver's effort −τ θ4'/φ' (the rates from the analysis).
#[test]
fn forces_on_coordinates_and_torques_on_bodies_do_virtual_work() -> Result<(), Error> {
    let m = Engine { a: A, b: B, r3: R3 };
    let p = 900.0;
    let on_x = Dynamics::builder()
        .coordinate_force("x", move |_| -p)
        .build::<Engine>()?;
    for k in 0..12 {
        let phi = TAU * f64::from(k) / 12.0 + 0.1;
        let motion = engine_motion(&m, phi, 50.0, 0.0);
        let (s, c) = phi.sin_cos();
        let exact = -p * A * s * (1.0 + A * c / (B * B - A * A * s * s).sqrt());
        close(
            on_x.inverse(&m, &motion)?.effort.phi,
            exact,
            1e-12,
            "force on x",
        );
    }
    let tau = 3.5;
    let massless = Dynamics::builder()
        .body(Body::new("rocker", 0.0).center("G4").angle("th4"))
        .torque("rocker", move |_| [0.0, 0.0, tau])
        .build::<MassFourBar>()?;
    let four_bar = FOUR_BAR;
    let mut pose = four_bar_start(&four_bar)?;
    for k in 0..12 {
        pose.phi = TAU * f64::from(k) / 12.0;
        let motion = four_bar.step(&pose, 7.0, 0.0)?;
        pose = motion.q;
        let effort = massless.inverse(&four_bar, &motion)?.effort.phi;
        close(
            effort,
            -tau * motion.qd.th4 / 7.0,
            1e-12,
            "torque on the rocker",
        );
    }
    Ok(())
}

/// The engine's definition as text, for the same model compiled at run
/// time.
pub(crate) const ENGINE_TEXT: &str =
    "struct Engine { params { a, b, r3 } drivers { phi } unknowns { th, x }
         points { G2 = polar(a / 2.0, phi); B = polar(a, phi); G3 = polar(a, phi) + polar(r3, th);
                  C = vec2(x, 0.0); O = vec2(0.0, 0.0); }
         loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); } }";

/// The engine's kinematics in closed form (independent of the library):
/// θ, x and the accelerations of G2, B, G3 and C, with θ', θ''.
pub(crate) struct EngineKinematics {
    pub(crate) th: f64,
    pub(crate) thdd: f64,
    pub(crate) x: f64,
    pub(crate) a_g2: [f64; 2],
    pub(crate) a_g3: [f64; 2],
    pub(crate) a_c: f64,
}

pub(crate) fn engine_kinematics(phi: f64, w: f64, al: f64) -> EngineKinematics {
    let (s, c) = phi.sin_cos();
    let sth = -A * s / B;
    let cth = (1.0 - sth * sth).sqrt();
    let th = sth.atan2(cth);
    // b cos θ θ' = −a cos φ ω; b cos θ θ'' − b sin θ θ'² = a sin φ ω² − a cos φ α.
    let thd = -A * c * w / (B * cth);
    let thdd = (A * s * w * w - A * c * al + B * sth * thd * thd) / (B * cth);
    let x = A * c + B * cth;
    let xdd = -A * c * w * w - A * s * al - B * cth * thd * thd - B * sth * thdd;
    let a_b = [A * (-c * w * w - s * al), A * (-s * w * w + c * al)];
    let a_g2 = [a_b[0] / 2.0, a_b[1] / 2.0];
    let a_g3 = [
        a_b[0] + R3 * (-cth * thd * thd - sth * thdd),
        a_b[1] + R3 * (-sth * thd * thd + cth * thdd),
    ];
    EngineKinematics {
        th,
        thdd,
        x,
        a_g2,
        a_g3,
        a_c: xdd,
    }
}

/// The planar cross product r × F (its z component).
pub(crate) fn cross(r: [f64; 2], f: [f64; 2]) -> f64 {
    r[0] * f[1] - r[1] * f[0]
}

/// Newton–Euler for the engine with gravity −g ŷ and the gas force −P x̂
/// on the piston: unknowns F12 (ground on crank at O), F32 (rod on crank at
/// B), F43 (piston on rod at C), N (wall on piston, along y) and the motor
/// torque T; eight equations: the crank's and the rod's forces and moments
/// about their centres of mass, the piston's forces. Returns the unknowns
/// in that order.
pub(crate) fn engine_newton_euler(phi: f64, w: f64, al: f64, p: f64) -> DVector<f64> {
    let k = engine_kinematics(phi, w, al);
    let (s, c) = phi.sin_cos();
    let b = [A * c, A * s];
    let g2 = [A * c / 2.0, A * s / 2.0];
    let g3 = [b[0] + R3 * k.th.cos(), b[1] + R3 * k.th.sin()];
    let cpt = [k.x, 0.0];
    // Columns: F12x F12y F32x F32y F43x F43y N T.
    let mut a = DMatrix::<f64>::zeros(8, 8);
    let mut rhs = DVector::<f64>::zeros(8);
    // Crank: F12 + F32 + m2 g = m2 a_G2; T + (O − G2) × F12 + (B − G2) × F32 = J2 α.
    a[(0, 0)] = 1.0;
    a[(0, 2)] = 1.0;
    rhs[0] = M2 * k.a_g2[0];
    a[(1, 1)] = 1.0;
    a[(1, 3)] = 1.0;
    rhs[1] = M2 * k.a_g2[1] + M2 * G;
    let (ro, rb) = ([-g2[0], -g2[1]], [b[0] - g2[0], b[1] - g2[1]]);
    a[(2, 0)] = -ro[1];
    a[(2, 1)] = ro[0];
    a[(2, 2)] = -rb[1];
    a[(2, 3)] = rb[0];
    a[(2, 7)] = 1.0;
    rhs[2] = J2 * al;
    // Rod: −F32 + F43 + m3 g = m3 a_G3; (B − G3) × (−F32) + (C − G3) × F43 = J3 θ''.
    a[(3, 2)] = -1.0;
    a[(3, 4)] = 1.0;
    rhs[3] = M3 * k.a_g3[0];
    a[(4, 3)] = -1.0;
    a[(4, 5)] = 1.0;
    rhs[4] = M3 * k.a_g3[1] + M3 * G;
    let (rb3, rc3) = (
        [b[0] - g3[0], b[1] - g3[1]],
        [cpt[0] - g3[0], cpt[1] - g3[1]],
    );
    a[(5, 2)] = rb3[1];
    a[(5, 3)] = -rb3[0];
    a[(5, 4)] = -rc3[1];
    a[(5, 5)] = rc3[0];
    rhs[5] = J3 * k.thdd;
    // Piston: −F43 + N ŷ + m4 g − P x̂ = m4 a_C.
    a[(6, 4)] = -1.0;
    rhs[6] = M4 * k.a_c + p;
    a[(7, 5)] = -1.0;
    a[(7, 6)] = 1.0;
    rhs[7] = M4 * G;
    a.lu()
        .solve(&rhs)
        .expect("the Newton–Euler system is regular")
}

/// The engine with crank, rod and piston masses, gravity and a gas force
/// that depends on the piston's position, at a crank speed that varies
/// (α ≠ 0): the crank torque against the Newton–Euler solve.
#[test]
fn an_engines_crank_torque_is_the_newton_euler_one() -> Result<(), Error> {
    let m = Engine { a: A, b: B, r3: R3 };
    // Gas pressure force falling with the volume: P = 2000 (0.3 / x)².
    let gas = |x: f64| 2000.0 * (0.3 / x).powi(2);
    let dynamics = Dynamics::builder()
        .body(Body::new("crank", M2).center("G2").angle("phi").inertia(J2))
        .body(Body::new("rod", M3).center("G3").angle("th").inertia(J3))
        .body(Body::new("piston", M4).center("C"))
        .gravity([0.0, -G, 0.0])
        .force("C", move |s| [-gas(s.position.x), 0.0, 0.0])
        .build::<Engine>()?;
    for k in 0..90 {
        let phi = TAU * f64::from(k) / 90.0 + 0.003;
        let (w, al) = (150.0 + 30.0 * phi.sin(), -800.0 * phi.cos());
        let motion = engine_motion(&m, phi, w, al);
        let forces = dynamics.inverse(&m, &motion)?;
        let x = engine_kinematics(phi, w, al).x;
        let expected = engine_newton_euler(phi, w, al, gas(x))[7];
        close(forces.effort.phi, expected, 1e-10, "crank torque");
        // The shaking force is −Σ m a_G.
        let kin = engine_kinematics(phi, w, al);
        let fx = -(M2 * kin.a_g2[0] + M3 * kin.a_g3[0] + M4 * kin.a_c);
        let fy = -(M2 * kin.a_g2[1] + M3 * kin.a_g3[1]);
        close(forces.shaking_force.x, fx, 1e-10, "shaking force x");
        close(forces.shaking_force.y, fy, 1e-10, "shaking force y");
        close(forces.power, forces.effort.phi * w, 1e-14, "power");
    }
    Ok(())
}

mechanism! {
    /// A four-bar with the centres of mass of its three moving links.
    pub struct MassFourBar {
        params   { a, b, c, d, g3x, g3y }
        drivers  { phi }
        unknowns { th3, th4 }
        points {
            G2 = polar(a / 2.0, phi);
            G3 = polar(a, phi) + polar(g3x, th3) + polar(g3y, th3 + 1.5707963267948966);
            G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
            A = vec2(0.0, 0.0);
            B = polar(a, phi);
            C = vec2(d, 0.0) + polar(c, th4);
            D = vec2(d, 0.0);
        }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
    }
}

/// The four-bar of the tests and its links' masses and moments of inertia.
pub(crate) const FOUR_BAR: MassFourBar = MassFourBar {
    a: 0.04,
    b: 0.12,
    c: 0.10,
    d: 0.11,
    g3x: 0.05,
    g3y: 0.02,
};
pub(crate) const FOUR_BAR_MASSES: [f64; 3] = [0.3, 0.9, 0.7];
pub(crate) const FOUR_BAR_INERTIAS: [f64; 3] = [5e-5, 1.4e-3, 7e-4];

/// The four-bar assembled at φ = 0 on the branch of the guess
/// θ3 = 1, θ4 = 1.6.
pub(crate) fn four_bar_start(m: &MassFourBar) -> Result<MassFourBarCoords, Error> {
    m.assemble(&MassFourBarCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 1.6,
    })
}

/// The four-bar's three links as bodies, with gravity.
pub(crate) fn four_bar_bodies() -> kinematics_core::dynamics::DynamicsBuilder {
    let ([m2, m3, m4], [j2, j3, j4]) = (FOUR_BAR_MASSES, FOUR_BAR_INERTIAS);
    Dynamics::builder()
        .body(Body::new("crank", m2).center("G2").angle("phi").inertia(j2))
        .body(
            Body::new("coupler", m3)
                .center("G3")
                .angle("th3")
                .inertia(j3),
        )
        .body(
            Body::new("rocker", m4)
                .center("G4")
                .angle("th4")
                .inertia(j4),
        )
        .gravity([0.0, -G, 0.0])
}

/// A four-bar with three moving masses and gravity, over a full turn at a
/// varying crank speed: the driving torque against Newton–Euler (nine
/// equations: each link's forces and moment about its centre of mass; the
/// four pin forces and the torque unknown), with the links' angular rates
/// and accelerations from the analysis and the centres' accelerations
/// formed here by the rigid-body formula a_G = a_P + α × r − ω² r.
#[test]
fn a_four_bars_driving_torque_is_the_newton_euler_one() -> Result<(), Error> {
    let m = FOUR_BAR;
    let (a, c, d, g3x, g3y) = (m.a, m.c, m.d, m.g3x, m.g3y);
    let (masses, inertias) = (FOUR_BAR_MASSES, FOUR_BAR_INERTIAS);
    let ([m2, m3, m4], [j2, j3, j4]) = (masses, inertias);
    let dynamics = four_bar_bodies().build::<MassFourBar>()?;
    let mut pose = four_bar_start(&m)?;
    for k in 0..120 {
        let phi = TAU * f64::from(k) / 120.0;
        let (w2, al2) = (20.0 + 4.0 * phi.cos(), 60.0 * phi.sin());
        pose.phi = phi;
        let motion = m.step(&pose, w2, al2)?;
        pose = motion.q;
        let forces = dynamics.inverse(&m, &motion)?;
        let ne = four_bar_newton_euler(&motion, masses, inertias, (a, c, d), (g3x, g3y));
        let x = &ne.x;
        let ([g2, g3, g4], [a_g2, a_g3, a_g4]) = (ne.centres, ne.accelerations);
        let al2 = motion.qdd.phi;
        let (al3, al4) = (motion.qdd.th3, motion.qdd.th4);
        let scale = |v: [f64; 2], s: f64| [v[0] * s, v[1] * s];
        close(forces.effort.phi, x[8], 1e-10, "driving torque");
        // The shaking force and moment: minus the inertia forces' sum and
        // their moment about the origin with the bodies' J α.
        let ma = [scale(a_g2, m2), scale(a_g3, m3), scale(a_g4, m4)];
        let fx = -(ma[0][0] + ma[1][0] + ma[2][0]);
        let mz = -(cross(g2, ma[0]) + cross(g3, ma[1]) + cross(g4, ma[2]))
            - (j2 * al2 + j3 * al3 + j4 * al4);
        close(forces.shaking_force.x, fx, 1e-10, "shaking force");
        close(forces.shaking_moment.z, mz, 1e-10, "shaking moment");
        assert_eq!(forces.shaking_moment.x, 0.0);
    }
    Ok(())
}

/// The four-bar's Newton–Euler solve (the test's own): the centres of mass
/// and their accelerations from the link angles, rates and accelerations
/// of `motion` by the rigid-body formula, and the nine unknowns F12
/// (ground on crank at A), F32 (coupler on crank at B), F43 (rocker on
/// coupler at C), F14 (ground on rocker at D) and the torque T.
pub(crate) struct FourBarNewtonEuler {
    pub(crate) x: DVector<f64>,
    pub(crate) centres: [[f64; 2]; 3],
    pub(crate) accelerations: [[f64; 2]; 3],
}

pub(crate) fn four_bar_newton_euler(
    motion: &MassFourBarMotion,
    [m2, m3, m4]: [f64; 3],
    [j2, j3, j4]: [f64; 3],
    (a, c, d): (f64, f64, f64),
    (g3x, g3y): (f64, f64),
) -> FourBarNewtonEuler {
    let (phi, w2, al2) = (motion.q.phi, motion.qd.phi, motion.qdd.phi);
    let (t3, t4) = (motion.q.th3, motion.q.th4);
    let (w3, w4) = (motion.qd.th3, motion.qd.th4);
    let (al3, al4) = (motion.qdd.th3, motion.qdd.th4);
    let e = |t: f64| [t.cos(), t.sin()];
    let scale = |v: [f64; 2], s: f64| [v[0] * s, v[1] * s];
    let add = |u: [f64; 2], v: [f64; 2]| [u[0] + v[0], u[1] + v[1]];
    let sub = |u: [f64; 2], v: [f64; 2]| [u[0] - v[0], u[1] - v[1]];
    // a of a point at r from a pivot or point P of a link turning with
    // (ω, α): a_P + α ẑ × r − ω² r.
    let acc = |a_p: [f64; 2], r: [f64; 2], w: f64, al: f64| {
        [
            a_p[0] - al * r[1] - w * w * r[0],
            a_p[1] + al * r[0] - w * w * r[1],
        ]
    };
    let pin_b = scale(e(phi), a);
    let pin_d = [d, 0.0];
    let pin_c = add(pin_d, scale(e(t4), c));
    let g2 = scale(pin_b, 0.5);
    let r3 = [
        g3x * t3.cos() - g3y * t3.sin(),
        g3x * t3.sin() + g3y * t3.cos(),
    ];
    let g3 = add(pin_b, r3);
    let g4 = add(pin_d, scale(e(t4), c / 2.0));
    let a_b = acc([0.0; 2], pin_b, w2, al2);
    let a_g2 = acc([0.0; 2], g2, w2, al2);
    let a_g3 = acc(a_b, r3, w3, al3);
    let a_g4 = acc([0.0; 2], sub(g4, pin_d), w4, al4);
    // Columns: F12 (ground on crank at A) x y, F32 (coupler on crank at
    // B), F43 (rocker on coupler at C), F14 (ground on rocker at D), T.
    let mut mat = DMatrix::<f64>::zeros(9, 9);
    let mut rhs = DVector::<f64>::zeros(9);
    let mut moment = |row: usize, col: usize, r: [f64; 2], sign: f64| {
        mat[(row, col)] += -sign * r[1];
        mat[(row, col + 1)] += sign * r[0];
    };
    // Crank.
    moment(2, 0, sub([0.0; 2], g2), 1.0);
    moment(2, 2, sub(pin_b, g2), 1.0);
    // Coupler: −F32 at B, F43 at C.
    moment(5, 2, sub(pin_b, g3), -1.0);
    moment(5, 4, sub(pin_c, g3), 1.0);
    // Rocker: −F43 at C, F14 at D.
    moment(8, 4, sub(pin_c, g4), -1.0);
    moment(8, 6, sub(pin_d, g4), 1.0);
    for i in 0..2 {
        mat[(i, i)] = 1.0;
        mat[(i, 2 + i)] = 1.0;
        mat[(3 + i, 2 + i)] = -1.0;
        mat[(3 + i, 4 + i)] = 1.0;
        mat[(6 + i, 4 + i)] = -1.0;
        mat[(6 + i, 6 + i)] = 1.0;
    }
    mat[(2, 8)] = 1.0;
    let weight = [0.0, G];
    for i in 0..2 {
        rhs[i] = m2 * (a_g2[i] + weight[i]);
        rhs[3 + i] = m3 * (a_g3[i] + weight[i]);
        rhs[6 + i] = m4 * (a_g4[i] + weight[i]);
    }
    (rhs[2], rhs[5], rhs[8]) = (j2 * al2, j3 * al3, j4 * al4);
    let x = mat
        .lu()
        .solve(&rhs)
        .expect("the Newton–Euler system is regular");
    FourBarNewtonEuler {
        x,
        centres: [g2, g3, g4],
        accelerations: [a_g2, a_g3, a_g4],
    }
}
