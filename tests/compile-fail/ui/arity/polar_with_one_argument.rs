use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x, y }
        loops { polar(a) == vec2(x, y); }
    }
}

fn main() {}
