use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x }
        constraints { x == a; }
        loops { polar(a, phi) == vec2(1.0, 2.0); }
    }
}

fn main() {}
