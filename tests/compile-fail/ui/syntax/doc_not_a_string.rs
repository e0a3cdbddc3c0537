use kinematics_core::mechanism;

mechanism! {
    struct M {
        params { #[doc = 42] a }
        drivers { phi }
        unknowns { x }
        constraints { x == a * phi; }
    }
}

fn main() {}
