//! The `Mechanism` impl: the generated methods behind the trait, for code
//! generic over mechanisms.

use proc_macro2::TokenStream;
use quote::quote;
use syn::ext::IdentExt;

use super::Ctx;
use crate::lower::CoordKind;

/// The `Mechanism` impl.
pub(super) fn mechanism_impl(cx: &Ctx<'_>, equations_of_motion: TokenStream) -> TokenStream {
    let pp = &cx.pp;
    let (nd, nu, ne, np, nf) = (cx.nd, cx.nu, cx.ne, cx.np, cx.nf);
    let point_dim = cx.model.point_dim;
    let id = &cx.id;
    let (name, coords, motion, coord) = (&id.name, &id.coords, &id.motion, &id.coord);
    let state = quote::format_ident!("{}StepState", name.unraw());
    let positions = quote::format_ident!("{}Positions", name.unraw());
    let pose_t = cx.pose_type();
    let (c_drivers, c_unknowns) = coord.split_at(nd);
    let coord_names: Vec<String> = coord.iter().map(|c| c.unraw().to_string()).collect();
    let eq_names: Vec<&str> = cx.model.equations.iter().map(|e| e.text.as_str()).collect();
    let point_names: Vec<String> = cx
        .def
        .points
        .iter()
        .map(|p| p.name.unraw().to_string())
        .collect();
    let frame_names: Vec<String> = cx
        .def
        .frames
        .iter()
        .map(|f| f.name.unraw().to_string())
        .collect();
    let coordinate_info = cx.model.kinds.iter().enumerate().map(|(j, k)| {
        let n = &coord_names[j];
        let role = if j < nd {
            quote!(Driver)
        } else {
            quote!(Unknown)
        };
        let kind = match k {
            CoordKind::Angle => quote!(Angle),
            CoordKind::Length => quote!(Length),
        };
        quote!(#pp::Coordinate { name: #n, role: #pp::Role::#role, kind: #pp::Kind::#kind })
    });
    // Newton–Raphson starts from the guess unless every block has a
    // closed form.
    let newton_guess = !cx.closed_path() || cx.mixed();
    quote! {
        #[automatically_derived]
        impl #pp::Mechanism for #name {
            type Coords = #coords;
            type Motion = #motion;
            type StepState = #state;
            type Positions = #positions;
            const DRIVERS: usize = #nd;
            const UNKNOWNS: usize = #nu;
            const EQUATIONS: usize = #ne;
            const POINTS: usize = #np;
            const POINT_DIM: usize = #point_dim;
            const FRAMES: usize = #nf;
            const COORDINATES: &'static [#pp::Coordinate] = &[#(#coordinate_info),*];
            const POINT_NAMES: &'static [&'static str] = &[#(#point_names),*];
            const FRAME_NAMES: &'static [&'static str] = &[#(#frame_names),*];
            const EQUATION_NAMES: &'static [&'static str] = &[#(#eq_names),*];
            const NEWTON_GUESS: bool = #newton_guess;

            #equations_of_motion

            fn assemble_with(&self, start: &#coords, options: &#pp::Options) -> #pp::Result<#coords, #pp::Error> {
                #name::assemble_with(self, start, options)
            }

            fn analyze_slices(
                &self,
                pose: &#coords,
                rates: &[f64],
                accelerations: &[f64],
                options: &#pp::Options,
            ) -> #pp::Result<#motion, #pp::Error> {
                let rates: [f64; #nd] = match <[f64; #nd]>::try_from(rates) {
                    ::core::result::Result::Ok(r) => r,
                    ::core::result::Result::Err(_) => return ::core::result::Result::Err(#pp::Error::InvalidOption {
                        name: "rates",
                        value: rates.len() as f64,
                        requirement: "must have one value per driver",
                    }),
                };
                let accelerations: [f64; #nd] = match <[f64; #nd]>::try_from(accelerations) {
                    ::core::result::Result::Ok(r) => r,
                    ::core::result::Result::Err(_) => return ::core::result::Result::Err(#pp::Error::InvalidOption {
                        name: "accelerations",
                        value: accelerations.len() as f64,
                        requirement: "must have one value per driver",
                    }),
                };
                #name::analyze_with(self, pose, rates, accelerations, options)
            }

            fn step_slices(
                &self,
                start: &#coords,
                rates: &[f64],
                accelerations: &[f64],
                options: &#pp::Options,
            ) -> #pp::Result<#motion, #pp::Error> {
                let (r, a) = #pp::driver_arrays::<#nd>(rates, accelerations)?;
                #name::step_with(self, start, r, a, options)
            }

            fn step_state(&self, options: &#pp::Options) -> #pp::Result<#state, #pp::Error> {
                self.__step_state(options)
            }

            fn step_modes(state: &mut #state) -> &mut [f64] {
                &mut state.modes
            }

            #[inline]
            fn step_carried(
                &self,
                start: &#coords,
                rates: &#coords,
                accelerations: &#coords,
                state: &mut #state,
            ) -> #pp::Result<#motion, #pp::Error> {
                state.__step(self, start, rates, accelerations)
            }

            #[inline]
            fn pose_carried(
                &self,
                start: &#coords,
                state: &mut #state,
            ) -> #pp::Result<#pose_t, #pp::Error> {
                state.__pose(self, start)
            }

            fn residual_into(&self, pose: &#coords, out: &mut [f64]) {
                let r = #name::residual(self, pose);
                for (o, v) in out.iter_mut().zip(r.iter()) {
                    *o = *v;
                }
            }

            fn jacobian_into(&self, pose: &#coords, out: &mut [f64]) {
                for o in out.iter_mut() {
                    *o = 0.0;
                }
                self.__jacobian_into(&[#(pose.#c_drivers),*], &[#(pose.#c_unknowns),*], out);
            }

            fn point_positions_into(&self, pose: &#coords, out: &mut [f64]) {
                let r = #name::point_positions(self, pose);
                for (o, v) in out.iter_mut().zip(r.iter().flat_map(|p| p.iter())) {
                    *o = *v;
                }
            }

            fn frame_rotations_into(&self, pose: &#coords, out: &mut [#pp::Matrix3<f64>]) {
                let r = #name::frame_rotations(self, pose);
                for (o, v) in out.iter_mut().zip(r.iter()) {
                    *o = *v;
                }
            }
        }
    }
}
