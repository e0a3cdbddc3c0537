use kinematics_core::mechanism;

mechanism! {
    struct M {
        params { a }
        joints { R }
    }
}

fn main() {}
