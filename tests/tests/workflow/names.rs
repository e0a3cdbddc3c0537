//! Names from the textbooks: a definition may call its unknowns `t3` and
//! `t4` though the built-in transforms have those names (the declared
//! item shadows the function, which cannot then be called in that
//! definition), and a parameter `T4` (not snake case: the generated
//! structs allow it). The four-bar written so gives the examples'
//! four-bar's numbers exactly, through the macro and at run time.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use kinematics_core::mechanism;
use kinematics_core::runtime::Model;
use kinematics_examples::FourBar;

mechanism! {
    /// The examples' four-bar, with the textbook's names.
    pub struct TextbookFourBar {
        params {
            /// Crank.
            a,
            /// Coupler.
            b,
            /// Rocker.
            c,
            /// Ground.
            d,
            /// An offset (unused).
            e,
            /// A torque (unused: the textbook's `T4`).
            T4
        }
        drivers  { phi }
        unknowns { t3, t4 }
        points   { C = vec2(d, 0.0) + polar(c, t4); }
        loops    { polar(a, phi) + polar(b, t3) == vec2(d, 0.0) + polar(c, t4); }
    }
}

const TEXT: &str = "struct TextbookFourBar {
    params   { a, b, c, d, e, T4 }
    drivers  { phi }
    unknowns { t3, t4 }
    points   { C = vec2(d, 0.0) + polar(c, t4); }
    loops    { polar(a, phi) + polar(b, t3) == vec2(d, 0.0) + polar(c, t4); }
}";

#[test]
fn textbook_names_shadow_the_built_in_functions() {
    let f = FourBar::CRANK_ROCKER;
    let want = f
        .assemble(&[0.5, 0.9, 1.7].into())
        .expect("the crank-rocker assembles");
    let g = TextbookFourBar {
        a: f.a,
        b: f.b,
        c: f.c,
        d: f.d,
        e: 0.0,
        T4: 0.0,
    };
    let got = g
        .assemble(&[0.5, 0.9, 1.7].into())
        .expect("the same four-bar assembles");
    assert_eq!((got.t3, got.t4), (want.th3, want.th4));
    let mut m = Model::compile(TEXT).expect("the names are accepted at run time too");
    m.set_values(&[f.a, f.b, f.c, f.d, 0.0, 0.0])
        .expect("values");
    let q = m.assemble(&[0.5, 0.9, 1.7]).expect("assembles");
    assert!((q[1] - want.th3).abs() < 1e-14 && (q[2] - want.th4).abs() < 1e-14);
}

#[test]
fn calling_a_shadowed_function_is_a_located_error() {
    let text = TEXT.replace(
        "polar(c, t4); }\n    loops",
        "polar(c, t4(phi)); }\n    loops",
    );
    let e = Model::compile(&text)
        .expect_err("t4 is an unknown here")
        .to_string();
    assert!(
        e.contains("`t4` is a coordinate of this definition, so it is not the built-in function `t4(…)` here"),
        "{e}"
    );
}
