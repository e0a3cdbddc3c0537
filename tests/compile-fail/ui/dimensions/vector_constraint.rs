use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x, y }
        constraints { polar(a, phi) == vec2(x, y); }
    }
}

fn main() {}
