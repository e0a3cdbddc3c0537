use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x, y }
        constraints { x == a * phi; 1.0 == 0.0; }
    }
}

fn main() {}
