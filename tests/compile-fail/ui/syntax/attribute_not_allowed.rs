use kinematics_core::mechanism;

mechanism! {
    struct M {
        params { #[derive(Debug)] a }
        drivers { phi }
        unknowns { x }
        constraints { x == a * phi; }
    }
}

fn main() {}
