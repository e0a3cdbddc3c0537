//! A single-cylinder two-stroke engine at 3000 rev/min: the crank torque
//! over a turn from the gas force and the inertia of the crank, rod and
//! piston, its mean, and the flywheel that keeps the speed within 1 %.
//!
//! Bore 50 mm, crank 25 mm, rod 100 mm, clearance 5 mm. The gas: from top
//! dead centre to bottom dead centre an expansion p = p₁ (h_c / h)^1.3
//! from p₁ = 40 bar, from bottom to top a compression from 1 bar, h the
//! height of the gas above the piston; the force (p − 1 bar) times the
//! piston's area pushes the piston toward the crank.
//!
//! Writes `target/kinematics/engine-forces.csv` (the efforts, energies,
//! power, shaking force and moment and the joint reactions, with units)
//! and `engine-forces.svg` (the crank torque beside its mean, and the
//! polar diagrams of the shaking force and of the joint reactions).

use std::f64::consts::{PI, TAU};
use std::path::Path;

use kinematics_core::dynamics::{Body, Dynamics, Joint, GROUND};
use kinematics_core::mechanism;

mechanism! {
    /// The engine's slider-crank: crank a, rod b, the rod's centre of mass
    /// at r3 from the crank pin, the crank's balanced at the shaft (its
    /// centre of mass at the origin), the piston at C on the x axis.
    pub struct Engine {
        params {
            /// Crank radius.
            a,
            /// Rod length.
            b,
            /// Rod's centre of mass from the crank pin.
            r3
        }
        drivers {
            /// Crank angle, from top dead centre.
            phi
        }
        unknowns {
            /// Rod angle.
            th,
            /// Piston position.
            x
        }
        points {
            /// Crankshaft.
            O = vec2(0.0, 0.0);
            /// Crank pin.
            B = polar(a, phi);
            /// Rod's centre of mass.
            G3 = polar(a, phi) + polar(r3, th);
            /// Piston pin.
            C = vec2(x, 0.0);
        }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let m = Engine {
        a: 0.025,
        b: 0.1,
        r3: 0.03,
    };
    let rpm = 3000.0;
    let omega = rpm * TAU / 60.0;
    let area = PI / 4.0 * 0.05 * 0.05;
    let (clearance, top) = (0.005, m.a + m.b);
    let gas = move |phi: f64, x: f64| {
        let h = clearance + top - x;
        let phi = phi.rem_euclid(TAU);
        let p = if phi < PI {
            40e5 * (clearance / h).powf(1.3)
        } else {
            1e5 * ((clearance + 2.0 * m.a) / h).powf(1.3)
        };
        (p - 1e5) * area
    };
    let dynamics = Dynamics::builder()
        .body(
            Body::new("crank", 1.2)
                .center("O")
                .angle("phi")
                .inertia(6e-4),
        )
        .body(
            Body::new("rod", 0.25)
                .center("G3")
                .angle("th")
                .inertia(2.5e-4),
        )
        .body(Body::new("piston", 0.3).center("C"))
        .force_on("piston", "C", move |s| [-gas(s.q(0), s.q(2)), 0.0, 0.0])
        .joint(Joint::revolute("main bearing", "O", GROUND, "crank").driven_by("phi"))
        .joint(Joint::revolute("crank pin", "B", "crank", "rod"))
        .joint(Joint::revolute("piston pin", "C", "rod", "piston"))
        .joint(Joint::prismatic(
            "cylinder wall",
            "C",
            GROUND,
            "piston",
            [1.0, 0.0],
        ))
        .build::<Engine>()?;
    let start = m.assemble(&EngineCoords {
        phi: 0.0,
        th: 0.0,
        x: 0.125,
    })?;
    let sweep = m
        .sweep(Engine::PHI, &start)
        .to(TAU)
        .steps(720)
        .rpm(rpm)
        .run();
    if let Some(stop) = &sweep.stop {
        return Err(format!("the sweep stopped: {stop}").into());
    }
    let forces = dynamics.along(&m, &sweep)?;
    let mean = forces.mean_effort(0).ok_or("no samples")?;
    let fluctuation = forces.energy_fluctuation(0).ok_or("no samples")?;
    let coefficient = 0.01;
    let flywheel = fluctuation / (coefficient * omega * omega);
    let peak = forces
        .samples
        .iter()
        .map(|s| s.effort[0])
        .fold(f64::NEG_INFINITY, f64::max);
    let shaking = forces
        .samples
        .iter()
        .map(|s| s.shaking_force.norm())
        .fold(0.0, f64::max);
    let largest = |joint: &str| {
        forces
            .samples
            .iter()
            .filter_map(|s| s.reactions.as_ref()?.get(joint))
            .map(|j| j.force.norm())
            .fold(0.0, f64::max)
    };
    println!("Single-cylinder two-stroke engine at {rpm} rev/min ({omega:.1} rad/s)\n");
    println!(
        "{:>6} {:>12} {:>10} {:>12}",
        "phi", "torque", "T", "|F_shaking|"
    );
    println!("{:>6} {:>12} {:>10} {:>12}", "deg", "N·m", "J", "N");
    for s in forces.samples.iter().step_by(60) {
        println!(
            "{:>6.0} {:>12.3} {:>10.4} {:>12.1}",
            s.at.to_degrees(),
            s.effort[0],
            s.kinetic_energy,
            s.shaking_force.norm()
        );
    }
    println!(
        "\nmean crank torque       {mean:>10.3} N·m (the engine gives {:.3} N·m, {:.2} kW)",
        -mean,
        -mean * omega / 1e3
    );
    println!("peak torque to drive it {peak:>10.3} N·m");
    println!("energy fluctuation      {fluctuation:>10.3} J");
    println!("flywheel for C_s = {coefficient}  {flywheel:>10.5} kg·m² (ΔE / (C_s ω²))");
    println!("largest shaking force   {shaking:>10.1} N");
    for joint in ["main bearing", "crank pin", "piston pin", "cylinder wall"] {
        println!("largest load, {joint:<13} {:>8.1} N", largest(joint));
    }
    let dir = Path::new("target/kinematics");
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join("engine-forces.csv"), forces.to_csv())?;
    kinematics_core::plot::plot_forces(&forces, &dir.join("engine-forces.svg"))?;
    println!(
        "\nwrote {0}/engine-forces.csv and {0}/engine-forces.svg",
        dir.display()
    );
    Ok(())
}
