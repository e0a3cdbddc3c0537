use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x, y }
        constraints { x == a * phi; y - y == 0.0; y == x; }
    }
}

fn main() {}
