//! The crank press of `examples/dynamics/press.mech` (a flywheel started
//! by an induction motor against a viscous load on the ram) run up from
//! standstill to its steady speed by forward dynamics, and its speed
//! fluctuation there against the flywheel estimate a designer makes from
//! a kinematic cycle at the mean speed, C_s ≈ ΔE / (I ω²), ΔE the energy
//! fluctuation of the driving torque by virtual power.

use std::f64::consts::TAU;

use kinematics_core::runtime::Model;

/// The press's parameters, as `examples/dynamics/press.toml` gives them.
const VALUES: [f64; 10] = [0.06, 0.24, 4.0, 0.8, 1.5, 6.0, 60.0, 0.2, 157.0, 20.0];

#[test]
fn the_press_runs_up_and_fluctuates_as_its_flywheel_estimate(
) -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/dynamics/");
    let model = Model::compile(&std::fs::read_to_string(format!("{root}press.mech"))?)?
        .with_values(&VALUES)?;
    let toml = std::fs::read_to_string(format!("{root}press.toml"))?;
    for (name, v) in model.parameters().iter().zip(VALUES) {
        assert!(
            toml.contains(&format!("{name} = {v:?}")),
            "press.toml's {name} is not {v}"
        );
    }
    let dynamics = model.dynamics()?;
    let start = model.assemble(&[0.0, 0.0, 0.3])?;
    // From standstill to 6 s.
    let up = dynamics
        .forward_of(&model, &start)
        .until(6.0)
        .samples(60)
        .tolerance(1e-10)
        .run()?;
    assert!(up.energy_error() < 1e-8, "{}", up.energy_error());
    let last = up.sweep.samples.last().ok_or("no samples")?;
    // Below the synchronous speed by the slip that balances the load.
    let omega = last.motion.qd[0];
    assert!(omega > 150.0 && omega < 157.0, "{omega}");
    // Three more cycles, finely sampled; the last two measured.
    let period = TAU / omega;
    let steady = dynamics
        .forward_of(&model, &last.motion.q)
        .rates(&[omega])
        .until(3.0 * period)
        .samples(3000)
        .tolerance(1e-11)
        .run()?;
    let speeds: Vec<f64> = steady.sweep.samples[1000..]
        .iter()
        .map(|s| s.motion.qd[0])
        .collect();
    let (lo, hi) = speeds
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &w| (l.min(w), h.max(w)));
    let mean = speeds.iter().sum::<f64>() / speeds.len() as f64;
    // Steady: the two cycles' mean speeds agree.
    let half = speeds.len() / 2;
    let first = speeds[..half].iter().sum::<f64>() / half as f64;
    assert!((first - mean).abs() < 1e-3 * mean, "{first} against {mean}");
    let simulated = (hi - lo) / mean;
    // The estimate: a turn at the mean speed, the driving torque's energy
    // fluctuation, the flywheel's inertia.
    let sweep = model
        .sweep("phi", &start)?
        .turn()
        .steps(720)
        .rate(mean)
        .run();
    let forces = dynamics.along_of(&model, &sweep)?;
    let estimate = forces
        .speed_fluctuation(0, VALUES[3], mean)
        .ok_or("no estimate")?;
    println!("C_s simulated {simulated:.5e}, estimated {estimate:.5e}, mean speed {mean:.4} rad/s");
    assert!(simulated > 1e-3, "it fluctuates: {simulated}");
    // The first-order estimate holds the drive torque and the inertia
    // constant over the cycle: it agrees within 3 % (2 % measured).
    assert!(
        (simulated / estimate - 1.0).abs() < 0.03,
        "{simulated} against {estimate}"
    );
    // The README prints the three numbers of this run: the page is read
    // back and checked against them (a check of the page; the physics is
    // the agreement above).
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md"))?;
    for shown in [
        format!("{mean:.1} rad/s"),
        format!("is {simulated:.3e}"),
        format!("gives {estimate:.3e}"),
    ] {
        assert!(readme.contains(&shown), "the README does not say `{shown}`");
    }
    Ok(())
}
