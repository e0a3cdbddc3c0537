// Sensitivities are taken with respect to parameters: a coordinate or an
// unknown name is an error at the name.
use kinematics_core::mechanism;

mechanism! {
    /// A slider-crank.
    pub struct SliderCrank {
        params { a, b }
        drivers { phi }
        unknowns { th, x }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
        sensitivities { a, x, a }
    }
}

fn main() {}
