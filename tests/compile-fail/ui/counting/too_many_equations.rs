use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a, b }
        drivers  { phi }
        unknowns { x }
        loops { polar(a, phi) == vec2(x, b); }
    }
}

fn main() {}
