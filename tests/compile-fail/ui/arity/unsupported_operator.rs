use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x }
        constraints { x == a % phi; }
    }
}

fn main() {}
