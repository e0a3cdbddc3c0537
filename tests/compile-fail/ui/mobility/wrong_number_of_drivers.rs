use kinematics_core::mechanism;

mechanism! {
    /// A four-bar (F = 1) declared with two drivers.
    struct FourBar {
        params   { a, b, c, d }
        drivers  { phi, th3 }
        unknowns { th4, s }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c + s, th4); }
        joints { R: 4 }
    }
}

fn main() {}
