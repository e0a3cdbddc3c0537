//! The `bodies`, `loads` and (item form) `joints` sections as Rust:
//! `dynamics_builder`, the sections with one parameter set's values as a
//! `kinematics_core::dynamics::DynamicsBuilder` (the constants evaluated
//! once, each load a closure of the instant, each joint with its axis),
//! and `dynamics`, the builder resolved against the mechanism. Nothing is
//! emitted for a definition without the sections.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::print::bind;
use super::Ctx;
use crate::cse::schedule;
use crate::dynamics::{Dynamics, JointKind, LoadTarget, Turning};
use crate::ir::{Id, Leaf};
use crate::motion::EquationsOfMotion;

/// The two methods, or nothing without the sections.
pub(super) fn dynamics(cx: &Ctx<'_>, dynamics: Option<&Dynamics>) -> TokenStream {
    let Some(dy) = dynamics else {
        return TokenStream::new();
    };
    let (g, pp, allow) = (cx.g(), &cx.pp, &cx.allow);
    let name = &cx.id.name;
    let dm = quote!(::kinematics_core::dynamics);
    let npar = cx.id.params.len();
    // The parameters from `values`, the coordinates and rates from the
    // instant a load is evaluated at.
    let leaf = |l: Leaf| match l {
        Leaf::Param(i) => {
            let i = Literal::usize_unsuffixed(i as usize);
            quote!(values[#i])
        }
        Leaf::Q(j) => {
            let j = Literal::usize_unsuffixed(j as usize);
            quote!(instant.q(#j))
        }
        Leaf::Qd(j) => {
            let j = Literal::usize_unsuffixed(j as usize);
            quote!(instant.qd(#j))
        }
        Leaf::Qdd(j) => {
            let j = Literal::usize_unsuffixed(j as usize);
            quote!(instant.qdd(#j))
        }
        Leaf::Time => quote!(instant.time()),
    };
    let constants = dy.constants();
    let mut roots = constants.clone();
    if let Some(p) = &dy.partials {
        roots.extend(&p.constants);
    }
    let sched = schedule(g, std::slice::from_ref(&roots));
    let (pr, lets) = bind(g, &sched, &leaf);
    let c = |id: Id| pr.element(id);
    let padded = |v: &[Id]| -> TokenStream {
        let e: Vec<TokenStream> = v.iter().map(|&id| c(id)).collect();
        match e.as_slice() {
            [x, y] => quote!([#x, #y, 0.0]),
            _ => quote!([#(#e),*]),
        }
    };
    let mut calls = Vec::new();
    if !dy.gravity.is_empty() {
        let gv = padded(&dy.gravity);
        calls.push(quote!(.gravity(#gv)));
    }
    for b in &dy.bodies {
        let (bn, center, mass) = (&b.name, &b.center, c(b.mass));
        let mut body = quote!(#dm::Body::new(#bn, #mass).center(#center));
        match &b.turning {
            Turning::No => {}
            Turning::Angle(terms) => {
                let names = terms.iter().map(|(n, _)| n);
                let coefficients = terms.iter().map(|&(_, k)| c(k));
                body.extend(quote!(.angle_sum(&[#((#names, #coefficients)),*])));
            }
            Turning::Frame(f) => body.extend(quote!(.frame(#f))),
        }
        match b.inertia.as_slice() {
            [] => {}
            [j] => {
                let j = c(*j);
                body.extend(quote!(.inertia(#j)));
            }
            rows => {
                let rows = rows.chunks(3).map(|r| {
                    let r = r.iter().map(|&id| c(id));
                    quote!([#(#r),*])
                });
                body.extend(quote!(.inertia_tensor([#(#rows),*])));
            }
        }
        calls.push(quote!(.body(#body)));
    }
    for s in &dy.springs {
        let (from, to) = (&s.from, &s.to);
        let (k, l0, damping) = (c(s.stiffness), c(s.free_length), c(s.damping));
        let mut spring =
            quote!(#dm::Spring::new(#from, #to).stiffness(#k).free_length(#l0).damping(#damping));
        if let Some([first, second]) = &s.between {
            spring.extend(quote!(.between(#first, #second)));
        }
        calls.push(quote!(.spring(#spring)));
    }
    for (index, load) in dy.loads.iter().enumerate() {
        // Each load its own straight line, from the instant.
        let sched = schedule(g, std::slice::from_ref(&load.value));
        let (lp, lets) = bind(g, &sched, &leaf);
        let e: Vec<TokenStream> = load.value.iter().map(|&id| lp.element(id)).collect();
        let vector = match e.as_slice() {
            [x, y] => quote!([#x, #y, 0.0]),
            [z] => quote!([0.0, 0.0, #z]),
            _ => quote!([#(#e),*]),
        };
        let closure = |value: TokenStream, ty: TokenStream| {
            quote! {
                move |instant: &#dm::Instant<'_>| -> #ty {
                    #(#lets)*
                    #value
                }
            }
        };
        let partials = dy
            .partials
            .as_ref()
            .and_then(|p| p.loads.get(index))
            .map(|roots| {
                let sched = schedule(g, std::slice::from_ref(roots));
                let (dp, lets) = bind(g, &sched, &leaf);
                let m = load.value.len().max(1);
                let stores: Vec<TokenStream> = roots
                    .iter()
                    .enumerate()
                    .filter(|(_, &id)| g.as_const(id) != Some(0.0))
                    .map(|(i, &id)| {
                        let (x, slot) = (i / m, load.slot(i % m));
                        let e = dp.element(id);
                        quote!(out[#x][#slot] = #e;)
                    })
                    .collect();
                let n = roots.len() / m;
                quote! {
                    .load_partials(move |instant: &#dm::Instant<'_>, out: &mut [[f64; 3]]| {
                        if out.len() < #n {
                            return;
                        }
                        #(#lets)*
                        #(#stores)*
                    })
                }
            });
        calls.push(match &load.target {
            LoadTarget::Point { point, body: None } => {
                let f = closure(vector, quote!([f64; 3]));
                quote!(.force(#point, #f))
            }
            LoadTarget::Point {
                point,
                body: Some(body),
            } => {
                let f = closure(vector, quote!([f64; 3]));
                quote!(.force_on(#body, #point, #f))
            }
            LoadTarget::Torque { body } => {
                let f = closure(vector, quote!([f64; 3]));
                quote!(.torque(#body, #f))
            }
            LoadTarget::Coordinate { coordinate } => {
                let f = e.first().cloned().unwrap_or_else(|| quote!(0.0));
                let f = closure(f, quote!(f64));
                quote!(.coordinate_force(#coordinate, #f))
            }
        });
        calls.extend(partials);
    }
    if let Some(p) = &dy.partials {
        // The constants' partials, in the builder's layout.
        let names: Vec<String> = p
            .params
            .iter()
            .map(|&k| syn::ext::IdentExt::unraw(&cx.def.params[k as usize].name).to_string())
            .collect();
        let per = constants.len();
        let design: Vec<TokenStream> = if per == 0 {
            Vec::new()
        } else {
            p.constants
                .chunks(per)
                .flat_map(|chunk| dy.design_layout(chunk))
                .map(|x| x.map_or_else(|| quote!(0.0), c))
                .collect()
        };
        calls.push(quote!(.design_parameters(&[#(#names),*], &[#(#design),*])));
        for (frame, roots) in &p.frames {
            let sched = schedule(g, std::slice::from_ref(roots));
            let (fp, lets) = bind(g, &sched, &leaf);
            let stores: Vec<TokenStream> = roots
                .iter()
                .enumerate()
                .filter(|(_, &id)| g.as_const(id) != Some(0.0))
                .map(|(i, &id)| {
                    let (x, c) = (i / 15, i % 15);
                    let e = fp.element(id);
                    quote!(out[#x][#c] = #e;)
                })
                .collect();
            let n = roots.len() / 15;
            calls.push(quote! {
                .frame_partials(#frame, move |instant: &#dm::Instant<'_>, out: &mut [[f64; 15]]| {
                    if out.len() < #n {
                        return;
                    }
                    #(#lets)*
                    #(#stores)*
                })
            });
        }
    }
    for j in &dy.joints {
        let (jn, point, [first, second]) = (&j.name, &j.point, &j.between);
        let axis: Vec<TokenStream> = j.axis.iter().map(|&id| c(id)).collect();
        let mut joint = match j.kind {
            JointKind::Revolute => quote!(#dm::Joint::revolute(#jn, #point, #first, #second)),
            JointKind::Spherical => quote!(#dm::Joint::spherical(#jn, #point, #first, #second)),
            JointKind::Prismatic => {
                quote!(#dm::Joint::prismatic(#jn, #point, #first, #second, [#(#axis),*]))
            }
            JointKind::Cylindrical => {
                quote!(#dm::Joint::cylindrical(#jn, #point, #first, #second, [#(#axis),*]))
            }
        };
        if j.kind == JointKind::Revolute && !axis.is_empty() {
            joint.extend(quote!(.about([#(#axis),*])));
        }
        if let Some(d) = &j.driver {
            joint.extend(quote!(.driven_by(#d)));
        }
        if let Some(q) = &j.coordinate {
            joint.extend(quote!(.coordinate(#q)));
        }
        calls.push(quote!(.joint(#joint)));
    }
    quote! {
        impl #name {
            /// The masses and loads of the definition's `bodies` and
            /// `loads` sections (and the joints of `joints`), with this
            /// parameter set's values: the constants (masses, inertias,
            /// gravity, springs, axes) evaluated here, each load a
            /// function of the instant. Add more joints for the reactions,
            /// then resolve it with `build::<Self>()`, or take
            /// [`Self::dynamics`].
            #[must_use]
            #allow
            pub fn dynamics_builder(&self) -> #dm::DynamicsBuilder {
                let values: [f64; #npar] = self.parameter_values();
                #(#lets)*
                #dm::DynamicsBuilder::new() #(#calls)*
            }

            /// The definition's masses and loads resolved against this
            /// mechanism, ready for `Dynamics::inverse` (the driving
            /// efforts, energies and shaking forces at a motion).
            ///
            /// # Errors
            /// `Error::InvalidDynamics` for a value the parameters make
            /// invalid (a negative or NaN mass, an inertia tensor that is
            /// not symmetric, …).
            pub fn dynamics(&self) -> #pp::Result<#dm::Dynamics, #pp::Error> {
                self.dynamics_builder()
                    .build_sections::<Self>(&self.parameter_values())
            }
        }
    }
}

/// The compiled equations of motion of the sections as items of the
/// mechanism's `Mechanism` implementation
/// (`kinematics_core::Mechanism::equations_of_motion` and its companions),
/// or nothing where they were not formed: one straight-line function of
/// the parameters, q, q̇, q̈ and the time writing Φ_q, M̃'s upper triangle,
/// f̃ and the loads' powers, or M and b and the powers where they are
/// reduced.
pub(super) fn motion(cx: &Ctx<'_>, eom: Option<&EquationsOfMotion>) -> TokenStream {
    let Some(eom) = eom else {
        return TokenStream::new();
    };
    let (g, allow, pp) = (cx.g(), &cx.allow, &cx.pp);
    let npar = cx.id.params.len();
    let coord = &cx.id.coord;
    let field = |j: u32| coord.get(j as usize).map(|c| quote!(#c));
    let leaf = |l: Leaf| match l {
        Leaf::Param(i) => {
            let i = Literal::usize_unsuffixed(i as usize);
            quote!(values[#i])
        }
        Leaf::Q(j) => field(j).map_or_else(|| quote!(f64::NAN), |c| quote!(q.#c)),
        Leaf::Qd(j) => field(j).map_or_else(|| quote!(f64::NAN), |c| quote!(qd.#c)),
        Leaf::Qdd(j) => field(j).map_or_else(|| quote!(f64::NAN), |c| quote!(qdd.#c)),
        Leaf::Time => quote!(time),
    };
    let roots = eom.roots();
    let sched = schedule(g, std::slice::from_ref(&roots));
    let (pr, lets) = bind(g, &sched, &leaf);
    let stores = roots.iter().enumerate().map(|(i, &id)| {
        let (i, e) = (Literal::usize_unsuffixed(i), pr.element(id));
        quote!(out[#i] = #e;)
    });
    let len = roots.len();
    let reduced = eom.reduced.is_some();
    quote! {
        const MOTION_OUTPUTS: usize = #len;
        const MOTION_REDUCED: bool = #reduced;

        #allow
        fn equations_of_motion(
            &self,
            q: &Self::Coords,
            qd: &Self::Coords,
            qdd: &Self::Coords,
            time: f64,
            out: &mut [f64],
        ) -> bool {
            if out.len() != #len {
                return false;
            }
            let values: [f64; #npar] = self.parameter_values();
            #(#lets)*
            #(#stores)*
            true
        }

        fn has_parameter_values(&self, values: &[f64]) -> bool {
            #pp::same_bits(values, &self.parameter_values())
        }
    }
}
