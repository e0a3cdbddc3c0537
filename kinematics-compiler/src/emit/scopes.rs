//! Keeps the lexical scopes of the generated functions shallow.
//!
//! Every `let` opens a scope nested in the one before it, to the end of
//! its block, and the debug information of a function is built by
//! walking that nesting recursively: a model with hundreds of loops has
//! functions with thousands of `let`s in a row, which overflow the code
//! generator's stack in a debug build. A block with that many is
//! rewritten so that a run of `let`s becomes one declaration of all their
//! names followed by their assignments:
//!
//! ```text
//! let a = f(x);            let (a, mut b, c);
//! let mut b = g(a);   →    a = f(x);
//! let [c, _] = h(b);       b = g(a);
//!                          [c, _] = h(b);
//! ```
//!
//! which is the same program (each name assigned once, before use, as
//! the borrow checker verifies) with one scope where there were three. A
//! run ends where a name would be declared before a statement of the run
//! that reads an outer binding of the same name (shadowing): that `let`
//! is kept as it is. Small models have no such blocks and are untouched.

use std::collections::HashSet;

use proc_macro2::{TokenStream, TokenTree};
use quote::{quote, ToTokens};
use syn::visit::Visit;
use syn::visit_mut::VisitMut;
use syn::{parse_quote, Block, Expr, ExprAssign, Ident, Local, Pat, Stmt, Token};

/// The size of the expression graph above which the expansion is checked
/// for long blocks: a smaller model cannot have one, and is neither
/// walked nor parsed again.
pub(super) const LARGE_GRAPH: usize = 2048;

/// Blocks with more `let`s than this are rewritten.
const MANY: usize = 256;

/// The most names one declaration takes.
const RUN: usize = 128;

/// `tokens` with every long run of `let`s in a block declared at once
/// (see the module docs); unchanged, and not parsed, when no block is
/// long.
pub(super) fn shallow(tokens: TokenStream) -> TokenStream {
    if most_lets(tokens.clone()) <= MANY {
        return tokens;
    }
    let Ok(mut file) = syn::parse2::<syn::File>(tokens.clone()) else {
        return tokens;
    };
    Shallow.visit_file_mut(&mut file);
    file.into_token_stream()
}

/// The most `let` keywords directly inside one group of `tokens` (a
/// block's statements are the tokens of one brace group), over every
/// group at every depth.
fn most_lets(tokens: TokenStream) -> usize {
    let mut here = 0;
    let mut most = 0;
    for t in tokens {
        match t {
            TokenTree::Ident(i) if i == "let" => here += 1,
            TokenTree::Group(g) => most = most.max(most_lets(g.stream())),
            _ => {}
        }
    }
    most.max(here)
}

struct Shallow;

impl VisitMut for Shallow {
    fn visit_block_mut(&mut self, block: &mut Block) {
        syn::visit_mut::visit_block_mut(self, block);
        let lets = block
            .stmts
            .iter()
            .filter(|s| matches!(s, Stmt::Local(_)))
            .count();
        if lets > MANY {
            block.stmts = regroup(std::mem::take(&mut block.stmts));
        }
    }
}

/// The names a `let` binds (with, beside, the left side of its assignment
/// form), when its pattern is a name (possibly `mut`, possibly typed) or
/// an array or tuple of names and `_`, and it has an initializer and no
/// `else`.
struct Split {
    /// Each bound name with its declaration (`mut x` or `x`) and type
    /// (`_` where none is written).
    names: Vec<(String, TokenStream, TokenStream)>,
}

fn split(local: &Local) -> Option<(Split, Expr)> {
    let init = local.init.as_ref()?;
    if init.diverge.is_some() {
        return None;
    }
    let (pat, ty) = match &local.pat {
        Pat::Type(t) => (&*t.pat, t.ty.to_token_stream()),
        p => (p, quote!(_)),
    };
    let one = |p: &Pat| -> Option<(Option<(String, TokenStream)>, Expr)> {
        match p {
            Pat::Ident(i) if i.by_ref.is_none() && i.subpat.is_none() && i.attrs.is_empty() => {
                let name = &i.ident;
                let decl = match i.mutability {
                    Some(_) => quote!(mut #name),
                    None => quote!(#name),
                };
                Some((Some((name.to_string(), decl)), parse_quote!(#name)))
            }
            Pat::Wild(_) => Some((None, parse_quote!(_))),
            _ => None,
        }
    };
    let mut names = Vec::new();
    let lhs = match pat {
        Pat::Ident(_) => {
            let (n, lhs) = one(pat)?;
            names.extend(n.map(|(s, d)| (s, d, ty)));
            lhs
        }
        Pat::Slice(_) | Pat::Tuple(_) if !matches!(local.pat, Pat::Type(_)) => {
            let elems = match pat {
                Pat::Slice(s) => &s.elems,
                Pat::Tuple(t) => &t.elems,
                _ => return None,
            };
            let mut parts = Vec::new();
            for p in elems {
                let (n, lhs) = one(p)?;
                names.extend(n.map(|(s, d)| (s, d, quote!(_))));
                parts.push(lhs);
            }
            if matches!(pat, Pat::Slice(_)) {
                parse_quote!([#(#parts),*])
            } else {
                parse_quote!((#(#parts,)*))
            }
        }
        _ => return None,
    };
    Some((Split { names }, lhs))
}

/// The identifiers among `names` that a syntax tree mentions.
struct Mentions<'a> {
    names: &'a HashSet<String>,
    found: HashSet<String>,
}

impl<'ast> Visit<'ast> for Mentions<'_> {
    fn visit_ident(&mut self, i: &'ast Ident) {
        let s = i.to_string();
        if self.names.contains(&s) {
            self.found.insert(s);
        }
    }

    fn visit_macro(&mut self, m: &'ast syn::Macro) {
        // A macro's input is tokens, not syntax: its identifiers are
        // counted as mentioned.
        for t in m.tokens.clone() {
            if let TokenTree::Ident(i) = t {
                self.visit_ident(&i);
            }
        }
        syn::visit::visit_macro(self, m);
    }
}

/// A run being gathered: the names to declare, and the statements.
#[derive(Default)]
struct Run {
    names: Vec<(TokenStream, TokenStream)>,
    declared: HashSet<String>,
    mentioned: HashSet<String>,
    stmts: Vec<Stmt>,
}

impl Run {
    fn flush(&mut self, out: &mut Vec<Stmt>) {
        let run = std::mem::take(self);
        if !run.names.is_empty() {
            let (decls, types): (Vec<_>, Vec<_>) = run.names.into_iter().unzip();
            let decl = if decls.len() == 1 {
                let (d, t) = (&decls[0], &types[0]);
                quote!(let #d: #t;)
            } else {
                quote!(let (#(#decls),*): (#(#types),*);)
            };
            if let Ok(s) = syn::parse2(decl) {
                out.push(s);
            }
        }
        out.extend(run.stmts);
    }
}

/// The statements of a long block with its runs of `let`s declared at once.
fn regroup(stmts: Vec<Stmt>) -> Vec<Stmt> {
    // Only the names some `let` of the block binds can clash.
    let bound: HashSet<String> = stmts
        .iter()
        .filter_map(|s| match s {
            Stmt::Local(l) => split(l),
            _ => None,
        })
        .flat_map(|(s, _)| s.names.into_iter().map(|(n, _, _)| n))
        .collect();
    let mentions = |f: &dyn Fn(&mut Mentions<'_>)| {
        let mut m = Mentions {
            names: &bound,
            found: HashSet::new(),
        };
        f(&mut m);
        m.found
    };
    let mut out = Vec::with_capacity(stmts.len());
    let mut run = Run::default();
    for stmt in stmts {
        let Stmt::Local(local) = &stmt else {
            if matches!(stmt, Stmt::Item(_)) {
                run.flush(&mut out);
                out.push(stmt);
            } else {
                run.mentioned.extend(mentions(&|m| m.visit_stmt(&stmt)));
                run.stmts.push(stmt);
            }
            continue;
        };
        let Some((split, lhs)) = split(local) else {
            run.flush(&mut out);
            out.push(stmt);
            continue;
        };
        let reads = match &local.init {
            Some(init) => mentions(&|m| m.visit_expr(&init.expr)),
            None => HashSet::new(),
        };
        // Declaring a name at the head of the run must not hide a binding
        // that the run (or this initializer) reads before the assignment.
        let clashes = split.names.iter().any(|(n, _, _)| {
            run.mentioned.contains(n) || run.declared.contains(n) || reads.contains(n)
        });
        if clashes || run.names.len() + split.names.len() > RUN {
            run.flush(&mut out);
        }
        if split.names.iter().any(|(n, _, _)| reads.contains(n)) {
            // `let x = f(x);`: the new binding cannot be declared before
            // its initializer reads the old one.
            out.push(stmt);
            continue;
        }
        run.mentioned.extend(reads);
        for (n, decl, ty) in split.names {
            run.declared.insert(n.clone());
            run.mentioned.insert(n);
            run.names.push((decl, ty));
        }
        let Stmt::Local(local) = stmt else { continue };
        let Some(init) = local.init else { continue };
        run.stmts.push(Stmt::Expr(
            Expr::Assign(ExprAssign {
                attrs: Vec::new(),
                left: Box::new(lhs),
                eq_token: Token![=](init.eq_token.span),
                right: init.expr,
            }),
            Some(local.semi_token),
        ));
    }
    run.flush(&mut out);
    out
}
