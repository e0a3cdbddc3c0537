// A planar body's angle is a sum of angular coordinates times constants.
use kinematics_core::mechanism;

mechanism! {
    /// A slider-crank with masses.
    pub struct SliderCrank {
        params { a, b, m }
        drivers { phi }
        unknowns { th, x }
        points { B = polar(a, phi); C = vec2(x, 0.0); }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
        bodies {
            rod(mass = m, center = B, angle = th * th);
            piston(mass = m, center = C, angle = x);
        }
    }
}

fn main() {}
