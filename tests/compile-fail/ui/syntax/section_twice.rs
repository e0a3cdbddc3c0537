use kinematics_core::mechanism;

mechanism! {
    struct M {
        params { a }
        drivers { phi }
        params { b }
    }
}

fn main() {}
