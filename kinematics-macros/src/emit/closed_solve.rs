//! Each closed-form block in the generated code: its coefficients, the call
//! of its form in `kinematics_core::closed`, and the bindings of its
//! unknowns and of their sines and cosines.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;

use super::print::Printer;
use super::Ctx;
use crate::closed::{Closed, Pattern};
use crate::ir::{Func, Id};

/// The blocks solved in order under `pr`'s names (`lets`: the stages of
/// the blocks' coefficients first), each binding its unknowns (`q_…`) and
/// the sines and cosines of its angles (`__c_…`, `__s_…`); `fallback`
/// returns from the enclosing function where a block is degenerate.
pub(super) fn solve_blocks(
    cx: &Ctx<'_>,
    pr: &Printer<'_>,
    lets: &[TokenStream],
    fallback: &TokenStream,
) -> TokenStream {
    let (pp, nd, nm) = (&cx.pp, cx.nd, cx.nm());
    let (coord, q) = (&cx.id.coord, &cx.id.q);
    let q_drivers = &q[..nd];
    let mut solve = TokenStream::new();
    let mut m = 0usize;
    let mut angle = 0usize;
    for (b, block_lets) in cx.closed.iter().zip(lets) {
        let Some(p) = &b.pattern else { continue };
        let names = cx.block_names(b).join(", ");
        let mode = if p.has_modes() {
            m += 1;
            let k = m - 1;
            quote!(&mut modes[#k],)
        } else {
            TokenStream::new()
        };
        let call = solve_call(cx, pr, b, p, mode);
        let outs = outputs(cx, b, p);
        solve.extend(quote! {
            #block_lets
            let #outs = match #call {
                ::core::result::Result::Ok(x) => x,
                ::core::result::Result::Err(disc) if disc < 0.0 => {
                    return ::core::result::Result::Err(#pp::closed::cannot_assemble(#names, disc, &Self::__NAMES, &[#(#q_drivers),*]));
                }
                ::core::result::Result::Err(_) => {
                    *modes = [::core::primitive::f64::NAN; #nm];
                    #fallback
                }
            };
        });
        for &c in &b.cols {
            if cx.model.kinds[nd + c] == crate::lower::CoordKind::Angle {
                let (qv, field) = (&q[nd + c], &coord[nd + c]);
                let cv = format_ident!("__c_{}", field.unraw());
                let sv = format_ident!("__s_{}", field.unraw());
                solve.extend(quote! {
                    let mut #cv = #cv;
                    let mut #sv = #sv;
                    let #qv = #pp::closed::near_carried(&mut #cv, &mut #sv, start.#field, &mut angles[#angle]);
                });
                angle += 1;
                for (i, o) in cx.offsets.iter().enumerate() {
                    if o.coord != nd + c {
                        continue;
                    }
                    let (ck, sk) = (pr.operand(o.cos_k), pr.operand(o.sin_k));
                    let off = format_ident!("__off_{}", i);
                    // sin(θ + k) = sin θ cos k + cos θ sin k;
                    // cos(θ + k) = cos θ cos k − sin θ sin k.
                    solve.extend(if o.func == Func::Sin {
                        quote!(let #off = #sv * #ck + #cv * #sk;)
                    } else {
                        quote!(let #off = #cv * #ck - #sv * #sk;)
                    });
                }
            }
        }
    }
    solve
}

/// The coefficients of a pattern (what its block's stage evaluates).
pub(super) fn coefficients(p: Option<&Pattern>) -> Vec<Id> {
    let flat = |m: &[[Id; 2]; 2]| m.iter().flatten().copied().collect::<Vec<_>>();
    match p {
        None => Vec::new(),
        Some(Pattern::Angle { a, b, c }) => vec![*a, *b, *c],
        Some(Pattern::Linear { a, c }) => vec![*a, *c],
        Some(Pattern::CircleCircle { k, p, q }) => [k.to_vec(), flat(p), flat(q)].concat(),
        Some(Pattern::CircleLine { k, p, v }) => [k.to_vec(), flat(p), v.to_vec()].concat(),
        Some(Pattern::Slide { k, p, w }) => [k.to_vec(), flat(p), flat(w)].concat(),
        Some(Pattern::LineLine { k, v0, v1 }) => [k.to_vec(), v0.to_vec(), v1.to_vec()].concat(),
    }
}

/// The call of the block's closed form, `mode` being `&mut modes[k],` or
/// nothing.
fn solve_call(
    cx: &Ctx<'_>,
    pr: &Printer<'_>,
    b: &Closed,
    p: &Pattern,
    mode: TokenStream,
) -> TokenStream {
    let pp = &cx.pp;
    let e = |id: &Id| pr.element(*id);
    let v = |x: &[Id; 2]| {
        let (a, b) = (e(&x[0]), e(&x[1]));
        quote!([#a, #b])
    };
    let m = |x: &[[Id; 2]; 2]| {
        let (r0, r1) = (v(&x[0]), v(&x[1]));
        quote!([#r0, #r1])
    };
    let first = &cx.id.coord[cx.nd + b.cols[0]];
    let angle_guess = quote!(|| {
        let (s, c) = #pp::math::sin_cos(start.#first);
        [c, s]
    });
    match p {
        Pattern::Angle { a, b, c } => {
            let (a, b, c) = (e(a), e(b), e(c));
            quote!(#pp::closed::angle(#a, #b, #c, #mode #angle_guess))
        }
        Pattern::Linear { a, c } => {
            let (a, c) = (e(a), e(c));
            quote!(#pp::closed::linear(#a, #c))
        }
        Pattern::CircleCircle { k, p, q } => {
            let (k, p, q) = (v(k), m(p), m(q));
            let second = &cx.id.coord[cx.nd + b.cols[1]];
            quote!(#pp::closed::circle_circle(#k, #p, #q, #mode || {
                let (s0, c0) = #pp::math::sin_cos(start.#first);
                let (s1, c1) = #pp::math::sin_cos(start.#second);
                [c0, s0, c1, s1]
            }))
        }
        Pattern::CircleLine { k, p, v: dir } => {
            let (k, p, dir) = (v(k), m(p), v(dir));
            quote!(#pp::closed::circle_line(#k, #p, #dir, #mode #angle_guess))
        }
        Pattern::Slide { k, p, w } => {
            let (k, p, w) = (v(k), m(p), m(w));
            let length = &cx.id.coord[cx.nd + b.cols[1]];
            quote!(#pp::closed::slide(#k, #p, #w, #mode || [start.#length, 0.0]))
        }
        Pattern::LineLine { k, v0, v1 } => {
            let (k, v0, v1) = (v(k), v(v0), v(v1));
            quote!(#pp::closed::line_line(#k, #v0, #v1))
        }
    }
}

/// The pattern binding the block's results: `__c_θ`, `__s_θ` for an
/// angle θ, `q_λ` for a length λ.
fn outputs(cx: &Ctx<'_>, b: &Closed, p: &Pattern) -> TokenStream {
    let nd = cx.nd;
    let name = |k: usize| cx.id.coord[nd + b.cols[k]].unraw();
    let q = |k: usize| &cx.id.q[nd + b.cols[k]];
    let cs = |k: usize| {
        (
            format_ident!("__c_{}", name(k)),
            format_ident!("__s_{}", name(k)),
        )
    };
    match p {
        Pattern::Angle { .. } => {
            let (c0, s0) = cs(0);
            quote!([#c0, #s0])
        }
        Pattern::Linear { .. } => {
            let q0 = q(0);
            quote!(#q0)
        }
        Pattern::CircleCircle { .. } => {
            let ((c0, s0), (c1, s1)) = (cs(0), cs(1));
            quote!([#c0, #s0, #c1, #s1])
        }
        Pattern::CircleLine { .. } | Pattern::Slide { .. } => {
            let (c0, s0) = cs(0);
            let q1 = q(1);
            quote!([#c0, #s0, #q1])
        }
        Pattern::LineLine { .. } => {
            let (q0, q1) = (q(0), q(1));
            quote!([#q0, #q1])
        }
    }
}
