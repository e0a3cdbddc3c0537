//! The closed-form path (`crate::closed`): what the emitters share about
//! it, the `BLOCKS` constant every mechanism has, and the modes type of a
//! mechanism with a closed-form block. Its methods are in
//! `closed_step`, the solution of each block in `closed_solve`.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;
use syn::Ident;

use super::Ctx;
use crate::closed::{Closed, Pattern};
use crate::ir::{Func, Id, Leaf, Node};

impl Ctx<'_> {
    /// Whether some block has a closed form: then stepping and assembly
    /// go through `__step_closed`, which solves the closed-form blocks
    /// exactly in their modes and any other block by Newton–Raphson on
    /// that block alone, from the guess.
    pub(super) fn closed_path(&self) -> bool {
        self.closed.iter().any(|b| b.pattern.is_some())
    }

    /// Whether the closed-form path also has Newton blocks (which need a
    /// guess: `assemble_in` then takes one).
    pub(super) fn mixed(&self) -> bool {
        self.closed_path() && self.closed.iter().any(|b| b.pattern.is_none())
    }

    /// The blocks with two assembly modes.
    fn mode_blocks(&self) -> Vec<&Closed> {
        self.closed
            .iter()
            .filter(|b| b.pattern.as_ref().is_some_and(Pattern::has_modes))
            .collect()
    }

    /// Number of unknown angles (carried by the closed-form path from one
    /// step to the next).
    pub(super) fn na(&self) -> usize {
        (self.nd..self.nd + self.nu)
            .filter(|&j| self.model.kinds[j] == crate::lower::CoordKind::Angle)
            .count()
    }

    /// Number of modes (0 without a closed-form path).
    pub(super) fn nm(&self) -> usize {
        if self.closed_path() {
            self.mode_blocks().len()
        } else {
            0
        }
    }

    /// The sines and cosines of parameter-only arguments that the
    /// closed-form path uses (evaluated once per stepper by
    /// `__param_trig`), in arena order; none without a closed-form path.
    pub(super) fn param_trig(&self) -> Vec<Id> {
        if !self.closed_path() {
            return Vec::new();
        }
        let g = self.g();
        let mut roots: Vec<Id> = self.newton_roots();
        roots.extend(self.analysis_stages().into_iter().flatten());
        roots.extend(self.offsets.iter().flat_map(|o| [o.cos_k, o.sin_k]));
        let live = g.reachable(&roots);
        let mut param_only = vec![false; g.len()];
        let mut out = Vec::new();
        for i in 0..g.len() {
            let node = g.node(Id::from_index(i));
            param_only[i] = match node {
                Node::Leaf(l) => matches!(l, Leaf::Param(_)),
                _ => node.children().all(|c| param_only[c.index()]),
            };
            if let Node::Call(Func::Sin | Func::Cos, x) = node {
                if live[i] && param_only[x.index()] && g.as_const(x).is_none() {
                    out.push(Id::from_index(i));
                }
            }
        }
        out
    }

    /// The drivers whose cosine or sine the closed-form step uses, with
    /// those nodes ([cos, sin]): a stepper carries them from step to step
    /// (`closed::carried_sin_cos`). None without a closed-form path.
    pub(super) fn driver_trig(&self) -> Vec<(usize, [Option<Id>; 2])> {
        if !self.closed_path() {
            return Vec::new();
        }
        let g = self.g();
        let mut roots: Vec<Id> = self.newton_roots();
        roots.extend(self.analysis_stages().into_iter().flatten());
        for b in self.closed {
            roots.extend(super::closed_solve::coefficients(b.pattern.as_ref()));
        }
        let live = g.reachable(&roots);
        let used = |f: Func, leaf: Id| g.find(&Node::Call(f, leaf)).filter(|t| live[t.index()]);
        (0..self.nd)
            .filter_map(|j| {
                let leaf = g.find(&Node::Leaf(Leaf::Q(u32::try_from(j).ok()?)))?;
                let pair = [used(Func::Cos, leaf), used(Func::Sin, leaf)];
                pair.iter().any(Option::is_some).then_some((j, pair))
            })
            .collect()
    }

    /// The unknowns of a block, by name.
    pub(super) fn block_names(&self, b: &Closed) -> Vec<String> {
        b.cols
            .iter()
            .map(|&c| self.id.coord[self.nd + c].unraw().to_string())
            .collect()
    }
}

/// The `BLOCKS` constant: how each block is solved.
pub(super) fn blocks_const(cx: &Ctx<'_>) -> TokenStream {
    let pp = &cx.pp;
    let entries = cx.closed.iter().map(|b| {
        let names = cx.block_names(b);
        let (method, modes) = match &b.pattern {
            Some(p) => (p.describe(), p.has_modes()),
            None => (crate::pipeline::NEWTON, false),
        };
        quote!(#pp::closed::Block { unknowns: &[#(#names),*], method: #method, modes: #modes })
    });
    quote! {
        /// How each diagonal block of the loop equations is solved, in
        /// solve order: in closed form where the block has one (needing
        /// no guess, with two assembly modes where it has two solutions),
        /// else by Newton–Raphson on that block alone from a guess, with
        /// the unknowns of the blocks before it known.
        pub const BLOCKS: &'static [#pp::closed::Block] = &[#(#entries),*];
    }
}

/// The modes type, when some block is closed-form.
pub(super) fn modes_type(cx: &Ctx<'_>) -> TokenStream {
    if !cx.closed_path() {
        return TokenStream::new();
    }
    let (pp, vis, name) = (&cx.pp, &cx.def.vis, &cx.id.name);
    let modes = format_ident!("{}Modes", name.unraw());
    let blocks = cx.mode_blocks();
    let nm = blocks.len();
    let fields: Vec<Ident> = blocks
        .iter()
        .map(|b| format_ident!("{}", cx.block_names(b).join("_")))
        .collect();
    let docs = blocks.iter().map(|b| {
        let method = b.pattern.as_ref().map_or("", Pattern::describe);
        format!(
            "The assembly mode of the block solving {} ({method}).",
            cx.block_names(b).join(", ")
        )
    });
    let idx: Vec<usize> = (0..nm).collect();
    let all_doc = format!("[`{name}::assemble_all`]:");
    let doc = format!(
        "The assembly modes of [`{name}`]: one per block of its loop equations with two \
         closed-form solutions (see [`kinematics_core::closed::Mode`]), for \
         [`{name}::assemble_in`]."
    );
    let item = super::types::with_serde(
        cx.def,
        quote! {
            #[doc = #doc]
            #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
            #vis struct #modes {
                #( #[doc = #docs] pub #fields: #pp::closed::Mode, )*
            }
        },
    );
    quote! {
        #item

        impl #modes {
            /// Every combination of modes (2^k for k blocks with two
            /// modes), lazily, in the order of
            #[doc = #all_doc]
            /// combination i has field j `Minus` where bit j of i is set.
            /// `nth` skips without visiting the combinations in between.
            #[must_use]
            pub fn all() -> #pp::closed::AllModes<Self> {
                #pp::closed::AllModes::new()
            }

            /// The modes as signs (±1), in field order.
            #[doc(hidden)]
            #[must_use]
            pub fn __signs(&self) -> [f64; #nm] {
                [#(self.#fields.sign()),*]
            }

            /// The modes of signs (±1), in field order.
            #[doc(hidden)]
            #[must_use]
            pub fn __from_signs(s: &[f64; #nm]) -> Self {
                Self { #( #fields: #pp::closed::Mode::from_sign(s[#idx]) ),* }
            }
        }

        #[automatically_derived]
        impl #pp::closed::ModeSet for #modes {
            const BLOCKS: usize = #nm;

            #[inline]
            fn mode(&self, j: usize) -> #pp::closed::Mode {
                match j {
                    #( #idx => self.#fields, )*
                    _ => #pp::closed::Mode::Plus,
                }
            }

            #[inline]
            fn set_mode(&mut self, j: usize, mode: #pp::closed::Mode) {
                match j {
                    #( #idx => self.#fields = mode, )*
                    _ => {}
                }
            }

            #[inline]
            fn all_plus() -> Self {
                Self { #( #fields: #pp::closed::Mode::Plus ),* }
            }
        }
    }
}
