//! The chapter's Example 4.2: R-RTR-RRT mechanism at φ = 45°, ω = 4.712 rad/s.
//!
//! Prints the computed velocities and accelerations beside the printed
//! answers of the textbook.
use kinematics_examples::RRtrRrt;

fn main() -> Result<(), kinematics_core::Error> {
    let m = RRtrRrt::EXAMPLE_4_2;
    let pose = m.assemble(&RRtrRrt::example_4_2_guess())?;
    let s = m.analyze(&pose, 4.712, 0.0)?;
    let (d, e) = (s.point_d(), s.point_e());
    println!("Example 4.2, R-RTR-RRT mechanism: AB = 0.100, AC = 0.150, CD = 0.075, DE = 0.200 m");
    println!("phi = 45 deg, omega = 4.712 rad/s");
    println!("{:<28} {:>12} {:>12}", "quantity", "computed", "book");
    let row = |name: &str, v: f64, book: f64| println!("{name:<28} {v:>12.3} {book:>12.3}");
    row("phi3 (deg)", pose.phi3.to_degrees(), 72.235);
    row("omega3 (rad/s)", s.qd.phi3, 1.807);
    row("alpha3 (rad/s^2)", s.qdd.phi3, 1.020);
    row("x_D (m)", d.position.x, -0.023);
    row("y_D (m)", d.position.y, -0.071);
    row("v_Dx (m/s)", d.velocity.x, 0.129);
    row("v_Dy (m/s)", d.velocity.y, -0.041);
    row("|v_D| (m/s)", d.speed(), 0.135);
    row("a_Dx (m/s^2)", d.acceleration.x, 0.147);
    row("a_Dy (m/s^2)", d.acceleration.y, 0.210);
    row("|a_D| (m/s^2)", d.acceleration.norm(), 0.256);
    row("x_E (m)", e.position.x, 0.164);
    row("v_E (m/s)", e.velocity.x, 0.113);
    row("a_E (m/s^2)", e.acceleration.x, 0.217);
    row("phi4 (deg)", pose.phi4.to_degrees(), 20.923);
    row("omega4 (rad/s)", s.qd.phi4, 0.221);
    row("alpha4 (rad/s^2)", s.qdd.phi4, -1.105);
    Ok(())
}
