// Each joint has a kind, a point and the bodies it joins, an axis where
// its kind needs one, and a driver only where a driver acts.
use kinematics_core::mechanism;

mechanism! {
    /// A slider-crank with its joints.
    pub struct SliderCrank {
        params { a, b, m }
        drivers { phi }
        unknowns { th, x }
        points { O = vec2(0.0, 0.0); B = polar(a, phi); C = vec2(x, 0.0); }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
        bodies {
            crank(mass = m, center = O, angle = phi);
            rod(mass = m, center = B, angle = th);
            piston(mass = m, center = C);
        }
        joints {
            bearing(hinge, O, between = (ground, crank));
            pin(revolute, B);
            wrist(spherical, C, between = (rod, piston));
            cylinder(prismatic, C, between = (ground, piston));
            slot(revolute, B, between = (crank, rod), axis = vec2(1.0, 0.0));
            guide(prismatic, C, between = (ground, piston), axis = vec2(1.0, 0.0), driver = x);
            bearing(revolute, O, between = (ground, crank));
            stub(revolute, Q, between = (ground, crank));
            wheel(revolute, O, between = (ground, wheel));
            twice(revolute, O, between = (crank, crank));
            motor(revolute, O, between = (ground, crank), torque = 1.0);
            lone(revolute);
        }
    }
}

fn main() {}
