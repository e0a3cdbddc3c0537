//! `analyze` and `analyze_with`: velocities and accelerations at an
//! assembled pose, Φ_u u' = −Φ_d d' and Φ_u u'' = −Φ_d d'' − γ, then every
//! point's and frame's motion.

use proc_macro2::TokenStream;
use quote::quote;

use super::print::bind;
use super::{guards, Ctx};
use crate::cse::schedule;

/// The analysis methods.
pub(super) fn analyze(cx: &Ctx<'_>) -> TokenStream {
    let (g, pp, allow) = (cx.g(), &cx.pp, &cx.allow);
    let inline_core = cx.inline_core();
    let nd = cx.nd;
    let id = &cx.id;
    let (coords, motion, coord) = (&id.coords, &id.motion, &id.coord);
    let q = &id.q;
    let (qd_drivers, qdd_drivers) = (&id.qd[..nd], &id.qdd[..nd]);
    let leaf = cx.leaf();
    // Φ with the velocity stage, whose sines and cosines it shares.
    let mut stages = cx.analysis_stages();
    stages[0].extend(cx.d.phi.iter().copied());
    let sched = schedule(g, &stages);
    let (pr, lets) = bind(g, &sched, &leaf);
    let phi: Vec<_> = cx.d.phi.iter().map(|&i| pr.element(i)).collect();
    let tail = cx.analysis_tail(
        &pr,
        [&lets[0], &lets[1], &lets[2]],
        &quote!(*pose),
        &quote!(#pp::closed::max_abs(&[#(#phi),*])),
    );
    let inputs = guards::inputs(cx, "pose", true);
    let scaling = cx.scaling();
    quote! {
        /// Velocities and accelerations at an assembled `pose`, for driver
        /// rates d' and accelerations d'' (a bare `f64` for one driver,
        /// else an array in declaration order). Solves
        /// Φ_u u' = −Φ_d d' and Φ_u u'' = −Φ_d d'' − γ, γ = (Φ_q q')_q q',
        /// then each point's v = r_q q' and a = r_q q'' + (r_q q')_q q'.
        ///
        /// # Errors
        /// Non-finite inputs or results, or a singular Jacobian (a
        /// dead-centre or toggle position).
        pub fn analyze(
            &self,
            pose: &#coords,
            rates: impl #pp::DriverValues<#nd>,
            accelerations: impl #pp::DriverValues<#nd>,
        ) -> #pp::Result<#motion, #pp::Error> {
            self.__analyze(pose, rates, accelerations, &#pp::Options::DEFAULT)
        }

        /// [`Self::analyze`] with explicit solver options.
        ///
        /// # Errors
        /// As [`Self::analyze`], and invalid options.
        pub fn analyze_with(
            &self,
            pose: &#coords,
            rates: impl #pp::DriverValues<#nd>,
            accelerations: impl #pp::DriverValues<#nd>,
            options: &#pp::Options,
        ) -> #pp::Result<#motion, #pp::Error> {
            self.__analyze(pose, rates, accelerations, options)
        }

        /// The body of [`Self::analyze`] and [`Self::analyze_with`]: inlined
        /// into each, so that with the default options their checks fold
        /// away at compile time.
        #[doc(hidden)]
        #inline_core
        #allow
        fn __analyze(
            &self,
            pose: &#coords,
            rates: impl #pp::DriverValues<#nd>,
            accelerations: impl #pp::DriverValues<#nd>,
            options: &#pp::Options,
        ) -> #pp::Result<#motion, #pp::Error> {
            options.validate()?;
            self.validate()?;
            let [#(#qd_drivers),*] = rates.into_array();
            let [#(#qdd_drivers),*] = accelerations.into_array();
            #inputs
            #( let #q = pose.#coord; )*
            #scaling
            #tail
        }
    }
}
