//! The `mechanism!` procedural macro.
//!
//! Use it through `kinematics-core`, which re-exports it and provides the
//! runtime the generated code calls. The expansion is one pipeline of pure
//! functions over `proc_macro2` tokens:
//!
//! ```text
//! parse → check → lower → (simplify, on construction) → diff → cse → emit
//! ```
//!
//! * `parse`: tokens to the syntax tree, spans kept;
//! * `check`: declarations (names, mobility), every error reported at once;
//! * `lower`: typed expressions to a hash-consed scalar DAG (`ir`);
//! * `simplify`: algebraic rewrites applied as each node is built;
//! * `validate`: the lowered model (equation count, structural rank);
//! * `diff` and `kinematics`: exact Jacobian, velocity and acceleration terms
//!   (time derivatives of points and frames by forward differentiation or
//!   from the partials, whichever is cheaper);
//! * `scale`: each equation's term scale, for scale-aware numerics;
//! * `blocks`: the block-triangular form of Φ_u, so that linear solves go
//!   block by block (a six-bar loop by loop);
//! * `cse`: which shared nodes get a `let`, in which order;
//! * `emit`: straight-line Rust and the generated types, one file per item.
//!
//! `names` holds the vocabulary the stages share (errors, the name table,
//! the built-ins); a stage uses only the stages before it.

#![forbid(unsafe_code)]

mod blocks;
mod check;
mod closed;
mod cse;
mod diff;
mod emit;
mod expand;
mod ir;
mod kinematics;
mod lower;
mod names;
mod parse;
mod scale;
mod sensitivity;
mod simplify;
mod validate;

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
    expand::expand(input.into()).into()
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
    match args.as_slice() {
        [seed, count] => {
            fuzz::accepted_expansions(*seed, usize::try_from(*count).unwrap_or(0)).into()
        }
        _ => quote::quote!(::core::compile_error!("expected `seed, count`");).into(),
    }
}

#[cfg(any(test, feature = "fuzz"))]
mod fuzz;
#[cfg(test)]
mod tests;
