use kinematics_core::mechanism;

mechanism! {
    /// A spatial loop gives three scalar equations, for three unknowns.
    pub struct Pointer {
        params   { l }
        drivers  { phi }
        unknowns { psi, th, s }
        loops { rot_z(psi) * rot_x(th) * vec3(0.0, l + s, 0.0) == vec3(0.3, phi, 0.2); }
    }
}

fn main() {}
