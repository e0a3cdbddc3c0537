// Each driver's handle is its name in upper case: `points` would be
// `POINTS`, already the number of points.
use kinematics_core::mechanism;

mechanism! {
    /// A crank.
    pub struct Crank {
        params { a }
        drivers { points }
        unknowns { }
        points { B = polar(a, points); }
    }
}

fn main() {}
