//! RSSR spatial four-bar of the notes' Example 7.3 (a = 102, b = 381,
//! c = 254 mm; the solution computes with d = 314 mm, the statement says
//! 315): output angle and velocity at φ = 60°, 240 rev/min; coupler
//! angular velocity with no spin about AB; accelerations at φ = 0,
//! 1200 rev/min and 3000 rev/min/s.
use kinematics_core::rigid::{no_spin_angular_acceleration, no_spin_angular_velocity};
use kinematics_examples::{rpm_to_rad_per_s, Rssr, RssrCoords};

fn main() -> Result<(), kinematics_core::Error> {
    for d in [0.315, 0.314] {
        let m = Rssr {
            a: 0.102,
            b: 0.381,
            c: 0.254,
            d,
        };
        println!("RSSR, d = {:.0} mm", d * 1000.0);
        let pose = m.assemble(&RssrCoords {
            phi: 60f64.to_radians(),
            psi: 1.5,
        })?;
        let s = m.analyze(&pose, rpm_to_rad_per_s(240.0), 0.0)?;
        let (a, b) = (s.point_a(), s.point_b());
        let w = no_spin_angular_velocity(&(b.position - a.position), &(b.velocity - a.velocity))?;
        println!("  phi = 60 deg, 240 rpm     computed          book");
        println!(
            "  psi (deg)             {:>12.3} {:>12}",
            pose.psi.to_degrees(),
            "88.42"
        );
        println!("  omega_o (rad/s)       {:>12.3} {:>12}", s.qd.psi, "10.7");
        println!(
            "  coupler |Omega| (rad/s){:>11.3} {:>12}",
            w.norm(),
            "3.61 / 3.64"
        );
        println!(
            "  coupler Omega (rad/s)  ({:.3}, {:.3}, {:.3})  (-2.239, -2.685, -1.013)",
            w.x, w.y, w.z
        );
        let pose = m.assemble(&RssrCoords { phi: 0.0, psi: 1.2 })?;
        let s = m.analyze(&pose, rpm_to_rad_per_s(1200.0), rpm_to_rad_per_s(3000.0))?;
        let (a, b) = (s.point_a(), s.point_b());
        let bb = b.position - a.position;
        let al = no_spin_angular_acceleration(&bb, &(b.acceleration - a.acceleration))?;
        println!("  phi = 0, 1200 rpm, 3000 rpm/s");
        println!(
            "  psi (deg)             {:>12.3} {:>12}",
            pose.psi.to_degrees(),
            "70.64"
        );
        println!(
            "  alpha_o (rad/s^2)     {:>12.1} {:>12}",
            s.qdd.psi, "12607"
        );
        println!(
            "  coupler alpha (rad/s^2) ({:.1}, {:.1}, {:.1})  (-53, -65.3, -4497)\n",
            al.x, al.y, al.z
        );
    }
    Ok(())
}
