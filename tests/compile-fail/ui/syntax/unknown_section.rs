use kinematics_core::mechanism;

mechanism! {
    struct M {
        params { a }
        masses { crank, rocker }
    }
}

fn main() {}
