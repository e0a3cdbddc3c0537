//! The sensitivities of a forward simulation's trajectory to the
//! parameters of a definition's `sensitivities` section
//! (`ForwardOf::sensitivities`) against fourth-order central differences
//! of whole trajectories between designs, each integrated at tolerance
//! 1e-12: a
//! motor-driven four-bar with gravity and a spring-damper, its crank's
//! flywheel inertia, the spring's stiffness and the crank's length (which
//! moves the kinematics too).

use kinematics_core::runtime::Model;

const FOUR_BAR: &str = "struct FourBar {
    params   { a, b, c, d, j2, k }
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
        crank(mass = 0.3, center = G2, angle = phi, inertia = j2);
        coupler(mass = 0.5, center = G3, angle = th3, inertia = 6.0e-4);
        rocker(mass = 0.4, center = G4, angle = th4, inertia = 3.5e-4);
    }
    loads {
        gravity(vec2(0.0, -9.81));
        force(phi, 0.5 * (1.0 - rate(phi) / 60.0));
        spring(P0, G3, stiffness = k, free_length = 0.10, damping = 2.0);
    }
    sensitivities { j2, k, a }
}";

const VALUES: [f64; 6] = [0.04, 0.12, 0.10, 0.11, 2.0e-3, 50.0];

/// φ and φ̇ at the samples of a 1 s run of the design `values`.
fn trajectory(model: &Model, values: &[f64]) -> Result<Vec<[f64; 2]>, Box<dyn std::error::Error>> {
    let m = model.with_values(values)?;
    let start = m.assemble(&[0.0, 1.2, 1.9])?;
    let run = m
        .dynamics()?
        .forward_of(&m, &start)
        .until(1.0)
        .samples(10)
        .tolerance(1e-12)
        .run()?;
    assert!(run.ended.is_complete());
    Ok(run
        .sweep
        .samples
        .iter()
        .map(|s| [s.motion.q[0], s.motion.qd[0]])
        .collect())
}

#[test]
fn the_trajectory_sensitivities_match_central_differences_between_designs(
) -> Result<(), Box<dyn std::error::Error>> {
    let model = Model::compile(FOUR_BAR)?;
    let m = model.with_values(&VALUES)?;
    let start = m.assemble(&[0.0, 1.2, 1.9])?;
    let run = m
        .dynamics()?
        .forward_of(&m, &start)
        .until(1.0)
        .samples(10)
        .tolerance(1e-12)
        .sensitivities()
        .run()?;
    assert!(run.ended.is_complete());
    assert_eq!(run.parameters, ["j2", "k", "a"]);
    assert_eq!(run.sensitivities.len(), 11);
    for (p, index) in [(0, 4), (1, 5), (2, 0)] {
        // The fourth-order central difference, (8 (f(p + h) − f(p − h))
        // − (f(p + 2h) − f(p − 2h))) / 12h: its truncation far below the
        // tolerance's noise over h.
        let h = 1e-4 * VALUES[index];
        let at = |offset: f64| -> Result<Vec<[f64; 2]>, Box<dyn std::error::Error>> {
            let mut v = VALUES;
            v[index] += offset;
            trajectory(&model, &v)
        };
        let (p1, m1, p2, m2) = (at(h)?, at(-h)?, at(2.0 * h)?, at(-2.0 * h)?);
        let fd: Vec<[f64; 2]> = (0..p1.len())
            .map(|i| {
                let d =
                    |j: usize| (8.0 * (p1[i][j] - m1[i][j]) - (p2[i][j] - m2[i][j])) / (12.0 * h);
                [d(0), d(1)]
            })
            .collect();
        let scale = fd
            .iter()
            .fold(0.0f64, |s, v| s.max(v[0].abs()).max(v[1].abs()));
        assert!(scale > 0.0);
        for (s, d) in run.sensitivities.iter().zip(&fd) {
            let (dp, dv) = (s.position[p], s.rate[p]);
            assert!(
                (dp - d[0]).abs() < 1e-6 * scale && (dv - d[1]).abs() < 1e-6 * scale,
                "{}: at t = {} ∂φ {dp} against {}, ∂φ' {dv} against {}",
                run.parameters[p],
                s.t,
                d[0],
                d[1]
            );
        }
        println!("{}: largest |∂(φ, φ')/∂p| {scale:.4e}", run.parameters[p]);
    }
    Ok(())
}

#[test]
fn sensitivities_need_a_sensitivities_section() -> Result<(), Box<dyn std::error::Error>> {
    let text = FOUR_BAR.replace("    sensitivities { j2, k, a }\n", "");
    let m = Model::compile(&text)?.with_values(&VALUES)?;
    let start = m.assemble(&[0.0, 1.2, 1.9])?;
    let e = m
        .dynamics()?
        .forward_of(&m, &start)
        .sensitivities()
        .run()
        .expect_err("refused");
    assert!(e.to_string().contains("no `sensitivities` section"), "{e}");
    // With the implicit method they are refused, by name.
    let m = Model::compile(FOUR_BAR)?.with_values(&VALUES)?;
    let e = m
        .dynamics()?
        .forward_of(&m, &start)
        .method(kinematics_core::dynamics::Method::Implicit)
        .sensitivities()
        .run()
        .expect_err("refused");
    assert!(e.to_string().contains("explicit method only"), "{e}");
    Ok(())
}

/// The sensitivities at work: the crank's flywheel inertia sized so that
/// the crank turns at 45 rad/s one second after starting, by Newton's
/// method on φ̇(1 s) with the derivative the sensitivities give, each
/// iteration one run.
#[test]
fn a_flywheel_is_sized_by_newtons_method_on_the_trajectory_sensitivity(
) -> Result<(), Box<dyn std::error::Error>> {
    let model = Model::compile(FOUR_BAR)?;
    let target = 45.0;
    let mut values = VALUES;
    let mut misses = Vec::new();
    for _ in 0..8 {
        let m = model.with_values(&values)?;
        let start = m.assemble(&[0.0, 1.2, 1.9])?;
        let run = m
            .dynamics()?
            .forward_of(&m, &start)
            .until(1.0)
            .samples(1)
            .tolerance(1e-10)
            .sensitivities()
            .run()?;
        let speed = run.sweep.samples.last().ok_or("no samples")?.motion.qd[0];
        let slope = run.sensitivities.last().ok_or("no sensitivities")?.rate[0];
        misses.push(speed - target);
        if (speed - target).abs() < 1e-7 {
            break;
        }
        values[4] -= (speed - target) / slope;
    }
    let last = *misses.last().ok_or("no iterations")?;
    assert!(last.abs() < 1e-7, "{misses:?}");
    // Newton's quadratic convergence: few iterations from 2e-3 kg·m².
    assert!(misses.len() <= 6, "{misses:?}");
    assert!(
        values[4] > 0.0 && (values[4] - VALUES[4]).abs() > 1e-5,
        "{}",
        values[4]
    );
    println!("j2 = {:.6e} kg·m², misses {misses:?}", values[4]);
    Ok(())
}

kinematics_core::mechanism! {
    /// The four-bar of [`FOUR_BAR`], generated.
    pub struct SensitiveFourBar {
        params   { a, b, c, d, j2, k }
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
            crank(mass = 0.3, center = G2, angle = phi, inertia = j2);
            coupler(mass = 0.5, center = G3, angle = th3, inertia = 6.0e-4);
            rocker(mass = 0.4, center = G4, angle = th4, inertia = 3.5e-4);
        }
        loads {
            gravity(vec2(0.0, -9.81));
            force(phi, 0.5 * (1.0 - rate(phi) / 60.0));
            spring(P0, G3, stiffness = k, free_length = 0.10, damping = 2.0);
        }
        sensitivities { j2, k, a }
    }
}

#[test]
fn a_generated_mechanism_gives_the_run_time_models_trajectory_sensitivities(
) -> Result<(), Box<dyn std::error::Error>> {
    let [a, b, c, d, j2, k] = VALUES;
    let g = SensitiveFourBar { a, b, c, d, j2, k };
    let start = g.assemble(&SensitiveFourBarCoords {
        phi: 0.0,
        th3: 1.2,
        th4: 1.9,
    })?;
    let generated = g
        .dynamics()?
        .forward(&g, &start)
        .until(1.0)
        .samples(10)
        .tolerance(1e-12)
        .sensitivities()
        .run()?;
    let m = Model::compile(FOUR_BAR)?.with_values(&VALUES)?;
    let run_time = m
        .dynamics()?
        .forward_of(&m, &[start.phi, start.th3, start.th4])
        .until(1.0)
        .samples(10)
        .tolerance(1e-12)
        .sensitivities()
        .run()?;
    assert_eq!(generated.parameters, run_time.parameters);
    assert_eq!(generated.sensitivities.len(), 11);
    for p in 0..3 {
        let scale = run_time.sensitivities.iter().fold(0.0f64, |s, x| {
            s.max(x.position[p].abs()).max(x.rate[p].abs())
        });
        for (x, y) in generated.sensitivities.iter().zip(&run_time.sensitivities) {
            assert!((x.position[p] - y.position[p]).abs() < 1e-8 * scale);
            assert!(
                (x.rate[p] - y.rate[p]).abs() < 1e-8 * scale,
                "{} at {}",
                generated.parameters[p],
                x.t
            );
        }
    }
    Ok(())
}

/// One free driver with no sensitivities takes the evaluation's lean path
/// (d̈ = −b/M with none of the loops over the drivers); with them, the
/// general one: the two runs' samples, energies and works agree to
/// round-off. (Not bit for bit: the general path's differences of the
/// accelerations assemble at other poses first, and each assembly starts
/// from the last, which moves the last bits.)
#[test]
fn the_lean_evaluation_is_the_general_one() -> Result<(), Box<dyn std::error::Error>> {
    let m = Model::compile(FOUR_BAR)?.with_values(&VALUES)?;
    let start = m.assemble(&[0.0, 1.2, 1.9])?;
    let dynamics = m.dynamics()?;
    let run = |sensitivities: bool| {
        let forward = dynamics
            .forward_of(&m, &start)
            .until(0.5)
            .samples(25)
            .tolerance(1e-10);
        let forward = if sensitivities {
            forward.sensitivities()
        } else {
            forward
        };
        Ok::<_, Box<dyn std::error::Error>>(forward.run()?)
    };
    let (lean, general) = (run(false)?, run(true)?);
    assert!(lean.ended.is_complete() && general.ended.is_complete());
    assert!(general.sensitivities.len() == general.sweep.samples.len());
    assert!(lean.statistics.compiled > 0 && lean.statistics.summed == 0);
    assert_eq!(lean.sweep.samples.len(), 26);
    assert_eq!(lean.sweep.samples.len(), general.sweep.samples.len());
    let close = |x: f64, y: f64, what: &str| {
        assert!(
            (x - y).abs() <= 1e-9 * (1.0 + y.abs()),
            "{what}: {x} against {y}"
        );
    };
    for (a, b) in lean.sweep.samples.iter().zip(&general.sweep.samples) {
        assert_eq!(a.at.to_bits(), b.at.to_bits());
        for (x, y) in [
            (&a.motion.q, &b.motion.q),
            (&a.motion.qd, &b.motion.qd),
            (&a.motion.qdd, &b.motion.qdd),
        ] {
            for (x, y) in x.iter().zip(y.iter()) {
                close(*x, *y, "the motion");
            }
        }
    }
    assert_eq!(lean.energy.len(), general.energy.len());
    for (a, b) in lean.energy.iter().zip(&general.energy) {
        close(a.kinetic, b.kinetic, "T");
        close(a.potential, b.potential, "V");
        assert_eq!(
            (a.work.len(), a.effort.len()),
            (b.work.len(), b.effort.len())
        );
        for (x, y) in a
            .work
            .iter()
            .zip(&b.work)
            .chain(a.effort.iter().zip(&b.effort))
        {
            close(*x, *y, "a work or an effort");
        }
    }
    Ok(())
}
