//! The compiled equations of motion a generated mechanism carries for its
//! `bodies` and `loads` sections (`Mechanism::equations_of_motion`),
//! against what they must equal: Φ_q against central differences of the
//! loop residual, ½ q̇ᵀ M̃ q̇ against the kinetic energy of the inverse
//! analysis, Cᵀ f̃ against its driving effort, a load's power against its
//! closed form; and a forward simulation through them against the same
//! simulation summing the bodies and loads at run time.

use super::efforts::*;
use super::sections::*;
use super::*;
use kinematics_core::{Coordinates, Mechanism};

/// The outputs of `equations_of_motion` at a motion, split: in all the
/// coordinates Φ_q (u × n), M̃ (n × n, from its upper triangle), f̃ and
/// the powers; reduced (`Mechanism::MOTION_REDUCED`), the driver's M and b
/// and the powers.
enum Split {
    Full {
        jacobian: DMatrix<f64>,
        mass: DMatrix<f64>,
        forces: DVector<f64>,
        powers: Vec<f64>,
    },
    Reduced {
        mass: f64,
        bias: f64,
        powers: Vec<f64>,
    },
}

impl Split {
    fn powers(&self) -> &[f64] {
        match self {
            Split::Full { powers, .. } | Split::Reduced { powers, .. } => powers,
        }
    }
}

fn split<M: Mechanism>(m: &M, q: &M::Coords, qd: &M::Coords, qdd: &M::Coords) -> Split {
    let (n, nu) = (M::COORDINATES.len(), M::UNKNOWNS);
    let mut out = vec![f64::NAN; M::MOTION_OUTPUTS];
    assert!(
        M::MOTION_OUTPUTS > 0,
        "the sections' equations are compiled"
    );
    assert!(m.equations_of_motion(q, qd, qdd, 0.0, &mut out));
    assert!(
        !m.equations_of_motion(q, qd, qdd, 0.0, &mut out[1..]),
        "a buffer of the wrong length is refused"
    );
    if M::MOTION_REDUCED {
        return Split::Reduced {
            mass: out[0],
            bias: out[1],
            powers: out[2..].to_vec(),
        };
    }
    let jacobian = DMatrix::from_row_slice(nu, n, &out[..nu * n]);
    let mut mass = DMatrix::zeros(n, n);
    let mut at = nu * n;
    for i in 0..n {
        for j in i..n {
            mass[(i, j)] = out[at];
            mass[(j, i)] = out[at];
            at += 1;
        }
    }
    let forces = DVector::from_column_slice(&out[at..at + n]);
    Split::Full {
        jacobian,
        mass,
        forces,
        powers: out[at + n..].to_vec(),
    }
}

/// Φ_q by central differences of the residual at `q`.
fn jacobian_by_differences<M: Mechanism>(m: &M, q: &M::Coords) -> DMatrix<f64> {
    let (n, ne) = (M::COORDINATES.len(), M::EQUATIONS);
    let mut out = DMatrix::zeros(ne, n);
    let (mut up, mut down) = (vec![0.0; ne], vec![0.0; ne]);
    for j in 0..n {
        let h = 1e-6 * (1.0 + q.get(j).expect("a coordinate").abs());
        let (mut a, mut b) = (*q, *q);
        a.set(j, q.get(j).expect("a coordinate") + h);
        b.set(j, q.get(j).expect("a coordinate") - h);
        m.residual_into(&a, &mut up);
        m.residual_into(&b, &mut down);
        for i in 0..ne {
            out[(i, j)] = (up[i] - down[i]) / (2.0 * h);
        }
    }
    out
}

/// C (n × d): the drivers' rows the identity, Φ_u C_u = −Φ_d.
fn coefficients(jacobian: &DMatrix<f64>, nd: usize) -> DMatrix<f64> {
    let (nu, n) = jacobian.shape();
    let phi_u = jacobian.columns(nd, nu).into_owned();
    let phi_d = jacobian.columns(0, nd).into_owned();
    let c_u = phi_u.lu().solve(&(-phi_d)).expect("Φ_u regular");
    let mut c = DMatrix::zeros(n, nd);
    for k in 0..nd {
        c[(k, k)] = 1.0;
    }
    c.rows_mut(nd, nu).copy_from(&c_u);
    c
}

/// The compiled equations at `motion`, checked: in all the coordinates,
/// Φ_q against central differences of the residual, ½ q̇ᵀ M̃ q̇ against
/// the `kinetic` energy and Cᵀ f̃ against the drivers' `efforts` of the
/// inverse analysis; reduced (one driver), ½ M ḋ² against the kinetic
/// energy and b (the effort at the motion's accelerations) against the
/// driving effort.
fn checked<M: Mechanism>(m: &M, motion: &M::Motion, kinetic: f64, efforts: &[f64]) -> Split {
    use kinematics_core::MotionState;
    let s = split(m, motion.q(), motion.qd(), motion.qdd());
    let n = M::COORDINATES.len();
    let qd = DVector::from_iterator(n, (0..n).map(|j| motion.qd().get(j).expect("a rate")));
    match &s {
        Split::Full {
            jacobian,
            mass,
            forces,
            ..
        } => {
            let fd = jacobian_by_differences(m, motion.q());
            for (a, b) in jacobian.iter().zip(fd.iter()) {
                close(*a, *b, 1e-8, "Φ_q against differences of the residual");
            }
            let t = 0.5 * (qd.transpose() * mass * &qd)[(0, 0)];
            close(t, kinetic, 1e-12, "½ q̇ᵀ M̃ q̇");
            let q = coefficients(jacobian, M::DRIVERS).transpose() * forces;
            assert_eq!(q.len(), efforts.len());
            for (q, effort) in q.iter().zip(efforts) {
                close(*q, *effort, 1e-11, "Cᵀ f̃ against the driving effort");
            }
        }
        Split::Reduced { mass, bias, .. } => {
            assert_eq!(
                (M::DRIVERS, efforts.len()),
                (1, 1),
                "reduced for one driver"
            );
            close(0.5 * mass * qd[0] * qd[0], kinetic, 1e-12, "½ M ḋ²");
            close(*bias, efforts[0], 1e-11, "b against the torque");
        }
    }
    s
}

/// The engine: Φ_q, the kinetic energy, the crank torque and the gas
/// force's power −p0 (x0/x)² ẋ over a turn at a varying speed.
#[test]
fn the_engines_compiled_equations_are_its_jacobian_energy_effort_and_power(
) -> Result<(), Box<dyn std::error::Error>> {
    let m = DEFINED_ENGINE;
    let dynamics = m.dynamics()?;
    for k in 0..24 {
        let phi = TAU * f64::from(k) / 24.0 + 0.01;
        let (w, al) = (150.0 + 30.0 * phi.sin(), -800.0 * phi.cos());
        let kin = engine_kinematics(phi, w, al);
        let pose = m.assemble(&DefinedEngineCoords {
            phi,
            th: kin.th,
            x: kin.x,
        })?;
        let motion = m.analyze(&pose, w, al)?;
        let inverse = dynamics.inverse(&m, &motion)?;
        let s = checked(&m, &motion, inverse.kinetic_energy, &[inverse.effort.phi]);
        assert!(
            matches!(s, Split::Reduced { .. }),
            "one driver, two unknowns"
        );
        let gas = -m.p0 * (m.x0 / motion.q.x).powi(2) * motion.qd.x;
        assert_eq!(s.powers().len(), 1);
        close(s.powers()[0], gas, 1e-12, "the gas force's power");
    }
    Ok(())
}

/// The spatial RSSR with inertia tensors: the same checks (its kinetic
/// energy holds the rotating tensors' ωᵀ J ω).
#[test]
fn the_rssrs_compiled_equations_are_its_jacobian_energy_and_effort(
) -> Result<(), Box<dyn std::error::Error>> {
    let m = DefinedRssr {
        a: 0.03,
        b: 0.12,
        c: 0.08,
        d: 0.1,
        g: G,
    };
    let dynamics = m.dynamics()?;
    let mut pose = m.assemble(&DefinedRssrCoords { phi: 0.7, psi: 1.1 })?;
    for k in 0..12 {
        pose.phi = 0.7 + 0.4 * f64::from(k);
        let motion = m.step(&pose, 9.0 + f64::from(k), 40.0 - 7.0 * f64::from(k))?;
        pose = motion.q;
        let inverse = dynamics.inverse(&m, &motion)?;
        assert!(
            inverse.kinetic_energy > 1e-4,
            "a test: T = {}",
            inverse.kinetic_energy
        );
        let s = checked(&m, &motion, inverse.kinetic_energy, &[inverse.effort.phi]);
        assert!(s.powers().is_empty(), "gravity reports no work of its own");
    }
    Ok(())
}

/// A forward simulation of the RSSR released under gravity, from its own
/// sections (through the compiled equations) and from the same
/// description built again (summed at run time): the same motion.
#[test]
fn a_forward_run_through_the_compiled_equations_is_the_summed_one(
) -> Result<(), Box<dyn std::error::Error>> {
    let m = DefinedRssr {
        a: 0.03,
        b: 0.12,
        c: 0.08,
        d: 0.1,
        g: G,
    };
    let own = m.dynamics()?;
    let summed = m.dynamics_builder().build::<DefinedRssr>()?;
    let start = m.assemble(&DefinedRssrCoords { phi: 0.7, psi: 1.1 })?;
    let run = |d: &Dynamics| {
        d.forward(&m, &start)
            .until(0.5)
            .samples(10)
            .tolerance(1e-11)
            .run()
    };
    let (a, b) = (run(&own)?, run(&summed)?);
    assert!(a.is_complete() && b.is_complete());
    // Every evaluation of the one compiled, none of the other.
    assert!(a.statistics.compiled >= a.statistics.evaluations && a.statistics.summed == 0);
    assert!(b.statistics.summed >= b.statistics.evaluations && b.statistics.compiled == 0);
    for (x, y) in a.sweep.samples.iter().zip(&b.sweep.samples) {
        close(x.motion.q.phi, y.motion.q.phi, 1e-10, "φ");
        close(x.motion.qd.phi, y.motion.qd.phi, 1e-9, "φ'");
    }
    // The same definition compiled at run time, through its compiled
    // equations too.
    let model = kinematics_core::runtime::Model::compile(text_of("DefinedRssr"))?
        .with_values(&m.parameter_values())?;
    let c = model
        .dynamics()?
        .forward_of(&model, &[start.phi, start.psi])
        .until(0.5)
        .samples(10)
        .tolerance(1e-11)
        .run()?;
    assert!(c.statistics.compiled >= c.statistics.evaluations && c.statistics.summed == 0);
    for (x, y) in c.sweep.samples.iter().zip(&a.sweep.samples) {
        close(x.motion.q[0], y.motion.q.phi, 1e-10, "run-time φ");
    }
    let end = a.sweep.samples.last().expect("samples").motion.q.phi;
    assert!((end - 0.7).abs() > 0.1, "a test: φ from 0.7 to {end}");
    assert!(a.energy_error() < 1e-9, "{}", a.energy_error());
    Ok(())
}

mechanism! {
    /// The motor-driven four-bar of the forward benchmark, its masses and
    /// loads as sections: one driver and two unknowns.
    pub struct DrivenFourBar {
        params   { a, b, c, d }
        drivers  { phi }
        unknowns { th3, th4 }
        points {
            G2 = polar(a / 2.0, phi);
            G3 = polar(a, phi) + polar(b / 2.0, th3);
            G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
            P0 = vec2(0.05, 0.15);
        }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
        bodies {
            crank(mass = 0.3, center = G2, angle = phi, inertia = 2.0e-3);
            coupler(mass = 0.5, center = G3, angle = th3, inertia = 6.0e-4);
            rocker(mass = 0.4, center = G4, angle = th4, inertia = 3.5e-4);
        }
        loads {
            gravity(vec2(0.0, -9.81));
            force(phi, 0.5 * (1.0 - rate(phi) / 60.0));
            spring(P0, G3, stiffness = 50.0, free_length = 0.10, damping = 2.0);
        }
    }
}

/// The benchmark's four-bar and its start from rest, assembled at φ = 0.
fn driven_four_bar() -> Result<(DrivenFourBar, DrivenFourBarCoords), kinematics_core::Error> {
    let m = DrivenFourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    let start = m.assemble(&DrivenFourBarCoords {
        phi: 0.0,
        th3: 1.2,
        th4: 1.9,
    })?;
    Ok((m, start))
}

/// The four-bar started by its motor, through the compiled equations
/// (one driver, two unknowns: the reduction written out) and summed: the
/// same motion.
#[test]
fn a_four_bars_start_up_through_the_compiled_equations_is_the_summed_one(
) -> Result<(), Box<dyn std::error::Error>> {
    let (m, start) = driven_four_bar()?;
    let run = |d: &Dynamics| {
        d.forward(&m, &start)
            .until(1.0)
            .samples(20)
            .tolerance(1e-11)
            .run()
    };
    let (a, b) = (
        run(&m.dynamics()?)?,
        run(&m.dynamics_builder().build::<DrivenFourBar>()?)?,
    );
    assert!(a.is_complete() && b.is_complete());
    assert!(a.statistics.compiled >= a.statistics.evaluations && a.statistics.summed == 0);
    assert_eq!(b.statistics.compiled, 0);
    for (x, y) in a.sweep.samples.iter().zip(&b.sweep.samples) {
        close(x.motion.q.phi, y.motion.q.phi, 1e-10, "φ");
        close(x.motion.qd.phi, y.motion.qd.phi, 1e-9, "φ'");
    }
    let end = a.sweep.samples.last().expect("samples").motion.q.phi;
    assert!(end > 10.0, "a test: the motor turns the crank to {end}");
    Ok(())
}

/// The run-time model of [`DrivenFourBar`], from this file's definition.
fn driven_four_bar_model() -> Result<kinematics_core::runtime::Model, Box<dyn std::error::Error>> {
    let text = kinematics_examples::mechanism_bodies(include_str!("compiled.rs"))
        .into_iter()
        .map(|(text, _)| text)
        .find(|text| text.contains("pub struct DrivenFourBar {"))
        .ok_or("the definition is in this file")?;
    Ok(kinematics_core::runtime::Model::compile(text)?.with_values(&[0.04, 0.12, 0.10, 0.11])?)
}

/// A run-time model's forward samples against the general path: each
/// sample's whole motion (every coordinate, every point's position,
/// velocity and acceleration) is `Model::step` at the sample's pose with
/// its rates and accelerations (no fused code), to round-off. The
/// evaluations of the integration leave the points out; the samples must
/// not.
#[test]
fn a_run_time_forward_runs_samples_are_the_models_own_steps(
) -> Result<(), Box<dyn std::error::Error>> {
    let model = driven_four_bar_model()?;
    let run = model
        .dynamics()?
        .forward_of(&model, &[0.0, 1.2, 1.9])
        .until(1.0)
        .samples(20)
        .tolerance(1e-11)
        .run()?;
    assert!(run.statistics.compiled >= run.statistics.evaluations && run.statistics.summed == 0);
    assert_eq!(run.sweep.samples.len(), 21);
    let same = |a: f64, b: f64, what: &str| {
        assert!(
            (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
            "{what}: {a} against {b}"
        );
    };
    for s in &run.sweep.samples {
        let m = &s.motion;
        let general = model.step(&m.q, &m.qd[..1], &m.qdd[..1])?;
        for (what, a, b) in [
            ("q", &m.q, &general.q),
            ("q'", &m.qd, &general.qd),
            ("q''", &m.qdd, &general.qdd),
        ] {
            for (x, y) in a.iter().zip(b.iter()) {
                same(*x, *y, what);
            }
        }
        assert_eq!(m.points.len(), 4);
        for (p, g) in m.points.iter().zip(&general.points) {
            for (x, y) in [
                (&p.position, &g.position),
                (&p.velocity, &g.velocity),
                (&p.acceleration, &g.acceleration),
            ] {
                for (a, b) in x.iter().zip(y.iter()) {
                    same(*a, *b, "a point's motion");
                }
            }
        }
    }
    Ok(())
}

/// A stop on the rocker (restitution 0.5) during the motor's start-up:
/// each impact's kinetic energies are read right after an evaluation of
/// the equations of motion, which left the points out. The run-time
/// model's impacts, energies and works equal the generated mechanism's,
/// whose motion is always whole, and the energy balance holds across the
/// impacts' losses.
#[test]
fn a_run_time_forward_runs_impacts_read_the_whole_motion() -> Result<(), Box<dyn std::error::Error>>
{
    use kinematics_core::dynamics::Event;
    let (m, start) = driven_four_bar()?;
    let stop = || Event::stop("th4", start.th4 + 0.05, 0.5).increasing();
    let generated = m
        .dynamics()?
        .forward(&m, &start)
        .until(0.3)
        .samples(30)
        .tolerance(1e-11)
        .stop_when(stop())
        .run()?;
    let model = driven_four_bar_model()?;
    let run_time = model
        .dynamics()?
        .forward_of(&model, &[start.phi, start.th3, start.th4])
        .until(0.3)
        .samples(30)
        .tolerance(1e-11)
        .stop_when(stop())
        .run()?;
    assert!(
        !generated.impacts.is_empty(),
        "a test: the rocker reaches its stop"
    );
    assert_eq!(generated.impacts.len(), run_time.impacts.len());
    for (a, b) in generated.impacts.iter().zip(&run_time.impacts) {
        close(a.t, b.t, 1e-9, "the impact's time");
        close(a.before, b.before, 1e-8, "the rate before");
        close(a.after, b.after, 1e-8, "the rate after");
    }
    assert_eq!(generated.energy.len(), run_time.energy.len());
    for (a, b) in generated.energy.iter().zip(&run_time.energy) {
        let scale = a.kinetic.abs() + a.potential.abs() + 1e-3;
        for (x, y, what) in [(a.kinetic, b.kinetic, "T"), (a.potential, b.potential, "V")]
            .into_iter()
            .chain(a.work.iter().zip(&b.work).map(|(x, y)| (*x, *y, "a work")))
        {
            assert!(
                (x - y).abs() <= 1e-8 * scale,
                "{what} at t = {}: {x} against {y}",
                a.t
            );
        }
    }
    let lost = run_time
        .work_names
        .iter()
        .position(|n| n.contains("impacts"))
        .ok_or("the impacts' work")?;
    let last = run_time.energy.last().ok_or("samples")?;
    assert!(
        last.work[lost] < 0.0,
        "a test: the impacts lose energy ({})",
        last.work[lost]
    );
    assert!(
        run_time.energy_error() < 1e-8,
        "{}",
        run_time.energy_error()
    );
    Ok(())
}

mechanism! {
    /// A pendulum of 2 kg.
    pub struct HeavySwing {
        params { } drivers { phi } unknowns { }
        points { G = polar(0.5, phi); }
        bodies { bob(mass = 2.0, center = G, angle = phi, inertia = 0.01); }
        loads { gravity(vec2(0.0, -9.81)); }
    }
}

mechanism! {
    /// The same pendulum of 1 kg: the same sizes, no parameters either.
    pub struct LightSwing {
        params { } drivers { phi } unknowns { }
        points { G = polar(0.5, phi); }
        bodies { bob(mass = 1.0, center = G, angle = phi, inertia = 0.03); }
        loads { gravity(vec2(0.0, -9.81)); }
    }
}

/// A description made from one mechanism's sections, run on another of
/// the same sizes and parameter values, is summed: the other's compiled
/// equations (its own masses) are not taken for it.
#[test]
fn another_mechanisms_sections_are_summed_not_compiled() -> Result<(), Box<dyn std::error::Error>> {
    let (heavy, light) = (HeavySwing {}, LightSwing {});
    let described = heavy.dynamics()?;
    let start = LightSwingCoords { phi: 0.3 };
    let on_light = described
        .forward(&light, &start)
        .until(0.5)
        .tolerance(1e-11)
        .run()?;
    assert_eq!(on_light.statistics.compiled, 0);
    assert!(on_light.statistics.summed > 0);
    let own = described
        .forward(&heavy, &HeavySwingCoords { phi: 0.3 })
        .until(0.5)
        .tolerance(1e-11)
        .run()?;
    assert!(own.statistics.compiled > 0 && own.statistics.summed == 0);
    // The heavy pendulum's motion either way (its inertia 0.01, not 0.03).
    let (x, y) = (
        on_light.sweep.samples.last().expect("samples"),
        own.sweep.samples.last().expect("samples"),
    );
    close(x.motion.q.phi, y.motion.q.phi, 1e-10, "φ(0.5 s)");
    // The same type at other values: summed too.
    let mut other = DEFINED_ENGINE;
    other.p0 = 1000.0;
    let kin = engine_kinematics(0.3, 0.0, 0.0);
    let start = other.assemble(&DefinedEngineCoords {
        phi: 0.3,
        th: kin.th,
        x: kin.x,
    })?;
    let run = DEFINED_ENGINE
        .dynamics()?
        .forward(&other, &start)
        .until(0.01)
        .run()?;
    assert!(run.statistics.compiled == 0 && run.statistics.summed > 0);
    Ok(())
}

/// Without `bodies` and `loads` sections there is nothing compiled.
#[test]
fn a_mechanism_without_sections_has_no_compiled_equations() {
    let m = Engine { a: A, b: B, r3: R3 };
    assert_eq!(<Engine as Mechanism>::MOTION_OUTPUTS, 0);
    let q = EngineCoords::default();
    assert!(!m.equations_of_motion(&q, &q, &q, 0.0, &mut []));
    assert!(!m.has_parameter_values(&m.parameter_values()));
}

mechanism! {
    /// A five-bar with two driven cranks and its four links' masses: two
    /// drivers, so its compiled equations are in all the coordinates.
    pub struct MassFiveBar {
        params   { a, b, c, d, e }
        drivers  { p1, p2 }
        unknowns { t3, t4 }
        points {
            G1 = polar(a / 2.0, p1);
            G2 = polar(a, p1) + polar(b / 2.0, t3);
            G3 = vec2(d, 0.0) + polar(e, p2) + polar(c / 2.0, t4);
            G4 = vec2(d, 0.0) + polar(e / 2.0, p2);
        }
        loops { polar(a, p1) + polar(b, t3) == vec2(d, 0.0) + polar(e, p2) + polar(c, t4); }
        bodies {
            left(mass = 0.3, center = G1, angle = p1, inertia = 2.0e-3);
            upper(mass = 0.5, center = G2, angle = t3, inertia = 6.0e-4);
            lower(mass = 0.4, center = G3, angle = t4, inertia = 3.5e-4);
            right(mass = 0.3, center = G4, angle = p2, inertia = 1.0e-3);
        }
        loads { gravity(vec2(0.0, -9.81)); }
    }
}

/// The five-bar (two drivers, two unknowns: not reduced): Φ_q, M̃ and f̃
/// against the residual's differences, the kinetic energy and both
/// cranks' torques of the inverse analysis, along a motion of both.
#[test]
fn a_five_bars_compiled_equations_are_its_jacobian_energy_and_efforts(
) -> Result<(), Box<dyn std::error::Error>> {
    let m = MassFiveBar {
        a: 0.05,
        b: 0.12,
        c: 0.12,
        d: 0.08,
        e: 0.05,
    };
    const { assert!(!<MassFiveBar as Mechanism>::MOTION_REDUCED) };
    let dynamics = m.dynamics()?;
    let mut pose = m.assemble(&MassFiveBarCoords {
        p1: 1.0,
        p2: 1.6,
        t3: 1.0,
        t4: 2.2,
    })?;
    for k in 0..10 {
        let s = f64::from(k);
        pose.p1 = 1.0 + 0.1 * s;
        pose.p2 = 1.6 - 0.05 * s;
        let motion = m.step(&pose, [3.0 + s, -2.0], [10.0, 4.0 - s])?;
        pose = motion.q;
        let inverse = dynamics.inverse(&m, &motion)?;
        let s = checked(
            &m,
            &motion,
            inverse.kinetic_energy,
            &[inverse.effort.p1, inverse.effort.p2],
        );
        assert!(matches!(s, Split::Full { .. }));
        assert!(s.powers().is_empty(), "gravity reports no work of its own");
    }
    Ok(())
}
