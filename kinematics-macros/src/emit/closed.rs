//! The closed-form path (`crate::closed`): for a mechanism whose every
//! block of loop equations has a closed form, `__step_closed` solves the
//! blocks in order with `kinematics_core::closed`, each from coefficients
//! evaluated with the unknowns of the blocks before it, checks the residual,
//! and analyses the motion with the sines and cosines the closed forms
//! produced (no trigonometric call for an unknown angle but its atan2).
//! Also the assembly without a guess (`assemble_in`, `assemble_all`), the
//! modes type, and the `BLOCKS` constant every mechanism has.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;
use syn::Ident;

use super::print::{bind_given, Printer};
use super::{guards, Ctx};
use crate::closed::{Closed, Pattern};
use crate::cse::schedule;
use crate::ir::{Func, Id, Leaf, Node};

impl Ctx<'_> {
    /// Whether every block has a closed form (then stepping and assembly
    /// without a guess go through `__step_closed`).
    pub(super) fn all_closed(&self) -> bool {
        !self.closed.is_empty() && self.closed.iter().all(|b| b.pattern.is_some())
    }

    /// The blocks with two assembly modes.
    fn mode_blocks(&self) -> Vec<&Closed> {
        self.closed
            .iter()
            .filter(|b| b.pattern.as_ref().is_some_and(Pattern::has_modes))
            .collect()
    }

    /// Number of unknown angles (carried by the closed-form path from one
    /// step to the next).
    pub(super) fn na(&self) -> usize {
        (self.nd..self.nd + self.nu)
            .filter(|&j| self.model.kinds[j] == crate::lower::CoordKind::Angle)
            .count()
    }

    /// Number of modes (0 unless every block is closed-form).
    pub(super) fn nm(&self) -> usize {
        if self.all_closed() {
            self.mode_blocks().len()
        } else {
            0
        }
    }

    /// The sines and cosines of parameter-only arguments that the
    /// closed-form path uses (evaluated once per stepper by
    /// `__param_trig`), in arena order; none unless every block is
    /// closed-form.
    pub(super) fn param_trig(&self) -> Vec<Id> {
        if !self.all_closed() {
            return Vec::new();
        }
        let g = self.g();
        let mut roots: Vec<Id> = self.newton_roots();
        roots.extend(self.analysis_stages().into_iter().flatten());
        roots.extend(self.offsets.iter().flat_map(|o| [o.cos_k, o.sin_k]));
        let live = g.reachable(&roots);
        let mut param_only = vec![false; g.len()];
        let mut out = Vec::new();
        for i in 0..g.len() {
            let node = g.node(Id::from_index(i));
            param_only[i] = match node {
                Node::Leaf(l) => matches!(l, Leaf::Param(_)),
                _ => node.children().all(|c| param_only[c.index()]),
            };
            if let Node::Call(Func::Sin | Func::Cos, x) = node {
                if live[i] && param_only[x.index()] && g.as_const(x).is_none() {
                    out.push(Id::from_index(i));
                }
            }
        }
        out
    }

    /// The unknowns of a block, by name.
    fn block_names(&self, b: &Closed) -> Vec<String> {
        b.cols
            .iter()
            .map(|&c| self.id.coord[self.nd + c].unraw().to_string())
            .collect()
    }
}

/// The `BLOCKS` constant: how each block is solved.
pub(super) fn blocks_const(cx: &Ctx<'_>) -> TokenStream {
    let pp = &cx.pp;
    let all = cx.all_closed();
    let entries = cx.closed.iter().map(|b| {
        let names = cx.block_names(b);
        let (method, modes) = match &b.pattern {
            Some(p) if all => (p.describe(), p.has_modes()),
            _ => ("Newton–Raphson", false),
        };
        quote!(#pp::closed::Block { unknowns: &[#(#names),*], method: #method, modes: #modes })
    });
    quote! {
        /// How each diagonal block of the loop equations is solved, in
        /// solve order: in closed form (needing no guess, with two
        /// assembly modes where it has two solutions) when every block of
        /// the mechanism has one, else by Newton–Raphson from a guess.
        pub const BLOCKS: &'static [#pp::closed::Block] = &[#(#entries),*];
    }
}

/// The modes type, when every block is closed-form.
pub(super) fn modes_type(cx: &Ctx<'_>) -> TokenStream {
    if !cx.all_closed() {
        return TokenStream::new();
    }
    let (pp, vis, name) = (&cx.pp, &cx.def.vis, &cx.id.name);
    let modes = format_ident!("{}Modes", name.unraw());
    let blocks = cx.mode_blocks();
    let nm = blocks.len();
    let fields: Vec<Ident> = blocks
        .iter()
        .map(|b| format_ident!("{}", cx.block_names(b).join("_")))
        .collect();
    let docs = blocks.iter().map(|b| {
        let method = b.pattern.as_ref().map_or("", Pattern::describe);
        format!(
            "The assembly mode of the block solving {} ({method}).",
            cx.block_names(b).join(", ")
        )
    });
    let combos = 1usize << nm;
    let all = (0..combos).map(|i| {
        let vals = (0..nm).map(|j| {
            if i >> j & 1 == 1 {
                quote!(#pp::closed::Mode::Minus)
            } else {
                quote!(#pp::closed::Mode::Plus)
            }
        });
        quote!(#modes { #( #fields: #vals ),* })
    });
    let idx: Vec<usize> = (0..nm).collect();
    let doc = format!(
        "The assembly modes of [`{name}`]: one per block of its loop equations with two \
         closed-form solutions (see [`kinematics_core::closed::Mode`]), for \
         [`{name}::assemble_in`]."
    );
    quote! {
        #[doc = #doc]
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        #vis struct #modes {
            #( #[doc = #docs] pub #fields: #pp::closed::Mode, )*
        }

        impl #modes {
            /// Every combination of modes, in the order of
            /// [`assemble_all`](#name::assemble_all): field j is `Minus`
            /// where bit j of the index is set.
            pub const ALL: [Self; #combos] = [#(#all),*];

            /// The modes as signs (±1), in field order.
            #[doc(hidden)]
            #[must_use]
            pub fn __signs(&self) -> [f64; #nm] {
                [#(self.#fields.sign()),*]
            }

            /// The modes of signs (±1), in field order.
            #[doc(hidden)]
            #[must_use]
            pub fn __from_signs(s: &[f64; #nm]) -> Self {
                Self { #( #fields: #pp::closed::Mode::from_sign(s[#idx]) ),* }
            }
        }
    }
}

/// The closed-form step and the assembly without a guess.
pub(super) fn closed_methods(cx: &Ctx<'_>) -> TokenStream {
    if !cx.all_closed() {
        return TokenStream::new();
    }
    let (g, d, pp, allow) = (cx.g(), cx.d, &cx.pp, &cx.allow);
    let (nd, nm) = (cx.nd, cx.nm());
    let id = &cx.id;
    let (coords, motion, coord, q) = (&id.coords, &id.motion, &id.coord, &id.q);
    let (c_drivers, c_unknowns) = coord.split_at(nd);
    let q_drivers = &q[..nd];
    let (qd_drivers, qdd_drivers) = (&id.qd[..nd], &id.qdd[..nd]);
    let modes = format_ident!("{}Modes", id.name.unraw());
    let combos = 1usize << nm;
    let ne = cx.ne;
    let na = cx.na();
    let nt = super::newton::unknown_trig(g, &cx.newton_roots(), cx.model.drivers).len();

    // The sines and cosines of the unknown angles, as the closed forms give
    // them.
    let mut given: HashMap<Id, Ident> = HashMap::new();
    for b in cx.closed {
        for &c in &b.cols {
            let Some(leaf) = g.find(&Node::Leaf(Leaf::Q(u32::try_from(nd + c).unwrap_or(0))))
            else {
                continue;
            };
            let name = id.coord[nd + c].unraw();
            for (f, prefix) in [(Func::Cos, "__c"), (Func::Sin, "__s")] {
                if let Some(t) = g.find(&Node::Call(f, leaf)) {
                    given.insert(t, format_ident!("{}_{}", prefix, name));
                }
            }
        }
    }
    for (i, o) in cx.offsets.iter().enumerate() {
        given.insert(o.node, format_ident!("__off_{}", i));
    }
    let pt = cx.param_trig();
    let npt = pt.len();
    let pt_names: Vec<Ident> = (0..npt).map(|i| format_ident!("__pt_{}", i)).collect();
    given.extend(pt.iter().copied().zip(pt_names.iter().cloned()));
    let leaf = cx.leaf();
    let param_trig = {
        // The offsets k of sin(θ + k): beyond 2²⁰ rad, θ + k rounds away
        // most of θ, so the addition theorem would not match the equations
        // as evaluated; then every value is NaN and the closed-form path
        // hands over to Newton–Raphson.
        let ks: Vec<Id> = cx
            .offsets
            .iter()
            .filter_map(|o| match g.node(o.cos_k) {
                Node::Call(_, k) => Some(k),
                _ => None,
            })
            .collect::<std::collections::BTreeSet<Id>>()
            .into_iter()
            .collect();
        let mut roots = pt.clone();
        roots.extend(&ks);
        let sched = schedule(g, &[roots]);
        let (pr, lets) = super::print::bind(g, &sched, &leaf);
        let values: Vec<_> = pt.iter().map(|&i| pr.expr(i)).collect();
        let far: Vec<_> = ks.iter().map(|&k| pr.operand(k)).collect();
        let lets = &lets[0];
        quote! {
            /// The sines and cosines of parameter-only angles (offsets),
            /// evaluated once per stepper; NaN where an offset is beyond
            /// 2²⁰ rad.
            #[doc(hidden)]
            #[inline(always)]
            #allow
            fn __param_trig(&self) -> [f64; #npt] {
                #lets
                if false #( || #far.abs() > 1048576.0 )* {
                    return [::core::primitive::f64::NAN; #npt];
                }
                [#(#values),*]
            }
        }
    };
    let far_check = |fallback: &TokenStream| {
        if npt == 0 {
            TokenStream::new()
        } else {
            quote! {
                if __pt_0.is_nan() {
                    *modes = [::core::primitive::f64::NAN; #nm];
                    #fallback
                }
            }
        }
    };
    let nb = cx.closed.len();
    let coefs: Vec<Vec<Id>> = cx
        .closed
        .iter()
        .map(|b| coefficients(b.pattern.as_ref()))
        .collect();
    let phi_check = |pr: &Printer<'_>, fallback: &TokenStream| {
        let phi: Vec<_> = d.phi.iter().map(|&i| pr.element(i)).collect();
        quote! {
            let __phi = [#(#phi),*];
            if !#pp::closed::at_round_off(&__phi, &__scaling.weights(options), options) {
                *modes = [::core::primitive::f64::NAN; #nm];
                let start = &#coords { #( #coord: #q ),* };
                #fallback
            }
        }
    };
    // The step: the blocks, Φ, then the analysis.
    let step_newton = quote!(return self.__step_newton(start, [#(#qd_drivers),*], [#(#qdd_drivers),*], options, __scaling););
    let mut stages = coefs.clone();
    stages.push(d.phi.clone());
    stages.extend(cx.analysis_stages());
    let sched = schedule(g, &stages);
    let (pr, lets) = bind_given(g, &sched, &leaf, given.clone());
    let step_solve = solve_blocks(cx, &pr, &lets, &step_newton);
    let step_check = phi_check(&pr, &step_newton);
    let step_far = far_check(&step_newton);
    let phi_lets = &lets[nb];
    let tail = cx.analysis_tail(
        &pr,
        [&lets[nb + 1], &lets[nb + 2], &lets[nb + 3]],
        &quote!(#coords { #( #coord: #q ),* }),
        &quote!(#pp::closed::max_abs(&__phi)),
    );
    // The assembly: the blocks, Φ, then Φ_u.
    let asm_newton = quote!(return self.__assemble_newton(start, options););
    let mut stages = coefs;
    stages.push(d.phi.clone());
    stages.push(cx.jac_flat());
    let sched = schedule(g, &stages);
    let (apr, alets) = bind_given(g, &sched, &leaf, given);
    let asm_solve = solve_blocks(cx, &apr, &alets, &asm_newton);
    let asm_check = phi_check(&apr, &asm_newton);
    let asm_far = far_check(&asm_newton);
    let (asm_phi_lets, asm_jac_lets) = (&alets[nb], &alets[nb + 1]);
    let asm_jac = cx.jac_array(&apr);
    let at_solution = cx.factor_at_solution();
    let nnz = cx.blocks.nnz();
    let inputs = guards::inputs(cx, "start", true);
    let asm_inputs = guards::inputs(cx, "start", false);
    quote! {
        /// A step in closed form: the blocks solved in order in the modes
        /// `modes` (±1; NaN: from the guess in `start`, then stored), each
        /// unknown angle from the previous solution in `angles` (see
        /// `closed::near_carried`), the
        /// residual checked, the motion analysed. Falls back to
        /// Newton–Raphson (resetting `modes`) where a block is degenerate
        /// or the residual is not at round-off.
        #[doc(hidden)]
        #[inline(always)]
        #allow
        fn __step_closed(
            &self,
            start: &#coords,
            rates: impl #pp::DriverValues<#nd>,
            accelerations: impl #pp::DriverValues<#nd>,
            options: &#pp::Options,
            __scaling: &#pp::Scaling<#ne>,
            modes: &mut [f64; #nm],
            angles: &mut [[f64; 3]; #na],
            __pt: &[f64; #npt],
        ) -> #pp::Result<#motion, #pp::Error> {
            let [#(#pt_names),*] = *__pt;
            let [#(#qd_drivers),*] = rates.into_array();
            let [#(#qdd_drivers),*] = accelerations.into_array();
            #step_far
            #inputs
            let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
            #step_solve
            #phi_lets
            #step_check
            #tail
        }

        /// An assembly in closed form: as `__step_closed`, positions only,
        /// with the conditioning and branch checks at the solution.
        #[doc(hidden)]
        #[inline(always)]
        #allow
        fn __assemble_closed(
            &self,
            start: &#coords,
            options: &#pp::Options,
            __scaling: &#pp::Scaling<#ne>,
            modes: &mut [f64; #nm],
            __pt: &[f64; #npt],
        ) -> #pp::Result<#coords, #pp::Error> {
            let [#(#pt_names),*] = *__pt;
            #asm_far
            let angles = &mut [[::core::primitive::f64::NAN; 3]; #na];
            #asm_inputs
            let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
            #asm_solve
            #asm_phi_lets
            #asm_check
            #asm_jac_lets
            let jac: [f64; #nnz] = #asm_jac;
            #at_solution
            let _ = (__conditioning, __det_sign);
            ::core::result::Result::Ok(#coords { #( #coord: #q ),* })
        }

        #param_trig

        /// The step again in the other combinations of modes, after the
        /// step in `modes` found its solution on the other branch than
        /// `Options::branch` asks: for closed-form blocks the branch is a
        /// choice, not a check. The first combination that succeeds is
        /// kept in `modes`; if none does, the error of the first.
        #[doc(hidden)]
        #[cold]
        #[inline(never)]
        #allow
        fn __step_other_branch(
            &self,
            first: #pp::Error,
            start: &#coords,
            rates: [f64; #nd],
            accelerations: [f64; #nd],
            options: &#pp::Options,
            scaling: &#pp::Scaling<#ne>,
            modes: &mut [f64; #nm],
            angles: &mut [[f64; 3]; #na],
            pt: &[f64; #npt],
        ) -> #pp::Result<#motion, #pp::Error> {
            for i in 0..#combos {
                let mut m: [f64; #nm] = ::core::array::from_fn(|j| if i >> j & 1 == 1 { -1.0 } else { 1.0 });
                if m.iter().zip(modes.iter()).all(|(a, b)| a.to_bits() == b.to_bits()) {
                    continue;
                }
                let r = self.__step_closed(start, rates, accelerations, options, scaling, &mut m, angles, pt);
                if r.is_ok() {
                    *modes = m;
                    return r;
                }
            }
            ::core::result::Result::Err(first)
        }

        /// `__step_other_branch` for `__assemble_closed`.
        #[doc(hidden)]
        #[cold]
        #[inline(never)]
        #allow
        fn __assemble_other_branch(
            &self,
            first: #pp::Error,
            start: &#coords,
            options: &#pp::Options,
            scaling: &#pp::Scaling<#ne>,
            modes: &mut [f64; #nm],
            pt: &[f64; #npt],
        ) -> #pp::Result<#coords, #pp::Error> {
            for i in 0..#combos {
                let mut m: [f64; #nm] = ::core::array::from_fn(|j| if i >> j & 1 == 1 { -1.0 } else { 1.0 });
                if m.iter().zip(modes.iter()).all(|(a, b)| a.to_bits() == b.to_bits()) {
                    continue;
                }
                let r = self.__assemble_closed(start, options, scaling, &mut m, pt);
                if r.is_ok() {
                    *modes = m;
                    return r;
                }
            }
            ::core::result::Result::Err(first)
        }

        /// The Newton–Raphson step from `start`, off the closed-form path.
        #[doc(hidden)]
        #[cold]
        #[inline(never)]
        fn __step_newton(
            &self,
            start: &#coords,
            rates: [f64; #nd],
            accelerations: [f64; #nd],
            options: &#pp::Options,
            scaling: &#pp::Scaling<#ne>,
        ) -> #pp::Result<#motion, #pp::Error> {
            let mut carry = [[0.0f64, 0.0f64, ::core::primitive::f64::NAN]; #nt];
            self.__step_core(start, rates, accelerations, options, scaling, &mut carry)
        }

        /// Assembles at the drivers `drivers` (a bare `f64` for one driver,
        /// else an array in declaration order) in the assembly modes
        /// `modes`, with no guess: every block of the loop equations is
        /// solved in closed form (see [`Self::BLOCKS`]). Unknown angles are
        /// returned in (−π, π].
        ///
        /// # Errors
        /// [`Error::CannotAssemble`](#pp::Error::CannotAssemble) when the
        /// links cannot close a loop at these drivers (past a limit
        /// position), invalid parameters, non-finite drivers, and a
        /// singular Jacobian at the solution.
        pub fn assemble_in(
            &self,
            drivers: impl #pp::DriverValues<#nd>,
            modes: &#modes,
        ) -> #pp::Result<#coords, #pp::Error> {
            self.validate()?;
            let d = drivers.into_array();
            let [#(#q_drivers),*] = d;
            let start = #coords { #( #c_drivers: #q_drivers, )* #( #c_unknowns: 0.0, )* };
            let scaling = self.__scaling(&d)?;
            let mut signs = modes.__signs();
            self.__assemble_closed(&start, &#pp::Options::DEFAULT, &scaling, &mut signs, &self.__param_trig())
        }

        /// Every assembly at the drivers `drivers`: one per combination of
        /// modes, in the order of
        #[doc = concat!("[`", stringify!(#modes), "::ALL`]")]
        /// (each as [`Self::assemble_in`]).
        pub fn assemble_all(
            &self,
            drivers: impl #pp::DriverValues<#nd>,
        ) -> [#pp::Result<#coords, #pp::Error>; #combos] {
            let d = drivers.into_array();
            ::core::array::from_fn(|i| self.assemble_in(d, &#modes::ALL[i]))
        }
    }
}

/// The blocks solved in order under `pr`'s names (`lets`: the stages of
/// the blocks' coefficients first), each binding its unknowns (`q_…`) and
/// the sines and cosines of its angles (`__c_…`, `__s_…`); `fallback`
/// returns from the enclosing function where a block is degenerate.
fn solve_blocks(
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
fn coefficients(p: Option<&Pattern>) -> Vec<Id> {
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
