use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { norm, pi }
        drivers  { phi }
        unknowns { x, y }
        loops { polar(norm, phi) == vec2(x, norm(vec2(y, 0.0))); }
    }
}

fn main() {}
