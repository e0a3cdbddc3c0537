//! `assemble` and `assemble_with`: the closed-form blocks in the modes of
//! the guess, the others (or the whole system) by Newton–Raphson from the
//! guess, its common path inline (`__pose_core`), the general damped solver
//! off it.

use proc_macro2::TokenStream;
use quote::quote;

use super::newton::unknown_trig;
use super::{guards, Ctx};

/// The assembly methods.
pub(super) fn assemble(cx: &Ctx<'_>) -> TokenStream {
    let (nd, ne, pp) = (cx.nd, cx.ne, &cx.pp);
    let id = &cx.id;
    let (coords, coord) = (&id.coords, &id.coord);
    let c_drivers = &coord[..nd];
    let nt = unknown_trig(cx.g(), &cx.newton_roots(), cx.model.drivers).len();
    let inputs = guards::inputs(cx, "start", false);
    let pose_t = cx.pose_type();
    // Newton–Raphson on the whole system, its common path inline.
    let newton = quote! {
        let mut carry = [[0.0f64, 0.0f64, ::core::primitive::f64::NAN]; #nt];
        self.__pose_core(start, options, &__scaling, &mut carry, true)
    };
    let (body, off_path) = if cx.closed_path() {
        // The closed-form blocks each in the mode of the guess, the others
        // by Newton on the block; Newton on the whole system off that path.
        let (nm, ndt) = (cx.nm(), cx.driver_trig().len());
        let body = quote! {
            let mut modes = [::core::primitive::f64::NAN; #nm];
            let mut angles = Self::__seeded(start);
            let mut dtrig = [[::core::primitive::f64::NAN; 3]; #ndt];
            let pt = self.__param_trig();
            let pose = match self.__assemble_closed(start, options, &__scaling, &mut modes, &mut angles, &pt, &mut dtrig, false) {
                ::core::result::Result::Err(e @ #pp::Error::WrongBranch { .. }) => {
                    self.__assemble_other_branch(e, start, options, &__scaling, &mut modes, &pt)
                }
                r => r,
            };
            pose.map(|p| p.q)
        };
        let off_path = quote! {
            /// Newton–Raphson from `start`, off the closed-form path.
            #[doc(hidden)]
            #[cold]
            #[inline(never)]
            fn __assemble_newton(
                &self,
                start: &#coords,
                options: &#pp::Options,
                __scaling: &#pp::Scaling<#ne>,
            ) -> #pp::Result<#pose_t, #pp::Error> {
                let mut carry = [[0.0f64, 0.0f64, ::core::primitive::f64::NAN]; #nt];
                self.__pose_core(start, options, __scaling, &mut carry, true)
            }
        };
        (body, off_path)
    } else {
        (quote!({ #newton }.map(|p| p.q)), TokenStream::new())
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
            let __scaling = self.__scaling(&[#(start.#c_drivers),*])?;
            #body
        }

        #off_path
    }
}
