// A body needs a mass that is a constant and a centre of mass that is a
// point; its keys are mass, center, angle, frame and inertia; a body that
// does not turn has no moment of inertia.
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
            crank(center = B, angle = phi);
            rod(mass = m, center = th, angle = th);
            piston(mass = m * x, center = C);
            slider(mass = m, center = C, masss = m);
            block(mass = m, center = C, inertia = 0.1);
            rod(mass = m, center = B);
        }
    }
}

fn main() {}
