//! Energy balance: the driver's work over a cycle, dampers, the power of spatial mechanisms against finite differences of their energy, Lagrange's equations of an arm, energy fluctuation, sweeps of forces.

use super::*;
#[allow(unused_imports)]
use super::{descriptions::*, efforts::*, reactions::*, sections::*};

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

/// The RSSR's bodies, with inertia tensors in its crank's and rocker's
/// frames and the coupler as a point mass, and gravity off the plane's
/// axes.
pub(crate) fn rssr_description() -> kinematics_core::dynamics::DynamicsBuilder {
    let tensor = |x: f64, y: f64, z: f64| [[x, 2e-6, 0.0], [2e-6, y, 1e-6], [0.0, 1e-6, z]];
    Dynamics::builder()
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
    let dynamics = rssr_description().build::<MassRssr>()?;
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
pub(crate) fn arm_bodies() -> kinematics_core::dynamics::DynamicsBuilder {
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
    let dynamics = sprung_four_bar()?;
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
        "phi (deg),Q_phi (N·m),T (J),V (J),P (W),Fs_x (N),Fs_y (N),Fs_z (N),Ms_x (N·m),Ms_y (N·m),Ms_z (N·m),\
         Ff_x (N),Ff_y (N),Ff_z (N),Mf_x (N·m),Mf_y (N·m),Mf_z (N·m)"
    );
    assert_eq!(csv.lines().count(), 1442);
    Ok(())
}

/// The four-bar's bodies with a spring between the centres of its crank
/// and rocker: a conservative cycle.
fn sprung_four_bar() -> Result<Dynamics, Error> {
    four_bar_bodies()
        .spring(Spring::new("G2", "G4").stiffness(800.0).free_length(0.09))
        .build::<MassFourBar>()
}

/// The same cycle swept with `.turn()`, which leaves out the closing
/// sample: the mean torque closes the cycle (the periodic trapezoidal
/// rule) and is zero to round-off, where the trapezoid over the samples
/// alone left out the last interval (a bias of about 1e-3 of the peak).
#[test]
fn the_mean_torque_of_a_turn_without_its_closing_sample_is_zero() -> Result<(), Error> {
    let m = FOUR_BAR;
    let dynamics = sprung_four_bar()?;
    let start = four_bar_start(&m)?;
    for steps in [360, 361, 1440] {
        let sweep = m
            .sweep(MassFourBar::PHI, &start)
            .turn()
            .steps(steps)
            .rpm(300.0)
            .run();
        assert!(sweep.stop.is_none());
        let forces = dynamics.along(&m, &sweep)?;
        assert_eq!(forces.samples.len(), steps);
        let peak = forces
            .samples
            .iter()
            .map(|s| s.effort[0].abs())
            .fold(0.0, f64::max);
        let mean = forces.mean_effort(0).expect("a turn");
        // What the samples alone give: the trapezoid short of its last
        // interval, the bias this rule removes.
        let open: f64 = forces
            .samples
            .windows(2)
            .map(|w| 0.5 * (w[0].effort[0] + w[1].effort[0]) * (w[1].at - w[0].at))
            .sum::<f64>()
            / (forces.samples[steps - 1].at - forces.samples[0].at);
        assert!(
            mean.abs() < 1e-9 * peak && open.abs() > 1e-5 * peak,
            "{steps} steps: mean {mean} N·m (open rule {open}), peak {peak} N·m"
        );
    }
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
    // The sweep, 1 effort, 3 energies and power, 4 vectors of 3, 4 joints
    // of 3.
    assert_eq!(csv.lines().nth(1).map(|l| l.split(',').count()), Some(29));
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
