use kinematics_core::mechanism;

mechanism! {
    /// An RSSR declared with one driver but without its passive freedom:
    /// F = 6(4 − 4 − 1) + 8 = 2.
    struct Rssr {
        params   { a, b, c, d }
        drivers  { phi }
        unknowns { psi }
        points {
            A = vec3(-a * cos(phi), 0.0, a * sin(phi));
            B = vec3(-d - c * cos(psi), c * sin(psi), 0.0);
        }
        constraints { norm(B - A) == b; }
        joints { links: 4, R: 2, S: 2 }
    }
}

fn main() {}
