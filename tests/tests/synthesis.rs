//! Dimensional synthesis: designs recovered from targets they pass
//! through, the literature's path-generation problems, constraints.

#![allow(missing_docs, clippy::unwrap_used)]

use kinematics_core::{
    mechanism,
    synthesis::{Synthesis, Timing},
};

/// Expands a definition with `mechanism!` and keeps its text in
/// `FOUR_BAR_TEXT`, for the same model compiled at run time.
macro_rules! with_text {
    ($($definition:tt)*) => {
        mechanism! { $($definition)* }
        /// The definition of [`FourBar`] as text.
        const FOUR_BAR_TEXT: &str = stringify!($($definition)*);
    };
}

with_text! {
    /// A four-bar with its coupler point P, ground pivots fixed.
    struct FourBar {
        params { a, b, c, d, p, beta }
        drivers { phi }
        unknowns { th3, th4 }
        points { P = polar(a, phi) + polar(p, th3 + beta); }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
        sensitivities { a, b, c, d, p, beta }
    }
}

/// The design the tests' targets come from.
const TRUTH: FourBar = FourBar {
    a: 1.0,
    b: 3.0,
    c: 2.5,
    d: 3.0,
    p: 1.5,
    beta: 0.6,
};

/// A starting design near [`TRUTH`].
const GUESS: FourBar = FourBar {
    a: 1.1,
    b: 2.8,
    c: 2.7,
    d: 3.0,
    p: 1.3,
    beta: 0.5,
};

/// [`TRUTH`] assembled at φ = 0.
fn start() -> FourBarCoords {
    TRUTH
        .assemble(&FourBarCoords {
            phi: 0.0,
            th3: 0.5,
            th4: 1.5,
        })
        .unwrap()
}

#[test]
fn a_design_is_recovered_from_five_points_with_prescribed_timing() {
    let start = start();
    let phis = [0.3, 1.1, 2.0, 3.5, 5.0];
    let targets = targets_of(&TRUTH, &start, &phis);
    let found = Synthesis::path(&GUESS, FourBar::PHI, "P", &targets, &start)
        .prescribed(&phis)
        .run()
        .unwrap();
    assert!(found.sum_squares < 1e-20, "{found:?}");
}

/// The targets of `truth`'s point P at the crank angles `phis`.
fn targets_of(truth: &FourBar, start: &FourBarCoords, phis: &[f64]) -> Vec<[f64; 2]> {
    phis.iter()
        .map(|&phi| {
            let pose = truth.assemble(&FourBarCoords { phi, ..*start }).unwrap();
            let p = truth.positions(&pose).P;
            [p.x, p.y]
        })
        .collect()
}

#[test]
fn free_and_relative_timing_recover_the_crank_angles_too() {
    let start = start();
    let phis = [0.3, 1.1, 2.0, 2.9, 3.5, 4.2, 5.0];
    let targets = targets_of(&TRUTH, &start, &phis);
    let guess = FourBar {
        a: 1.05,
        b: 2.9,
        c: 2.6,
        d: 3.0,
        p: 1.45,
        beta: 0.55,
    };
    // Free timing from angles 0.1 rad off.
    let off: Vec<f64> = phis.iter().map(|p| p + 0.1).collect();
    let found = Synthesis::path(&guess, FourBar::PHI, "P", &targets, &start)
        .driver_guesses(&off)
        .run()
        .unwrap();
    assert!(found.sum_squares < 1e-20, "{found:?}");
    for (got, want) in found.driver_values.iter().zip(&phis) {
        assert!((got - want).abs() < 1e-8, "{got} {want}");
    }
    assert!((found.design.b - 3.0).abs() < 1e-8 && (found.design.beta - 0.6).abs() < 1e-8);
    assert_eq!(
        found.full_turn,
        Some(true),
        "a = 1 is the shortest and 1 + 3 ≤ 2.5 + 3"
    );
    // Relative timing: increments known, the first angle found.
    let steps: Vec<f64> = phis.iter().map(|p| p - phis[0]).collect();
    let start2 = FourBarCoords { phi: 0.2, ..start };
    let found = Synthesis::path(&guess, FourBar::PHI, "P", &targets, &start2)
        .timing(Timing::Relative(steps))
        .run()
        .unwrap();
    assert!(found.sum_squares < 1e-20, "{found:?}");
    assert!((found.driver_values[0] - 0.3).abs() < 1e-8);
}

/// Input–output pairs (φ, θ4) of [`TRUTH`], from its closed form.
fn true_pairs(start: &FourBarCoords) -> Vec<(f64, f64)> {
    [0.2, 0.9, 1.6, 2.4, 3.3, 4.4]
        .iter()
        .map(|&phi| {
            (
                phi,
                TRUTH
                    .assemble(&FourBarCoords { phi, ..*start })
                    .unwrap()
                    .th4,
            )
        })
        .collect()
}

#[test]
fn function_generation_recovers_the_output_angles() {
    let start = start();
    let pairs = true_pairs(&start);
    let guess = FourBar {
        a: 0.9,
        b: 3.2,
        c: 2.3,
        ..TRUTH
    };
    let found = Synthesis::function(&guess, FourBar::PHI, "th4", &pairs, &start)
        .vary(&["a", "b", "c"])
        .run()
        .unwrap();
    assert!(found.sum_squares < 1e-20, "{found:?}");
    assert!((found.design.a - 1.0).abs() < 1e-8);
    assert!((found.design.c - 2.5).abs() < 1e-8);
    // θ4 of the design found, assembled on its own, at each input.
    for (phi, psi) in &pairs {
        let pose = found
            .design
            .assemble(&FourBarCoords { phi: *phi, ..start })
            .unwrap();
        assert!((pose.th4 - psi).abs() < 1e-9);
    }
}

#[test]
fn bounds_hold_at_every_result_and_grashof_is_enforced() {
    let start = start();
    let phis = [0.3, 1.1, 2.0, 3.5, 5.0];
    let targets = targets_of(&TRUTH, &start, &phis);
    // The best c is 2.5; held to [2.6, 3]: c ends inside, on the bound.
    let found = Synthesis::path(&GUESS, FourBar::PHI, "P", &targets, &start)
        .prescribed(&phis)
        .bounds("c", 2.6, 3.0)
        .run()
        .unwrap();
    assert!(
        found.design.c >= 2.6 && found.design.c <= 3.0,
        "{}",
        found.design.c
    );
    assert!((found.design.c - 2.6).abs() < 1e-6, "{}", found.design.c);
    assert!(found.sum_squares > 1e-8, "the bound costs accuracy");
    // Grashof with the crank shortest, while a coupler point that wants a
    // non-Grashof design (b large) is fitted: the inequalities hold.
    // (1 + 4.2 > 2 + 3: a rocker-rocker, assembled for φ ≥ 0.54 rad.)
    let non_grashof = FourBar {
        a: 1.0,
        b: 4.2,
        c: 2.0,
        d: 3.0,
        p: 1.5,
        beta: 0.6,
    };
    let s2 = non_grashof
        .assemble(&FourBarCoords {
            phi: 1.0,
            th3: 0.5,
            th4: 1.5,
        })
        .unwrap();
    let phis2 = [0.8, 1.2, 1.6, 2.0];
    let targets2 = targets_of(&non_grashof, &s2, &phis2);
    let found = Synthesis::path(&TRUTH, FourBar::PHI, "P", &targets2, &s2)
        .prescribed(&phis2)
        .vary(&["a", "b", "c", "p", "beta"])
        .grashof_crank("a", "b", "c", "d", 0.05)
        .run()
        .unwrap();
    let m = found.design;
    assert!(found.constraints_met);
    let lengths = [m.a, m.b, m.c, m.d];
    let (s, l) = (
        lengths.iter().copied().fold(f64::INFINITY, f64::min),
        lengths.iter().copied().fold(0.0, f64::max),
    );
    assert!(
        s + l <= lengths.iter().sum::<f64>() - s - l - 0.05 + 1e-9,
        "{m:?}"
    );
    assert!(m.a <= s + 1e-12, "{m:?}");
    assert_eq!(found.full_turn, Some(true));
}

#[test]
fn mistakes_are_errors_that_say_what_is_wrong() {
    let start = start();
    let t = [[0.0, 1.0], [1.0, 2.0]];
    let msg = |r: Result<_, kinematics_core::Error>| {
        r.map(|_: kinematics_core::synthesis::Synthesized<FourBar>| ())
            .unwrap_err()
            .to_string()
    };
    assert!(
        msg(Synthesis::path(&TRUTH, FourBar::PHI, "Q", &t, &start).run()).contains("no point `Q`")
    );
    assert!(msg(Synthesis::path(&TRUTH, FourBar::PHI, "P", &t, &start)
        .vary(&["e"])
        .run())
    .contains("`e` is not a parameter"));
    assert!(
        msg(Synthesis::path(&TRUTH, FourBar::PHI, "P", &[[1.0, 2.0, 3.0]], &start).run())
            .contains("3 components")
    );
    assert!(msg(Synthesis::path(&TRUTH, FourBar::PHI, "P", &t, &start)
        .prescribed(&[0.1])
        .run())
    .contains("one driver value per target"));
    assert!(
        msg(Synthesis::function(&TRUTH, FourBar::PHI, "phi", &[(0.0, 1.0)], &start).run())
            .contains("no unknown `phi`")
    );
    assert!(msg(Synthesis::path(&TRUTH, FourBar::PHI, "P", &t, &start)
        .bounds("a", 2.0, 1.0)
        .run())
    .contains("lo < hi"));
}

#[test]
fn morgan_and_wamplers_problem_7_is_solved_exactly_from_random_starts() {
    use kinematics_examples::literature::MORGAN_WAMPLER_7;
    use kinematics_examples::synthesis_runs::morgan_wampler;
    // The first start of twenty that reaches E < 1e-20.
    let found = (0..20)
        .filter_map(|seed| morgan_wampler(seed).ok())
        .find(|r| r.sum_squares < 1e-20)
        .expect("a start of twenty reaches the exact solution");
    // Checked on its own: the design assembled at each crank angle found
    // puts P on the target, to 1e-10.
    let m = found.design;
    assert_eq!(m.d, 1.0, "the pivots are the problem's");
    let (mut found_modes, mut worst) = (None, 0.0f64);
    for modes in kinematics_examples::FourBarModes::all() {
        let w = MORGAN_WAMPLER_7
            .iter()
            .zip(&found.driver_values)
            .map(|(t, &phi)| match m.assemble_in(phi, &modes) {
                Ok(pose) => {
                    let p = m.positions(&pose).P;
                    (p.x - t[0]).hypot(p.y - t[1])
                }
                Err(_) => f64::INFINITY,
            })
            .fold(0.0f64, f64::max);
        if w < 1e-10 {
            found_modes = Some(modes);
            worst = w;
        }
    }
    assert!(
        found_modes.is_some(),
        "one assembly mode puts P on all five points"
    );
    assert!(worst < 1e-10);
}

/// The nine-point problem's exact solutions cross a branch: an exact
/// solution of its loop and coupler equations with every angle an unknown
/// (computed independently of this library: SciPy's Levenberg–Marquardt on
/// those 36 equations written by hand, then Newton steps; E < 2e-30)
/// passes the first target in the other assembly mode than the other
/// eight. So the published best error, zero, is not reachable by a design
/// that runs on one branch, which is what `Synthesis` looks for.
#[test]
fn the_exact_nine_point_solution_needs_both_assembly_modes() {
    use kinematics_examples::literature::NINE_POINTS;
    use kinematics_examples::{PlacedFourBar, PlacedFourBarModes};
    let m = PlacedFourBar {
        x0: 1.074_792_956_135_832_7,
        y0: 0.455_410_275_065_994_46,
        theta0: -2.705_818_830_789_655_6,
        d: 1.651_861_076_425_315_4,
        a: 1.150_381_284_995_437_6,
        b: 1.066_585_452_808_838_3,
        c: 1.743_798_004_136_658,
        p: 0.675_377_682_142_430_3,
        beta: 0.185_266_161_609_688_56,
    };
    let phis = [
        3.951_322_051_520_598_7,
        5.130_254_367_389_051,
        5.545_336_074_701_741_5,
        5.883_474_730_517_064,
        6.038_762_969_886_956,
        6.307_204_182_846_377,
        6.555_864_654_524_639,
        7.172_790_330_673_54,
        7.710_881_955_693_418,
    ];
    // For each target, the modes in which P reaches it at its crank angle.
    let reaching: Vec<Vec<usize>> = NINE_POINTS
        .iter()
        .zip(phis)
        .map(|(t, phi)| {
            PlacedFourBarModes::all()
                .enumerate()
                .filter(|(_, modes)| {
                    m.assemble_in(phi, modes).is_ok_and(|pose| {
                        let p = m.positions(&pose).P;
                        (p.x - t[0]).hypot(p.y - t[1]) < 1e-12
                    })
                })
                .map(|(k, _)| k)
                .collect()
        })
        .collect();
    assert!(reaching.iter().all(|r| r.len() == 1), "{reaching:?}");
    assert!(
        reaching[1..].iter().all(|r| r == &reaching[1]) && reaching[0] != reaching[1],
        "{reaching:?}"
    );
}

/// `design` as a run-time model of [`FOUR_BAR_TEXT`].
fn runtime_model(design: &FourBar) -> kinematics_core::runtime::Model {
    let mut m = kinematics_core::runtime::Model::compile(FOUR_BAR_TEXT).unwrap();
    m.set_values(&[
        design.a,
        design.b,
        design.c,
        design.d,
        design.p,
        design.beta,
    ])
    .unwrap();
    m
}

/// A run-time model is synthesised as the generated mechanism is: from
/// the same start, with free timing, both find the true design (the
/// targets are points of its coupler curve), the same crank angles, and
/// the same design to 1e-9.
#[test]
fn a_run_time_model_is_synthesised_as_the_generated_one() {
    let start = start();
    let phis = [0.3, 1.1, 2.0, 2.9, 3.5, 4.2, 5.0];
    let targets = targets_of(&TRUTH, &start, &phis);
    let off: Vec<f64> = phis.iter().map(|p| p + 0.1).collect();
    let generated = Synthesis::path(&GUESS, FourBar::PHI, "P", &targets, &start)
        .driver_guesses(&off)
        .run()
        .unwrap();
    let model = runtime_model(&GUESS);
    let start_vec = vec![start.phi, start.th3, start.th4];
    let found = Synthesis::path(&model, "phi", "P", &targets, &start_vec)
        .driver_guesses(&off)
        .run()
        .unwrap();
    assert!(found.sum_squares < 1e-20, "{found:?}");
    assert_eq!(found.full_turn, Some(true));
    for (got, want) in found.driver_values.iter().zip(&phis) {
        assert!((got - want).abs() < 1e-8, "{got} {want}");
    }
    let truth = [1.0, 3.0, 2.5, 3.0, 1.5, 0.6];
    let general = [
        generated.design.a,
        generated.design.b,
        generated.design.c,
        generated.design.d,
        generated.design.p,
        generated.design.beta,
    ];
    for ((got, g), want) in found.design.values().iter().zip(general).zip(truth) {
        assert!((got - want).abs() < 1e-8, "{got} against the true {want}");
        assert!((got - g).abs() < 1e-9, "{got} against the generated {g}");
    }
}

/// Function generation, bounds and a named subset of the parameters on a
/// run-time model: θ4 of the design found, assembled on its own, passes
/// through every pair; a bound that excludes the true c holds.
#[test]
fn a_run_time_model_takes_function_generation_and_bounds() {
    let start = start();
    let pairs = true_pairs(&start);
    let guess = runtime_model(&FourBar {
        a: 0.9,
        b: 3.2,
        c: 2.3,
        ..TRUTH
    });
    let start_vec = vec![start.phi, start.th3, start.th4];
    let found = Synthesis::function(&guess, "phi", "th4", &pairs, &start_vec)
        .vary(&["a", "b", "c"])
        .run()
        .unwrap();
    assert!(found.sum_squares < 1e-20, "{found:?}");
    for (phi, psi) in &pairs {
        let pose = found
            .design
            .assemble(&[*phi, start.th3, start.th4])
            .unwrap();
        assert!((pose[2] - psi).abs() < 1e-9);
    }
    // The best c is 2.5; held to [2.6, 3], it ends on the bound.
    let bounded = Synthesis::function(&guess, "phi", "th4", &pairs, &start_vec)
        .vary(&["a", "b", "c"])
        .bounds("c", 2.6, 3.0)
        .run()
        .unwrap();
    let c = bounded.design.values()[2];
    assert!((2.6..=3.0).contains(&c), "{c}");
    assert!(bounded.sum_squares > 1e-12, "{bounded:?}");
}

/// Mistakes in a run-time synthesis are errors that name what is wrong.
#[test]
fn run_time_synthesis_mistakes_are_errors() {
    let model = runtime_model(&GUESS);
    let start = vec![0.0, 0.5, 1.5];
    let targets = [[1.0, 2.0], [2.0, 1.0]];
    for (driver, point, needle) in [
        ("th3", "P", "no driver `th3`; its drivers are phi"),
        ("psi", "P", "no driver `psi`"),
        ("phi", "Q", "no point `Q`; its points are P"),
    ] {
        match Synthesis::path(&model, driver, point, &targets, &start).run() {
            Err(kinematics_core::Error::InvalidGeometry { detail, .. }) => {
                assert!(detail.contains(needle), "{detail}");
            }
            other => panic!("expected an error, got {other:?}"),
        }
    }
    match Synthesis::path(&model, "phi", "P", &targets, &start)
        .vary(&["a", "e"])
        .run()
    {
        Err(kinematics_core::Error::InvalidGeometry { detail, .. }) => {
            assert!(detail.contains("`e` is not a parameter"), "{detail}");
        }
        other => panic!("expected an error, got {other:?}"),
    }
}

/// `in_order` keeps free crank angles increasing through the targets:
/// from starting angles out of order (sorted first) the true design and
/// its increasing angles are recovered; for targets listed against the
/// crank's turn, the angles found still increase (to 1e-10 rad) and the
/// fit is no longer exact.
#[test]
fn in_order_keeps_the_free_crank_angles_increasing() {
    let start = start();
    let phis = [0.3, 1.1, 2.0, 2.9, 3.5, 4.2, 5.0];
    let targets = targets_of(&TRUTH, &start, &phis);
    let guesses = [0.4, 1.0, 2.1, 3.0, 2.8, 4.3, 4.9];
    let found = Synthesis::path(&GUESS, FourBar::PHI, "P", &targets, &start)
        .driver_guesses(&guesses)
        .in_order()
        .run()
        .unwrap();
    assert!(found.sum_squares < 1e-20, "{found:?}");
    assert!(found.constraints_met);
    for (got, want) in found.driver_values.iter().zip(&phis) {
        assert!((got - want).abs() < 1e-8, "{got} {want}");
    }
    // The same points listed with two swapped: no increasing timing puts
    // P through them in that order.
    let mut swapped = targets.clone();
    swapped.swap(2, 3);
    let found = Synthesis::path(&GUESS, FourBar::PHI, "P", &swapped, &start)
        .driver_guesses(&phis)
        .in_order()
        .run()
        .unwrap();
    assert!(found.constraints_met, "{found:?}");
    let v = &found.driver_values;
    for w in v.windows(2) {
        assert!(w[0] <= w[1] + 1e-10, "{v:?}");
    }
    assert!(
        v[v.len() - 1] <= v[0] + std::f64::consts::TAU + 1e-10,
        "{v:?}"
    );
    assert!(found.sum_squares > 1e-6, "{found:?}");
}
