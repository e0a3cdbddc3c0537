//! The compiler of the mechanism definition language: one pipeline of pure
//! functions over `proc_macro2` tokens, used at compile time by the
//! `mechanism!` macro (`kinematics-macros`, a thin shell over
//! [`expand`]) and at run time on text ([`compile_str`]).
//!
//! ```text
//! parse → check → lower → (simplify, on construction) → diff → cse → emit
//! ```
//!
//! * [`limits`]: the nesting and size of the tokens, checked without
//!   recursion before anything recurses on them;
//! * `parse`: tokens to the syntax tree, spans kept;
//! * `check`: declarations (names, mobility), every error reported at once;
//! * `lower`: typed expressions to a hash-consed scalar DAG ([`ir`]);
//! * `simplify`: algebraic rewrites applied as each node is built;
//! * `validate`: the lowered model (equation count, structural rank);
//! * `diff` and `kinematics`: exact Jacobian, velocity and acceleration terms
//!   (time derivatives of points and frames by forward differentiation or
//!   from the partials, whichever is cheaper);
//! * `scale`: each equation's term scale, for scale-aware numerics;
//! * `blocks` and `closed`: the block-triangular form of Φ_u, so that
//!   solves go block by block (a six-bar loop by loop), and the blocks
//!   solved in closed form;
//! * `sensitivity`: the partial derivatives with respect to parameters;
//! * [`dynamics`]: the masses, loads and joints of the `bodies`, `loads`
//!   and `joints` sections, as roots of the graph;
//! * `cse`: which shared nodes get a `let`, in which order;
//! * `emit`: the Rust back end, straight-line Rust and the generated types,
//!   one file per item.
//!
//! `names` holds the vocabulary the stages share (errors, the name table,
//! the built-ins); a stage uses only the stages before it.
//!
//! The front and middle end end in a [`Compiled`] definition: the
//! expression graph and the roots of each stage, which a back end turns
//! into code ([`Compiled::to_rust`] for the macro's).
//!
//! ```
//! let model = kinematics_compiler::compile_str(
//!     "/// Slider-crank.
//!      pub struct SliderCrank {
//!          params   { a, b }
//!          drivers  { phi }
//!          unknowns { th, x }
//!          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
//!      }",
//! )?;
//! assert_eq!(model.name(), "SliderCrank");
//! assert_eq!((model.drivers(), model.unknowns()), (1, 2));
//! // Φ_u is 2 × 2.
//! assert_eq!(model.jacobian().len(), 2);
//! # Ok::<(), kinematics_compiler::Diagnostics>(())
//! ```

#![forbid(unsafe_code)]

mod blocks;
mod check;
mod closed;
mod cse;
mod diagnostic;
mod diff;
pub mod dynamics;
mod emit;
pub mod ir;
mod kinematics;
pub mod limits;
mod lower;
pub mod motion;
mod names;
mod parse;
mod pipeline;
mod scale;
mod sensitivity;
mod simplify;
mod validate;

pub use closed::ClosedForm;
pub use diagnostic::{compile_str, Diagnostic, Diagnostics};
pub use kinematics::DerivedFrame;
pub use pipeline::{
    compile, expand, op_counts, Block, Compiled, FrameRoots, Kind, Mobility, PointRoots,
};
pub use sensitivity::Partials;

/// Definitions built by structure to pass the limits, for robustness
/// tests. Not part of the API.
#[cfg(any(test, feature = "fuzz"))]
#[doc(hidden)]
pub mod adversarial;
/// Seeded mutations of valid definitions, for robustness tests. Not part of
/// the API.
#[cfg(any(test, feature = "fuzz"))]
#[doc(hidden)]
pub mod fuzz;
#[cfg(test)]
mod tests;
