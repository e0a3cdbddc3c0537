// A driver handle belongs to its mechanism: a slider-crank's crank cannot
// drive a four-bar's sweep.
use kinematics_core::mechanism;

mechanism! {
    /// Four-bar.
    pub struct FourBar {
        params { a, b, c, d }
        drivers { phi }
        unknowns { th3, th4 }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
    }
}

mechanism! {
    /// Slider-crank.
    pub struct SliderCrank {
        params { a, b }
        drivers { phi }
        unknowns { th, x }
        loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
    }
}

fn main() {
    let m = FourBar { a: 0.04, b: 0.12, c: 0.10, d: 0.11 };
    let start = FourBarCoords { phi: 0.0, th3: 1.0, th4: 1.6 };
    let _ = m.sweep(SliderCrank::PHI, &start).run();
}
