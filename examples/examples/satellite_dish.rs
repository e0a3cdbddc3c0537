//! Satellite dish of the notes' Example 7.4: ω₁ = 6 rad/s (ω̇₁ = 3) about z,
//! ω₂ = 2 rad/s (ω̇₂ = 1.5) about the mount's x axis, θ = 25°, horn at 1.4 m.
use kinematics_examples::{SatelliteDish, SatelliteDishCoords};

fn main() -> Result<(), kinematics_core::Error> {
    let m = SatelliteDish { r: 1.4 };
    let pose = m.assemble(&SatelliteDishCoords {
        phi: 0.0,
        th: 25f64.to_radians(),
    })?;
    let s = m.analyze(&pose, [6.0, 2.0], [3.0, 1.5])?;
    let (dish, a) = (s.frame_dish(), s.point_a());
    let v3 = |v: &kinematics_core::nalgebra::Vector3<f64>| {
        format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z)
    };
    println!(
        "omega of the dish  {} rad/s     (book (2, 0, 6))",
        v3(&dish.angular_velocity)
    );
    println!(
        "alpha of the dish  {} rad/s^2   (book (1.5, 12, 3))",
        v3(&dish.angular_acceleration)
    );
    println!(
        "velocity of A      {} m/s       (book (-7.6, -1.18, 2.54))",
        v3(&a.velocity)
    );
    println!(
        "acceleration of A  {} m/s^2     (book (10.4, -51.6, -0.46))",
        v3(&a.acceleration)
    );
    Ok(())
}
