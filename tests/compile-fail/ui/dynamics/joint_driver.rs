// A driver acts in the joint whose motion it is: an angle in a revolute
// joint, a length in a prismatic one.
use kinematics_core::mechanism;

mechanism! {
    /// A slider-crank whose crank is said to slide.
    pub struct SliderCrank {
        params { a, b, m }
        drivers { phi }
        unknowns { th, x }
        points { O = vec2(0.0, 0.0); B = polar(a, phi); C = vec2(x, 0.0); }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
        bodies { crank(mass = m, center = O, angle = phi); }
        joints {
            bearing(prismatic, O, between = (ground, crank), axis = vec2(1.0, 0.0), driver = phi);
        }
    }
}

fn main() {}
