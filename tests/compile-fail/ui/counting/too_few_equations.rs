use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a, b, c, d }
        drivers  { phi }
        unknowns { th3, th4, th5 }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
    }
}

fn main() {}
