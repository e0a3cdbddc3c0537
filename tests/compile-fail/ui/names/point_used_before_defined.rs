use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a, b }
        drivers  { phi }
        unknowns { x, y }
        points {
            B = C + polar(a, phi);
            C = vec2(b, 0.0);
        }
        loops { B == vec2(x, y); }
    }
}

fn main() {}
