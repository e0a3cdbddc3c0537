use kinematics_core::mechanism;

mechanism! {
    struct M {
        params { a }
    }
}

fn main() {}
