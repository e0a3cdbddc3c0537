//! Run-time models against the generated ones, bad descriptions and their errors, mass sensitivities.

use super::*;
#[allow(unused_imports)]
use super::{efforts::*, energy::*, reactions::*, sections::*};

/// The arm's definition as text, for the same model compiled at run time.
pub(crate) const MASS_ARM_TEXT: &str = "
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
pub(crate) struct ArmBothWays {
    pub(crate) generated: MassArm,
    pub(crate) model: kinematics_core::runtime::Model,
    pub(crate) mg: MassArmMotion,
    pub(crate) mr: kinematics_core::runtime::Motion,
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
    // A force that names no body acts on the one its point moves with: B
    // on the crank, as if named.
    let crank = || {
        Dynamics::builder()
            .body(Body::new("crank", 1.0).center("G2").angle("phi"))
            .joint(Joint::revolute("bearing", "O", GROUND, "crank").driven_by("phi"))
    };
    let unplaced = crank()
        .force("B", |_| [1.0, 0.0, 0.0])
        .build::<Engine>()
        .expect("builds");
    let placed = crank()
        .force_on("crank", "B", |_| [1.0, 0.0, 0.0])
        .build::<Engine>()
        .expect("builds");
    assert_eq!(
        unplaced
            .reactions(&engine, &motion)
            .expect("B is on the crank"),
        placed.reactions(&engine, &motion).expect("named")
    );
    // At crank 90° the rod translates (θ' = 0): a force at its G3 is still
    // placed on it, by the accelerations.
    let motion = engine_motion(&engine, std::f64::consts::FRAC_PI_2, 10.0, 0.0);
    fn load(_: &kinematics_core::dynamics::Instant<'_>) -> [f64; 3] {
        [3.0, -2.0, 0.0]
    }
    let unplaced = engine_with_joints().force("G3", load).build::<Engine>();
    let placed = engine_with_joints()
        .force_on("rod", "G3", load)
        .build::<Engine>();
    assert_eq!(
        unplaced
            .expect("builds")
            .reactions(&engine, &motion)
            .expect("placed"),
        placed
            .expect("builds")
            .reactions(&engine, &motion)
            .expect("named")
    );
    // At 0° the piston is at rest; the fixed O is the crank's pivot, on the
    // crank and on the frame: the force must say which.
    let motion = engine_motion(&engine, 0.0, 10.0, 0.0);
    let e = engine_with_joints()
        .force("O", load)
        .build::<Engine>()
        .expect("builds")
        .reactions(&engine, &motion)
        .expect_err("a pivot");
    assert!(
        e.to_string()
            .contains("`O` is a pivot of `crank` on the frame"),
        "{e}"
    );
    // At the crank pin, B is on the crank and on the rod: named by its
    // point and the two bodies, in both syntaxes.
    let pinned = engine_with_joints()
        .force("B", |_| [1.0, 0.0, 0.0])
        .build::<Engine>()
        .expect("builds");
    let e = pinned
        .reactions(&engine, &motion)
        .expect_err("B is on two bodies");
    assert!(
        e.to_string().contains(
            "the force at point `B` names no body, and `B` moves with `crank` and `rod` (a pin"
        ) && e.to_string().contains("`force(B, …, on = body)`")
            && e.to_string().contains("`.force_on(\"body\", \"B\", …)`"),
        "{e}"
    );
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
        e.to_string().contains("the force at point `C`")
            && e.to_string().contains("must be finite"),
        "{e}"
    );
    // A motion that is not finite where the reactions read it: named by
    // the body whose centre of mass it is (G3, the third point, the rod's).
    let mut motion = engine_motion(&engine, 0.5, 10.0, 0.0);
    motion.points[2].acceleration.x = f64::NAN;
    let e = engine_with_joints()
        .build::<Engine>()
        .expect("builds")
        .reactions(&engine, &motion)
        .expect_err("not finite");
    assert!(
        e.to_string()
            .contains("the centre of mass `G3` of body `rod` has a position, velocity or acceleration that is not finite"),
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
