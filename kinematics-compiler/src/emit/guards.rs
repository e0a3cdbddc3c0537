//! Input and output guards of the generated code: every input checked for
//! NaN and infinity (one sum in the common case, the named checks only when
//! it fails), declared lengths checked for sign, outputs checked before
//! they are returned.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;
use syn::Ident;

use super::Ctx;

/// `checks`, a list of `finite(…)?;` statements over `values`, run only when
/// the fast test fails: the sum of the values is finite. A NaN or an infinity
/// among them makes the sum NaN or infinite, so the common case costs one add
/// per value and one branch, and the error still names the offending value.
/// (Finite values whose sum overflows only send it to the named checks, which
/// then pass.)
pub(super) fn guarded(values: &[TokenStream], checks: &TokenStream) -> TokenStream {
    if values.is_empty() {
        return TokenStream::new();
    }
    let sum = super::print::chain(values, &quote!(+));
    quote! {
        if !(#sum).is_finite() {
            #checks
        }
    }
}

/// The `validate` method: every parameter finite, every declared length
/// and every distance of a `norm(v) == b` constraint positive.
pub(super) fn validate(cx: &Ctx<'_>) -> TokenStream {
    let (pp, params) = (&cx.pp, &cx.id.params);
    let param_names: Vec<String> = params.iter().map(|c| c.unraw().to_string()).collect();
    let lengths: Vec<&Ident> = cx
        .def
        .params
        .iter()
        .filter(|p| p.length)
        .map(|p| &p.name)
        .collect();
    let length_names: Vec<String> = lengths.iter().map(|c| c.unraw().to_string()).collect();
    // Distances of `norm(v) == b` constraints not already declared lengths.
    let (distances, distance_names): (Vec<&Ident>, Vec<String>) = cx
        .model
        .distances
        .iter()
        .filter_map(|(k, _)| cx.def.params.get(*k as usize))
        .filter(|p| !p.length)
        .map(|p| (&p.name, p.name.unraw().to_string()))
        .unzip();
    let finite = guarded(
        &params.iter().map(|p| quote!(self.#p)).collect::<Vec<_>>(),
        &quote!(#( #pp::finite(#pp::Input::Parameter, #param_names, self.#params)?; )*),
    );
    quote! {
        /// Checks that every parameter is finite, and that every
        /// parameter declared a length, or the distance b of a
        /// constraint `norm(v) == b`, is positive.
        ///
        /// # Errors
        /// [`Error::NonFinite`](::kinematics_core::Error::NonFinite) or
        /// [`Error::InvalidParameter`](::kinematics_core::Error::InvalidParameter)
        /// naming the parameter.
        #[inline]
        pub fn validate(&self) -> #pp::Result<(), #pp::Error> {
            #finite
            #( #pp::positive(#length_names, self.#lengths)?; )*
            #( #pp::positive_distance(#distance_names, self.#distances)?; )*
            ::core::result::Result::Ok(())
        }
    }
}

/// The checks of the coordinates of `source` (`start` or `pose`), and with
/// `rates` the driver rates and accelerations `qd_…`, `qdd_…`.
pub(super) fn inputs(cx: &Ctx<'_>, source: &str, rates: bool) -> TokenStream {
    let pp = &cx.pp;
    let source = format_ident!("{}", source);
    let (c_drivers, c_unknowns) = cx.id.coord.split_at(cx.nd);
    let qd_drivers = if rates { &cx.id.qd[..cx.nd] } else { &[][..] };
    let qdd_drivers = if rates { &cx.id.qdd[..cx.nd] } else { &[][..] };
    let driver_names: Vec<String> = c_drivers.iter().map(|c| c.unraw().to_string()).collect();
    let unknown_names: Vec<String> = c_unknowns.iter().map(|c| c.unraw().to_string()).collect();
    let values: Vec<TokenStream> = c_drivers
        .iter()
        .chain(c_unknowns)
        .map(|c| quote!(#source.#c))
        .chain(qd_drivers.iter().chain(qdd_drivers).map(|v| quote!(#v)))
        .collect();
    let rate_names = if rates { &driver_names[..] } else { &[][..] };
    guarded(
        &values,
        &quote! {
            #( #pp::finite(#pp::Input::Driver, #driver_names, #source.#c_drivers)?; )*
            #( #pp::finite(#pp::Input::Guess, #unknown_names, #source.#c_unknowns)?; )*
            #( #pp::finite(#pp::Input::DriverRate, #rate_names, #qd_drivers)?; )*
            #( #pp::finite(#pp::Input::DriverAcceleration, #rate_names, #qdd_drivers)?; )*
        },
    )
}

/// The check of the solved rates and accelerations `qd_…`, `qdd_…` of the
/// unknowns.
pub(super) fn solved_rates(cx: &Ctx<'_>) -> TokenStream {
    let pp = &cx.pp;
    let c_unknowns = &cx.id.coord[cx.nd..];
    let (qd_unknowns, qdd_unknowns) = (&cx.id.qd[cx.nd..], &cx.id.qdd[cx.nd..]);
    let names: Vec<String> = c_unknowns.iter().map(|c| c.unraw().to_string()).collect();
    let values: Vec<TokenStream> = qd_unknowns
        .iter()
        .chain(qdd_unknowns)
        .map(|v| quote!(#v))
        .collect();
    guarded(
        &values,
        &quote! {
            #( #pp::finite(#pp::Input::Computed, #names, #qd_unknowns)?; )*
            #( #pp::finite(#pp::Input::Computed, #names, #qdd_unknowns)?; )*
        },
    )
}

/// The check that every output is finite, from the expressions `terms` of
/// every point's and frame's components (summed: one test on the hot
/// path); where one is not, `points` and `frames` (the arrays of the
/// motion) are built to name it.
pub(super) fn outputs(
    cx: &Ctx<'_>,
    terms: &[TokenStream],
    points: &[TokenStream],
    frames: &[TokenStream],
) -> TokenStream {
    let pp = &cx.pp;
    if terms.is_empty() {
        return TokenStream::new();
    }
    let (dim, np, nf) = (cx.model.point_dim, cx.np, cx.nf);
    let sum = super::print::chain(terms, &quote!(+));
    quote! {
        if !(#sum).is_finite() {
            let points: [#pp::PointMotion<#dim>; #np] = [#(#points),*];
            let frames: [#pp::FrameState; #nf] = [#(#frames),*];
            #pp::finite_outputs(
                &points,
                <Self as #pp::Mechanism>::POINT_NAMES,
                &frames,
                <Self as #pp::Mechanism>::FRAME_NAMES,
            )?;
        }
    }
}
