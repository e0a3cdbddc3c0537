use kinematics_core::mechanism;

mechanism! {
    struct FourBar {
        params   { a, b, c, d }
        drivers  { phi }
        unknowns { th3, th4 }
        loops { polar(a, phi) + polar(b, th) == vec2(d, 0.0) + polar(c, th4); }
    }
}

fn main() {}
