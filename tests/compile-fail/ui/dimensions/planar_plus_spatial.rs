use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a, h }
        drivers  { phi }
        unknowns { y }
        points {
            A = polar(a, phi) + vec3(0.0, 0.0, h);
            B = vec3(0.0, y, h);
        }
        constraints { norm(B) == a; }
    }
}

fn main() {}
