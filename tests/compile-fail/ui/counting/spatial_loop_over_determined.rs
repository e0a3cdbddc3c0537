use kinematics_core::mechanism;

mechanism! {
    /// A spatial loop is three scalar equations: two unknowns are too few.
    struct M {
        params   { l }
        drivers  { phi }
        unknowns { th, s }
        loops { rot_z(phi) * vec3(l, 0.0, s) == vec3(l * cos(th), l * sin(th), 0.5); }
    }
}

fn main() {}
