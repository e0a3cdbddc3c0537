//! Joint reactions against Newton–Euler solves of an engine and a four-bar, forces on coordinates and springs between links.

use super::*;
#[allow(unused_imports)]
use super::{descriptions::*, efforts::*, energy::*, sections::*};

/// The gas force on the engine's piston at x: 2000 (0.3 / x)² N.
pub(crate) fn gas(x: f64) -> f64 {
    2000.0 * (0.3 / x).powi(2)
}

/// The engine's links as bodies, gravity, the gas force on the piston and
/// the joints: the crank's bearing (driven), the crank pin, the piston pin
/// and the cylinder.
pub(crate) fn engine_with_joints() -> kinematics_core::dynamics::DynamicsBuilder {
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

/// The total force and moment of the engine on its frame (Norton's shaking
/// force: weights and the gas force included) from the virtual-power sums,
/// against the ground's reactions of the Newton–Euler solve negated: the
/// crank's bearing at O, the cylinder's normal force and moment at C and
/// the driver's torque; and the inertial part alone, −Σ m a_G, differs
/// from it by the weights and the gas force.
#[test]
fn the_engines_force_on_its_frame_is_its_ground_reactions() -> Result<(), Error> {
    let m = Engine { a: A, b: B, r3: R3 };
    let dynamics = engine_with_joints().build::<Engine>()?;
    for k in 0..24 {
        let phi = TAU * f64::from(k) / 24.0 + 0.03;
        let (w, al) = (150.0 + 30.0 * phi.sin(), -800.0 * phi.cos());
        let motion = engine_motion(&m, phi, w, al);
        let (f, r) = (
            dynamics.inverse(&m, &motion)?,
            dynamics.reactions(&m, &motion)?,
        );
        let get = |name: &str| r.get(name).expect("a joint of the engine");
        let (bearing, cylinder) = (get("bearing"), get("cylinder"));
        let x = motion.q.x;
        let scale = bearing.force.norm() + cylinder.force.norm();
        let near = |p: f64, q: f64, what: &str| {
            assert!(
                (p - q).abs() <= 1e-11 * scale,
                "{what} at {phi}: {p} against {q}"
            );
        };
        near(
            f.frame_force.x,
            -(bearing.force.x + cylinder.force.x),
            "force x",
        );
        near(
            f.frame_force.y,
            -(bearing.force.y + cylinder.force.y),
            "force y",
        );
        // About O: the bearing's force passes through it; the cylinder's
        // acts at C = (x, 0); the driver's torque reacts on the frame.
        let torque = bearing.effort.expect("driven");
        let at_c = x * cylinder.force.y;
        near(
            f.frame_moment.z,
            -(torque + at_c + cylinder.moment.z),
            "moment",
        );
        let weights = -G * (M2 + M3 + M4);
        near(
            f.frame_force.x - f.shaking_force.x,
            -gas(x),
            "the gas force",
        );
        near(f.frame_force.y - f.shaking_force.y, weights, "the weights");
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
