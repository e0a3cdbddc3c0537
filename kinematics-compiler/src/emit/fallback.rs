//! The expansion of a definition with errors: its types and stubs of every
//! generated item, beside the `compile_error!`s, so that uses of the
//! mechanism elsewhere add no knock-on errors.

use proc_macro2::TokenStream;
use quote::quote;
use syn::ext::IdentExt;

use super::types::{types, Idents};
use crate::names::accessor_name;
use crate::parse::Definition;

/// Fallback expansion for a definition with errors: the types and stub
/// methods, so the user sees the definition's errors and not knock-on errors
/// at every use of the mechanism.
pub fn fallback(def: &Definition, errors: TokenStream) -> TokenStream {
    // Keep only the first declaration of each name, so that a duplicated
    // name is reported once, by the macro, and not again as a duplicate field.
    let mut def = def.clone();
    let mut seen = std::collections::HashSet::new();
    def.params
        .retain(|d| seen.insert(d.name.unraw().to_string()));
    let mut seen = std::collections::HashSet::new();
    def.drivers
        .retain(|d| seen.insert(d.name.unraw().to_string()));
    def.unknowns
        .retain(|d| seen.insert(d.name.unraw().to_string()));
    let mut seen = std::collections::HashSet::new();
    def.points.retain(|p| seen.insert(accessor_name(&p.name)));
    let def = &def;
    let id = Idents::new(def);
    // The dimension is unknown when lowering failed; guess it from the
    // spelling so that uses of the stub types add no knock-on errors.
    let spatial = def.points.iter().any(|p| {
        let t = quote::ToTokens::to_token_stream(&p.expr).to_string();
        [
            "vec3",
            "rot",
            "t1",
            "t2",
            "t3",
            "t4",
            "t5",
            "t6",
            "t7",
            "screw",
            "translation",
            "spherical",
        ]
        .iter()
        .any(|w| t.contains(w))
    });
    let point_dim: usize = if spatial { 3 } else { 2 };
    let types = types(def, &id, None, point_dim);
    let Idents {
        name,
        coords,
        motion,
        stepper,
        ..
    } = &id;
    let vis = &def.vis;
    let state = quote::format_ident!("{}StepState", syn::ext::IdentExt::unraw(name));
    let positions = quote::format_ident!("{}Positions", syn::ext::IdentExt::unraw(name));
    let pp = quote!(::kinematics_core::__private);
    let (nd, nu, np, nf) = (
        def.drivers.len(),
        def.unknowns.len(),
        def.points.len(),
        def.frames.len(),
    );
    let vtype = if spatial {
        quote!(#pp::Vector3<f64>)
    } else {
        quote!(#pp::Vector2<f64>)
    };
    let unavailable = quote!(::core::unreachable!("the mechanism definition has errors"));
    let param_names: Vec<String> = def
        .params
        .iter()
        .map(|p| syn::ext::IdentExt::unraw(&p.name).to_string())
        .collect();
    let npar = param_names.len();
    quote! {
        #errors
        #types
        #[allow(unused_variables, clippy::unused_self, dead_code, clippy::missing_errors_doc, clippy::missing_panics_doc)]
        impl #name {
            /// Number of drivers.
            pub const DRIVERS: usize = #nd;
            /// Number of unknowns.
            pub const UNKNOWNS: usize = #nu;
            /// Number of scalar equations.
            pub const EQUATIONS: usize = #nu;
            /// Number of points.
            pub const POINTS: usize = #np;
            /// Number of frames.
            pub const FRAMES: usize = #nf;
            /// The parameters' names.
            pub const PARAMETERS: [&'static str; #npar] = [#(#param_names),*];
            /// Unavailable: the definition has errors.
            pub fn parameter_values(&self) -> [f64; #npar] { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn validate(&self) -> #pp::Result<(), #pp::Error> { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn assemble(&self, start: &#coords) -> #pp::Result<#coords, #pp::Error> { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn assemble_with(&self, start: &#coords, options: &#pp::Options) -> #pp::Result<#coords, #pp::Error> { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn step(&self, start: &#coords, rates: impl #pp::DriverValues<#nd>, accelerations: impl #pp::DriverValues<#nd>) -> #pp::Result<#motion, #pp::Error> { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn step_with(&self, start: &#coords, rates: impl #pp::DriverValues<#nd>, accelerations: impl #pp::DriverValues<#nd>, options: &#pp::Options) -> #pp::Result<#motion, #pp::Error> { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn analyze(&self, pose: &#coords, rates: impl #pp::DriverValues<#nd>, accelerations: impl #pp::DriverValues<#nd>) -> #pp::Result<#motion, #pp::Error> { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn analyze_with(&self, pose: &#coords, rates: impl #pp::DriverValues<#nd>, accelerations: impl #pp::DriverValues<#nd>, options: &#pp::Options) -> #pp::Result<#motion, #pp::Error> { #unavailable }
            /// Unavailable: the definition has errors.
            #[must_use]
            pub fn residual(&self, pose: &#coords) -> [f64; #nu] { #unavailable }
            /// Unavailable: the definition has errors.
            #[must_use]
            pub fn point_positions(&self, pose: &#coords) -> [#vtype; #np] { #unavailable }
            /// Unavailable: the definition has errors.
            #[must_use]
            pub fn positions(&self, pose: &#coords) -> #positions { #unavailable }
            /// Unavailable: the definition has errors.
            #[must_use]
            pub fn frame_rotations(&self, pose: &#coords) -> [#pp::Matrix3<f64>; #nf] { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn stepper(&self, options: &#pp::Options) -> #pp::Result<#stepper<'_>, #pp::Error> { #unavailable }
        }
        /// Unavailable: the definition has errors.
        #vis struct #stepper<'m>(&'m #name);
        /// Unavailable: the definition has errors.
        #[derive(Debug, Clone)]
        #vis struct #state;
        #[allow(unused_variables, clippy::unused_self, dead_code, clippy::missing_errors_doc)]
        impl #stepper<'_> {
            /// Unavailable: the definition has errors.
            pub fn step(&mut self, start: &#coords, rates: impl #pp::DriverValues<#nd>, accelerations: impl #pp::DriverValues<#nd>) -> #pp::Result<#motion, #pp::Error> { #unavailable }
            /// Unavailable: the definition has errors.
            pub fn pose(&mut self, start: &#coords) -> #pp::Result<#pp::Pose<#coords, #positions>, #pp::Error> { #unavailable }
        }
        #[automatically_derived]
        #[allow(unused_variables)]
        impl #pp::Mechanism for #name {
            type Coords = #coords;
            type Motion = #motion;
            type StepState = #state;
            type Positions = #positions;
            const DRIVERS: usize = #nd;
            const UNKNOWNS: usize = #nu;
            const EQUATIONS: usize = #nu;
            const POINTS: usize = #np;
            const POINT_DIM: usize = #point_dim;
            const FRAMES: usize = #nf;
            const COORDINATES: &'static [#pp::Coordinate] = &[];
            const POINT_NAMES: &'static [&'static str] = &[];
            const FRAME_NAMES: &'static [&'static str] = &[];
            const EQUATION_NAMES: &'static [&'static str] = &[];
            fn assemble_with(&self, start: &#coords, options: &#pp::Options) -> #pp::Result<#coords, #pp::Error> { #unavailable }
            fn analyze_slices(&self, pose: &#coords, rates: &[f64], accelerations: &[f64], options: &#pp::Options) -> #pp::Result<#motion, #pp::Error> { #unavailable }
            fn step_slices(&self, start: &#coords, rates: &[f64], accelerations: &[f64], options: &#pp::Options) -> #pp::Result<#motion, #pp::Error> { #unavailable }
            fn step_state(&self, options: &#pp::Options) -> #pp::Result<#state, #pp::Error> { #unavailable }
            fn step_modes(state: &mut #state) -> &mut [f64] { #unavailable }
            fn step_carried(&self, start: &#coords, rates: &#coords, accelerations: &#coords, state: &mut #state) -> #pp::Result<#motion, #pp::Error> { #unavailable }
            fn pose_carried(&self, start: &#coords, state: &mut #state) -> #pp::Result<#pp::Pose<#coords, #positions>, #pp::Error> { #unavailable }
            fn residual_into(&self, pose: &#coords, out: &mut [f64]) { #unavailable }
            fn jacobian_into(&self, pose: &#coords, out: &mut [f64]) { #unavailable }
            fn point_positions_into(&self, pose: &#coords, out: &mut [f64]) { #unavailable }
            fn frame_rotations_into(&self, pose: &#coords, out: &mut [#pp::Matrix3<f64>]) { #unavailable }
        }
    }
}
