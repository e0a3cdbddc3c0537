//! The chapter's Example 4.1: R-TRR mechanism at φ = 45°, n = 30 rev/min.
//!
//! Prints the computed velocities and accelerations beside the printed
//! answers of the textbook.
use kinematics_examples::{rpm_to_rad_per_s, RTrr};

fn main() -> Result<(), kinematics_core::Error> {
    let m = RTrr::EXAMPLE_4_1;
    let pose = m.assemble(&RTrr::example_4_1_guess())?;
    let omega = rpm_to_rad_per_s(30.0);
    let s = m.analyze(&pose, omega, 0.0)?;
    let b = s.point_b();
    println!("Example 4.1, R-TRR mechanism: AC = 0.100 m, BC = 0.300 m, phi = 45 deg, n = 30 rpm");
    println!("{:<28} {:>12} {:>12}", "quantity", "computed", "book");
    let row = |name: &str, v: f64, book: f64| println!("{name:<28} {v:>12.3} {book:>12.3}");
    row("x_B (m)", b.position.x, 0.256);
    row("y_B (m)", b.position.y, 0.256);
    row("v_Bx (m/s)", b.velocity.x, -0.999);
    row("v_By (m/s)", b.velocity.y, 0.609);
    row("|v_B| (m/s)", b.speed(), 1.171);
    row("a_Bx (m/s^2)", b.acceleration.x, -1.802);
    // The book's −4.255 is the value for ω = π (30 rev/min exactly); with its
    // rounded ω = 3.141, used here as in the rest of the example, −4.2534.
    row("a_By (m/s^2)", b.acceleration.y, -4.255);
    row("|a_B| (m/s^2)", b.acceleration.norm(), 4.620);
    row("phi3 (deg)", pose.phi3.to_degrees(), 58.633);
    row("omega3 (rad/s)", s.qd.phi3, 3.903);
    row("alpha3 (rad/s^2)", s.qdd.phi3, -2.252);
    row("slider rate s' (m/s)", s.qd.s, f64::NAN);
    Ok(())
}
