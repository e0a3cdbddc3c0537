//! Inverse dynamics (`kinematics_core::dynamics`) against independent
//! computations written here: the exact closed form of a slider-crank's
//! gas-force torque, Newton–Euler solves of a slider-crank engine and of a
//! four-bar with gravity (every body's equations of motion, the joint
//! forces and the driving torque as unknowns, with the kinematics in
//! closed form or from the rigid-body formulas), the energy balance over a
//! cycle at varying speed, and the power against finite differences of
//! the energy for spatial mechanisms (an RSSR and a six-axis arm with
//! inertia tensors).

// A test harness: a failed step should stop it.
#![allow(missing_docs, clippy::expect_used, clippy::panic)]

use std::f64::consts::TAU;

use kinematics_core::dynamics::{Body, Dynamics, Joint, Spring, GROUND};
use kinematics_core::nalgebra::{DMatrix, DVector, Vector3};
use kinematics_core::{mechanism, Error};

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

const A: f64 = 0.05;
const B: f64 = 0.2;
const R3: f64 = 0.07;
const M2: f64 = 1.1;
const J2: f64 = 4e-4;
const M3: f64 = 0.6;
const J3: f64 = 2.5e-3;
const M4: f64 = 0.45;
const G: f64 = 9.81;

fn close(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * (1.0 + b.abs()),
        "{what}: {a} against {b} (difference {:.2e})",
        (a - b).abs()
    );
}

/// The engine's motion at φ with rate ω and acceleration α, assembled on
/// the branch with the piston at x > 0.
fn engine_motion(m: &Engine, phi: f64, w: f64, al: f64) -> EngineMotion {
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
const ENGINE_TEXT: &str = "struct Engine { params { a, b, r3 } drivers { phi } unknowns { th, x }
         points { G2 = polar(a / 2.0, phi); B = polar(a, phi); G3 = polar(a, phi) + polar(r3, th);
                  C = vec2(x, 0.0); O = vec2(0.0, 0.0); }
         loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); } }";

/// The engine's kinematics in closed form (independent of the library):
/// θ, x and the accelerations of G2, B, G3 and C, with θ', θ''.
struct EngineKinematics {
    th: f64,
    thdd: f64,
    x: f64,
    a_g2: [f64; 2],
    a_g3: [f64; 2],
    a_c: f64,
}

fn engine_kinematics(phi: f64, w: f64, al: f64) -> EngineKinematics {
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
fn cross(r: [f64; 2], f: [f64; 2]) -> f64 {
    r[0] * f[1] - r[1] * f[0]
}

/// Newton–Euler for the engine with gravity −g ŷ and the gas force −P x̂
/// on the piston: unknowns F12 (ground on crank at O), F32 (rod on crank at
/// B), F43 (piston on rod at C), N (wall on piston, along y) and the motor
/// torque T; eight equations: the crank's and the rod's forces and moments
/// about their centres of mass, the piston's forces. Returns the unknowns
/// in that order.
fn engine_newton_euler(phi: f64, w: f64, al: f64, p: f64) -> DVector<f64> {
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
const FOUR_BAR: MassFourBar = MassFourBar {
    a: 0.04,
    b: 0.12,
    c: 0.10,
    d: 0.11,
    g3x: 0.05,
    g3y: 0.02,
};
const FOUR_BAR_MASSES: [f64; 3] = [0.3, 0.9, 0.7];
const FOUR_BAR_INERTIAS: [f64; 3] = [5e-5, 1.4e-3, 7e-4];

/// The four-bar assembled at φ = 0 on the branch of the guess
/// θ3 = 1, θ4 = 1.6.
fn four_bar_start(m: &MassFourBar) -> Result<MassFourBarCoords, Error> {
    m.assemble(&MassFourBarCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 1.6,
    })
}

/// The four-bar's three links as bodies, with gravity.
fn four_bar_bodies() -> kinematics_core::dynamics::DynamicsBuilder {
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
struct FourBarNewtonEuler {
    x: DVector<f64>,
    centres: [[f64; 2]; 3],
    accelerations: [[f64; 2]; 3],
}

fn four_bar_newton_euler(
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

/// The gas force on the engine's piston at x: 2000 (0.3 / x)² N.
fn gas(x: f64) -> f64 {
    2000.0 * (0.3 / x).powi(2)
}

/// The engine's links as bodies, gravity, the gas force on the piston and
/// the joints: the crank's bearing (driven), the crank pin, the piston pin
/// and the cylinder.
fn engine_with_joints() -> kinematics_core::dynamics::DynamicsBuilder {
    Dynamics::builder()
        .body(Body::new("crank", M2).center("G2").angle("phi").inertia(J2))
        .body(Body::new("rod", M3).center("G3").angle("th").inertia(J3))
        .body(Body::new("piston", M4).center("C"))
        .gravity([0.0, -G, 0.0])
        .force_on("piston", "C", |s| [-gas(s.position.x), 0.0, 0.0])
        .joint(Joint::revolute("bearing", "O", GROUND, "crank").driven_by("phi"))
        .joint(Joint::revolute("crank pin", "B", "crank", "rod"))
        .joint(Joint::revolute("piston pin", "C", "rod", "piston"))
        .joint(Joint::prismatic(
            "cylinder",
            "C",
            GROUND,
            "piston",
            [1.0, 0.0],
        ))
}

/// Every joint reaction of the engine (crank bearing, crank pin, piston
/// pin, the cylinder's normal force) by the library's Newton–Euler over
/// the declared joints, against the test's own solve; the crank torque in
/// the bearing equals the virtual-power effort.
#[test]
fn an_engines_joint_reactions_are_the_newton_euler_ones() -> Result<(), Error> {
    let m = Engine { a: A, b: B, r3: R3 };
    let dynamics = engine_with_joints().build::<Engine>()?;
    for k in 0..36 {
        let phi = TAU * f64::from(k) / 36.0 + 0.02;
        let (w, al) = (150.0 + 30.0 * phi.sin(), -800.0 * phi.cos());
        let motion = engine_motion(&m, phi, w, al);
        let r = dynamics.reactions(&m, &motion)?;
        let x = engine_newton_euler(phi, w, al, gas(engine_kinematics(phi, w, al).x));
        let get = |name: &str| r.get(name).expect("a joint of the engine");
        let scale = x.amax();
        let near = |a: f64, b: f64, what: &str| {
            assert!((a - b).abs() <= 1e-10 * scale, "{what}: {a} against {b}");
        };
        near(get("bearing").force.x, x[0], "bearing x");
        near(get("bearing").force.y, x[1], "bearing y");
        near(get("crank pin").force.x, -x[2], "crank pin x");
        near(get("crank pin").force.y, -x[3], "crank pin y");
        near(get("piston pin").force.x, -x[4], "piston pin x");
        near(get("piston pin").force.y, -x[5], "piston pin y");
        near(get("cylinder").force.y, x[6], "cylinder normal force");
        near(get("cylinder").force.x, 0.0, "no friction");
        near(get("cylinder").moment.z, 0.0, "cylinder moment");
        let effort = get("bearing").effort.expect("driven");
        near(effort, x[7], "torque");
        close(
            effort,
            dynamics.inverse(&m, &motion)?.effort.phi,
            1e-10,
            "both methods",
        );
        // The crank pin's force in the rod's axes: along the rod and across.
        let th = motion.q.th;
        let f = get("crank pin").force;
        near(
            get("crank pin").force_in_body.x,
            f.x * th.cos() + f.y * th.sin(),
            "along the rod",
        );
    }
    // The same joints on the engine compiled at run time.
    let model = kinematics_core::runtime::Model::compile(ENGINE_TEXT)
        .expect("compiles")
        .with_values(&[A, B, R3])?;
    let at_run_time = engine_with_joints().build_for(&model)?;
    let motion = engine_motion(&m, 1.0, 150.0, -800.0);
    let q = [motion.q.phi, motion.q.th, motion.q.x];
    let run_time = model.analyze(&q, &[150.0], &[-800.0])?;
    let (rg, rr) = (
        dynamics.reactions(&m, &motion)?,
        at_run_time.reactions_of(&model, &run_time)?,
    );
    for (g, r) in rg.joints.iter().zip(&rr.joints) {
        assert_eq!(g.name, r.name);
        for i in 0..2 {
            close(r.force[i], g.force[i], 1e-12, "run-time reaction");
        }
    }
    Ok(())
}

/// The gas force given as a force on the piston's coordinate x, acting in
/// the cylinder joint that x measures: the same reactions and torque as
/// the force applied to the piston at C; without the joint named, a clear
/// error.
#[test]
fn a_force_on_a_coordinate_acts_in_its_joint() -> Result<(), Error> {
    let m = Engine { a: A, b: B, r3: R3 };
    let joints = |d: kinematics_core::dynamics::DynamicsBuilder, coordinate: bool| {
        let cylinder = Joint::prismatic("cylinder", "C", GROUND, "piston", [1.0, 0.0]);
        d.body(Body::new("crank", M2).center("G2").angle("phi").inertia(J2))
            .body(Body::new("rod", M3).center("G3").angle("th").inertia(J3))
            .body(Body::new("piston", M4).center("C"))
            .gravity([0.0, -G, 0.0])
            .joint(Joint::revolute("bearing", "O", GROUND, "crank").driven_by("phi"))
            .joint(Joint::revolute("crank pin", "B", "crank", "rod"))
            .joint(Joint::revolute("piston pin", "C", "rod", "piston"))
            .joint(if coordinate {
                cylinder.coordinate("x")
            } else {
                cylinder
            })
    };
    let on_x = joints(
        Dynamics::builder().coordinate_force("x", |s| -gas(s.q(2))),
        true,
    )
    .build::<Engine>()?;
    let at_c = engine_with_joints().build::<Engine>()?;
    for k in 0..12 {
        let phi = TAU * f64::from(k) / 12.0 + 0.2;
        let motion = engine_motion(&m, phi, 140.0, 300.0);
        let (r1, r2) = (on_x.reactions(&m, &motion)?, at_c.reactions(&m, &motion)?);
        for (a, b) in r1.joints.iter().zip(&r2.joints) {
            for i in 0..2 {
                close(a.force[i], b.force[i], 1e-10, "reaction");
            }
        }
        close(
            on_x.inverse(&m, &motion)?.effort.phi,
            at_c.inverse(&m, &motion)?.effort.phi,
            1e-10,
            "torque",
        );
    }
    let unplaced =
        joints(Dynamics::builder().coordinate_force("x", |_| -100.0), false).build::<Engine>()?;
    let motion = engine_motion(&m, 0.4, 140.0, 0.0);
    let e = unplaced
        .reactions(&m, &motion)
        .expect_err("no joint measured by x");
    assert!(e.to_string().contains(".coordinate("), "{e}");
    Ok(())
}

/// Every joint reaction of the four-bar with gravity against the test's
/// Newton–Euler solve (nine equations), over a full turn at varying speed.
#[test]
fn a_four_bars_joint_reactions_are_the_newton_euler_ones() -> Result<(), Error> {
    let m = FOUR_BAR;
    let (a, c, d, g3x, g3y) = (m.a, m.c, m.d, m.g3x, m.g3y);
    let (masses, inertias) = (FOUR_BAR_MASSES, FOUR_BAR_INERTIAS);
    let dynamics = four_bar_bodies()
        .joint(Joint::revolute("A", "A", GROUND, "crank").driven_by("phi"))
        .joint(Joint::revolute("B", "B", "crank", "coupler"))
        .joint(Joint::revolute("C", "C", "coupler", "rocker"))
        .joint(Joint::revolute("D", "D", GROUND, "rocker"))
        .build::<MassFourBar>()?;
    let mut pose = four_bar_start(&m)?;
    for k in 0..72 {
        let phi = TAU * f64::from(k) / 72.0;
        let (w2, al2) = (20.0 + 4.0 * phi.cos(), 60.0 * phi.sin());
        pose.phi = phi;
        let motion = m.step(&pose, w2, al2)?;
        pose = motion.q;
        let x = four_bar_newton_euler(&motion, masses, inertias, (a, c, d), (g3x, g3y)).x;
        let r = dynamics.reactions(&m, &motion)?;
        let scale = x.amax();
        let near = |p: f64, q: f64, what: &str| {
            assert!(
                (p - q).abs() <= 1e-10 * scale,
                "{what} at step {k}: {p} against {q}"
            );
        };
        let get = |name: &str| r.get(name).expect("a joint").force;
        // The test's unknowns: F12 (ground on crank), F32 (coupler on
        // crank), F43 (rocker on coupler), F14 (ground on rocker), T.
        near(get("A").x, x[0], "A x");
        near(get("A").y, x[1], "A y");
        near(get("B").x, -x[2], "B x");
        near(get("B").y, -x[3], "B y");
        near(get("C").x, -x[4], "C x");
        near(get("C").y, -x[5], "C y");
        near(get("D").x, x[6], "D x");
        near(get("D").y, x[7], "D y");
        near(
            r.get("A").and_then(|j| j.effort).expect("driven"),
            x[8],
            "torque",
        );
        // The rocker's bearing force in the rocker's axes.
        let t4 = motion.q.th4;
        let f = get("D");
        let along = r.get("D").expect("a joint").force_in_body.x;
        near(along, f.x * t4.cos() + f.y * t4.sin(), "D along the rocker");
    }
    Ok(())
}

/// A spring and damper between the crank and the rocker, in the
/// reactions: the torque the Newton–Euler solve finds in the crank's
/// bearing equals the virtual-power effort (checked on its own against the
/// energy above), and the spring's forces, internal, cancel in the
/// balance of the whole linkage: the ground's reactions at A and D plus
/// the weights equal Σ m a_G.
#[test]
fn a_spring_between_links_is_internal_to_the_reactions() -> Result<(), Error> {
    let m = FOUR_BAR;
    let dynamics = four_bar_bodies()
        .spring(
            Spring::new("G2", "G4")
                .stiffness(800.0)
                .free_length(0.09)
                .damping(4.0)
                .between("crank", "rocker"),
        )
        .joint(Joint::revolute("A", "A", GROUND, "crank").driven_by("phi"))
        .joint(Joint::revolute("B", "B", "crank", "coupler"))
        .joint(Joint::revolute("C", "C", "coupler", "rocker"))
        .joint(Joint::revolute("D", "D", GROUND, "rocker"))
        .build::<MassFourBar>()?;
    let mut pose = four_bar_start(&m)?;
    for k in 0..24 {
        pose.phi = TAU * f64::from(k) / 24.0;
        let motion = m.step(&pose, 15.0, 40.0)?;
        pose = motion.q;
        let r = dynamics.reactions(&m, &motion)?;
        let torque = r.get("A").and_then(|j| j.effort).expect("driven");
        close(
            torque,
            dynamics.inverse(&m, &motion)?.effort.phi,
            1e-10,
            "spring: both methods",
        );
        let ground = r.get("A").expect("A").force + r.get("D").expect("D").force;
        let masses = FOUR_BAR_MASSES;
        let points = [motion.point_g2(), motion.point_g3(), motion.point_g4()];
        for i in 0..2 {
            let momentum: f64 = points
                .iter()
                .zip(masses)
                .map(|(p, mass)| mass * p.acceleration[i])
                .sum();
            let weight = if i == 1 {
                -G * masses.iter().sum::<f64>()
            } else {
                0.0
            };
            close(ground[i] + weight, momentum, 1e-10, "the linkage's balance");
        }
    }
    let unplaced = four_bar_bodies()
        .spring(Spring::new("G2", "G4").stiffness(800.0))
        .joint(Joint::revolute("A", "A", GROUND, "crank").driven_by("phi"))
        .build::<MassFourBar>()?;
    let motion = m.step(&pose, 15.0, 0.0)?;
    let e = unplaced
        .reactions(&m, &motion)
        .expect_err("the spring has no bodies");
    assert!(e.to_string().contains(".between("), "{e}");
    Ok(())
}

/// Over a full cycle at varying speed, with gravity and a spring (no
/// damping, no other load), the work of the driver ∫ Q φ' dt equals the
/// change of kinetic plus potential energy, to 1e-9 relative; the
/// integral by Simpson's rule on 4000 intervals.
#[test]
fn the_drivers_work_over_a_cycle_is_the_change_of_energy() -> Result<(), Error> {
    let m = FOUR_BAR;
    let dynamics = four_bar_bodies()
        .spring(Spring::new("G2", "G4").stiffness(800.0).free_length(0.09))
        .build::<MassFourBar>()?;
    // φ(t) = 8 t + 0.6 sin 3t over t ∈ [0, t1] with φ(t1) − φ(0) past 2π.
    let phi = |t: f64| {
        (
            8.0 * t + 0.6 * (3.0 * t).sin(),
            8.0 + 1.8 * (3.0 * t).cos(),
            -5.4 * (3.0 * t).sin(),
        )
    };
    let t1 = 0.9;
    let n = 4000;
    let mut pose = four_bar_start(&m)?;
    let (mut work, mut energy) = (0.0, [0.0f64; 2]);
    for i in 0..=n {
        let t = t1 * f64::from(i) / f64::from(n);
        let (p, w, al) = phi(t);
        pose.phi = p;
        let motion = m.step(&pose, w, al)?;
        pose = motion.q;
        let f = dynamics.inverse(&m, &motion)?;
        let weight = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        work += weight * f.power;
        let e = f.kinetic_energy + f.potential_energy;
        if i == 0 {
            energy[0] = e;
        }
        energy[1] = e;
    }
    work *= t1 / f64::from(n) / 3.0;
    assert!(phi(t1).0 > TAU, "a full cycle");
    let change = energy[1] - energy[0];
    assert!(
        change.abs() > 0.05,
        "the energy changes ({change} J): a test"
    );
    assert!(
        (work - change).abs() <= 1e-9 * change.abs(),
        "work {work} J against the change of energy {change} J"
    );
    Ok(())
}

/// With a damper in the spring, the drivers' work exceeds the change of
/// energy by the damper's dissipation ∫ c L'² dt, which is positive.
#[test]
fn a_damper_takes_work_from_the_driver() -> Result<(), Error> {
    let m = FOUR_BAR;
    let build = |c: f64| {
        Dynamics::builder()
            .body(
                Body::new("rocker", 0.7)
                    .center("G4")
                    .angle("th4")
                    .inertia(7e-4),
            )
            .spring(
                Spring::new("G2", "G4")
                    .stiffness(800.0)
                    .free_length(0.09)
                    .damping(c),
            )
            .build::<MassFourBar>()
    };
    let (plain, damped) = (build(0.0)?, build(3.0)?);
    let pose = m.assemble(&MassFourBarCoords {
        phi: 1.0,
        th3: 1.0,
        th4: 1.6,
    })?;
    let motion = m.analyze(&pose, 10.0, 0.0)?;
    let (p0, p1) = (plain.inverse(&m, &motion)?, damped.inverse(&m, &motion)?);
    // L' of G2–G4 from the motion, and the damper's power c L'².
    let (g2, g4) = (motion.point_g2(), motion.point_g4());
    let dr = g4.position - g2.position;
    let ld = dr.dot(&(g4.velocity - g2.velocity)) / dr.norm();
    assert!(ld.abs() > 1e-3, "the spring moves");
    close(p1.power - p0.power, 3.0 * ld * ld, 1e-12, "damper power");
    Ok(())
}

mechanism! {
    /// An RSSR with a frame for the crank (about z through A₀) and one for
    /// the rocker (about x through B₀), and the coupler's centre of mass.
    pub struct MassRssr {
        params   { a, b, c, d }
        drivers  { phi }
        unknowns { psi }
        frames {
            crank = rot_y(-phi);
            rocker = translation(vec3(-d, 0.0, 0.0)) * rot_z(-psi);
        }
        points {
            A = vec3(-a * cos(phi), 0.0, a * sin(phi));
            B = vec3(-d - c * cos(psi), c * sin(psi), 0.0);
            G2 = vec3(-a * cos(phi) / 2.0, 0.0, a * sin(phi) / 2.0);
            G3 = 0.5 * (vec3(-a * cos(phi), 0.0, a * sin(phi)) + vec3(-d - c * cos(psi), c * sin(psi), 0.0));
            G4 = vec3(-d - c * cos(psi) / 2.0, c * sin(psi) / 2.0, 0.0);
        }
        constraints { norm(B - A) == b; }
    }
}

/// d(T + V)/dt by the fourth-order central difference of the energy along
/// a motion, against the drivers' power Σ Q_k ḋ_k (no other load than
/// gravity): for the RSSR with inertia tensors in its crank's and rocker's
/// frames and the coupler as a point mass.
#[test]
fn the_power_of_an_rssr_is_the_rate_of_its_energy() -> Result<(), Error> {
    let m = MassRssr {
        a: 0.03,
        b: 0.12,
        c: 0.08,
        d: 0.1,
    };
    let tensor = |x: f64, y: f64, z: f64| [[x, 2e-6, 0.0], [2e-6, y, 1e-6], [0.0, 1e-6, z]];
    let dynamics = Dynamics::builder()
        .body(
            Body::new("crank", 0.2)
                .center("G2")
                .frame("crank")
                .inertia_tensor(tensor(3e-5, 1e-5, 3e-5)),
        )
        .body(Body::new("coupler", 0.4).center("G3"))
        .body(
            Body::new("rocker", 0.3)
                .center("G4")
                .frame("rocker")
                .inertia_tensor(tensor(2e-5, 4e-5, 5e-5)),
        )
        .gravity([0.0, -G, -2.0])
        .build::<MassRssr>()?;
    let start = m.assemble(&MassRssrCoords { phi: 0.7, psi: 1.1 })?;
    let at = |t: f64| (0.7 + 9.0 * t + 20.0 * t * t, 9.0 + 40.0 * t, 40.0);
    let energy = |t: f64| -> Result<f64, Error> {
        let (p, w, al) = at(t);
        let mut q = start;
        q.phi = p;
        let motion = m.step(&q, w, al)?;
        let f = dynamics.inverse(&m, &motion)?;
        Ok(f.kinetic_energy + f.potential_energy)
    };
    for t in [0.0, 0.01, 0.03] {
        let h = 1e-4;
        let rate = (-energy(t + 2.0 * h)? + 8.0 * energy(t + h)? - 8.0 * energy(t - h)?
            + energy(t - 2.0 * h)?)
            / (12.0 * h);
        let (p, w, al) = at(t);
        let mut q = start;
        q.phi = p;
        let motion = m.step(&q, w, al)?;
        let f = dynamics.inverse(&m, &motion)?;
        assert!(f.power.abs() > 1e-3, "power {} W: a test", f.power);
        close(f.power, rate, 1e-8, "power against d(T + V)/dt");
        // The frames turn: the rotational energy is part of the total.
        let crank = motion.frames[0];
        assert!(crank.angular_velocity.norm() > 1.0);
    }
    Ok(())
}

mechanism! {
    /// Three links of an arm: waist q1 about z, shoulder q2 and elbow q3
    /// about y, each link's centre of mass in its frame.
    pub struct MassArm {
        params   { d1, a2, a3 }
        drivers  { q1, q2, q3 }
        unknowns { }
        frames {
            base = t3(0.0, 0.0, d1, q1);
            upper = base * t2(0.0, 0.0, 0.0, q2);
            fore = upper * t2(a2, 0.0, 0.0, q3);
        }
        points {
            G1 = base * vec3(0.0, 0.01, -d1 / 2.0);
            G2 = upper * vec3(a2 / 2.0, 0.0, 0.01);
            G3 = fore * vec3(a3 / 2.0, 0.005, 0.0);
        }
    }
}

/// The arm's three links as bodies with their inertia tensors (in their
/// frames' axes), with gravity along −z.
fn arm_bodies() -> kinematics_core::dynamics::DynamicsBuilder {
    let tensor = |x: f64, y: f64, z: f64| [[x, 0.002, 0.0], [0.002, y, 0.001], [0.0, 0.001, z]];
    Dynamics::builder()
        .body(
            Body::new("base", 4.0)
                .center("G1")
                .frame("base")
                .inertia_tensor(tensor(0.05, 0.05, 0.02)),
        )
        .body(
            Body::new("upper", 3.0)
                .center("G2")
                .frame("upper")
                .inertia_tensor(tensor(0.01, 0.07, 0.07)),
        )
        .body(
            Body::new("fore", 2.0)
                .center("G3")
                .frame("fore")
                .inertia_tensor(tensor(0.006, 0.03, 0.03)),
        )
        .gravity([0.0, 0.0, -G])
}

/// An arm of three drivers with inertia tensors: the drivers' power
/// Σ Q_k q̇_k against d(T + V)/dt by finite differences along a joint
/// trajectory; at rest, the shoulder's torque against the moment of the
/// weights about its axis.
#[test]
fn the_power_of_an_arm_is_the_rate_of_its_energy() -> Result<(), Error> {
    let m = MassArm {
        d1: 0.4,
        a2: 0.5,
        a3: 0.4,
    };
    let dynamics = arm_bodies().build::<MassArm>()?;
    let traj = |t: f64| {
        let q = [0.3 + 1.2 * t, -0.4 + 0.8 * t * t, 0.9 - 1.5 * t + t * t * t];
        let qd = [1.2, 1.6 * t, -1.5 + 3.0 * t * t];
        let qdd = [0.0, 1.6, 6.0 * t];
        (q, qd, qdd)
    };
    let energy = |t: f64| -> Result<f64, Error> {
        let (q, qd, qdd) = traj(t);
        let motion = m.step(
            &MassArmCoords {
                q1: q[0],
                q2: q[1],
                q3: q[2],
            },
            qd,
            qdd,
        )?;
        let f = dynamics.inverse(&m, &motion)?;
        Ok(f.kinetic_energy + f.potential_energy)
    };
    for t in [0.1, 0.4, 0.7] {
        let h = 1e-4;
        let rate = (-energy(t + 2.0 * h)? + 8.0 * energy(t + h)? - 8.0 * energy(t - h)?
            + energy(t - 2.0 * h)?)
            / (12.0 * h);
        let (q, qd, qdd) = traj(t);
        let motion = m.step(
            &MassArmCoords {
                q1: q[0],
                q2: q[1],
                q3: q[2],
            },
            qd,
            qdd,
        )?;
        let f = dynamics.inverse(&m, &motion)?;
        let power = f.effort.q1 * qd[0] + f.effort.q2 * qd[1] + f.effort.q3 * qd[2];
        close(
            f.power,
            power,
            1e-14,
            "power as the sum of the efforts' powers",
        );
        close(f.power, rate, 1e-8, "power against d(T + V)/dt");
        assert!(f.effort.q2.abs() > 1.0, "the shoulder holds the arm up");
    }
    // At rest, only gravity: the shoulder's torque is the moment of the
    // weights of the upper arm and forearm about its axis (y of the
    // upper arm's frame, through the shoulder), computed here from the
    // centres' positions.
    let q = [0.3, -0.4, 0.9];
    let motion = m.step(
        &MassArmCoords {
            q1: q[0],
            q2: q[1],
            q3: q[2],
        },
        [0.0; 3],
        [0.0; 3],
    )?;
    let f = dynamics.inverse(&m, &motion)?;
    let shoulder = Vector3::new(0.0, 0.0, 0.4);
    let axis = motion.frames[1].rotation * Vector3::y();
    let weight =
        |p: Vector3<f64>, mass: f64| (p - shoulder).cross(&Vector3::new(0.0, 0.0, -G * mass));
    let g2 = motion.point_g2().position;
    let g3 = motion.point_g3().position;
    let moment = (weight(g2, 3.0) + weight(g3, 2.0)).dot(&axis);
    // The motor holds the arm: its torque balances the weights' moment.
    close(f.effort.q2, -moment, 1e-12, "static shoulder torque");
    assert_eq!(f.kinetic_energy, 0.0);
    Ok(())
}

/// Each joint torque of the arm, not only their power, by Lagrange's
/// equations Q_k = d/dt ∂T/∂q̇_k − ∂T/∂q_k + ∂V/∂q_k with T(q, q̇) and V(q)
/// from the library's energies: ∂T/∂q̇_k by the central difference at
/// Δq̇ = 1 (exact, T being quadratic in q̇), its time derivative and ∂/∂q_k
/// by fourth-order central differences. The gyroscopic terms ω × J ω,
/// which do no work, show here.
#[test]
fn each_joint_torque_of_an_arm_satisfies_lagranges_equations() -> Result<(), Error> {
    let m = MassArm {
        d1: 0.4,
        a2: 0.5,
        a3: 0.4,
    };
    let dynamics = arm_bodies().build::<MassArm>()?;
    // T and V at (q, q̇).
    let energies = |q: [f64; 3], qd: [f64; 3]| -> Result<(f64, f64), Error> {
        let motion = m.step(
            &MassArmCoords {
                q1: q[0],
                q2: q[1],
                q3: q[2],
            },
            qd,
            [0.0; 3],
        )?;
        let f = dynamics.inverse(&m, &motion)?;
        Ok((f.kinetic_energy, f.potential_energy))
    };
    let traj = |t: f64| {
        let q = [0.3 + 1.2 * t, -0.4 + 0.8 * t * t, 0.9 - 1.5 * t + t * t * t];
        let qd = [1.2, 1.6 * t, -1.5 + 3.0 * t * t];
        let qdd = [0.0, 1.6, 6.0 * t];
        (q, qd, qdd)
    };
    let shifted = |v: [f64; 3], k: usize, h: f64| {
        let mut v = v;
        v[k] += h;
        v
    };
    // Fourth-order central difference of f at 0 with step h.
    let d4 = |f: &dyn Fn(f64) -> Result<f64, Error>, h: f64| -> Result<f64, Error> {
        Ok((-f(2.0 * h)? + 8.0 * f(h)? - 8.0 * f(-h)? + f(-2.0 * h)?) / (12.0 * h))
    };
    for t in [0.2, 0.5] {
        let (q, qd, qdd) = traj(t);
        let motion = m.step(
            &MassArmCoords {
                q1: q[0],
                q2: q[1],
                q3: q[2],
            },
            qd,
            qdd,
        )?;
        let f = dynamics.inverse(&m, &motion)?;
        let efforts = [f.effort.q1, f.effort.q2, f.effort.q3];
        for (k, &effort) in efforts.iter().enumerate() {
            // ∂T/∂q̇_k along the trajectory at t + s.
            let momentum = |s: f64| -> Result<f64, Error> {
                let (q, qd, _) = traj(t + s);
                let plus = energies(q, shifted(qd, k, 1.0))?.0;
                let minus = energies(q, shifted(qd, k, -1.0))?.0;
                Ok((plus - minus) / 2.0)
            };
            let rate = d4(&momentum, 1e-3)?;
            let lagrangian = |h: f64| -> Result<f64, Error> {
                let (t_, v) = energies(shifted(q, k, h), qd)?;
                Ok(v - t_)
            };
            let expected = rate + d4(&lagrangian, 1e-4)?;
            assert!(
                (effort - expected).abs() <= 1e-7 * (1.0 + expected.abs()),
                "t = {t}, joint {}: {effort} against Lagrange's {expected}",
                k + 1
            );
        }
    }
    Ok(())
}

/// Along a turn at constant speed with no loads but gravity and a spring,
/// the drivers' work over the turn is zero (the energy returns), so the
/// mean torque is zero; the work from the start is the change of energy,
/// so the fluctuation a flywheel must absorb is max − min of T + V. The
/// CSV has a column per quantity with its unit.
#[test]
fn the_mean_torque_and_energy_fluctuation_of_a_turn() -> Result<(), Error> {
    let m = FOUR_BAR;
    let dynamics = four_bar_bodies()
        .spring(Spring::new("G2", "G4").stiffness(800.0).free_length(0.09))
        .build::<MassFourBar>()?;
    let start = four_bar_start(&m)?;
    let sweep = m
        .sweep(MassFourBar::PHI, &start)
        .to(TAU)
        .steps(1440)
        .rpm(300.0)
        .run();
    assert!(sweep.stop.is_none());
    let forces = dynamics.along(&m, &sweep)?;
    assert_eq!(forces.samples.len(), 1441);
    let peak = forces
        .samples
        .iter()
        .map(|s| s.effort[0].abs())
        .fold(0.0, f64::max);
    let mean = forces.mean_effort(0).expect("a turn");
    assert!(
        peak > 1.0 && mean.abs() < 1e-9 * peak,
        "mean {mean} N·m, peak {peak} N·m"
    );
    let energy: Vec<f64> = forces
        .samples
        .iter()
        .map(|s| s.kinetic_energy + s.potential_energy)
        .collect();
    let range = energy.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - energy.iter().copied().fold(f64::INFINITY, f64::min);
    let fluctuation = forces.energy_fluctuation(0).expect("a turn");
    assert!(
        (fluctuation - range).abs() < 1e-5 * range,
        "ΔE {fluctuation} J against max − min of T + V {range} J"
    );
    let csv = forces.to_csv();
    let header = csv.lines().next().expect("a header");
    assert_eq!(
        header,
        "phi (deg),Q_phi (N·m),T (J),V (J),P (W),Fs_x (N),Fs_y (N),Fs_z (N),Ms_x (N·m),Ms_y (N·m),Ms_z (N·m)"
    );
    assert_eq!(csv.lines().count(), 1442);
    Ok(())
}

mechanism! {
    /// A crank with an unbalanced mass at its pin.
    pub struct Unbalanced {
        params   { r }
        drivers  { phi }
        unknowns { }
        points   { P = polar(r, phi); }
    }
}

/// A mass m at radius r on a crank turned at constant speed ω under
/// gravity: the torque is m g r cos φ, its mean over a turn zero, and the
/// energy a flywheel must absorb the potential's swing ΔE = 2 m g r; with
/// a flywheel of I the coefficient of speed fluctuation is 2 m g r/(I ω²).
#[test]
fn an_unbalanced_cranks_energy_fluctuation_is_its_potentials_swing() -> Result<(), Error> {
    let (mass, r, w, inertia) = (2.0, 0.15, 12.0, 0.8);
    let m = Unbalanced { r };
    let dynamics = Dynamics::builder()
        .body(Body::new("weight", mass).center("P"))
        .gravity([0.0, -G, 0.0])
        .build::<Unbalanced>()?;
    let sweep = m
        .sweep(Unbalanced::PHI, &UnbalancedCoords { phi: 0.0 })
        .to(TAU)
        .steps(720)
        .rpm(w * 60.0 / TAU)
        .run();
    let forces = dynamics.along(&m, &sweep)?;
    for s in &forces.samples {
        close(s.effort[0], mass * G * r * s.at.cos(), 1e-12, "m g r cos φ");
    }
    let swing = 2.0 * mass * G * r;
    let fluctuation = forces.energy_fluctuation(0).expect("a turn");
    assert!(
        (fluctuation - swing).abs() < 1e-4 * swing,
        "ΔE {fluctuation} against 2 m g r {swing}"
    );
    let cs = forces.speed_fluctuation(0, inertia, w).expect("a turn");
    assert!(
        (cs - swing / (inertia * w * w)).abs() < 1e-4 * cs,
        "C_s {cs}"
    );
    assert!(forces.mean_effort(0).expect("a turn").abs() < 1e-12);
    assert_eq!(forces.speed_fluctuation(0, 0.0, w), None);
    Ok(())
}

/// The joint reactions along a sweep: at each sample those of
/// `reactions`, in the CSV as three columns per joint; and a run-time
/// model's sweep of forces equals the generated one's.
#[test]
fn a_sweep_of_forces_carries_the_joint_reactions() -> Result<(), Box<dyn std::error::Error>> {
    let m = Engine { a: A, b: B, r3: R3 };
    let dynamics = engine_with_joints().build::<Engine>()?;
    let start = engine_motion(&m, 0.0, 1.0, 0.0).q;
    let sweep = m
        .sweep(Engine::PHI, &start)
        .turn()
        .steps(36)
        .rpm(1500.0)
        .run();
    let forces = dynamics.along(&m, &sweep)?;
    for (s, f) in sweep.samples.iter().zip(&forces.samples) {
        let r = dynamics.reactions(&m, &s.motion)?;
        assert_eq!(f.reactions.as_ref(), Some(&r));
    }
    let csv = forces.to_csv();
    let header = csv.lines().next().unwrap_or_default();
    assert!(
        header.ends_with(",R_bearing_x (N),R_bearing_y (N),M_bearing (N·m),R_crank pin_x (N),R_crank pin_y (N),M_crank pin (N·m),R_piston pin_x (N),R_piston pin_y (N),M_piston pin (N·m),R_cylinder_x (N),R_cylinder_y (N),M_cylinder (N·m)"),
        "{header}"
    );
    assert_eq!(csv.lines().nth(1).map(|l| l.split(',').count()), Some(23));
    // The same sweep of the engine compiled at run time.
    let model = kinematics_core::runtime::Model::compile(ENGINE_TEXT)?.with_values(&[A, B, R3])?;
    let at_run_time = engine_with_joints().build_for(&model)?;
    let q = [start.phi, start.th, start.x];
    let run = model.sweep("phi", &q)?.turn().steps(36).rpm(1500.0).run();
    let other = at_run_time.along_of(&model, &run)?;
    assert_eq!(other.samples.len(), forces.samples.len());
    for (g, r) in forces.samples.iter().zip(&other.samples) {
        close(r.effort[0], g.effort[0], 1e-10, "run-time effort");
        let (gr, rr) = (g.reactions.as_ref(), r.reactions.as_ref());
        for (a, b) in gr
            .map_or(&[][..], |x| &x.joints[..])
            .iter()
            .zip(rr.map_or(&[][..], |x| &x.joints[..]))
        {
            close(b.force.x, a.force.x, 1e-10, "run-time reaction");
        }
    }
    Ok(())
}

/// The arm's definition as text, for the same model compiled at run time.
const MASS_ARM_TEXT: &str = "
    struct MassArm {
        params   { d1, a2, a3 }
        drivers  { q1, q2, q3 }
        unknowns { }
        frames {
            base = t3(0.0, 0.0, d1, q1);
            upper = base * t2(0.0, 0.0, 0.0, q2);
            fore = upper * t2(a2, 0.0, 0.0, q3);
        }
        points {
            G1 = base * vec3(0.0, 0.01, -d1 / 2.0);
            G2 = upper * vec3(a2 / 2.0, 0.0, 0.01);
            G3 = fore * vec3(a3 / 2.0, 0.005, 0.0);
        }
    }";

/// The arm generated and compiled at run time, each stepped to the same
/// motion (q = (0.3, −0.4, 0.9), q' = (1.2, −0.7, 2), q'' = (3, 1.6, −2.5)).
struct ArmBothWays {
    generated: MassArm,
    model: kinematics_core::runtime::Model,
    mg: MassArmMotion,
    mr: kinematics_core::runtime::Motion,
}

impl ArmBothWays {
    fn new() -> Result<Self, Box<dyn std::error::Error>> {
        let generated = MassArm {
            d1: 0.4,
            a2: 0.5,
            a3: 0.4,
        };
        let model = kinematics_core::runtime::Model::compile(MASS_ARM_TEXT)?
            .with_values(&[0.4, 0.5, 0.4])?;
        let (q, qd, qdd) = ([0.3, -0.4, 0.9], [1.2, -0.7, 2.0], [3.0, 1.6, -2.5]);
        let mg = generated.step(&MassArmCoords::from(q), qd, qdd)?;
        let mr = model.step(&q, &qd, &qdd)?;
        Ok(Self {
            generated,
            model,
            mg,
            mr,
        })
    }
}

/// The same description resolved against the arm compiled at run time
/// gives the generated arm's forces (the same sums over the run-time
/// model's own analysis), and the engine's likewise with its unknowns.
#[test]
fn a_run_time_model_has_the_same_forces() -> Result<(), Box<dyn std::error::Error>> {
    let describe = || arm_bodies().torque("fore", |s| [0.0, 0.3 * s.qd(2), 0.0]);
    let arm = ArmBothWays::new()?;
    let (dg, dr) = (
        describe().build::<MassArm>()?,
        describe().build_for(&arm.model)?,
    );
    let (generated, model, mg, mr) = (&arm.generated, &arm.model, &arm.mg, &arm.mr);
    let (fg, fr) = (dg.inverse(generated, mg)?, dr.inverse_of(model, mr)?);
    for (k, g) in [fg.effort.q1, fg.effort.q2, fg.effort.q3]
        .into_iter()
        .enumerate()
    {
        close(fr.effort[k], g, 1e-12, "run-time effort");
    }
    close(
        fr.kinetic_energy,
        fg.kinetic_energy,
        1e-12,
        "kinetic energy",
    );
    close(
        fr.potential_energy,
        fg.potential_energy,
        1e-12,
        "potential energy",
    );
    for i in 0..3 {
        close(
            fr.shaking_force[i],
            fg.shaking_force[i],
            1e-12,
            "shaking force",
        );
        close(
            fr.shaking_moment[i],
            fg.shaking_moment[i],
            1e-12,
            "shaking moment",
        );
    }
    // A model of other sizes is refused.
    let engine = kinematics_core::runtime::Model::compile(
        "struct E { params { a, b } drivers { phi } unknowns { th, x } \
         loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); } }",
    )?
    .with_values(&[0.05, 0.2])?;
    let pose = engine.assemble(&[0.5, -0.1, 0.24])?;
    let motion = engine.analyze(&pose, &[10.0], &[0.0])?;
    assert!(matches!(
        dr.inverse_of(&engine, &motion),
        Err(Error::InvalidDynamics { .. })
    ));
    Ok(())
}

/// Names that do not exist, negative masses, tensors that are not
/// symmetric, planar bodies given frames, loads that are not finite: each
/// an `InvalidDynamics` error naming the item and what is wrong.
#[test]
fn bad_descriptions_are_errors_that_say_what_is_wrong() {
    let message = |r: Result<kinematics_core::dynamics::Dynamics, Error>| match r {
        Err(e @ Error::InvalidDynamics { .. }) => e.to_string(),
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("accepted"),
    };
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G9"))
            .build::<Engine>(),
    );
    assert!(
        m.contains("body `crank`") && m.contains("no point `G9`") && m.contains("G2, B, G3, C"),
        "{m}"
    );
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", -1.0).center("G2"))
            .build::<Engine>(),
    );
    assert!(m.contains("mass is -1"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("rod", 1.0))
            .build::<Engine>(),
    );
    assert!(m.contains("no centre of mass"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("rod", 1.0).center("G3").frame("rod"))
            .build::<Engine>(),
    );
    assert!(m.contains("planar") && m.contains(".angle("), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("rod", 1.0).center("G3").angle("x"))
            .build::<Engine>(),
    );
    assert!(m.contains("`x`, which is a length"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("piston", 1.0).center("C").inertia(0.1))
            .build::<Engine>(),
    );
    assert!(m.contains("does not turn"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(
                Body::new("crank", 1.0)
                    .center("G2")
                    .frame("crank")
                    .inertia_tensor([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
            )
            .build::<MassRssr>(),
    );
    assert!(m.contains("symmetric"), "{m}");
    let m = message(
        Dynamics::builder()
            .spring(Spring::new("B", "C").stiffness(f64::NAN))
            .build::<Engine>(),
    );
    assert!(
        m.contains("spring from `B` to `C`") && m.contains("stiffness is NaN"),
        "{m}"
    );
    let m = message(
        Dynamics::builder()
            .force("D", |_| [0.0; 3])
            .build::<Engine>(),
    );
    assert!(m.contains("force at `D`"), "{m}");
    let m = message(
        Dynamics::builder()
            .gravity([0.0, f64::INFINITY, 0.0])
            .build::<Engine>(),
    );
    assert!(m.contains("gravity"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G2").angle("phi"))
            .joint(Joint::revolute("bearing", "O", GROUND, "crank").driven_by("th"))
            .build::<Engine>(),
    );
    assert!(
        m.contains("joint `bearing`") && m.contains("no driver `th`"),
        "{m}"
    );
    let m = message(
        Dynamics::builder()
            .joint(Joint::prismatic(
                "cylinder",
                "C",
                GROUND,
                "piston",
                [1.0, 0.0],
            ))
            .build::<Engine>(),
    );
    assert!(
        m.contains("no body `piston`") && m.contains("`ground` for the frame"),
        "{m}"
    );
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G2").angle("phi"))
            .joint(Joint::revolute("bearing", "O", "crank", "crank"))
            .build::<Engine>(),
    );
    assert!(m.contains("to itself"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G2").angle("phi"))
            .joint(Joint::prismatic("slide", "O", GROUND, "crank", [0.0, 0.0]).driven_by("phi"))
            .build::<Engine>(),
    );
    assert!(m.contains("axis"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G2").frame("crank"))
            .joint(Joint::revolute("bearing", "A", GROUND, "crank"))
            .build::<MassRssr>(),
    );
    assert!(m.contains("needs its axis") && m.contains(".about("), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G2").angle("phi"))
            .joint(Joint::spherical("ball", "O", GROUND, "crank"))
            .build::<Engine>(),
    );
    assert!(m.contains("revolute or prismatic, not spherical"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G2").frame("crank"))
            .joint(Joint::spherical("ball", "A", GROUND, "crank").driven_by("phi"))
            .build::<MassRssr>(),
    );
    assert!(m.contains("transmits no driver's effort"), "{m}");
    let m = message(
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G2").frame("crank"))
            .joint(Joint::revolute("bearing", "A", GROUND, "crank").about([0.0, f64::NAN, 1.0]))
            .build::<MassRssr>(),
    );
    assert!(m.contains("finite and not zero"), "{m}");
    // Reactions that the joints do not determine, or a force on no body.
    let engine = Engine { a: A, b: B, r3: R3 };
    let motion = engine_motion(&engine, 0.5, 10.0, 0.0);
    let partial = Dynamics::builder()
        .body(Body::new("crank", 1.0).center("G2").angle("phi"))
        .body(Body::new("rod", 1.0).center("G3").angle("th"))
        .joint(Joint::revolute("bearing", "O", GROUND, "crank").driven_by("phi"))
        .joint(Joint::revolute("crank pin", "B", "crank", "rod"))
        .build::<Engine>()
        .expect("builds");
    let e = partial
        .reactions(&engine, &motion)
        .expect_err("underdetermined");
    assert!(
        e.to_string()
            .contains("5 unknown reaction components for the 6 equations"),
        "{e}"
    );
    let unplaced = Dynamics::builder()
        .body(Body::new("crank", 1.0).center("G2").angle("phi"))
        .force("B", |_| [1.0, 0.0, 0.0])
        .joint(Joint::revolute("bearing", "O", GROUND, "crank").driven_by("phi"))
        .build::<Engine>()
        .expect("builds");
    let e = unplaced
        .reactions(&engine, &motion)
        .expect_err("the force has no body");
    assert!(e.to_string().contains("force_on"), "{e}");
    // A load that is not finite at the instant.
    let engine = Engine { a: A, b: B, r3: R3 };
    let dynamics = Dynamics::builder()
        .force("C", |s| [1.0 / (s.position.x - s.position.x), 0.0, 0.0])
        .build::<Engine>()
        .expect("builds");
    let motion = engine_motion(&engine, 0.5, 10.0, 0.0);
    let e = dynamics
        .inverse(&engine, &motion)
        .expect_err("the force is infinite");
    assert!(
        e.to_string().contains("a force") && e.to_string().contains("must be finite"),
        "{e}"
    );
    // Built for one mechanism, used with another.
    let four_bar = MassFourBar {
        a: 0.04,
        b: 0.12,
        c: 0.1,
        d: 0.11,
        g3x: 0.0,
        g3y: 0.0,
    };
    let pose = four_bar
        .assemble(&MassFourBarCoords {
            phi: 0.0,
            th3: 1.0,
            th4: 1.6,
        })
        .expect("assembles");
    let motion = four_bar.analyze(&pose, 1.0, 0.0).expect("analyses");
    let e = Dynamics::builder()
        .build::<Engine>()
        .expect("builds")
        .inverse(&four_bar, &motion);
    assert!(matches!(e, Err(Error::InvalidDynamics { .. })), "{e:?}");
}

/// The driving torque's sensitivities to each link's mass and moment of
/// inertia, over a turn at a varying crank speed, against central
/// differences of the test's own Newton–Euler torque with that mass or
/// moment changed (the torque is linear in both, so the differences are
/// exact to round-off).
#[test]
fn a_four_bars_torque_sensitivities_to_its_masses_are_newton_eulers() -> Result<(), Error> {
    let m = FOUR_BAR;
    let dynamics = four_bar_bodies().build::<MassFourBar>()?;
    let mut pose = four_bar_start(&m)?;
    for k in 0..24 {
        let phi = TAU * f64::from(k) / 24.0;
        pose.phi = phi;
        let motion = m.step(&pose, 20.0 + 4.0 * phi.cos(), 60.0 * phi.sin())?;
        pose = motion.q;
        let s = dynamics.mass_sensitivities(&m, &motion)?;
        let names: Vec<&str> = s.iter().map(|b| b.body.as_str()).collect();
        assert_eq!(names, ["crank", "coupler", "rocker"]);
        for (b, body) in s.iter().enumerate() {
            let torque = |dm: f64, dj: f64| {
                let (mut masses, mut inertias) = (FOUR_BAR_MASSES, FOUR_BAR_INERTIAS);
                masses[b] += dm;
                inertias[b] += dj;
                let ne = four_bar_newton_euler(
                    &motion,
                    masses,
                    inertias,
                    (m.a, m.c, m.d),
                    (m.g3x, m.g3y),
                );
                ne.x[8]
            };
            let (h, hj) = (1e-2, 1e-4);
            let dm = (torque(h, 0.0) - torque(-h, 0.0)) / (2.0 * h);
            let dj = (torque(0.0, hj) - torque(0.0, -hj)) / (2.0 * hj);
            close(body.mass[0], dm, 1e-8, "∂T/∂m");
            let inertia = body
                .inertia
                .as_ref()
                .expect("a planar link turning by an angle");
            close(inertia[0], dj, 1e-8, "∂T/∂J");
        }
    }
    Ok(())
}

/// A run-time model's mass sensitivities are the generated mechanism's,
/// on the spatial arm (three drivers; its links turn with frames, so no
/// sensitivity to a moment of inertia).
#[test]
fn a_run_time_model_has_the_same_mass_sensitivities() -> Result<(), Box<dyn std::error::Error>> {
    let arm = ArmBothWays::new()?;
    let (dg, dr) = (
        arm_bodies().build::<MassArm>()?,
        arm_bodies().build_for(&arm.model)?,
    );
    let (sg, sr) = (
        dg.mass_sensitivities(&arm.generated, &arm.mg)?,
        dr.mass_sensitivities_of(&arm.model, &arm.mr)?,
    );
    assert_eq!(sg.len(), sr.len());
    for (g, r) in sg.iter().zip(&sr) {
        assert_eq!(g.body, r.body);
        assert!(g.inertia.is_none() && r.inertia.is_none());
        assert_eq!(g.mass.len(), 3);
        for (a, b) in r.mass.iter().zip(&g.mass) {
            close(*a, *b, 1e-12, "run-time ∂Q/∂m");
        }
    }
    Ok(())
}

/// The text of this file's `mechanism!` of the mechanism `name`, for the
/// same definition compiled at run time.
fn text_of(name: &str) -> &'static str {
    let head = format!("pub struct {name} {{");
    kinematics_examples::mechanism_bodies(include_str!("dynamics.rs"))
        .into_iter()
        .map(|(text, _)| text)
        .find(|text| text.contains(&head))
        .expect("the definition is in this file")
}

mechanism! {
    /// A slider-crank engine with its links' masses, gravity and gas force
    /// in `bodies` and `loads` sections.
    pub struct DefinedEngine {
        params   { a, b, r3, m2, j2, m3, j3, m4, g, p0, x0 }
        drivers  { phi }
        unknowns { th, x }
        points {
            G2 = polar(a / 2.0, phi);
            B = polar(a, phi);
            G3 = polar(a, phi) + polar(r3, th);
            C = vec2(x, 0.0);
        }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
        bodies {
            crank(mass = m2, center = G2, angle = phi, inertia = j2);
            rod(mass = m3, center = G3, angle = th, inertia = j3);
            piston(mass = m4, center = C);
        }
        loads {
            gravity(vec2(0.0, -g));
            // The gas force falls with the volume: p0 (x0 / x)².
            force(C, vec2(-p0 * powi(x0 / x, 2), 0.0), on = piston);
        }
    }
}

const DEFINED_ENGINE: DefinedEngine = DefinedEngine {
    a: A,
    b: B,
    r3: R3,
    m2: M2,
    j2: J2,
    m3: M3,
    j3: J3,
    m4: M4,
    g: G,
    p0: 2000.0,
    x0: 0.3,
};

/// The engine defined with `bodies` and `loads` sections, at a varying
/// crank speed: the crank torque against the test's Newton–Euler solve
/// (the gas force 2000 (0.3 / x)², as [`gas`]), generated by the macro
/// and compiled at run time from the same text.
#[test]
fn an_engine_defined_with_bodies_and_loads_has_the_newton_euler_torque(
) -> Result<(), Box<dyn std::error::Error>> {
    let m = DEFINED_ENGINE;
    let dynamics = m.dynamics()?;
    let model = kinematics_core::runtime::Model::compile(text_of("DefinedEngine"))?
        .with_values(&m.parameter_values())?;
    let run_time = model.dynamics()?;
    for k in 0..90 {
        let phi = TAU * f64::from(k) / 90.0 + 0.003;
        let (w, al) = (150.0 + 30.0 * phi.sin(), -800.0 * phi.cos());
        let kin = engine_kinematics(phi, w, al);
        let pose = m.assemble(&DefinedEngineCoords {
            phi,
            th: kin.th,
            x: kin.x,
        })?;
        let motion = m.analyze(&pose, w, al)?;
        let forces = dynamics.inverse(&m, &motion)?;
        let expected = engine_newton_euler(phi, w, al, gas(kin.x))[7];
        close(forces.effort.phi, expected, 1e-10, "crank torque");
        let fx = -(M2 * kin.a_g2[0] + M3 * kin.a_g3[0] + M4 * kin.a_c);
        close(forces.shaking_force.x, fx, 1e-10, "shaking force x");
        // The same definition compiled at run time.
        let rm = model.analyze(&[phi, pose.th, pose.x], &[w], &[al])?;
        let rf = run_time.inverse_of(&model, &rm)?;
        close(
            rf.effort[0],
            forces.effort.phi,
            1e-13,
            "run-time crank torque",
        );
        close(
            rf.potential_energy,
            forces.potential_energy,
            1e-13,
            "run-time potential energy",
        );
    }
    Ok(())
}

mechanism! {
    /// A massless slider-crank with a damper on the piston, a spring from
    /// the crank pin to a fixed point and a torque on the rod.
    pub struct Damped {
        params   { a, b, c, k, l0, t0 }
        drivers  { phi }
        unknowns { th, x }
        points {
            B = polar(a, phi);
            C = vec2(x, 0.0);
            O = vec2(0.0, 0.0);
            D = vec2(0.0, 0.1);
        }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
        bodies { rod(mass = 0.0, center = B, angle = th); }
        loads {
            force(x, -c * rate(x));
            spring(D, B, stiffness = k, free_length = l0);
            torque(rod, t0 * rate(th));
        }
    }
}

/// Each load of the `loads` section by virtual work, with massless links:
/// a damper −c ẋ on the piston needs the effort c ω (dx/dφ)², a spring
/// from D to the crank pin B the effort k (L − L₀) ∂L/∂φ, a torque τ on
/// the rod the effort −τ dθ/dφ, with x, θ and L in closed form and their
/// derivatives by central differences of the closed form.
#[test]
fn each_load_of_a_loads_section_does_its_virtual_work() -> Result<(), Error> {
    let (a, b) = (0.05, 0.2);
    let (c, k, l0, t0) = (30.0, 800.0, 0.08, 0.02);
    let x_of = |phi: f64| a * phi.cos() + (b * b - (a * phi.sin()).powi(2)).sqrt();
    let th_of = |phi: f64| (-(a / b) * phi.sin()).asin();
    let l_of = |phi: f64| (a * phi.cos()).hypot(a * phi.sin() - 0.1);
    let d = |f: &dyn Fn(f64) -> f64, phi: f64| {
        let h = 1e-5;
        (-f(phi + 2.0 * h) + 8.0 * f(phi + h) - 8.0 * f(phi - h) + f(phi - 2.0 * h)) / (12.0 * h)
    };
    let w = 40.0;
    for (terms, name) in [
        ((c, 0.0, 0.0), "damper"),
        ((0.0, k, 0.0), "spring"),
        ((0.0, 0.0, t0), "torque"),
    ] {
        let m = Damped {
            a,
            b,
            c: terms.0,
            k: terms.1,
            l0,
            t0: terms.2,
        };
        let dynamics = m.dynamics()?;
        for j in 0..24 {
            let phi = TAU * f64::from(j) / 24.0 + 0.1;
            let pose = m.assemble(&DampedCoords {
                phi,
                th: th_of(phi),
                x: x_of(phi),
            })?;
            let motion = m.analyze(&pose, w, 0.0)?;
            let effort = dynamics.inverse(&m, &motion)?.effort.phi;
            let (dx, dth, dl) = (d(&x_of, phi), d(&th_of, phi), d(&l_of, phi));
            let expected = match name {
                "damper" => c * w * dx * dx,
                "spring" => k * (l_of(phi) - l0) * dl,
                _ => -(t0 * dth * w) * dth,
            };
            close(effort, expected, 1e-8, name);
        }
    }
    Ok(())
}

mechanism! {
    /// An RSSR with its links' masses.
    pub struct DefinedRssr {
        params   { a, b, c, d, g }
        drivers  { phi }
        unknowns { psi }
        frames {
            crank = rot_y(-phi);
            rocker = translation(vec3(-d, 0.0, 0.0)) * rot_z(-psi);
        }
        points {
            A = vec3(-a * cos(phi), 0.0, a * sin(phi));
            B = vec3(-d - c * cos(psi), c * sin(psi), 0.0);
            G2 = vec3(-a * cos(phi) / 2.0, 0.0, a * sin(phi) / 2.0);
            G3 = 0.5 * (vec3(-a * cos(phi), 0.0, a * sin(phi)) + vec3(-d - c * cos(psi), c * sin(psi), 0.0));
            G4 = vec3(-d - c * cos(psi) / 2.0, c * sin(psi) / 2.0, 0.0);
        }
        constraints { norm(B - A) == b; }
        bodies {
            crank(mass = 0.2, center = G2, frame = crank,
                  inertia = [[3e-5, 2e-6, 0.0], [2e-6, 1e-5, 1e-6], [0.0, 1e-6, 3e-5]]);
            coupler(mass = 0.4, center = G3);
            rocker(mass = 0.3, center = G4, frame = rocker,
                   inertia = [[2e-5, 2e-6, 0.0], [2e-6, 4e-5, 1e-6], [0.0, 1e-6, 5e-5]]);
        }
        loads { gravity(vec3(0.0, -g, -2.0)); }
    }
}

/// The RSSR defined with sections: the drivers' power against the
/// fourth-order central difference of its energy T + V along a motion
/// (gravity the only load), and the same forces from the definition
/// compiled at run time.
#[test]
fn an_rssr_defined_with_bodies_and_loads_has_the_power_of_its_energy(
) -> Result<(), Box<dyn std::error::Error>> {
    let m = DefinedRssr {
        a: 0.03,
        b: 0.12,
        c: 0.08,
        d: 0.1,
        g: G,
    };
    let dynamics = m.dynamics()?;
    let model = kinematics_core::runtime::Model::compile(text_of("DefinedRssr"))?
        .with_values(&m.parameter_values())?;
    let run_time = model.dynamics()?;
    let start = m.assemble(&DefinedRssrCoords { phi: 0.7, psi: 1.1 })?;
    let at = |t: f64| (0.7 + 9.0 * t + 20.0 * t * t, 9.0 + 40.0 * t, 40.0);
    let motion_at = |t: f64| -> Result<DefinedRssrMotion, Error> {
        let (p, w, al) = at(t);
        let mut q = start;
        q.phi = p;
        m.step(&q, w, al)
    };
    let energy = |t: f64| -> Result<f64, Error> {
        let f = dynamics.inverse(&m, &motion_at(t)?)?;
        Ok(f.kinetic_energy + f.potential_energy)
    };
    for t in [0.0, 0.01, 0.03] {
        let h = 1e-4;
        let rate = (-energy(t + 2.0 * h)? + 8.0 * energy(t + h)? - 8.0 * energy(t - h)?
            + energy(t - 2.0 * h)?)
            / (12.0 * h);
        let motion = motion_at(t)?;
        let f = dynamics.inverse(&m, &motion)?;
        assert!(f.power.abs() > 1e-3, "power {} W: a test", f.power);
        close(f.power, rate, 1e-8, "power against d(T + V)/dt");
        let (_, w, al) = at(t);
        let rm = model.analyze(&[motion.q.phi, motion.q.psi], &[w], &[al])?;
        let rf = run_time.inverse_of(&model, &rm)?;
        close(rf.effort[0], f.effort.phi, 1e-13, "run-time effort");
        close(
            rf.kinetic_energy,
            f.kinetic_energy,
            1e-13,
            "run-time energy",
        );
    }
    Ok(())
}

mechanism! {
    /// An RSSR whose crank turns about y through O and whose rocker turns
    /// about z through D, with the frames that carry them (the crank's
    /// arm along its frame's x, the rocker's likewise), and the coupler a
    /// point mass between its two ball joints.
    pub struct ReactedRssr {
        params   { a, b, c, d }
        drivers  { phi }
        unknowns { psi }
        frames {
            crank = rot_y(phi);
            rocker = translation(vec3(-d, 0.0, 0.0)) * rot_z(psi);
        }
        points {
            O = vec3(0.0, 0.0, 0.0);
            A = vec3(a * cos(phi), 0.0, -a * sin(phi));
            B = vec3(-d + c * cos(psi), c * sin(psi), 0.0);
            D = vec3(-d, 0.0, 0.0);
            G2 = vec3(a * cos(phi) / 2.0, 0.0, -a * sin(phi) / 2.0);
            G3 = 0.5 * (vec3(a * cos(phi), 0.0, -a * sin(phi)) + vec3(-d + c * cos(psi), c * sin(psi), 0.0));
            G4 = vec3(-d + c * cos(psi) / 2.0, c * sin(psi) / 2.0, 0.0);
        }
        constraints { norm(B - A) == b; }
        bodies {
            crank(mass = 0.2, center = G2, frame = crank,
                  inertia = [[3e-5, 2e-6, 0.0], [2e-6, 1e-5, 1e-6], [0.0, 1e-6, 3e-5]]);
            coupler(mass = 0.4, center = G3);
            rocker(mass = 0.3, center = G4, frame = rocker,
                   inertia = [[2e-5, 2e-6, 0.0], [2e-6, 4e-5, 1e-6], [0.0, 1e-6, 5e-5]]);
        }
        loads { gravity(vec3(0.0, -9.81, -2.0)); }
        joints {
            bearing(revolute, O, between = (ground, crank), axis = vec3(0.0, 1.0, 0.0), driver = phi);
            crank_ball(spherical, A, between = (crank, coupler));
            rocker_ball(spherical, B, between = (coupler, rocker));
            pivot(revolute, D, between = (ground, rocker), axis = vec3(0.0, 0.0, 1.0));
        }
    }
}

/// The reactions of the RSSR's four joints (two revolute, two spherical:
/// 17 unknowns for the 18 equations of three bodies, the coupler free to
/// spin about the line through its balls) against a Newton–Euler solution
/// written here, over a turn at varying speed:
///
/// - the coupler, a point mass at the middle of A and B, takes F_A from
///   the crank and −F_B from the rocker: F_A − F_B = m₃ (a₃ − g), and its
///   moments about its centre, h × (F_A + F_B) = 0 with h = (B − A)/2,
///   make F_A + F_B = λ (B − A);
/// - the rocker turns freely about z at D: ((B − D) × F_B)_z equals the
///   z component of (G₄ − D) × m₄ (a₄ − g) + J₄ α₄ + ω₄ × J₄ ω₄, which
///   gives λ;
/// - the crank: the motor's torque about y, the bearings' forces from
///   each body's momentum, and their moments normal to the axes.
///
/// ω and α of the links are those of their axes (φ' y, ψ' z), and the
/// inertia tensors are turned by rotations written here. The joints are
/// those of the definition's `joints` section; the driver's torque also
/// equals the virtual-power effort, and the run-time model and the same
/// joints declared in Rust (the bearing's axis not of unit length) give
/// the same reactions.
#[test]
fn the_joint_reactions_of_an_rssr_match_a_newton_euler_solution(
) -> Result<(), Box<dyn std::error::Error>> {
    use kinematics_core::nalgebra::Matrix3;
    let m = ReactedRssr {
        a: 0.03,
        b: 0.12,
        c: 0.08,
        d: 0.1,
    };
    // The joints of the definition's `joints` section, and the same
    // joints declared in Rust (the reactions from both, compared below).
    let dynamics = m.dynamics()?;
    let declared = Dynamics::builder()
        .body(
            Body::new("crank", 0.2)
                .center("G2")
                .frame("crank")
                .inertia_tensor([[3e-5, 2e-6, 0.0], [2e-6, 1e-5, 1e-6], [0.0, 1e-6, 3e-5]]),
        )
        .body(Body::new("coupler", 0.4).center("G3"))
        .body(
            Body::new("rocker", 0.3)
                .center("G4")
                .frame("rocker")
                .inertia_tensor([[2e-5, 2e-6, 0.0], [2e-6, 4e-5, 1e-6], [0.0, 1e-6, 5e-5]]),
        )
        .gravity([0.0, -G, -2.0])
        .joint(
            Joint::revolute("bearing", "O", GROUND, "crank")
                .about([0.0, 2.0, 0.0])
                .driven_by("phi"),
        )
        .joint(Joint::spherical("crank_ball", "A", "crank", "coupler"))
        .joint(Joint::spherical("rocker_ball", "B", "coupler", "rocker"))
        .joint(Joint::revolute("pivot", "D", GROUND, "rocker").about([0.0, 0.0, 1.0]))
        .build::<ReactedRssr>()?;
    let model = kinematics_core::runtime::Model::compile(text_of("ReactedRssr"))?
        .with_values(&m.parameter_values())?;
    let run_time = model.dynamics()?;
    let g = Vector3::new(0.0, -G, -2.0);
    let (m2, m3, m4) = (0.2, 0.4, 0.3);
    let tensor = |x: f64, y: f64, z: f64| Matrix3::new(x, 2e-6, 0.0, 2e-6, y, 1e-6, 0.0, 1e-6, z);
    let (j2, j4) = (tensor(3e-5, 1e-5, 3e-5), tensor(2e-5, 4e-5, 5e-5));
    let mut pose = m.assemble(&ReactedRssrCoords { phi: 0.0, psi: 1.1 })?;
    let mut checked = 0;
    for k in 0..72 {
        let phi = TAU * f64::from(k) / 72.0;
        let (w, al) = (12.0 + 5.0 * phi.sin(), 30.0 * phi.cos());
        pose.phi = phi;
        let motion = m.step(&pose, w, al)?;
        pose = motion.q;
        let (psi, wp, ap) = (motion.q.psi, motion.qd.psi, motion.qdd.psi);
        let v = |p: &kinematics_core::PointMotion<3>| (p.position, p.acceleration);
        let (a_pt, _) = v(motion.point_a());
        let (b_pt, _) = v(motion.point_b());
        let (d_pt, _) = v(motion.point_d());
        let (g2, a2) = v(motion.point_g2());
        let (_, a3) = v(motion.point_g3());
        let (g4, a4) = v(motion.point_g4());
        let (s, c) = phi.sin_cos();
        let r2 = Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c);
        let (s, c) = psi.sin_cos();
        let r4 = Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        let (j2, j4) = (r2 * j2 * r2.transpose(), r4 * j4 * r4.transpose());
        let (w2, al2) = (Vector3::y() * w, Vector3::y() * al);
        let (w4, al4) = (Vector3::z() * wp, Vector3::z() * ap);
        // The coupler, then the rocker about its axis.
        let kk = (a3 - g) * m3;
        let rocker = (g4 - d_pt).cross(&((a4 - g) * m4)) + j4 * al4 + w4.cross(&(j4 * w4));
        let arm = b_pt - d_pt;
        let lambda = (2.0 * rocker.z + arm.cross(&kk).z) / arm.cross(&(b_pt - a_pt)).z;
        let f_a = ((b_pt - a_pt) * lambda + kk) / 2.0;
        let f_b = ((b_pt - a_pt) * lambda - kk) / 2.0;
        // The crank about O (at the origin), and the bearings.
        let crank = g2.cross(&((a2 - g) * m2)) + j2 * al2 + w2.cross(&(j2 * w2));
        let moment_o = crank + a_pt.cross(&f_a);
        let torque = moment_o.y;
        let moment_o = moment_o - Vector3::y() * torque;
        let f_o = (a2 - g) * m2 + f_a;
        let f_d = (a4 - g) * m4 - f_b;
        let moment_d = rocker - arm.cross(&f_b);
        close(moment_d.z, 0.0, 1e-12, "no moment about the rocker's axis");
        let r = dynamics.reactions(&m, &motion)?;
        assert!(r.spatial);
        let get = |n: &str| r.get(n).expect("a joint");
        let scale = 1.0 + f_o.norm().max(f_d.norm());
        let same = |got: Vector3<f64>, want: Vector3<f64>, what: &str| {
            for i in 0..3 {
                close(got[i] / scale, want[i] / scale, 1e-10, what);
            }
        };
        same(get("crank_ball").force, f_a, "F_A");
        same(get("rocker_ball").force, f_b, "F_B");
        same(get("bearing").force, f_o, "F_O");
        same(get("pivot").force, f_d, "F_D");
        same(get("bearing").moment, moment_o, "M_O");
        same(get("pivot").moment, moment_d, "M_D");
        same(
            get("crank_ball").moment,
            Vector3::zeros(),
            "no moment at a ball joint",
        );
        same(
            get("rocker_ball").force_in_body,
            r4.transpose() * f_b,
            "F_B in the rocker's axes",
        );
        let effort = get("bearing").effort.expect("driven");
        close(effort, torque, 1e-10, "the motor's torque");
        close(
            effort,
            dynamics.inverse(&m, &motion)?.effort.phi,
            1e-10,
            "the motor's torque by virtual power",
        );
        let rm = model.analyze(&[motion.q.phi, motion.q.psi], &[w], &[al])?;
        let rr = run_time.reactions_of(&model, &rm)?;
        let rd = declared.reactions(&m, &motion)?;
        assert_eq!((rr.joints.len(), rd.joints.len()), (4, 4));
        for ((x, y), z) in rr.joints.iter().zip(&r.joints).zip(&rd.joints) {
            assert!(x.name == y.name && z.name == y.name);
            same(x.force, y.force, "run-time force");
            same(x.moment, y.moment, "run-time moment");
            same(z.force, y.force, "the joints declared in Rust");
            same(z.moment, y.moment, "the joints declared in Rust");
        }
        checked += 1;
    }
    assert_eq!(checked, 72);
    Ok(())
}

/// A coupler with inertia about the line through its two ball joints
/// cannot be held by them: the reactions say so rather than return forces
/// that miss an equation.
#[test]
fn a_spinning_coupler_with_inertia_is_an_error() -> Result<(), Box<dyn std::error::Error>> {
    let m = ReactedRssr {
        a: 0.03,
        b: 0.12,
        c: 0.08,
        d: 0.1,
    };
    let dynamics = Dynamics::builder()
        .body(Body::new("crank", 0.2).center("G2").frame("crank"))
        .body(
            Body::new("coupler", 0.4)
                .center("G3")
                .frame("rocker")
                .inertia_tensor([[1e-3, 0.0, 0.0], [0.0, 2e-3, 0.0], [0.0, 0.0, 3e-3]]),
        )
        .body(Body::new("rocker", 0.3).center("G4").frame("rocker"))
        .joint(
            Joint::revolute("O", "O", GROUND, "crank")
                .about([0.0, 1.0, 0.0])
                .driven_by("phi"),
        )
        .joint(Joint::spherical("A", "A", "crank", "coupler"))
        .joint(Joint::spherical("B", "B", "coupler", "rocker"))
        .joint(Joint::revolute("D", "D", GROUND, "rocker").about([0.0, 0.0, 1.0]))
        .build::<ReactedRssr>()?;
    let pose = m.assemble(&ReactedRssrCoords { phi: 0.4, psi: 1.1 })?;
    let motion = m.step(&pose, 20.0, 50.0)?;
    let e = dynamics
        .reactions(&m, &motion)
        .expect_err("no reactions satisfy it");
    assert!(e.to_string().contains("spins about the line"), "{e}");
    Ok(())
}

/// The examples' gas engine declares its joints in its definition: over a
/// turn at varying speed its reactions are those of the same joints
/// declared in Rust on the same bodies and loads, the bearing's torque is
/// the virtual-power effort (also with a torque on the driver's
/// coordinate, which acts in the bearing), and the frame's reactions (the
/// bearing's and the cylinder's forces) balance the links' weight,
/// inertia and the gas.
#[test]
fn the_joints_of_the_gas_engines_definition_give_its_reactions(
) -> Result<(), Box<dyn std::error::Error>> {
    use kinematics_examples::{GasEngine, GasEngineCoords};
    let g = GasEngine::SMALL;
    let dynamics = g.dynamics()?;
    let gas = move |x: f64| g.p1 * g.area * (g.h1 / (g.h0 + g.a + g.b - x)).powf(1.3);
    let declared = Dynamics::builder()
        .body(
            Body::new("crank", g.m2)
                .center("O")
                .angle("phi")
                .inertia(g.j2),
        )
        .body(
            Body::new("rod", g.m3)
                .center("G3")
                .angle("th")
                .inertia(g.j3),
        )
        .body(Body::new("piston", g.m4).center("C"))
        .gravity([0.0, -G, 0.0])
        .force_on("piston", "C", move |s| [-gas(s.q(2)), 0.0, 0.0])
        .joint(Joint::revolute("bearing", "O", GROUND, "crank").driven_by("phi"))
        .joint(Joint::revolute("crank_pin", "B", "crank", "rod"))
        .joint(Joint::revolute("piston_pin", "C", "rod", "piston"))
        .joint(Joint::prismatic(
            "cylinder",
            "C",
            GROUND,
            "piston",
            [2.0, 0.0],
        ))
        .build::<GasEngine>()?;
    let helped = g
        .dynamics_builder()
        .coordinate_force("phi", |_| 5.0)
        .build::<GasEngine>()?;
    let mut pose = g.assemble(&GasEngineCoords {
        phi: 0.0,
        th: 0.0,
        x: 0.125,
    })?;
    for k in 0..36 {
        let phi = TAU * f64::from(k) / 36.0;
        let (w, al) = (300.0 + 40.0 * phi.cos(), 2000.0 * phi.sin());
        pose.phi = phi;
        let motion = g.step(&pose, w, al)?;
        pose = motion.q;
        let r = dynamics.reactions(&g, &motion)?;
        let rd = declared.reactions(&g, &motion)?;
        assert!(!r.spatial);
        let names: Vec<&str> = r.joints.iter().map(|j| j.name.as_str()).collect();
        assert_eq!(names, ["bearing", "crank_pin", "piston_pin", "cylinder"]);
        let scale = 1.0 + r.joints.iter().map(|j| j.force.norm()).fold(0.0, f64::max);
        for (x, y) in r.joints.iter().zip(&rd.joints) {
            for i in 0..3 {
                close(x.force[i] / scale, y.force[i] / scale, 1e-12, &x.name);
                close(x.moment[i] / scale, y.moment[i] / scale, 1e-12, &x.name);
            }
        }
        let effort = r.get("bearing").and_then(|j| j.effort).expect("driven");
        close(
            effort,
            dynamics.inverse(&g, &motion)?.effort.phi,
            1e-10,
            "the bearing's torque by virtual power",
        );
        // A torque of 5 N·m on the crank's coordinate acts in the joint its
        // driver acts in: the motor gives 5 N·m less, by both methods.
        let helped_torque = helped
            .reactions(&g, &motion)?
            .get("bearing")
            .and_then(|j| j.effort)
            .expect("driven");
        close(helped_torque, effort - 5.0, 1e-10, "a torque on phi");
        close(
            helped_torque,
            helped.inverse(&g, &motion)?.effort.phi,
            1e-10,
            "a torque on phi by virtual power",
        );
        // The frame holds the links: the force it exerts on them is their
        // rate of momentum less their weight and the gas force.
        let ground =
            r.get("bearing").expect("bearing").force + r.get("cylinder").expect("cylinder").force;
        let parts = [
            (g.m2, motion.point_o().acceleration),
            (g.m3, motion.point_g3().acceleration),
            (g.m4, motion.point_c().acceleration),
        ];
        let momentum = parts
            .iter()
            .fold([0.0; 2], |s, (m, a)| [s[0] + m * a[0], s[1] + m * a[1]]);
        let weight = -G * (g.m2 + g.m3 + g.m4);
        close(
            ground.x / scale,
            (momentum[0] + gas(motion.q.x)) / scale,
            1e-10,
            "x balance",
        );
        close(
            ground.y / scale,
            (momentum[1] - weight) / scale,
            1e-10,
            "y balance",
        );
    }
    Ok(())
}
