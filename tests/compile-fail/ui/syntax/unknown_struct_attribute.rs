// An attribute the parameters struct cannot take (no derive of its own
// asks for it) is an error at the attribute.
use kinematics_core::mechanism;

mechanism! {
    /// A crank.
    #[inline]
    pub struct Crank {
        params { a }
        drivers { phi }
        unknowns { }
        points { B = polar(a, phi); }
    }
}

fn main() {}
