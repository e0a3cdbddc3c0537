//! Slider-crank (the chapter's Problem 4.3 dimensions: AB = 0.1 m,
//! BC = 0.2 m, n = 60 rev/min) over a full turn, every 30°.
//!
//! The last column is the closed-form slider position
//! x = a cos φ + √(b² − (a sin φ − e)²), an independent check of the
//! assembled one.
use kinematics_examples::{rpm_to_rad_per_s, SliderCrank, SliderCrankCoords};

fn main() -> Result<(), kinematics_core::Error> {
    let m = SliderCrank {
        a: 0.1,
        b: 0.2,
        e: 0.0,
    };
    let omega = rpm_to_rad_per_s(60.0);
    println!("Slider-crank: AB = {} m, BC = {} m, offset e = {} m, n = 60 rpm (omega = {omega:.4} rad/s)\n", m.a, m.b, m.e);
    println!(
        "{:>6} {:>8} {:>9} {:>9} {:>9} {:>9} {:>9} {:>11}",
        "phi", "th", "w_rod", "a_rod", "x_C", "v_C", "a_C", "x_C closed"
    );
    println!(
        "{:>6} {:>8} {:>9} {:>9} {:>9} {:>9} {:>9} {:>11}",
        "deg", "deg", "rad/s", "rad/s2", "m", "m/s", "m/s2", "m"
    );
    let mut pose = m.assemble(&SliderCrankCoords {
        phi: 0.0,
        th: 0.0,
        x: 0.3,
    })?;
    for k in 0..=12 {
        let phi = f64::from(k) * 30f64.to_radians();
        pose.phi = phi;
        pose = m.assemble(&pose)?;
        let s = m.analyze(&pose, omega, 0.0)?;
        let closed = m.a * phi.cos() + (m.b * m.b - (m.a * phi.sin() - m.e).powi(2)).sqrt();
        println!(
            "{:>6.1} {:>8.3} {:>9.4} {:>9.4} {:>9.5} {:>9.5} {:>9.5} {:>11.5}",
            phi.to_degrees(),
            pose.th.to_degrees(),
            s.qd.th,
            s.qdd.th,
            pose.x,
            s.qd.x,
            s.qdd.x,
            closed
        );
    }
    Ok(())
}
