//! The robot arm of the worked problem, as a serial chain of joint
//! transforms: ω₁ = ω₄ = ω₅ = 1 rad/s, L₁ = 1.2, L₂ = 0.6, L₃ = 0.2 m,
//! α = 60°.
use kinematics_examples::{RobotArm, RobotArmCoords};

fn main() -> Result<(), kinematics_core::Error> {
    let m = RobotArm {
        l1: 1.2,
        l2: 0.6,
        l3: 0.2,
        alpha: 60f64.to_radians(),
    };
    let pose = m.assemble(&RobotArmCoords {
        q1: 0.0,
        q4: 0.0,
        q5: 0.0,
    })?;
    let s = m.analyze(&pose, [1.0, 1.0, 1.0], [0.0, 0.0, 0.0])?;
    let v3 = |v: &kinematics_core::nalgebra::Vector3<f64>| {
        format!("({:.4}, {:.4}, {:.4})", v.x, v.y, v.z)
    };
    println!(
        "omega of the arm   {} rad/s",
        v3(&s.frame_arm().angular_velocity)
    );
    println!(
        "alpha of the arm   {} rad/s^2",
        v3(&s.frame_arm().angular_acceleration)
    );
    println!(
        "v_B                {} m/s     (book (-1.12, -0.20, -0.69))",
        v3(&s.point_b().velocity)
    );
    println!("a_A                {} m/s^2", v3(&s.point_a().acceleration));
    println!("a_B                {} m/s^2", v3(&s.point_b().acceleration));
    Ok(())
}
