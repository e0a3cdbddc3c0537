use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x }
        constraints { norm(a * phi) == x; }
    }
}

fn main() {}
