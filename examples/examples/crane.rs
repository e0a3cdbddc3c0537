//! Crane of the notes' Practical Exercise 2: cab at 0.30 rad/s about the
//! vertical, boom raised at 0.50 rad/s relative to the cab, both constant;
//! boom 12 m at 30° elevation.
use kinematics_examples::{Crane, CraneCoords};

fn main() -> Result<(), kinematics_core::Error> {
    let m = Crane { l: 12.0 };
    let pose = m.assemble(&CraneCoords {
        phi: 0.0,
        th: 30f64.to_radians(),
    })?;
    let s = m.analyze(&pose, [0.30, 0.50], [0.0, 0.0])?;
    let (boom, tip) = (s.frame_boom(), s.point_p());
    let v3 = |v: &kinematics_core::nalgebra::Vector3<f64>| {
        format!("({:.4}, {:.4}, {:.4})", v.x, v.y, v.z)
    };
    println!("z vertical, boom in the x-z plane at this instant");
    println!(
        "(i)   omega of the boom       {} rad/s",
        v3(&boom.angular_velocity)
    );
    println!(
        "(ii)  alpha of the boom       {} rad/s^2",
        v3(&boom.angular_acceleration)
    );
    println!("(iii) velocity of the tip     {} m/s", v3(&tip.velocity));
    println!(
        "(iv)  acceleration of the tip {} m/s^2",
        v3(&tip.acceleration)
    );
    Ok(())
}
