//! The `sensitivities { … }` section: the types of the result, and
//! `sensitivities(&motion)`, which solves Φ_u ∂u/∂p = −Φ_p and the
//! velocity and acceleration equations differentiated with respect to each
//! chosen parameter (see `crate::sensitivity`), and forms every point's
//! ∂r/∂p, ∂v/∂p, ∂a/∂p. Nothing is generated without the section.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;

use super::print::{bind, Printer};
use super::Ctx;
use crate::cse::schedule;
use crate::ir::Id;
use crate::sensitivity::Partials;

/// The items of the section, or nothing.
pub(super) fn sensitivities(cx: &Ctx<'_>, s: Option<&Partials>) -> TokenStream {
    let Some(s) = s else {
        return TokenStream::new();
    };
    let (g, pp, allow) = (cx.g(), &cx.pp, &cx.allow);
    let (nd, nu, np) = (cx.nd, cx.nu, cx.np);
    let dim = cx.model.point_dim;
    let id = &cx.id;
    let (name, coords, motion) = (&id.name, &id.coords, &id.motion);
    let (coord, q, qd, qdd) = (&id.coord, &id.q, &id.qd, &id.qdd);
    let vis = &cx.def.vis;
    let one = format_ident!("{}Sensitivity", name.unraw());
    let all = format_ident!("{}Sensitivities", name.unraw());
    let leaf = cx.leaf();
    let roots = s.roots();
    let mut jac_roots: Vec<Id> = cx.d.jac.iter().flatten().copied().collect();
    jac_roots.extend(&roots);
    let sched = schedule(g, &[jac_roots]);
    let (pr, lets) = bind(g, &sched, &leaf);
    let lets = &lets[0];
    let e = |i: Id| pr.element(i);
    // Φ_u, full.
    let jac_rows: Vec<TokenStream> =
        cx.d.jac
            .iter()
            .map(|row| {
                let r: Vec<_> = row.iter().map(|&i| e(i)).collect();
                quote!([#(#r),*])
            })
            .collect();
    // Σ_j m[j] x[j] as tokens.
    let dot = |m: &[Id], x: &str| -> TokenStream {
        let x = format_ident!("{}", x);
        let terms: Vec<TokenStream> = m
            .iter()
            .enumerate()
            .filter(|(_, &i)| g.as_const(i) != Some(0.0))
            .map(|(j, &i)| {
                let ei = e(i);
                quote!(#ei * #x[#j])
            })
            .collect();
        if terms.is_empty() {
            quote!(0.0f64)
        } else {
            super::print::chain(&terms, &quote!(+))
        }
    };
    let params: Vec<syn::Ident> = s
        .params
        .iter()
        .map(|&k| cx.def.params[k as usize].name.clone())
        .collect();
    let per_param: Vec<TokenStream> = s
        .params
        .iter()
        .enumerate()
        .map(|(k, _)| {
            let rhs_u: Vec<TokenStream> = s.phi_p[k]
                .iter()
                .map(|&i| {
                    let ei = e(i);
                    quote!(-(#ei))
                })
                .collect();
            let rhs_ud: Vec<TokenStream> = (0..s.vel_p[k].len())
                .map(|i| {
                    let p = e(s.vel_p[k][i]);
                    let u = dot(&s.vel_u[i], "s");
                    quote!(-(#p + #u))
                })
                .collect();
            let rhs_udd: Vec<TokenStream> = (0..s.acc_p[k].len())
                .map(|i| {
                    let p = e(s.acc_p[k][i]);
                    let u = dot(&s.acc_u[i], "s");
                    let ud = dot(&s.acc_ud[i], "sd");
                    quote!(-(#p + #u + #ud))
                })
                .collect();
            let vector = |c: Vec<TokenStream>| {
                if dim == 3 {
                    quote!(#pp::Vector3::new(#(#c),*))
                } else {
                    quote!(#pp::Vector2::new(#(#c),*))
                }
            };
            let points: Vec<TokenStream> = (0..np)
                .map(|n| {
                    let pos = vector(
                        (0..dim)
                            .map(|c| {
                                let p = e(s.pos_p[k][n][c]);
                                let u = dot(&s.pos_u[n][c], "s");
                                quote!(#p + #u)
                            })
                            .collect(),
                    );
                    let vel = vector(
                        (0..dim)
                            .map(|c| {
                                let p = e(s.vel_pt_p[k][n][c]);
                                let u = dot(&s.vel_pt_u[n][c], "s");
                                let ud = dot(&s.vel_pt_ud[n][c], "sd");
                                quote!(#p + #u + #ud)
                            })
                            .collect(),
                    );
                    let acc = vector(
                        (0..dim)
                            .map(|c| {
                                let p = e(s.acc_pt_p[k][n][c]);
                                let u = dot(&s.acc_pt_u[n][c], "s");
                                let ud = dot(&s.acc_pt_ud[n][c], "sd");
                                let udd = dot(&s.acc_pt_udd[n][c], "sdd");
                                quote!(#p + #u + #ud + #udd)
                            })
                            .collect(),
                    );
                    quote!(#pp::PointMotion { position: #pos, velocity: #vel, acceleration: #acc })
                })
                .collect();
            let zeros = vec![quote!(0.0f64); nd];
            let (s_j, sd_j, sdd_j): (Vec<_>, Vec<_>, Vec<_>) = (0..nu)
                .map(|j| (quote!(s[#j]), quote!(sd[#j]), quote!(sdd[#j])))
                .fold((vec![], vec![], vec![]), |mut acc, (a, b, c)| {
                    acc.0.push(a);
                    acc.1.push(b);
                    acc.2.push(c);
                    acc
                });
            quote! {
                {
                    let s: [f64; #nu] = lu.solve(&[#(#rhs_u),*]);
                    let sd: [f64; #nu] = lu.solve(&[#(#rhs_ud),*]);
                    let sdd: [f64; #nu] = lu.solve(&[#(#rhs_udd),*]);
                    let _ = (&s, &sd, &sdd);
                    #one {
                        q: #coords::from([#(#zeros,)* #(#s_j),*]),
                        qd: #coords::from([#(#zeros,)* #(#sd_j),*]),
                        qdd: #coords::from([#(#zeros,)* #(#sdd_j),*]),
                        points: [#(#points),*],
                    }
                }
            }
        })
        .collect();
    let accessors = cx.def.points.iter().enumerate().map(|(n, p)| {
        let acc = format_ident!("{}", crate::names::accessor_name(&p.name));
        let text = format!(
            "The derivatives of point `{}`'s position, velocity and acceleration with respect \
             to the parameter.",
            p.name
        );
        quote! {
            #[doc = #text]
            #[must_use]
            #[inline]
            pub fn #acc(&self) -> &#pp::PointMotion<#dim> {
                &self.points[#n]
            }
        }
    });
    let field_docs: Vec<String> = params
        .iter()
        .map(|p| format!("With respect to parameter `{}`.", p.unraw()))
        .collect();
    let nk = params.len();
    let one_doc = format!(
        "The derivatives of a motion of [`{name}`] with respect to one parameter: of the \
         coordinates, their rates and accelerations (zero for the drivers), and of every \
         point's position, velocity and acceleration, in the point's units per unit of the \
         parameter."
    );
    let all_doc = format!(
        "The design sensitivities of a motion of [`{name}`], a field per parameter of its \
         `sensitivities` section (see [`{name}::sensitivities`])."
    );
    let items = super::types::with_serde(
        cx.def,
        quote! {
            #[doc = #one_doc]
            #[derive(Debug, Clone, Copy, PartialEq)]
            #vis struct #one {
                /// ∂q/∂p.
                pub q: #coords,
                /// ∂q'/∂p.
                pub qd: #coords,
                /// ∂q''/∂p.
                pub qdd: #coords,
                /// ∂r/∂p, ∂v/∂p and ∂a/∂p of every point, in declaration
                /// order.
                pub points: [#pp::PointMotion<#dim>; #np],
            }
        },
    );
    let all_item = super::types::with_serde(
        cx.def,
        quote! {
            #[doc = #all_doc]
            #[derive(Debug, Clone, Copy, PartialEq)]
            #vis struct #all {
                #( #[doc = #field_docs] pub #params: #one, )*
            }
        },
    );
    let pname_text: Vec<String> = params.iter().map(|p| p.unraw().to_string()).collect();
    let param_index: Vec<usize> = (0..params.len()).collect();
    let _ = &pr as &Printer<'_>;
    quote! {
        #items

        impl #one {
            #(#accessors)*
        }

        #all_item

        impl #all {
            /// The parameters, in the order of the section.
            pub const PARAMETERS: [&'static str; #nk] = [#(#pname_text),*];

            /// The sensitivities as an array, in the order of
            /// [`Self::PARAMETERS`].
            #[must_use]
            pub fn to_array(&self) -> [#one; #nk] {
                [#(self.#params),*]
            }
        }

        #[automatically_derived]
        impl ::kinematics_core::tolerance::Sensitive for #name {
            const PARAMETERS: &'static [&'static str] = &[#(#pname_text),*];

            fn motion_sensitivities_into(
                &self,
                motion: &#motion,
                coordinates: &mut [f64],
                points: &mut [f64],
            ) -> #pp::Result<(), #pp::Error> {
                let all = self.sensitivities(motion)?;
                let (mut i, mut j) = (0usize, 0usize);
                for one in all.to_array() {
                    for c in [&one.q, &one.qd, &one.qdd] {
                        let mut k = 0usize;
                        while let ::core::option::Option::Some(v) = #pp::Coordinates::get(c, k) {
                            if let ::core::option::Option::Some(o) = coordinates.get_mut(i) {
                                *o = v;
                            }
                            i += 1;
                            k += 1;
                        }
                    }
                    for p in &one.points {
                        for v in p
                            .position
                            .iter()
                            .chain(p.velocity.iter())
                            .chain(p.acceleration.iter())
                        {
                            if let ::core::option::Option::Some(o) = points.get_mut(j) {
                                *o = *v;
                            }
                            j += 1;
                        }
                    }
                }
                ::core::result::Result::Ok(())
            }

            fn position_sensitivities_into(
                &self,
                motion: &#motion,
                coordinates: &mut [f64],
                points: &mut [f64],
            ) -> #pp::Result<(), #pp::Error> {
                let all = self.sensitivities(motion)?;
                let (mut i, mut j) = (0usize, 0usize);
                for one in all.to_array() {
                    let mut c = 0usize;
                    while let ::core::option::Option::Some(v) = #pp::Coordinates::get(&one.q, c) {
                        if let ::core::option::Option::Some(o) = coordinates.get_mut(i) {
                            *o = v;
                        }
                        i += 1;
                        c += 1;
                    }
                    for p in &one.points {
                        for v in p.position.iter() {
                            if let ::core::option::Option::Some(o) = points.get_mut(j) {
                                *o = *v;
                            }
                            j += 1;
                        }
                    }
                }
                ::core::result::Result::Ok(())
            }

            fn parameter(&self, k: usize) -> f64 {
                match k {
                    #(#param_index => self.#params,)*
                    _ => ::core::primitive::f64::NAN,
                }
            }

            fn set_parameter(&mut self, k: usize, value: f64) -> bool {
                match k {
                    #(#param_index => {
                        self.#params = value;
                        true
                    })*
                    _ => false,
                }
            }
        }

        impl #name {
            /// Design sensitivities of `motion` (a solved motion of this
            /// mechanism, from `step`, `analyze` or a sweep): for each
            /// parameter p of the `sensitivities` section, ∂u/∂p from
            /// Φ_u ∂u/∂p = −Φ_p, ∂u'/∂p and ∂u''/∂p from the velocity and
            /// acceleration equations differentiated with respect to p,
            /// and every point's ∂r/∂p = r_p + r_u ∂u/∂p, ∂v/∂p and ∂a/∂p.
            /// All partial derivatives are exact; the three solves per
            /// parameter share one factorisation of Φ_u.
            ///
            /// # Errors
            /// [`Error::Singular`](#pp::Error::Singular) when Φ_u is
            /// singular at the pose, [`Error::NonFinite`](#pp::Error::NonFinite)
            /// when a result is not finite.
            #allow
            pub fn sensitivities(&self, motion: &#motion) -> #pp::Result<#all, #pp::Error> {
                #( let #q = motion.q.#coord; )*
                #( let #qd = motion.qd.#coord; )*
                #( let #qdd = motion.qdd.#coord; )*
                #lets
                let jac: [[f64; #nu]; #nu] = [#(#jac_rows),*];
                let lu = match #pp::Lu::<#nu>::factor(&jac, 0.0) {
                    ::core::result::Result::Ok(lu) => lu,
                    ::core::result::Result::Err(f) => {
                        return ::core::result::Result::Err(#pp::describe(
                            f,
                            &Self::__NAMES,
                            &[#(#q),*],
                        ));
                    }
                };
                let out = #all { #( #params: #per_param, )* };
                for (k, one) in out.to_array().iter().enumerate() {
                    let mut sum = 0.0f64;
                    for j in 0..#nd + #nu {
                        use #pp::Coordinates as _;
                        sum += one.q.get(j).unwrap_or(0.0)
                            + one.qd.get(j).unwrap_or(0.0)
                            + one.qdd.get(j).unwrap_or(0.0);
                    }
                    for p in &one.points {
                        sum += p.position.sum() + p.velocity.sum() + p.acceleration.sum();
                    }
                    if !sum.is_finite() {
                        return ::core::result::Result::Err(#pp::Error::NonFinite {
                            input: #pp::Input::Computed,
                            name: #all::PARAMETERS[k],
                            value: sum,
                        });
                    }
                }
                ::core::result::Result::Ok(out)
            }
        }
    }
}
