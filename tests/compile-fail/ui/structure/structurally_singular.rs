use kinematics_core::mechanism;

mechanism! {
    /// x is fixed twice; y and z appear only together.
    struct M {
        params   { a }
        drivers  { phi }
        unknowns { x, y, z }
        constraints {
            x == a * phi;
            powi(x, 2) == a;
            y + z == 1.0;
        }
    }
}

fn main() {}
