use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { }
        points {
            A = polar(a, phi);
            B = rot_z(phi) * vec3(a, 0.0, 0.0);
        }
    }
}

fn main() {}
