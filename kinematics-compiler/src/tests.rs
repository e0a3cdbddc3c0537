//! Tests of the whole expansion.

use quote::quote;

use crate::fuzz::four_bar;

#[test]
fn four_bar_expansion_snapshot() {
    let tokens = crate::expand(four_bar());
    let file: syn::File = syn::parse2(tokens).expect("the expansion is valid Rust");
    insta::assert_snapshot!(prettyplease::unparse(&file));
}

#[test]
fn four_bar_operation_count_after_cse() {
    let [(_, newton), (_, analysis)] = crate::op_counts(four_bar()).expect("valid definition");
    let (newton_tree, newton_shared) = (newton.tree, newton.shared as u64);
    let (analysis_tree, analysis_shared) = (analysis.tree, analysis.shared as u64);
    println!("residual and Jacobian: {newton_tree} operations as trees, {newton_shared} after CSE");
    println!("analysis: {analysis_tree} operations as trees, {analysis_shared} after CSE");
    assert!(newton_shared <= newton_tree);
    // The analysis (Jacobian, both right-hand sides, three points with their
    // velocities and accelerations) repeats sin/cos and products heavily as
    // trees; sharing must remove most of it.
    assert!(
        analysis_shared * 2 < analysis_tree,
        "expected CSE to at least halve the work: {analysis_shared} of {analysis_tree}"
    );
}

#[test]
fn errors_come_back_as_compile_errors_not_panics() {
    let out = crate::expand(quote! {
        struct M {
            params { a }
            drivers { phi }
            unknowns { x }
            constraints { x * polar(a, phi) == 1.0 }
        }
    });
    let text = out.to_string();
    assert!(text.contains("compile_error"), "{text}");
}

/// Expands each of `mutants`: never a panic, never the marker of a
/// compiler bug, and an accepted one is valid Rust. Returns how many were
/// rejected with errors and how many accepted.
fn expand_mutants(mutants: Vec<proc_macro2::TokenStream>) -> (usize, usize) {
    let (mut errors, mut accepted) = (0, 0);
    for ts in mutants {
        let input = ts.to_string();
        let out = std::panic::catch_unwind(|| crate::expand(ts))
            .unwrap_or_else(|_| panic!("the macro panicked on: {input}"));
        let text = out.to_string();
        assert!(!text.contains("a bug of the mechanism compiler"), "{input}");
        if text.contains("compile_error") {
            errors += 1;
        } else {
            // Accepted definitions must expand to valid Rust.
            syn::parse2::<syn::File>(out)
                .unwrap_or_else(|e| panic!("invalid expansion ({e}) of: {input}"));
            accepted += 1;
        }
    }
    (errors, accepted)
}

#[test]
fn mutated_definitions_give_code_or_errors_never_a_panic() {
    let (errors, accepted) = expand_mutants(crate::fuzz::mutants(0xF00D, 3000));
    println!("{errors} rejected with errors, {accepted} accepted");
    // Both outcomes must be exercised for the test to mean anything.
    assert!(errors > 1000 && accepted > 30, "{errors} / {accepted}");
}

#[test]
fn mutated_definitions_with_bodies_and_loads_give_code_or_errors_never_a_panic() {
    let bases = crate::fuzz::dynamics_definitions();
    let (errors, accepted) = expand_mutants(crate::fuzz::mutants_of(&bases, 0xD1A, 3000));
    assert!(errors > 1000 && accepted > 30, "{errors} / {accepted}");
}

#[test]
fn the_mutation_bases_are_valid_definitions() {
    for def in crate::fuzz::definitions()
        .into_iter()
        .chain(crate::fuzz::dynamics_definitions())
    {
        let text = crate::expand(def.clone()).to_string();
        assert!(!text.contains("compile_error"), "{def}\n{text}");
    }
}

/// A body's angle is a function of the pose: `rate(…)` in it is an error,
/// not an angle that silently does not turn.
#[test]
fn a_bodys_angle_may_not_use_a_rate() {
    let r = crate::compile_str(
        "struct M { params { a } drivers { phi } unknowns { } points { B = polar(a, phi); }
         bodies { crank(mass = 1.0, center = B, angle = rate(phi)); } }",
    );
    let message = r.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(message.contains("may not use `rate(…)`"), "{message}");
}
