//! Models the runtime's unit tests share.

use super::Model;

/// A planar four-bar: crank a at φ, coupler b at θ3, rocker c at θ4
/// from D = (d, 0); points B (the crank pin) and C (the rocker pin).
pub(super) const FOUR_BAR: &str = "
pub struct FourBar {
    params { a, b, c, d }
    drivers  { phi }
    unknowns { th3, th4 }
    points { B = polar(a, phi); C = vec2(d, 0.0) + polar(c, th4); }
    loops { B + polar(b, th3) == C; }
}";

/// [`FOUR_BAR`] as a crank-rocker: a = 0.04, b = 0.12, c = 0.10,
/// d = 0.11.
pub(super) fn crank_rocker() -> Model {
    Model::compile(FOUR_BAR)
        .expect("the four-bar compiles")
        .with_values(&[0.04, 0.12, 0.10, 0.11])
        .expect("its values")
}
