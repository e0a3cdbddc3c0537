use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { r }
        drivers  { t }
        unknowns { y }
        constraints { powi(y, 2) + powi(t, 2) == powi(r, 2); }
        joints { R: 2 }
    }
}

fn main() {}
