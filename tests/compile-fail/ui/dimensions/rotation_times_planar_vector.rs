use kinematics_core::mechanism;

mechanism! {
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { }
        points { A = rot_z(phi) * polar(a, phi); }
    }
}

fn main() {}
