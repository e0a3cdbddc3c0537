// Each load names what it acts on and has a value of the right dimension;
// a coordinate's rate may be used only in a load; gravity is a constant.
use kinematics_core::mechanism;

mechanism! {
    /// A slider-crank with loads.
    pub struct SliderCrank {
        params { a, b, m, p }
        drivers { phi }
        unknowns { th, x }
        points { B = polar(a, phi); C = vec2(x, 0.0) + vec2(rate(x), 0.0); }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
        bodies { rod(mass = m, center = B, angle = th); }
        loads {
            gravity(vec2(0.0, -9.81 * x));
            forse(C, vec2(p, 0.0));
            force(p, 1.0);
            force(C, vec3(p, 0.0, 0.0));
            torque(crank, p);
            force(C);
            spring(B, C, stiffness = p, between = rod);
        }
    }
}

fn main() {}
