use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a, b }
        drivers  { phi }
        unknowns { x, y }
        loops { polar(a, phi) + b == vec2(x, y); }
    }
}

fn main() {}
