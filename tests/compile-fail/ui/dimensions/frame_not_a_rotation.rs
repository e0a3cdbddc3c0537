use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { l }
        drivers  { q }
        unknowns { }
        frames { link = vec3(l, 0.0, 0.0); }
    }
}

fn main() {}
