//! Crank-rocker four-bar over a full turn of the crank, every 30°.
//!
//! a = 0.04 m, b = 0.12 m, c = 0.10 m, d = 0.11 m; coupler point P at
//! p = 0.06 m from B, β = 30° from BC; the crank turns at a constant
//! φ' = 10 rad/s. For each crank angle the table gives the coupler and rocker
//! angles θ3, θ4, their angular velocities ω and accelerations α, and the
//! velocity and acceleration of the coupler point P.
use kinematics_examples::FourBar;

fn main() -> Result<(), kinematics_core::Error> {
    let m = FourBar::CRANK_ROCKER;
    let omega = 10.0;
    println!(
        "Crank-rocker four-bar: a = {} m, b = {} m, c = {} m, d = {} m, p = {} m, beta = 30 deg",
        m.a, m.b, m.c, m.d, m.p
    );
    println!("crank speed phi' = {omega} rad/s (constant)\n");
    println!(
        "{:>6} {:>8} {:>8} {:>8} {:>8} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8}",
        "phi", "th3", "th4", "w3", "w4", "a3", "a4", "vPx", "vPy", "aPx", "aPy"
    );
    println!(
        "{:>6} {:>8} {:>8} {:>8} {:>8} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8}",
        "deg", "deg", "deg", "rad/s", "rad/s", "rad/s2", "rad/s2", "m/s", "m/s", "m/s2", "m/s2"
    );
    let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS)?;
    for k in 0..=12 {
        pose.phi = f64::from(k) * 30f64.to_radians();
        // Continue from the previous pose: the branch is kept.
        pose = m.assemble(&pose)?;
        let s = m.analyze(&pose, omega, 0.0)?;
        let p = s.point_p();
        println!(
            "{:>6.1} {:>8.3} {:>8.3} {:>8.4} {:>8.4} {:>9.3} {:>9.3} {:>8.4} {:>8.4} {:>8.3} {:>8.3}",
            pose.phi.to_degrees(),
            pose.th3.to_degrees(),
            pose.th4.to_degrees(),
            s.qd.th3,
            s.qd.th4,
            s.qdd.th3,
            s.qdd.th4,
            p.velocity.x,
            p.velocity.y,
            p.acceleration.x,
            p.acceleration.y,
        );
    }
    Ok(())
}
