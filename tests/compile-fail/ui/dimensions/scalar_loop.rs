use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x, y }
        loops { a * phi == x; }
        constraints { y == x; }
    }
}

fn main() {}
