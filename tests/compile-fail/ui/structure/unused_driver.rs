use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi, psi }
        unknowns { x }
        constraints { x == a * phi; }
    }
}

fn main() {}
