// Each item of `bodies` is a body with its properties by name.
use kinematics_core::mechanism;

mechanism! {
    struct M {
        params { a }
        drivers { phi }
        unknowns { }
        points { B = polar(a, phi); }
        bodies { crank, rocker }
    }
}

fn main() {}
