//! The closed-form methods: `__step_closed` solves the blocks in order,
//! each closed-form one with `kinematics_core::closed` from coefficients
//! evaluated with the unknowns of the blocks before it and any other by
//! Newton–Raphson on that block alone, checks the residual, and analyses
//! the motion with the sines and cosines the blocks produced (no
//! trigonometric call for an unknown angle of a closed-form block but its
//! atan2); `__assemble_closed` does the same for positions only;
//! `assemble_in` and `assemble_all` assemble in named modes (with no guess
//! unless there are Newton blocks); the retries in other modes where
//! `Options::branch` asks for the other branch.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;
use syn::Ident;

use super::closed_solve::{coefficients, newton_block_fns, solve_blocks};
use super::print::{bind_given, Printer};
use super::{guards, Ctx};
use crate::cse::schedule;
use crate::ir::{Func, Id, Leaf, Node};

/// The closed-form step and the assembly in named modes (without a guess
/// unless some block is solved by Newton–Raphson).
pub(super) fn closed_methods(cx: &Ctx<'_>) -> TokenStream {
    if !cx.closed_path() {
        return TokenStream::new();
    }
    let (g, d, pp, allow) = (cx.g(), cx.d, &cx.pp, &cx.allow);
    let inline_core = cx.inline_core();
    let (nd, nm) = (cx.nd, cx.nm());
    let id = &cx.id;
    let (coords, motion, coord, q) = (&id.coords, &id.motion, &id.coord, &id.q);
    let (c_drivers, c_unknowns) = coord.split_at(nd);
    let q_drivers = &q[..nd];
    let (qd_drivers, qdd_drivers) = (&id.qd[..nd], &id.qdd[..nd]);
    let modes = format_ident!("{}Modes", id.name.unraw());
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
        // Each distinct argument's sine and cosine from one call of the
        // table's `sin_cos` (a stateless step pays for these at every
        // call, where the platform's `sincos` would cost a third of it).
        let mut args: Vec<Id> = Vec::new();
        let mut which: Vec<Option<(usize, bool)>> = Vec::new();
        for &i in &pt {
            which.push(match g.node(i) {
                Node::Call(f @ (Func::Sin | Func::Cos), x) => {
                    let j = args.iter().position(|&a| a == x).unwrap_or_else(|| {
                        args.push(x);
                        args.len() - 1
                    });
                    Some((j, f == Func::Sin))
                }
                _ => None,
            });
        }
        let mut roots: Vec<Id> = pt
            .iter()
            .zip(&which)
            .filter(|(_, w)| w.is_none())
            .map(|(&i, _)| i)
            .collect();
        roots.extend(&args);
        roots.extend(&ks);
        let sched = schedule(g, &[roots]);
        let (pr, lets) = super::print::bind(g, &sched, &leaf);
        let sc: Vec<Ident> = (0..args.len())
            .map(|j| format_ident!("__sc_{}", j))
            .collect();
        let sc_values: Vec<_> = args.iter().map(|&x| pr.operand(x)).collect();
        let values: Vec<_> = pt
            .iter()
            .zip(&which)
            .map(|(&i, w)| match *w {
                Some((j, true)) => {
                    let v = &sc[j];
                    quote!(#v.0)
                }
                Some((j, false)) => {
                    let v = &sc[j];
                    quote!(#v.1)
                }
                None => pr.expr(i),
            })
            .collect();
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
                #( let #sc = #pp::math::table::in_range(#sc_values); )*
                [#(#values),*]
            }
        }
    };
    // The carried values of the unknown angles, in slot order (block by
    // block, each block's columns in order), seeded from a guess.
    let seeded = {
        let fields: Vec<&Ident> = cx
            .closed
            .iter()
            .flat_map(|b| b.cols.iter().map(|&c| nd + c))
            .filter(|&j| cx.model.kinds[j] == crate::lower::CoordKind::Angle)
            .map(|j| &id.coord[j])
            .collect();
        quote! {
            /// The carried (cos, sin, angle) of each unknown angle, seeded
            /// from the guess `start`: a stateless step or assembly takes
            /// the modes and the solution's angles from them (an angle
            /// near the guess's without an atan2).
            #[doc(hidden)]
            #[inline(always)]
            fn __seeded(start: &#coords) -> [[f64; 3]; #na] {
                [#(#pp::closed::seeded(start.#fields)),*]
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
    // The drivers' sines and cosines, carried by a stepper from one step
    // to the next.
    let dtrig = cx.driver_trig();
    let ndt = dtrig.len();
    let mut step_given = given.clone();
    let mut dtrig_lets = Vec::new();
    for (k, (j, [cos, sin])) in dtrig.iter().enumerate() {
        let name = id.coord[*j].unraw();
        let (cv, sv) = (
            format_ident!("__cd_{}", name),
            format_ident!("__sd_{}", name),
        );
        let qv = &q[*j];
        dtrig_lets.push(quote! {
            let [#cv, #sv] = #pp::closed::carried_sin_cos(#qv, &mut __dtrig[#k]);
        });
        step_given.extend(cos.map(|t| (t, cv.clone())));
        step_given.extend(sin.map(|t| (t, sv.clone())));
    }
    let nb = cx.closed.len();
    let coefs: Vec<Vec<Id>> = cx
        .closed
        .iter()
        .map(|b| coefficients(b.pattern.as_ref()))
        .collect();
    // Φ at the closed-form solution: beyond round-off (cancellation in a
    // closed form), Newton–Raphson from the guess in fresh modes; above
    // the bound every step's pose is brought to (at extreme scales),
    // Newton–Raphson from the solution itself, to polish it in the same
    // modes.
    let phi_check = |pr: &Printer<'_>, fallback: &TokenStream| {
        let phi: Vec<_> = d.phi.iter().map(|&i| pr.element(i)).collect();
        quote! {
            let __phi = [#(#phi),*];
            match #pp::closed::closing(&__phi, &__scaling.weights(options), options) {
                #pp::closed::Closing::Closed => {}
                #pp::closed::Closing::Polish => {
                    let start = &#coords { #( #coord: #q ),* };
                    #fallback
                }
                #pp::closed::Closing::Refuse => {
                    *modes = [::core::primitive::f64::NAN; #nm];
                    let start = &#coords { #( #coord: #q ),* };
                    #fallback
                }
            }
        }
    };
    // The step: the blocks, Φ, then the analysis.
    let step_newton = quote!(return self.__step_newton(start, [#(#qd_drivers),*], [#(#qdd_drivers),*], options, __scaling););
    let mut stages = coefs.clone();
    stages.push(d.phi.clone());
    stages.extend(cx.analysis_stages());
    let sched = schedule(g, &stages);
    let (pr, lets) = bind_given(g, &sched, &leaf, step_given.clone());
    let step_solve = solve_blocks(cx, &pr, &lets, &step_newton, &TokenStream::new());
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
    let asm_newton = quote!(return self.__assemble_newton(start, options, __scaling););
    let mut stages = coefs;
    stages.push(d.phi.clone());
    stages.push(cx.jac_flat());
    stages.push(d.pos.iter().flatten().copied().collect());
    let sched = schedule(g, &stages);
    let (apr, alets) = bind_given(g, &sched, &leaf, step_given);
    // In the modes asked for, a Newton block that does not converge is an
    // error: Newton–Raphson on the whole system could find another mode.
    let asm_failed = quote! {
        if strict {
            return ::core::result::Result::Err(#pp::describe(f, &Self::__NAMES, &__q));
        }
    };
    let asm_solve = solve_blocks(cx, &apr, &alets, &asm_newton, &asm_failed);
    let asm_check = phi_check(&apr, &asm_newton);
    let asm_far = far_check(&asm_newton);
    let (asm_phi_lets, asm_jac_lets) = (&alets[nb], &alets[nb + 1]);
    let asm_jac = cx.jac_array(&apr);
    let pose_ok = cx.pose_at_solution(&apr, &alets[nb + 2]);
    let pose_t = cx.pose_type();
    let nnz = cx.blocks.nnz();
    // Carried values to compute afresh.
    let fresh = quote!(&mut [[::core::primitive::f64::NAN; 3]; #na]);
    let fresh_dtrig = quote!(&mut [[::core::primitive::f64::NAN; 3]; #ndt]);
    let inputs = guards::inputs(cx, "start", true);
    let asm_inputs = guards::inputs(cx, "start", false);
    let newton_blocks = newton_block_fns(cx);
    let assemble_in = if cx.mixed() {
        quote! {
            /// Assembles at the drivers of `start` in the assembly modes
            /// `modes`: the closed-form blocks of the loop equations
            /// exactly, with no guess; the other blocks (see
            /// [`Self::BLOCKS`]) by Newton–Raphson from the values of
            /// their unknowns in `start`, which is all of `start` that is
            /// read besides the drivers. Unknown angles of closed-form
            /// blocks are returned in (−π, π].
            ///
            /// # Errors
            /// [`Error::CannotAssemble`](#pp::Error::CannotAssemble) when
            /// the links cannot close a closed-form block at these drivers
            /// (past a limit position), the errors of Newton–Raphson on
            /// the whole system when a Newton block does not converge
            /// from its guess, invalid parameters, non-finite inputs, and
            /// a singular Jacobian at the solution.
            pub fn assemble_in(
                &self,
                start: &#coords,
                modes: &#modes,
            ) -> #pp::Result<#coords, #pp::Error> {
                self.validate()?;
                let d = [#(start.#c_drivers),*];
                let scaling = self.__scaling(&d)?;
                let mut signs = modes.__signs();
                self.__assemble_closed(start, &#pp::Options::DEFAULT, &scaling, &mut signs, #fresh, &self.__param_trig(), #fresh_dtrig, true)
                    .map(|p| p.q)
            }

            /// Every assembly at the drivers of `start`, lazily: for each
            /// combination of modes, in the order of
            #[doc = concat!("[`", stringify!(#modes), "::all`],")]
            /// the modes and the assembly in them (as
            /// [`Self::assemble_in`], the Newton blocks from the same
            /// guess). Nothing is assembled until asked for; `nth` skips
            /// combinations without assembling them.
            pub fn assemble_all(
                &self,
                start: &#coords,
            ) -> #pp::closed::Assemblies<#modes, impl FnMut(&#modes) -> #pp::Result<#coords, #pp::Error> + '_> {
                let start = *start;
                #pp::closed::Assemblies::new(move |m: &#modes| self.assemble_in(&start, m))
            }
        }
    } else {
        quote! {
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
                self.__assemble_closed(&start, &#pp::Options::DEFAULT, &scaling, &mut signs, #fresh, &self.__param_trig(), #fresh_dtrig, true)
                    .map(|p| p.q)
            }

            /// Every assembly at the drivers `drivers`, lazily: for each
            /// combination of modes, in the order of
            #[doc = concat!("[`", stringify!(#modes), "::all`],")]
            /// the modes and the assembly in them (as
            /// [`Self::assemble_in`]). Nothing is assembled until asked
            /// for; `nth` skips combinations without assembling them.
            pub fn assemble_all(
                &self,
                drivers: impl #pp::DriverValues<#nd>,
            ) -> #pp::closed::Assemblies<#modes, impl FnMut(&#modes) -> #pp::Result<#coords, #pp::Error> + '_> {
                let d = drivers.into_array();
                #pp::closed::Assemblies::new(move |m: &#modes| self.assemble_in(d, m))
            }
        }
    };
    quote! {
        /// A step in closed form: the blocks solved in order in the modes
        /// `modes` (±1; NaN: from the guess in `start`, then stored), each
        /// unknown angle from the previous solution in `angles` (see
        /// `closed::near_carried`) and each driver's sine and cosine from
        /// the previous step's in `__dtrig` (`closed::carried_sin_cos`), the
        /// residual checked, the motion analysed. Falls back to
        /// Newton–Raphson (resetting `modes`) where a block is degenerate
        /// or the residual is not at round-off.
        #[doc(hidden)]
        #inline_core
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
            __dtrig: &mut [[f64; 3]; #ndt],
        ) -> #pp::Result<#motion, #pp::Error> {
            let [#(#pt_names),*] = *__pt;
            let [#(#qd_drivers),*] = rates.into_array();
            let [#(#qdd_drivers),*] = accelerations.into_array();
            #step_far
            #inputs
            let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
            #(#dtrig_lets)*
            #step_solve
            #phi_lets
            #step_check
            #tail
        }

        /// An assembly in closed form: as `__step_closed`, positions only
        /// (the unknown angles and the drivers' sines and cosines carried
        /// in `angles` and `__dtrig` as there; all NaN: computed afresh),
        /// with the conditioning and branch checks at the solution;
        /// `strict` where the modes were asked for (then a Newton block
        /// that does not converge is an error, not a hand-over to
        /// Newton–Raphson on the whole system).
        #[doc(hidden)]
        #inline_core
        #allow
        fn __assemble_closed(
            &self,
            start: &#coords,
            options: &#pp::Options,
            __scaling: &#pp::Scaling<#ne>,
            modes: &mut [f64; #nm],
            angles: &mut [[f64; 3]; #na],
            __pt: &[f64; #npt],
            __dtrig: &mut [[f64; 3]; #ndt],
            strict: bool,
        ) -> #pp::Result<#pose_t, #pp::Error> {
            let [#(#pt_names),*] = *__pt;
            #asm_far
            #asm_inputs
            let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
            #(#dtrig_lets)*
            #asm_solve
            #asm_phi_lets
            #asm_check
            #asm_jac_lets
            let jac: [f64; #nnz] = #asm_jac;
            #pose_ok
        }

        #param_trig

        #seeded

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
            dtrig: &mut [[f64; 3]; #ndt],
        ) -> #pp::Result<#motion, #pp::Error> {
            for mut m in #pp::closed::other_modes(*modes) {
                let r = self.__step_closed(start, rates, accelerations, options, scaling, &mut m, angles, pt, dtrig);
                if r.is_ok() {
                    *modes = m;
                    return r;
                }
            }
            ::core::result::Result::Err(first)
        }

        /// `__step_other_branch` for `__assemble_closed` (from values
        /// computed afresh).
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
        ) -> #pp::Result<#pose_t, #pp::Error> {
            for mut m in #pp::closed::other_modes(*modes) {
                let r = self.__assemble_closed(start, options, scaling, &mut m, #fresh, pt, #fresh_dtrig, false);
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

        #assemble_in

        #newton_blocks
    }
}
