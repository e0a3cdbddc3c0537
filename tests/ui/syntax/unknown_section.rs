use kinematics_core::mechanism;

mechanism! {
    struct M {
        params { a }
        bodies { crank, rocker }
    }
}

fn main() {}
