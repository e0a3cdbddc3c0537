//! Crank-rocker four-bar over a full turn of the crank.
use kinematics_core::mechanism;

mechanism! {
    /// Planar crank-rocker four-bar. Ground pivots A = (0, 0) and D = (d, 0).
    pub struct FourBar {
        params {
            /// Crank AB (m).
            a,
            /// Coupler BC (m).
            b,
            /// Rocker DC (m).
            c,
            /// Ground AD (m).
            d,
            /// Distance from B to the coupler point P (m).
            p,
            /// Angle of BP from BC (rad).
            beta
        }
        drivers  { phi }
        unknowns { th3, th4 }
        points {
            B = polar(a, phi);
            C = vec2(d, 0.0) + polar(c, th4);
            P = B + polar(p, th3 + beta);
        }
        loops { B + polar(b, th3) == C; }
    }
}

fn main() -> Result<(), kinematics_core::Error> {
    let m = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 30f64.to_radians(),
    };
    let mut pose = m.assemble(&FourBarCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 2.0,
    })?;
    for k in 0..=12 {
        pose.phi = f64::from(k) * 30f64.to_radians();
        pose = m.assemble(&pose)?;
        let s = m.analyze(&pose, 10.0, 0.0)?;
        println!(
            "{:6.1} {:8.3} {:8.3} {:8.3} {:8.3} {:9.3} {:9.3} {:8.4} {:8.4}",
            pose.phi.to_degrees(),
            pose.th3.to_degrees(),
            pose.th4.to_degrees(),
            s.qd.th3,
            s.qd.th4,
            s.qdd.th3,
            s.qdd.th4,
            s.point_p().speed(),
            s.point_p().acceleration.norm()
        );
    }
    Ok(())
}
