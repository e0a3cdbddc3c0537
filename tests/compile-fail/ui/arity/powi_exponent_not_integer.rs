use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x }
        constraints { x == powi(a, 1.5) * phi; }
    }
}

fn main() {}
