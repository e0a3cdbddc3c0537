use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x }
        constraints { x == polar(a, phi) * polar(a, phi); }
    }
}

fn main() {}
