use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a, b, a }
        drivers  { phi }
        unknowns { x, y }
        loops { polar(b, phi) == vec2(x, y + a); }
    }
}

fn main() {}
