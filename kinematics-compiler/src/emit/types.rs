//! The generated types: the parameters struct, the coordinates, the motion
//! with its accessors, and the names the rest of the expansion uses.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;
use syn::Ident;

use crate::ir::Leaf;
use crate::lower::CoordKind;
use crate::names::{accessor_name, frame_accessor_name};
use crate::parse::Definition;

/// Names used in the generated code.
pub(super) struct Idents {
    pub(super) name: Ident,
    pub(super) coords: Ident,
    pub(super) motion: Ident,
    pub(super) stepper: Ident,
    pub(super) params: Vec<Ident>,
    pub(super) coord: Vec<Ident>,
    pub(super) q: Vec<Ident>,
    pub(super) qd: Vec<Ident>,
    pub(super) qdd: Vec<Ident>,
}

impl Idents {
    pub(super) fn new(def: &Definition) -> Self {
        let coord: Vec<Ident> = def
            .drivers
            .iter()
            .chain(&def.unknowns)
            .map(|d| d.name.clone())
            .collect();
        let pre = |p: &str| {
            coord
                .iter()
                .map(|c| format_ident!("{}_{}", p, c.unraw()))
                .collect::<Vec<_>>()
        };
        Idents {
            name: def.name.clone(),
            coords: format_ident!("{}Coords", def.name.unraw()),
            motion: format_ident!("{}Motion", def.name.unraw()),
            stepper: format_ident!("{}Stepper", def.name.unraw()),
            params: def.params.iter().map(|d| d.name.clone()).collect(),
            q: pre("q"),
            qd: pre("qd"),
            qdd: pre("qdd"),
            coord,
        }
    }

    pub(super) fn leaf(&self) -> impl Fn(Leaf) -> TokenStream + '_ {
        move |l| match l {
            Leaf::Param(i) => {
                let p = &self.params[i as usize];
                quote!(self.#p)
            }
            Leaf::Q(j) => {
                let v = &self.q[j as usize];
                quote!(#v)
            }
            Leaf::Qd(j) => {
                let v = &self.qd[j as usize];
                quote!(#v)
            }
            Leaf::Qdd(j) => {
                let v = &self.qdd[j as usize];
                quote!(#v)
            }
            // The lowering lets `time` into the loads' values only, which
            // are emitted as closures of the instant (`emit::dynamics`):
            // reaching here is a bug of the compiler, stopped at compile
            // time.
            Leaf::Time => quote!(::core::compile_error!(
                "the time reached the kinematics: a bug of the mechanism compiler"
            )),
        }
    }
}

/// The type definitions, shared by the full expansion and the error fallback.
pub(super) fn types(
    def: &Definition,
    id: &Idents,
    kinds: Option<&[CoordKind]>,
    point_dim: usize,
) -> TokenStream {
    let Idents {
        name,
        coords,
        motion,
        params,
        coord,
        ..
    } = id;
    let vis = &def.vis;
    let docs = &def.docs;
    let param_docs: Vec<_> = def.params.iter().map(|p| &p.docs).collect();
    let nd = def.drivers.len();
    let coord_docs: Vec<TokenStream> = def
        .drivers
        .iter()
        .chain(&def.unknowns)
        .enumerate()
        .map(|(j, d)| {
            let role = if j < nd { "Driver" } else { "Unknown" };
            let kind = match kinds.and_then(|k| k.get(j)) {
                Some(CoordKind::Angle) => {
                    " (an angle, rad; its rate is an angular velocity, rad/s)"
                }
                Some(CoordKind::Length) => " (a length, in the units of the parameters)",
                None => "",
            };
            let text = format!("{role} `{}`{kind}.", d.name);
            let user = &d.docs;
            quote!(#[doc = #text] #(#user)*)
        })
        .collect();
    let np = def.points.len();
    let accessors = def.points.iter().enumerate().map(|(k, p)| {
        let acc = format_ident!("{}", accessor_name(&p.name));
        let text = format!("Position, velocity and acceleration of point `{}`.", p.name);
        let user = &p.docs;
        quote! {
            #[doc = #text]
            #(#user)*
            #[must_use]
            #[inline]
            pub fn #acc(&self) -> &::kinematics_core::__private::PointMotion<#point_dim> {
                &self.points[#k]
            }
        }
    });
    let nf = def.frames.len();
    let frame_accessors = def.frames.iter().enumerate().map(|(k, f)| {
        let acc = format_ident!("{}", frame_accessor_name(&f.name));
        let text = format!(
            "Orientation, angular velocity and acceleration of frame `{}`, and the motion of \
             its origin.",
            f.name
        );
        let user = &f.docs;
        quote! {
            #[doc = #text]
            #(#user)*
            #[must_use]
            #[inline]
            pub fn #acc(&self) -> &::kinematics_core::__private::FrameState {
                &self.frames[#k]
            }
        }
    });
    let coords_doc =
        format!("Coordinates of [`{name}`]: the drivers, then the unknowns, in declaration order.");
    let motion_doc = format!(
        "Motion of [`{name}`] at one instant: coordinates q, their rates q' and \
         accelerations q'' (angular for angle coordinates), and every point's motion."
    );
    let idx: Vec<usize> = (0..coord.len()).collect();
    let n = coord.len();
    let c_drivers = &coord[..nd];
    let handles = driver_handles(def, id, kinds);
    let positions_item = positions_type(def, id, point_dim);
    let attrs = &def.attrs;
    let motion_item = with_serde(
        def,
        quote! {
            #[doc = #motion_doc]
            #[derive(Debug, Clone, Copy, PartialEq)]
            #vis struct #motion {
                /// Coordinates q.
                pub q: #coords,
                /// Rates q' (angular velocities ω for angles).
                pub qd: #coords,
                /// Accelerations q'' (angular accelerations α for angles).
                pub qdd: #coords,
                /// Every point's motion, in declaration order.
                pub points: [::kinematics_core::__private::PointMotion<#point_dim>; #np],
                /// Every frame's orientation and motion, in declaration order.
                pub frames: [::kinematics_core::__private::FrameState; #nf],
                /// Conditioning of Φ_u: the distance of the scaled Jacobian
                /// (equations divided by the size of their terms, unknowns by
                /// their natural units) to the nearest singular matrix, of
                /// order one at a regular pose and tending to 0 at a
                /// dead-centre or toggle position; each unknown is within
                /// tolerance / conditioning of the exact pose. See
                /// `kinematics_core::MotionState::conditioning`.
                pub conditioning: f64,
                /// Sign of det Φ_u, ±1: the assembly branch (it changes only
                /// through a singular configuration).
                pub det_sign: f64,
                /// max |Φ_i| at the pose, in the equations' units: how well
                /// the loops close.
                pub residual: f64,
            }
        },
    );
    let serde_required = serde_required(def);
    let coords_item = with_serde(
        def,
        quote! {
            #[doc = #coords_doc]
            #[derive(Debug, Clone, Copy, PartialEq, Default)]
            // The coordinates' names as the definition gives them (a
            // textbook's `T4`).
            #[allow(non_snake_case)]
            #vis struct #coords {
                #( #coord_docs pub #coord: f64, )*
            }
        },
    );
    quote! {
        #handles

        #(#docs)*
        #[derive(Debug, Clone, Copy, PartialEq)]
        #(#attrs)*
        #[allow(non_snake_case)]
        #vis struct #name {
            #( #(#param_docs)* pub #params: f64, )*
        }

        #coords_item

        #serde_required

        #positions_item

        #[automatically_derived]
        impl ::core::convert::From<[f64; #n]> for #coords {
            /// The coordinates from an array in declaration order: the
            /// drivers, then the unknowns.
            #[inline]
            fn from(q: [f64; #n]) -> Self {
                let [#(#coord),*] = q;
                Self { #(#coord),* }
            }
        }

        #[automatically_derived]
        impl ::core::convert::From<#coords> for [f64; #n] {
            /// The coordinates as an array in declaration order: the
            /// drivers, then the unknowns.
            #[inline]
            fn from(q: #coords) -> Self {
                [#(q.#coord),*]
            }
        }

        #[automatically_derived]
        impl ::kinematics_core::__private::DriverValues<#nd> for #coords {
            /// The drivers' fields, in declaration order.
            #[inline]
            fn into_array(self) -> [f64; #nd] {
                [#(self.#c_drivers),*]
            }
        }

        #[automatically_derived]
        impl ::kinematics_core::__private::DriverValues<#nd> for &#coords {
            /// The drivers' fields, in declaration order.
            #[inline]
            fn into_array(self) -> [f64; #nd] {
                [#(self.#c_drivers),*]
            }
        }

        #[automatically_derived]
        impl ::kinematics_core::__private::Coordinates for #coords {
            #[inline]
            fn get(&self, j: usize) -> ::core::option::Option<f64> {
                match j {
                    #( #idx => ::core::option::Option::Some(self.#coord), )*
                    _ => ::core::option::Option::None,
                }
            }
            #[inline]
            fn set(&mut self, j: usize, value: f64) -> bool {
                match j {
                    #( #idx => { self.#coord = value; true } )*
                    _ => false,
                }
            }
        }

        #motion_item

        impl #motion {
            #(#accessors)*
            #(#frame_accessors)*
        }

        #[automatically_derived]
        impl ::kinematics_core::__private::MotionState for #motion {
            type Coords = #coords;
            #[inline]
            fn q(&self) -> &#coords {
                &self.q
            }
            #[inline]
            fn qd(&self) -> &#coords {
                &self.qd
            }
            #[inline]
            fn qdd(&self) -> &#coords {
                &self.qdd
            }
            #[inline]
            fn q_mut(&mut self) -> &mut #coords {
                &mut self.q
            }
            type Point = ::kinematics_core::__private::PointMotion<#point_dim>;
            #[inline]
            fn points(&self) -> &[Self::Point] {
                &self.points
            }
            #[inline]
            fn frames(&self) -> &[::kinematics_core::__private::FrameState] {
                &self.frames
            }
            #[inline]
            fn conditioning(&self) -> f64 {
                self.conditioning
            }
            #[inline]
            fn det_sign(&self) -> f64 {
                self.det_sign
            }
            #[inline]
            fn residual(&self) -> f64 {
                self.residual
            }
        }
    }
}

/// Each driver's typed handle (`FourBar::PHI`), and `sweep` and `simulate`
/// taking it.
fn driver_handles(def: &Definition, id: &Idents, kinds: Option<&[CoordKind]>) -> TokenStream {
    let (name, coords) = (&id.name, &id.coords);
    let pp = quote!(::kinematics_core::__private);
    let mut seen = std::collections::HashSet::new();
    let consts = def.drivers.iter().enumerate().filter_map(|(j, d)| {
        let handle = crate::names::driver_handle_name(&d.name);
        // A handle that collides is reported by the checks; left out here.
        if crate::names::TAKEN_HANDLES.contains(&handle.as_str()) || !seen.insert(handle.clone()) {
            return None;
        }
        let handle = format_ident!("{}", handle);
        let text = d.name.unraw().to_string();
        let (unit, what) = match kinds.and_then(|k| k.get(j)) {
            Some(CoordKind::Length) => (quote!(Length), "a length"),
            _ => (quote!(Angle), "an angle"),
        };
        let doc = format!(
            "Driver `{text}` ({what}), for [`{name}::sweep`] and the profiles of \
             [`{name}::simulate`]."
        );
        Some(quote! {
            #[doc = #doc]
            pub const #handle: #pp::sweep::Driver<#name, #pp::sweep::#unit> =
                #pp::sweep::Driver::__new(#j, #text);
        })
    });
    let sweep_doc = format!(
        "A sweep of `driver` (one of the handles, e.g. [`{name}::{}`]) from the pose \
         `start`, the other drivers held at rest: set its range, steps, rate and options on \
         the builder, then `run()` it or iterate over it. See \
         [`SweepBuilder`](::kinematics_core::sweep::SweepBuilder).",
        def.drivers
            .first()
            .map_or_else(String::new, |d| crate::names::driver_handle_name(&d.name))
    );
    quote! {
        #[allow(clippy::unreadable_literal)]
        impl #name {
            #(#consts)*

            #[doc = #sweep_doc]
            pub fn sweep<U>(
                &self,
                driver: #pp::sweep::Driver<#name, U>,
                start: &#coords,
            ) -> #pp::sweep::SweepBuilder<'_, #name, U> {
                #pp::sweep::SweepBuilder::new(self, driver, start)
            }

            /// A simulation in time from the pose `start`: give the
            /// drivers' motion with `profile`, the duration and steps on
            /// the builder, then `run()` it or iterate over it. See
            /// [`Simulation`](::kinematics_core::sweep::Simulation).
            pub fn simulate(
                &self,
                start: &#coords,
            ) -> #pp::sweep::Simulation<'_, #name, #pp::sweep::AtRest> {
                #pp::sweep::Simulation::new(self, start)
            }
        }
    }
}

/// `item` with the serde derives of the definition, if any (see
/// `kinematics_core::__with_serde`): those under a `cfg_attr` predicate
/// under the same predicate.
pub(super) fn with_serde(def: &Definition, item: TokenStream) -> TokenStream {
    let conditional = def
        .serde_cfg_derives
        .iter()
        .map(|(predicate, paths)| quote!(#[cfg_attr(#predicate, derive(#(#paths),*))]));
    let item = quote!(#(#conditional)* #item);
    let paths = &def.serde_derives;
    if paths.is_empty() {
        item
    } else {
        quote!(::kinematics_core::__with_serde! { [#(#paths),*] #item })
    }
}

/// For each `cfg_attr` predicate under which the definition derives serde's
/// traits, a check (under the same predicate) that kinematics-core has its
/// `serde` feature, with the fix in the error.
fn serde_required(def: &Definition) -> TokenStream {
    let checks = def.serde_cfg_derives.iter().map(|(predicate, _)| {
        quote!(
            #[cfg(#predicate)]
            ::kinematics_core::__serde_required! {}
        )
    });
    quote!(#(#checks)*)
}

/// The positions of the points by name: `FourBarPositions { A, B, … }`.
fn positions_type(def: &Definition, id: &Idents, point_dim: usize) -> TokenStream {
    let (name, vis) = (&id.name, &def.vis);
    let positions = format_ident!("{}Positions", name.unraw());
    let vtype = if point_dim == 3 {
        quote!(::kinematics_core::__private::Vector3<f64>)
    } else {
        quote!(::kinematics_core::__private::Vector2<f64>)
    };
    let fields = def.points.iter().map(|p| {
        let field = &p.name;
        let doc = format!("Position of point `{}`.", p.name.unraw());
        quote!(#[doc = #doc] pub #field: #vtype,)
    });
    let doc = format!(
        "The positions of the points of [`{name}`] at one pose, by name (see \
         [`{name}::positions`])."
    );
    with_serde(
        def,
        quote! {
            #[doc = #doc]
            #[derive(Debug, Clone, Copy, PartialEq)]
            #[allow(non_snake_case)]
            #vis struct #positions {
                #(#fields)*
            }
        },
    )
}
