//! Printing the expression DAG as Rust: each scheduled node a `let`, each
//! output an expression over the bound names.

use std::collections::HashMap;

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use syn::Ident;

use crate::cse::Schedule;
use crate::ir::{Graph, Id, Leaf, Node};

/// The name in `core::f64::consts` of a constant equal to `v`, so that the
/// generated code reads `TAU` rather than its digits (and does not trip
/// lints that flag approximations of known constants).
pub(super) fn named_constant(v: f64) -> Option<&'static str> {
    use std::f64::consts as c;
    let table = [
        (c::PI, "PI"),
        (c::TAU, "TAU"),
        (c::FRAC_PI_2, "FRAC_PI_2"),
        (c::FRAC_PI_3, "FRAC_PI_3"),
        (c::FRAC_PI_4, "FRAC_PI_4"),
        (c::FRAC_PI_6, "FRAC_PI_6"),
        (c::FRAC_PI_8, "FRAC_PI_8"),
        (c::FRAC_1_PI, "FRAC_1_PI"),
        (c::FRAC_2_PI, "FRAC_2_PI"),
        (c::FRAC_2_SQRT_PI, "FRAC_2_SQRT_PI"),
        (c::SQRT_2, "SQRT_2"),
        (c::FRAC_1_SQRT_2, "FRAC_1_SQRT_2"),
        (c::E, "E"),
        (c::LN_2, "LN_2"),
        (c::LN_10, "LN_10"),
        (c::LOG2_E, "LOG2_E"),
        (c::LOG10_E, "LOG10_E"),
        (c::LOG2_10, "LOG2_10"),
        (c::LOG10_2, "LOG10_2"),
    ];
    table
        .iter()
        .find(|(x, _)| x.to_bits() == v.to_bits())
        .map(|(_, n)| *n)
}

/// Turns node ids into Rust expressions.
pub(super) struct Printer<'a> {
    pub(super) g: &'a Graph,
    pub(super) names: HashMap<Id, Ident>,
    leaf: &'a dyn Fn(Leaf) -> TokenStream,
    /// Nodes printed as a given variable instead of their definition.
    given: HashMap<Id, Ident>,
}

impl Printer<'_> {
    /// The expression for `id`: its binding if it has one.
    pub(super) fn expr(&self, id: Id) -> TokenStream {
        match self.names.get(&id) {
            Some(name) => quote!(#name),
            None => self.body(id),
        }
    }

    /// `id` as an array element: parenthesised unless atomic, so that
    /// `[a - b, -c]` cannot be misread as a missing comma.
    pub(super) fn element(&self, id: Id) -> TokenStream {
        self.operand(id)
    }

    /// `id` as an operand: parenthesised unless atomic.
    pub(super) fn operand(&self, id: Id) -> TokenStream {
        let atomic = self.names.contains_key(&id)
            || self.given.contains_key(&id)
            || match self.g.node(id) {
                // Method calls bind tighter than any operator.
                Node::Leaf(_) | Node::Call(..) | Node::Powi(..) | Node::Atan2(..) => true,
                Node::Const(bits) => f64::from_bits(bits) >= 0.0,
                _ => false,
            };
        let e = self.expr(id);
        if atomic {
            e
        } else {
            quote!((#e))
        }
    }

    /// The defining expression of `id`, ignoring its own binding.
    pub(super) fn body(&self, id: Id) -> TokenStream {
        if let Some(v) = self.given.get(&id) {
            return quote!(#v);
        }
        match self.g.node(id) {
            Node::Const(bits) => {
                let v = f64::from_bits(bits);
                if !v.is_finite() {
                    // Never produced (the simplifier folds only finite values);
                    // the run-time finiteness checks would report it.
                    return quote!(::core::primitive::f64::NAN);
                }
                let magnitude = match named_constant(v.abs()) {
                    Some(name) => {
                        let name = format_ident!("{}", name);
                        quote!(::core::f64::consts::#name)
                    }
                    None => {
                        let lit = Literal::f64_suffixed(v.abs());
                        quote!(#lit)
                    }
                };
                if v < 0.0 {
                    quote!(-#magnitude)
                } else {
                    magnitude
                }
            }
            Node::Leaf(l) => (self.leaf)(l),
            Node::Add(a, b) => {
                let neg = |x: Id| match self.g.node(x) {
                    Node::Neg(y) if !self.names.contains_key(&x) => Some(y),
                    _ => None,
                };
                match (neg(a), neg(b)) {
                    (_, Some(y)) => {
                        let (a, y) = (self.operand(a), self.operand(y));
                        quote!(#a - #y)
                    }
                    (Some(x), None) => {
                        let (b, x) = (self.operand(b), self.operand(x));
                        quote!(#b - #x)
                    }
                    (None, None) => {
                        let (a, b) = (self.operand(a), self.operand(b));
                        quote!(#a + #b)
                    }
                }
            }
            Node::Mul(a, b) => {
                let (a, b) = (self.operand(a), self.operand(b));
                quote!(#a * #b)
            }
            Node::Div(a, b) => {
                let (a, b) = (self.operand(a), self.operand(b));
                quote!(#a / #b)
            }
            Node::Neg(a) => {
                let a = self.operand(a);
                quote!(-#a)
            }
            // The functions of `kinematics_core::math`: the standard
            // library's, or libm's in a `no_std` build.
            Node::Powi(a, n) => {
                let a = self.expr(a);
                let n = Literal::i32_unsuffixed(n);
                quote!(::kinematics_core::__private::math::powi(#a, #n))
            }
            Node::Call(f, a) => {
                let a = self.expr(a);
                let m = format_ident!("{}", f.method());
                quote!(::kinematics_core::__private::math::#m(#a))
            }
            Node::Atan2(y, x) => {
                let (y, x) = (self.expr(y), self.expr(x));
                quote!(::kinematics_core::__private::math::atan2(#y, #x))
            }
        }
    }
}

/// The number of values a stage binds with one `let` each; a longer stage
/// declares them in groups of this size (see [`bind_given`]).
const LONG_STAGE: usize = 128;

/// Names the bindings of a schedule `t0, t1, …` and emits each stage's
/// `let`s.
pub(super) fn bind<'a>(
    g: &'a Graph,
    sched: &Schedule,
    leaf: &'a dyn Fn(Leaf) -> TokenStream,
) -> (Printer<'a>, Vec<TokenStream>) {
    bind_given(g, sched, leaf, HashMap::new())
}

/// [`bind`], with the nodes of `given` printed as the given variables.
pub(super) fn bind_given<'a>(
    g: &'a Graph,
    sched: &Schedule,
    leaf: &'a dyn Fn(Leaf) -> TokenStream,
    given: HashMap<Id, Ident>,
) -> (Printer<'a>, Vec<TokenStream>) {
    let _ = &sched.bound;
    let mut p = Printer {
        g,
        names: HashMap::new(),
        leaf,
        given,
    };
    let mut stages = Vec::new();
    let mut n = 0usize;
    for lets in &sched.stages {
        let mut code = TokenStream::new();
        // Every `let` opens a lexical scope nested in the one before, and
        // the debug information of a function with thousands of them
        // overflows the code generator's stack: a long stage declares its
        // values a group at a time (one scope per group) and assigns them.
        let grouped = lets.len() > LONG_STAGE;
        for group in lets.chunks(if grouped {
            LONG_STAGE
        } else {
            lets.len().max(1)
        }) {
            let names: Vec<Ident> = (n..n + group.len())
                .map(|k| format_ident!("t{}", k))
                .collect();
            if grouped {
                let types = names.iter().map(|_| quote!(f64));
                code.extend(quote!(let (#(#names),*): (#(#types),*);));
            }
            for (&id, name) in group.iter().zip(names) {
                let body = p.body(id);
                if grouped {
                    code.extend(quote!(#name = #body;));
                } else {
                    code.extend(quote!(let #name = #body;));
                }
                p.names.insert(id, name);
            }
            n += group.len();
        }
        stages.push(code);
    }
    (p, stages)
}

/// `t₀ op t₁ op …` for an associative `op` (`+` or `*`), nested no deeper
/// than a few dozen levels however many terms there are: up to 64 terms
/// are written as one chain (as a person would write them), more are
/// grouped 64 to a parenthesised chain, recursively. rustc walks an
/// expression recursively, and a chain of hundreds of terms (the input
/// guard of a model with hundreds of coordinates) overflows its stack.
pub(super) fn chain(terms: &[TokenStream], op: &TokenStream) -> TokenStream {
    const GROUP: usize = 64;
    if terms.len() <= GROUP {
        let mut out = TokenStream::new();
        for (i, t) in terms.iter().enumerate() {
            if i > 0 {
                out.extend(op.clone());
            }
            out.extend(t.clone());
        }
        return out;
    }
    let groups: Vec<TokenStream> = terms
        .chunks(GROUP)
        .map(|g| {
            let inner = chain(g, op);
            quote!((#inner))
        })
        .collect();
    chain(&groups, op)
}
