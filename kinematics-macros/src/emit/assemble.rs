//! `assemble` and `assemble_with`: Newton–Raphson on Φ(d, u) = 0 from a
//! guess, by the general damped solver, with the driver-only part of Φ and
//! Φ_u evaluated once.

use proc_macro2::TokenStream;
use quote::quote;

use super::newton::driver_frontier;
use super::print::bind;
use super::{guards, Ctx};
use crate::cse::schedule;

/// The assembly methods.
pub(super) fn assemble(cx: &Ctx<'_>) -> TokenStream {
    let (g, d, pp) = (cx.g(), cx.d, &cx.pp);
    let (nd, ne, nnz) = (cx.nd, cx.ne, cx.blocks.nnz());
    let id = &cx.id;
    let (coords, coord, q) = (&id.coords, &id.coord, &id.q);
    let (q_drivers, q_unknowns) = q.split_at(nd);
    let (c_drivers, c_unknowns) = coord.split_at(nd);
    let leaf = cx.leaf();
    let newton_roots = cx.newton_roots();
    let sched = schedule(
        g,
        &[
            driver_frontier(g, &newton_roots, cx.model.drivers),
            newton_roots,
        ],
    );
    let (pr, lets) = bind(g, &sched, &leaf);
    let (hoisted, iterated) = (&lets[0], &lets[1]);
    let phi: Vec<_> = d.phi.iter().map(|&i| pr.element(i)).collect();
    let jac = cx.jac_array(&pr);
    let inputs = guards::inputs(cx, "start", false);
    let scaling = cx.scaling();
    let solver = cx.solver();
    let at_solution = cx.factor_at_solution();
    let newton = quote! {
            #scaling
            #hoisted
            let mut u = [#(start.#c_unknowns),*];
            let mut phi = [0.0f64; #ne];
            let mut jac = [0.0f64; #nnz];
            let solved = #pp::newton(&mut u, &mut phi, &mut jac, &__scaling, options, |u, phi, jac| {
                let [#(#q_unknowns),*] = *u;
                #iterated
                *phi = [#(#phi),*];
                *jac = #jac;
            }, #solver);
            let [#(#q_unknowns),*] = u;
            if let ::core::result::Result::Err(f) = solved {
                return ::core::result::Result::Err(#pp::describe(f, &Self::__NAMES, &[#(#q),*]));
            }
            // The singularity and the branch are judged at the solution.
            #at_solution
            let _ = (__conditioning, __det_sign);
            ::core::result::Result::Ok(#coords { #( #coord: #q ),* })
    };
    let (body, off_path) = if cx.closed_path() {
        // The closed-form blocks each in the mode of the guess, the others
        // by Newton on the block; Newton on the whole system off that path.
        let nm = cx.nm();
        let body = quote! {
            let __scaling = self.__scaling(&[#(#q_drivers),*])?;
            let mut modes = [::core::primitive::f64::NAN; #nm];
            let pt = self.__param_trig();
            match self.__assemble_closed(start, options, &__scaling, &mut modes, &pt, false) {
                ::core::result::Result::Err(e @ #pp::Error::WrongBranch { .. }) => {
                    self.__assemble_other_branch(e, start, options, &__scaling, &mut modes, &pt)
                }
                r => r,
            }
        };
        let off_path = quote! {
            /// Newton–Raphson from `start`, off the closed-form path.
            #[doc(hidden)]
            #[cold]
            #[inline(never)]
            fn __assemble_newton(&self, start: &#coords, options: &#pp::Options) -> #pp::Result<#coords, #pp::Error> {
                let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
                #newton
            }
        };
        (body, off_path)
    } else {
        (newton, TokenStream::new())
    };
    quote! {
        /// Assembles the mechanism: solves the loop-closure equations
        /// Φ(d, u) = 0 for the unknowns u, with the drivers d and a guess
        /// of u taken from `start`. Each block of the equations with a
        /// closed form ([`Self::BLOCKS`]) is solved exactly in the
        /// assembly mode the guess lies in, each other block by
        /// Newton–Raphson on that block from the guess; a mechanism
        /// without closed-form blocks by Newton–Raphson on the whole
        /// system from the guess, which finds the assembly branch nearest
        /// it.
        ///
        /// # Errors
        /// Non-finite parameters or start values, a singular Jacobian, or
        /// no convergence; each names the item involved.
        pub fn assemble(&self, start: &#coords) -> #pp::Result<#coords, #pp::Error> {
            self.assemble_with(start, &#pp::Options::DEFAULT)
        }

        /// [`Self::assemble`] with explicit solver options.
        ///
        /// # Errors
        /// As [`Self::assemble`], and invalid options.
        pub fn assemble_with(&self, start: &#coords, options: &#pp::Options) -> #pp::Result<#coords, #pp::Error> {
            options.validate()?;
            self.validate()?;
            #inputs
            let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
            #body
        }

        #off_path
    }
}
