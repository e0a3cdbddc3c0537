use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { norm }
        drivers  { phi }
        unknowns { x, y }
        loops { polar(norm, phi) == vec2(x, y); }
    }
}

fn main() {}
