// Degrees and revolutions per minute exist for angle drivers only: a
// slider's position is a length.
use kinematics_core::mechanism;

mechanism! {
    /// An inverted slider-crank driven by its slider.
    pub struct SliderDriven {
        params { a, d }
        drivers { s }
        unknowns { phi, th }
        loops { polar(a, phi) + polar(s, th) == vec2(d, 0.0); }
    }
}

fn main() {
    let m = SliderDriven { a: 0.05, d: 0.12 };
    let start = SliderDrivenCoords { s: 0.1, phi: 1.0, th: -0.4 };
    let _ = m.sweep(SliderDriven::S, &start).to_deg(30.0).run();
}
