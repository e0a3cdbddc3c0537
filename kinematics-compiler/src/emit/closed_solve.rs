//! Each block of the closed-form path in the generated code: for a
//! closed-form block its coefficients, the call of its form in
//! `kinematics_core::closed`, and the bindings of its unknowns and of their
//! sines and cosines; for any other block the call of its own
//! Newton–Raphson function (`newton_block_fns`) and the same bindings.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;

use super::print::Printer;
use super::Ctx;
use crate::closed::{Closed, Pattern};
use std::collections::HashMap;

use crate::ir::{Func, Id, Leaf, Node};

/// The blocks solved in order under `pr`'s names (`lets`: the stages of
/// the blocks' coefficients first), each binding its unknowns (`q_…`) and
/// the sines and cosines of its angles (`__c_…`, `__s_…`); `fallback`
/// returns from the enclosing function where a block is degenerate, and
/// where a Newton block does not converge after `newton_failed` (which
/// sees the failure `f` and the coordinates `__q` it was solved at).
pub(super) fn solve_blocks(
    cx: &Ctx<'_>,
    pr: &Printer<'_>,
    lets: &[TokenStream],
    fallback: &TokenStream,
    newton_failed: &TokenStream,
) -> TokenStream {
    let (pp, nd, nm) = (&cx.pp, cx.nd, cx.nm());
    let (coord, q) = (&cx.id.coord, &cx.id.q);
    let q_drivers = &q[..nd];
    let mut solve = TokenStream::new();
    let mut m = 0usize;
    let mut angle = 0usize;
    let mut known: Vec<bool> = (0..cx.nd + cx.nu).map(|j| j < nd).collect();
    for (i, (b, block_lets)) in cx.closed.iter().zip(lets).enumerate() {
        let Some(p) = &b.pattern else {
            solve.extend(newton_block_call(cx, i, b, &known, fallback, newton_failed));
            let (_, angles) = angle_trig(cx, &own_coords(cx, b));
            angle += angles.len();
            for &c in &b.cols {
                known[nd + c] = true;
            }
            for (j, cv, sv) in &angles {
                solve.extend(offsets_of(cx, pr, *j, cv, sv));
            }
            continue;
        };
        for &c in &b.cols {
            known[nd + c] = true;
        }
        let names = cx.block_names(b).join(", ");
        let mode = if p.has_modes() {
            m += 1;
            let k = m - 1;
            quote!(&mut modes[#k],)
        } else {
            TokenStream::new()
        };
        let call = solve_call(cx, pr, b, p, mode, angle);
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
                solve.extend(offsets_of(cx, pr, nd + c, &cv, &sv));
            }
        }
    }
    solve
}

/// The bindings `__off_…` of sin(θ + k) and cos(θ + k) for the angle of
/// coordinate `coord`, from its cosine `cv` and sine `sv` by the addition
/// theorem.
fn offsets_of(
    cx: &Ctx<'_>,
    pr: &Printer<'_>,
    coord: usize,
    cv: &syn::Ident,
    sv: &syn::Ident,
) -> TokenStream {
    let mut out = TokenStream::new();
    for (i, o) in cx.offsets.iter().enumerate() {
        if o.coord != coord {
            continue;
        }
        let (ck, sk) = (pr.operand(o.cos_k), pr.operand(o.sin_k));
        let off = format_ident!("__off_{}", i);
        // sin(θ + k) = sin θ cos k + cos θ sin k;
        // cos(θ + k) = cos θ cos k − sin θ sin k.
        out.extend(if o.func == Func::Sin {
            quote!(let #off = #sv * #ck + #cv * #sk;)
        } else {
            quote!(let #off = #cv * #ck - #sv * #sk;)
        });
    }
    out
}

/// The name of the function solving block `i` by Newton–Raphson.
fn newton_block_name(i: usize) -> syn::Ident {
    format_ident!("__newton_block_{}", i)
}

/// The solution of Newton block `i` (binding its unknowns `q_…`): every
/// coordinate marked `known` passed as bound, the others (its own
/// unknowns, and later ones it does not involve) from `start`;
/// `newton_failed`, then `fallback`, where it does not converge.
fn newton_block_call(
    cx: &Ctx<'_>,
    i: usize,
    b: &Closed,
    known: &[bool],
    fallback: &TokenStream,
    newton_failed: &TokenStream,
) -> TokenStream {
    let (nd, nm) = (cx.nd, cx.nm());
    let (coord, q) = (&cx.id.coord, &cx.id.q);
    let args = known.iter().enumerate().map(|(j, &k)| {
        let (qv, field) = (&q[j], &coord[j]);
        if k {
            quote!(#qv)
        } else {
            quote!(start.#field)
        }
    });
    let guess = b.cols.iter().map(|&c| {
        let field = &coord[nd + c];
        quote!(start.#field)
    });
    let outs = b.cols.iter().map(|&c| &q[nd + c]);
    let name = newton_block_name(i);
    // The cosines and sines of the angles solved before, and of its own.
    let angle_names = |coords: &[usize]| -> Vec<syn::Ident> {
        let (_, angles) = angle_trig(cx, coords);
        angles.into_iter().flat_map(|(_, c, s)| [c, s]).collect()
    };
    let known_coords: Vec<usize> = (nd..known.len()).filter(|&j| known[j]).collect();
    let known_trig = angle_names(&known_coords);
    let own_trig = angle_names(&own_coords(cx, b));
    // The coordinates of the failure: the block's at its last iterate.
    let failed = if newton_failed.is_empty() {
        TokenStream::new()
    } else {
        let (at, k) = (b.cols.iter().map(|&c| nd + c), 0..b.cols.len());
        quote! {
            let mut __q = __q;
            #( __q[#at] = last[#k]; )*
            #newton_failed
        }
    };
    quote! {
        let __q = [#(#args),*];
        let ([#(#outs),*], [#(#own_trig),*]) = match self.#name(__q, [#(#guess),*], [#(#known_trig),*], angles, __scaling, options) {
            ::core::result::Result::Ok(x) => x,
            ::core::result::Result::Err((f, last)) => {
                #failed
                *modes = [::core::primitive::f64::NAN; #nm];
                #fallback
            }
        };
    }
}

/// The functions solving the Newton blocks of a mechanism with a
/// closed-form path: Newton–Raphson on the block's equations in its
/// unknowns alone, the coordinates of the blocks before it given (and the
/// cosines and sines of their angles, as the caller has them). Full
/// Newton steps while each passes the Armijo test, the sines and cosines
/// of the block's angles carried from one iterate to the next
/// (`sin_cos_after`); off that path the general damped solver, with the
/// block's rows and columns of the scaling.
pub(super) fn newton_block_fns(cx: &Ctx<'_>) -> TokenStream {
    let inline_core = cx.inline_core();
    let (g, d, pp, allow) = (cx.g(), cx.d, &cx.pp, &cx.allow);
    let (nd, ne) = (cx.nd, cx.ne);
    let n = nd + cx.nu;
    let q = &cx.id.q;
    let leaf = cx.leaf();
    let na_all = cx.na();
    let mut out = TokenStream::new();
    let mut earlier: Vec<usize> = Vec::new();
    // The slot of each unknown angle in the carried `angles`, in solve
    // order (as `solve_blocks` counts them).
    let mut slot = 0usize;
    for (i, b) in cx.closed.iter().enumerate() {
        if b.pattern.is_some() {
            let own = own_coords(cx, b);
            slot += angle_trig(cx, &own).1.len();
            earlier.extend(own);
            continue;
        }
        let k = b.cols.len();
        let own: Vec<u32> = b
            .cols
            .iter()
            .map(|&c| u32::try_from(nd + c).unwrap_or(u32::MAX))
            .collect();
        let phi: Vec<Id> = b.rows.iter().map(|&r| d.phi[r]).collect();
        let jac: Vec<Vec<Id>> = b
            .rows
            .iter()
            .map(|&r| b.cols.iter().map(|&c| d.jac[r][c]).collect())
            .collect();
        let roots: Vec<Id> = phi.iter().chain(jac.iter().flatten()).copied().collect();
        // In coordinate order, as the caller passes them.
        earlier.sort_unstable();
        let (given_known, known_trig) = angle_trig(cx, &earlier);
        let (given_own, own_trig) = angle_trig(cx, &own_coords(cx, b));
        let mut given = given_known;
        given.extend(given_own);
        let hoist = super::newton::frontier(g, &roots, &|j| own.contains(&j));
        let sched = crate::cse::schedule(g, &[hoist, roots]);
        let (pr, lets) = super::print::bind_given(g, &sched, &leaf, given);
        let (hoisted, iterated) = (&lets[0], &lets[1]);
        let phi: Vec<TokenStream> = phi.iter().map(|&r| pr.element(r)).collect();
        let jac: Vec<TokenStream> = jac
            .iter()
            .map(|row| {
                let row = row.iter().map(|&e| pr.element(e));
                quote!([#(#row),*])
            })
            .collect();
        let own_q: Vec<&syn::Ident> = b.cols.iter().map(|&c| &q[nd + c]).collect();
        let (rows, cols) = (&b.rows, &b.cols);
        let name = newton_block_name(i);
        let (nk, na) = (known_trig.len(), own_trig.len());
        let known_names = known_trig.iter().flat_map(|(_, c, s)| [c, s]);
        let own_names: Vec<&syn::Ident> = own_trig.iter().flat_map(|(_, c, s)| [c, s]).collect();
        let slots: Vec<usize> = (slot..slot + na).collect();
        slot += na;
        let carried = own_trig.iter().enumerate().map(|(m, (j, c, s))| {
            let qv = &q[*j];
            quote! {
                let (#s, #c) = #pp::sin_cos_after(__t[#m][1], __t[#m][0], #qv, #qv - __t[#m][2]);
                __t[#m] = [#c, #s, #qv];
            }
        });
        let store: Vec<TokenStream> = own_trig
            .iter()
            .zip(&slots)
            .map(|((j, c, s), k)| {
                let qv = &q[*j];
                quote!(angles[#k] = [#c, #s, #qv];)
            })
            .collect();
        let fresh: Vec<TokenStream> = own_trig
            .iter()
            .map(|(j, c, s)| {
                let qv = &q[*j];
                quote!(let (#s, #c) = #pp::math::sin_cos(#qv);)
            })
            .collect();
        let doc = format!(
            "Newton–Raphson on the block solving {} alone, from `guess`, the \
             coordinates of the blocks before it given in `q` and the cosines and sines of \
             their angles in `trig`: the solution and the cosines and sines of its angles, \
             or where it does not converge, the failure (its indices among all equations \
             and unknowns) and the last iterate.",
            cx.block_names(b).join(", ")
        );
        out.extend(quote! {
            #[doc = #doc]
            #[doc(hidden)]
            #inline_core
            #allow
            fn #name(
                &self,
                q: [f64; #n],
                guess: [f64; #k],
                trig: [f64; 2 * #nk],
                angles: &mut [[f64; 3]; #na_all],
                scaling: &#pp::Scaling<#ne>,
                options: &#pp::Options,
            ) -> ::core::result::Result<([f64; #k], [f64; 2 * #na]), (#pp::Failure, [f64; #k])> {
                let [#(#q),*] = q;
                let [#(#known_names),*] = trig;
                #hoisted
                let sc = #pp::Scaling::<#k> {
                    row: [#(scaling.row[#rows]),*],
                    col: [#(scaling.col[#cols]),*],
                };
                // The common path: full Newton steps until the residual is
                // at round-off (as the closed-form path checks it after
                // the last block), no other test.
                let w = sc.weights(options);
                let fine = #pp::Options { tolerance: options.tolerance.min(1e-12), ..*options };
                let mut fast = #pp::FastNewton::new();
                let mut u = guess;
                // [cos, sin, angle] of the block's angles: the last
                // solution's, carried from the step before (NaN angle:
                // computed afresh).
                let mut __t: [[f64; 3]; #na] = [#(angles[#slots]),*];
                loop {
                    let [#(#own_q),*] = u;
                    #(#carried)*
                    #iterated
                    let phi = [#(#phi),*];
                    match fast.assess(&phi, &w, &fine) {
                        #pp::Next::Converged => {
                            #(#store)*
                            return ::core::result::Result::Ok((u, [#(#own_names),*]));
                        }
                        #pp::Next::Continue => {}
                        #pp::Next::Fallback => break,
                    }
                    let jac = [#(#jac),*];
                    match #pp::dense_solve(&jac, &phi, &sc, options.singularity_threshold) {
                        ::core::result::Result::Ok(step) => fast.advance(&mut u, &step),
                        ::core::result::Result::Err(_) => break,
                    }
                }
                // Off it: the damped solver from the guess, which reports
                // the failure.
                let mut u = guess;
                let mut phi = [0.0f64; #k];
                let mut jac = [[0.0f64; #k]; #k];
                let solved = #pp::newton(&mut u, &mut phi, &mut jac, &sc, options, |u, phi, jac| {
                    let [#(#own_q),*] = *u;
                    #(#fresh)*
                    #iterated
                    *phi = [#(#phi),*];
                    *jac = [#(#jac),*];
                }, |jac, rhs| #pp::dense_solve(jac, rhs, &sc, options.singularity_threshold));
                match solved {
                    ::core::result::Result::Ok(_) => {
                        let [#(#own_q),*] = u;
                        #(#fresh)*
                        #(#store)*
                        ::core::result::Result::Ok((u, [#(#own_names),*]))
                    }
                    ::core::result::Result::Err(f) => {
                        #( angles[#slots][2] = ::core::primitive::f64::NAN; )*
                        ::core::result::Result::Err((f.in_subsystem(&[#(#rows),*], &[#(#cols),*]), u))
                    }
                }
            }
        });
        earlier.extend(own_coords(cx, b));
    }
    out
}

/// The coordinate indices of a block's unknowns, in the block's order.
fn own_coords(cx: &Ctx<'_>, b: &Closed) -> Vec<usize> {
    b.cols.iter().map(|&c| cx.nd + c).collect()
}

/// Unknown angles: each one's coordinate index and the names of its
/// cosine and sine.
type AngleNames = Vec<(usize, syn::Ident, syn::Ident)>;

/// The unknown angles among the coordinates `coords`: the names of their
/// cosines and sines (`__c_…`, `__s_…`, as the closed-form path binds
/// them), and the graph's cos and sin nodes of each, to print as those
/// names.
fn angle_trig(cx: &Ctx<'_>, coords: &[usize]) -> (HashMap<Id, syn::Ident>, AngleNames) {
    let g = cx.g();
    let mut given = HashMap::new();
    let mut names = Vec::new();
    for &j in coords {
        if cx.model.kinds[j] != crate::lower::CoordKind::Angle {
            continue;
        }
        let field = cx.id.coord[j].unraw();
        let (cv, sv) = (
            format_ident!("__c_{}", field),
            format_ident!("__s_{}", field),
        );
        if let Some(leaf) = u32::try_from(j)
            .ok()
            .and_then(|j| g.find(&Node::Leaf(Leaf::Q(j))))
        {
            for (f, v) in [(Func::Cos, &cv), (Func::Sin, &sv)] {
                if let Some(t) = g.find(&Node::Call(f, leaf)) {
                    given.insert(t, v.clone());
                }
            }
        }
        names.push((j, cv, sv));
    }
    (given, names)
}

/// The coefficients of a pattern (what its block's stage evaluates).
pub(super) fn coefficients(p: Option<&Pattern>) -> Vec<Id> {
    p.map_or_else(Vec::new, Pattern::coefficients)
}

/// The call of the block's closed form, `mode` being `&mut modes[k],` or
/// nothing.
fn solve_call(
    cx: &Ctx<'_>,
    pr: &Printer<'_>,
    b: &Closed,
    p: &Pattern,
    mode: TokenStream,
    slot: usize,
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
    // The guess's cosine and sine, from the carried values where they are
    // the guess's (the block's first angle has carried slot `slot`).
    let angle_guess = quote!(|| #pp::closed::guess_trig(&angles[#slot], start.#first));
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
            let next = slot + 1;
            quote!(#pp::closed::circle_circle(#k, #p, #q, #mode || {
                let [c0, s0] = #pp::closed::guess_trig(&angles[#slot], start.#first);
                let [c1, s1] = #pp::closed::guess_trig(&angles[#next], start.#second);
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
