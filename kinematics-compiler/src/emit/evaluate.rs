//! Plain evaluations at a pose: `residual`, `point_positions`,
//! `frame_rotations`, and the Jacobian behind `Mechanism::jacobian_into`.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;

use super::print::bind;
use super::Ctx;
use crate::cse::schedule;
use crate::ir::{Id, Node};

/// The evaluation methods.
pub(super) fn evaluate(cx: &Ctx<'_>) -> TokenStream {
    let (g, d, pp, allow) = (cx.g(), cx.d, &cx.pp, &cx.allow);
    let (nd, nu, ne, np, nf) = (cx.nd, cx.nu, cx.ne, cx.np, cx.nf);
    let id = &cx.id;
    let (coords, coord, q) = (&id.coords, &id.coord, &id.q);
    let (q_drivers, q_unknowns) = q.split_at(nd);
    let (c_drivers, c_unknowns) = coord.split_at(nd);
    let leaf = cx.leaf();

    // Point positions alone.
    let pos_flat: Vec<Id> = d.pos.iter().flatten().copied().collect();
    let sched = schedule(g, std::slice::from_ref(&pos_flat));
    let (pr, lets) = bind(g, &sched, &leaf);
    let vtype = if cx.model.point_dim == 3 {
        quote!(#pp::Vector3<f64>)
    } else {
        quote!(#pp::Vector2<f64>)
    };
    let positions: Vec<_> = d.pos.iter().map(|c| cx.vector(&pr, c)).collect();
    let positions_type = format_ident!("{}Positions", id.name.unraw());
    let point_names: Vec<&syn::Ident> = cx.def.points.iter().map(|p| &p.name).collect();
    let idx: Vec<usize> = (0..np).collect();
    let positions_fn = quote! {
        /// Positions of the points (in declaration order) at `pose`, which
        /// should be assembled: r_P(q).
        #[must_use]
        #allow
        pub fn point_positions(&self, pose: &#coords) -> [#vtype; #np] {
            #( let #q = pose.#coord; )*
            #(#lets)*
            [#(#positions),*]
        }

        /// Positions of the points at `pose`, by name (`.P` for point
        /// `P`), as [`Self::point_positions`].
        #[must_use]
        pub fn positions(&self, pose: &#coords) -> #positions_type {
            let p = self.point_positions(pose);
            #positions_type { #( #point_names: p[#idx], )* }
        }
    };

    // Frame rotations alone.
    let rot_flat: Vec<Id> = d
        .frames
        .iter()
        .flat_map(|f| f.rotation.iter().flatten().copied())
        .collect();
    let sched = schedule(g, std::slice::from_ref(&rot_flat));
    let (pr, lets) = bind(g, &sched, &leaf);
    let rotations: Vec<_> = d
        .frames
        .iter()
        .map(|f| cx.matrix(&pr, &f.rotation))
        .collect();
    let rotations_fn = quote! {
        /// Rotation matrices R(q) of the frames (in declaration order) at
        /// `pose`.
        #[must_use]
        #allow
        pub fn frame_rotations(&self, pose: &#coords) -> [#pp::Matrix3<f64>; #nf] {
            #( let #q = pose.#coord; )*
            #(#lets)*
            [#(#rotations),*]
        }
    };

    // Φ_u into a row-major slice, nonzero entries only (the caller zeroes
    // it), with no N×N array of its own.
    let sched = schedule(g, std::slice::from_ref(&cx.jac_flat()));
    let (pr, lets) = bind(g, &sched, &leaf);
    let stores = d.jac.iter().enumerate().flat_map(|(r, row)| {
        let pr = &pr;
        row.iter().enumerate().filter_map(move |(c, &i)| {
            let zero = matches!(g.node(i), Node::Const(b) if f64::from_bits(b) == 0.0);
            let k = r * nu + c;
            let e = pr.expr(i);
            (!zero).then(
                || quote!(if let ::core::option::Option::Some(o) = out.get_mut(#k) { *o = #e; }),
            )
        })
    });
    let jacobian_fn = quote! {
        #[doc(hidden)]
        #[inline]
        #allow
        fn __jacobian_into(&self, d: &[f64; #nd], u: &[f64; #nu], out: &mut [f64]) {
            let [#(#q_drivers),*] = *d;
            let [#(#q_unknowns),*] = *u;
            #(#lets)*
            #(#stores)*
        }
    };

    // Φ alone.
    let sched = schedule(g, std::slice::from_ref(&d.phi));
    let (pr, lets) = bind(g, &sched, &leaf);
    let phi: Vec<_> = d.phi.iter().map(|&i| pr.element(i)).collect();
    let phi_fn = quote! {
        #[doc(hidden)]
        #[inline]
        #allow
        fn __phi(&self, d: &[f64; #nd], u: &[f64; #nu]) -> [f64; #ne] {
            let [#(#q_drivers),*] = *d;
            let [#(#q_unknowns),*] = *u;
            #(#lets)*
            [#(#phi),*]
        }
    };

    quote! {
        /// Residuals Φ_i of the loop-closure equations at `pose` (zero
        /// when assembled), in the order of [`Self::EQUATIONS`].
        #[must_use]
        pub fn residual(&self, pose: &#coords) -> [f64; #ne] {
            self.__phi(&[#(pose.#c_drivers),*], &[#(pose.#c_unknowns),*])
        }

        #positions_fn
        #rotations_fn
        #jacobian_fn
        #phi_fn
    }
}
