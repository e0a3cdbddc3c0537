//! The `mechanism!` procedural macro: a thin shell over the compiler of
//! the definition language (`kinematics-compiler`), whose Rust back end
//! writes the generated items.
//!
//! Use it through `kinematics-core`, which re-exports it and provides the
//! runtime the generated code calls.

#![forbid(unsafe_code)]

/// Declares a mechanism by its vector loop-closure equations: parameters,
/// drivers, unknowns, points, loops, constraints, frames and joints.
///
/// ```ignore
/// mechanism! {
///     /// Crank-rocker four-bar.
///     pub struct FourBar {
///         params   { a, b, c, d }
///         drivers  { phi }
///         unknowns { th3, th4 }
///         loops    { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
///     }
/// }
/// ```
///
/// Use it through `kinematics-core`, which re-exports it with the runtime
/// the generated code calls; its `guide::language` module is the reference
/// of the language and of what is generated.
#[proc_macro]
pub fn mechanism(input: proc_macro::TokenStream) -> proc_macro::TokenStream {
    kinematics_compiler::expand(input.into()).into()
}

/// Expands the seeded mutants of the robustness test that the macro
/// accepts (`fuzz_accepted!(seed, count)`), so that a test crate can prove
/// they all compile. Only with the `fuzz` feature; not part of the API.
#[cfg(feature = "fuzz")]
#[doc(hidden)]
#[proc_macro]
pub fn __fuzz_accepted(input: proc_macro::TokenStream) -> proc_macro::TokenStream {
    let parsed = syn::parse::Parser::parse2(
        syn::punctuated::Punctuated::<syn::LitInt, syn::Token![,]>::parse_terminated,
        input.into(),
    );
    let args: Vec<u64> = parsed
        .map(|p| p.iter().filter_map(|l| l.base10_parse().ok()).collect())
        .unwrap_or_default();
    let count = |c: &u64| usize::try_from(*c).unwrap_or(0);
    match args.as_slice() {
        [seed, n] => kinematics_compiler::fuzz::accepted_expansions(*seed, count(n)).into(),
        // The bases with bodies and loads.
        [seed, n, 1] => kinematics_compiler::fuzz::accepted_expansions_of(
            &kinematics_compiler::fuzz::dynamics_definitions(),
            *seed,
            count(n),
        )
        .into(),
        _ => quote::quote!(::core::compile_error!("expected `seed, count` or `seed, count, 1`");)
            .into(),
    }
}
