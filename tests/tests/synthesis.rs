//! Dimensional synthesis: designs recovered from targets they pass
//! through, the literature's path-generation problems, constraints.

use kinematics_core::{mechanism, synthesis::Synthesis};

mechanism! {
    /// A four-bar with its coupler point P, ground pivots fixed.
    struct FourBar {
        params { a, b, c, d, p, beta }
        drivers { phi }
        unknowns { th3, th4 }
        points { P = polar(a, phi) + polar(p, th3 + beta); }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
        sensitivities { a, b, c, p, beta }
    }
}

#[test]
fn a_design_is_recovered_from_five_points_with_prescribed_timing() {
    let truth = FourBar { a: 1.0, b: 3.0, c: 2.5, d: 3.0, p: 1.5, beta: 0.6 };
    let start = truth.assemble(&FourBarCoords { phi: 0.0, th3: 0.5, th4: 1.5 }).unwrap();
    let phis = [0.3, 1.1, 2.0, 3.5, 5.0];
    let targets: Vec<[f64; 2]> = phis
        .iter()
        .map(|&phi| {
            let pose = truth.assemble(&FourBarCoords { phi, ..start }).unwrap();
            let p = truth.positions(&pose).P;
            [p.x, p.y]
        })
        .collect();
    let guess = FourBar { a: 1.1, b: 2.8, c: 2.7, d: 3.0, p: 1.3, beta: 0.5 };
    let found = Synthesis::path(&guess, FourBar::PHI, "P", &targets, &start)
        .prescribed(&phis)
        .run()
        .unwrap();
    println!("{found:#?}");
    assert!(found.sum_squares < 1e-20);
}
