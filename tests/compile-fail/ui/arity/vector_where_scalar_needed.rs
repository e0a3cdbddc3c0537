use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x }
        points { B = polar(a, phi); }
        constraints { x == sin(B); }
    }
}

fn main() {}
