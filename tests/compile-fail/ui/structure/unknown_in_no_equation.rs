use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x, y }
        constraints { x == a * phi; x * x == a; }
    }
}

fn main() {}
