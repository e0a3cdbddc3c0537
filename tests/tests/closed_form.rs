//! Closed-form assembly: no guess, both modes, against Newton.
use kinematics_core::mechanism;

mechanism! {
    /// Four-bar.
    pub struct FourBar {
        params { a, b, c, d, p, beta }
        drivers { phi }
        unknowns { th3, th4 }
        points { P = polar(a, phi) + polar(p, th3 + beta); }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
    }
}

#[test]
fn smoke() {
    let m = FourBar {
        a: 1.0,
        b: 3.0,
        c: 2.5,
        d: 3.5,
        p: 1.0,
        beta: 0.3,
    };
    for r in m.assemble_all(0.7) {
        println!("{r:?}");
    }
    println!("{:?}", FourBar::BLOCKS);
}
