use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a, b }
        drivers  { a }
        unknowns { x, y }
        loops { polar(b, a) == vec2(x, y); }
    }
}

fn main() {}
