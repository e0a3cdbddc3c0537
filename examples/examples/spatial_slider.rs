//! Spatial crank and slider of the notes' Example 7.2 at φ = 90°,
//! ω = 10 rad/s: slider velocity and the coupler's angular velocity with no
//! spin about AB.
use kinematics_core::rigid::no_spin_angular_velocity;
use kinematics_examples::{SpatialSlider, SpatialSliderCoords};

fn main() -> Result<(), kinematics_core::Error> {
    let m = SpatialSlider {
        a: 50.0,
        b: 175.0,
        h: 75.0,
    };
    let pose = m.assemble(&SpatialSliderCoords {
        phi: 90f64.to_radians(),
        y: 140.0,
    })?;
    let s = m.analyze(&pose, 10.0, 0.0)?;
    let (a, b) = (s.point_a(), s.point_b());
    let w = no_spin_angular_velocity(&(b.position - a.position), &(b.velocity - a.velocity))?;
    println!("Spatial crank and slider, a = 50, b = 175, h = 75 mm, phi = 90 deg, 10 rad/s");
    println!("slider position y = {:.3} mm (book 150)", pose.y);
    println!("slider velocity   = {:.3} mm/s (book -250)", s.qd.y);
    println!(
        "coupler Omega, no spin about AB = ({:.3}, {:.3}, {:.3}) rad/s",
        w.x, w.y, w.z
    );
    Ok(())
}
