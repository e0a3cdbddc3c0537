//! Emission: straight-line Rust for the scheduled expressions, and the
//! generated types and impls.
//!
//! The generated code reaches the runtime only through absolute paths
//! (`::kinematics_core::__private::…` and `::core::…`).

use std::collections::HashMap;

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use syn::ext::IdentExt;
use syn::Ident;

use crate::blocks::{block_triangular, Block};
use crate::check::{accessor_name, frame_accessor_name};
use crate::cse::{op_count, schedule, OpCount, Schedule};
use crate::ir::{Func, Graph, Id, Leaf, Node};
use crate::kinematics::Derived;
use crate::lower::{CoordKind, Model};
use crate::parse::Definition;
use crate::scale::Scales;

/// The name in `core::f64::consts` of a constant equal to `v`, so that the
/// generated code reads `TAU` rather than its digits (and does not trip
/// lints that flag approximations of known constants).
fn named_constant(v: f64) -> Option<&'static str> {
    use std::f64::consts as c;
    let table = [
        (c::PI, "PI"),
        (c::TAU, "TAU"),
        (c::FRAC_PI_2, "FRAC_PI_2"),
        (c::FRAC_PI_3, "FRAC_PI_3"),
        (c::FRAC_PI_4, "FRAC_PI_4"),
        (c::FRAC_PI_6, "FRAC_PI_6"),
        (c::FRAC_PI_8, "FRAC_PI_8"),
        (c::FRAC_1_PI, "FRAC_1_PI"),
        (c::FRAC_2_PI, "FRAC_2_PI"),
        (c::FRAC_2_SQRT_PI, "FRAC_2_SQRT_PI"),
        (c::SQRT_2, "SQRT_2"),
        (c::FRAC_1_SQRT_2, "FRAC_1_SQRT_2"),
        (c::E, "E"),
        (c::LN_2, "LN_2"),
        (c::LN_10, "LN_10"),
        (c::LOG2_E, "LOG2_E"),
        (c::LOG10_E, "LOG10_E"),
        (c::LOG2_10, "LOG2_10"),
        (c::LOG10_2, "LOG10_2"),
    ];
    table
        .iter()
        .find(|(x, _)| x.to_bits() == v.to_bits())
        .map(|(_, n)| *n)
}

/// Turns node ids into Rust expressions.
struct Printer<'a> {
    g: &'a Graph,
    names: HashMap<Id, Ident>,
    leaf: &'a dyn Fn(Leaf) -> TokenStream,
    /// Nodes printed as a given variable instead of their definition.
    given: HashMap<Id, Ident>,
}

impl Printer<'_> {
    /// The expression for `id`: its binding if it has one.
    fn expr(&self, id: Id) -> TokenStream {
        match self.names.get(&id) {
            Some(name) => quote!(#name),
            None => self.body(id),
        }
    }

    /// `id` as an array element: parenthesised unless atomic, so that
    /// `[a - b, -c]` cannot be misread as a missing comma.
    fn element(&self, id: Id) -> TokenStream {
        self.operand(id)
    }

    /// `id` as an operand: parenthesised unless atomic.
    fn operand(&self, id: Id) -> TokenStream {
        let atomic = self.names.contains_key(&id)
            || self.given.contains_key(&id)
            || match self.g.node(id) {
                // Method calls bind tighter than any operator.
                Node::Leaf(_) | Node::Call(..) | Node::Powi(..) | Node::Atan2(..) => true,
                Node::Const(bits) => f64::from_bits(bits) >= 0.0,
                _ => false,
            };
        let e = self.expr(id);
        if atomic {
            e
        } else {
            quote!((#e))
        }
    }

    /// The defining expression of `id`, ignoring its own binding.
    fn body(&self, id: Id) -> TokenStream {
        if let Some(v) = self.given.get(&id) {
            return quote!(#v);
        }
        match self.g.node(id) {
            Node::Const(bits) => {
                let v = f64::from_bits(bits);
                if !v.is_finite() {
                    // Never produced (the simplifier folds only finite values);
                    // the run-time finiteness checks would report it.
                    return quote!(::core::primitive::f64::NAN);
                }
                let magnitude = match named_constant(v.abs()) {
                    Some(name) => {
                        let name = format_ident!("{}", name);
                        quote!(::core::f64::consts::#name)
                    }
                    None => {
                        let lit = Literal::f64_suffixed(v.abs());
                        quote!(#lit)
                    }
                };
                if v < 0.0 {
                    quote!(-#magnitude)
                } else {
                    magnitude
                }
            }
            Node::Leaf(l) => (self.leaf)(l),
            Node::Add(a, b) => {
                let neg = |x: Id| match self.g.node(x) {
                    Node::Neg(y) if !self.names.contains_key(&x) => Some(y),
                    _ => None,
                };
                match (neg(a), neg(b)) {
                    (_, Some(y)) => {
                        let (a, y) = (self.operand(a), self.operand(y));
                        quote!(#a - #y)
                    }
                    (Some(x), None) => {
                        let (b, x) = (self.operand(b), self.operand(x));
                        quote!(#b - #x)
                    }
                    (None, None) => {
                        let (a, b) = (self.operand(a), self.operand(b));
                        quote!(#a + #b)
                    }
                }
            }
            Node::Mul(a, b) => {
                let (a, b) = (self.operand(a), self.operand(b));
                quote!(#a * #b)
            }
            Node::Div(a, b) => {
                let (a, b) = (self.operand(a), self.operand(b));
                quote!(#a / #b)
            }
            Node::Neg(a) => {
                let a = self.operand(a);
                quote!(-#a)
            }
            Node::Powi(a, n) => {
                let a = self.operand(a);
                let n = Literal::i32_unsuffixed(n);
                quote!(#a.powi(#n))
            }
            Node::Call(f, a) => {
                let a = self.operand(a);
                let m = format_ident!("{}", f.method());
                quote!(#a.#m())
            }
            Node::Atan2(y, x) => {
                let (y, x) = (self.operand(y), self.expr(x));
                quote!(#y.atan2(#x))
            }
        }
    }
}

/// Names the bindings of a schedule `t0, t1, …` and emits each stage's
/// `let`s.
fn bind<'a>(
    g: &'a Graph,
    sched: &Schedule,
    leaf: &'a dyn Fn(Leaf) -> TokenStream,
) -> (Printer<'a>, Vec<TokenStream>) {
    bind_given(g, sched, leaf, HashMap::new())
}

/// [`bind`], with the nodes of `given` printed as the given variables.
fn bind_given<'a>(
    g: &'a Graph,
    sched: &Schedule,
    leaf: &'a dyn Fn(Leaf) -> TokenStream,
    given: HashMap<Id, Ident>,
) -> (Printer<'a>, Vec<TokenStream>) {
    let _ = &sched.bound;
    let mut p = Printer {
        g,
        names: HashMap::new(),
        leaf,
        given,
    };
    let mut stages = Vec::new();
    let mut n = 0usize;
    for lets in &sched.stages {
        let mut code = TokenStream::new();
        for &id in lets {
            let body = p.body(id);
            let name = format_ident!("t{}", n);
            n += 1;
            code.extend(quote!(let #name = #body;));
            p.names.insert(id, name);
        }
        stages.push(code);
    }
    (p, stages)
}

/// Names used in the generated code.
struct Idents {
    name: Ident,
    coords: Ident,
    motion: Ident,
    params: Vec<Ident>,
    coord: Vec<Ident>,
    q: Vec<Ident>,
    qd: Vec<Ident>,
    qdd: Vec<Ident>,
}

impl Idents {
    fn new(def: &Definition) -> Self {
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
            params: def.params.iter().map(|d| d.name.clone()).collect(),
            q: pre("q"),
            qd: pre("qd"),
            qdd: pre("qdd"),
            coord,
        }
    }

    fn leaf(&self) -> impl Fn(Leaf) -> TokenStream + '_ {
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
        }
    }
}

/// The type definitions, shared by the full expansion and the error fallback.
fn types(
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
    quote! {
        #(#docs)*
        #[derive(Debug, Clone, Copy, PartialEq)]
        #vis struct #name {
            #( #(#param_docs)* pub #params: f64, )*
        }

        #[doc = #coords_doc]
        #[derive(Debug, Clone, Copy, PartialEq, Default)]
        #vis struct #coords {
            #( #coord_docs pub #coord: f64, )*
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
        }

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
        }
    }
}

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
        ..
    } = &id;
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
            pub fn frame_rotations(&self, pose: &#coords) -> [#pp::Matrix3<f64>; #nf] { #unavailable }
        }
        #[automatically_derived]
        #[allow(unused_variables)]
        impl #pp::Mechanism for #name {
            type Coords = #coords;
            type Motion = #motion;
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
            fn residual_into(&self, pose: &#coords, out: &mut [f64]) { #unavailable }
            fn jacobian_into(&self, pose: &#coords, out: &mut [f64]) { #unavailable }
            fn point_positions_into(&self, pose: &#coords, out: &mut [f64]) { #unavailable }
            fn frame_rotations_into(&self, pose: &#coords, out: &mut [#pp::Matrix3<f64>]) { #unavailable }
        }
    }
}

/// `checks`, a list of `finite(…)?;` statements over `values`, run only when
/// the fast test fails: the sum of the values is finite. A NaN or an infinity
/// among them makes the sum NaN or infinite, so the common case costs one add
/// per value and one branch, and the error still names the offending value.
/// (Finite values whose sum overflows only send it to the named checks, which
/// then pass.)
fn guarded(values: &[TokenStream], checks: &TokenStream) -> TokenStream {
    if values.is_empty() {
        return TokenStream::new();
    }
    quote! {
        if !(#( #values )+*).is_finite() {
            #checks
        }
    }
}

/// Linear solves with Φ_u through its block-triangular form ([`blocks`]):
/// each diagonal block of the scaled matrix Φ̃_u = diag(1/S) Φ_u diag(unit)
/// (the local `__scaling`, see `kinematics_core::solve::Scaling`) factored
/// on its own, then forward substitution over the blocks. The matrix is the
/// local `jac`, which holds only the structurally nonzero entries of Φ_u,
/// row by row (so that a large sparse mechanism keeps no N×N array); the
/// factors are `__lu_0`, ….
struct BlockSolve {
    blocks: Vec<Block>,
    /// The index in `jac` of each nonzero entry (r, c).
    slot: Vec<Vec<Option<usize>>>,
    /// (r, c) of each entry of `jac`, in order.
    entries: Vec<(usize, usize)>,
    /// Whether each unknown is a length (its column scale is L, not 1).
    is_length: Vec<bool>,
    nu: usize,
}

impl BlockSolve {
    fn new(g: &Graph, jac: &[Vec<Id>], is_length: &[bool]) -> Self {
        let nonzero: Vec<Vec<bool>> = jac
            .iter()
            .map(|row| {
                row.iter()
                    .map(|&id| !matches!(g.node(id), Node::Const(b) if f64::from_bits(b) == 0.0))
                    .collect()
            })
            .collect();
        let mut entries = Vec::new();
        let slot = nonzero
            .iter()
            .enumerate()
            .map(|(r, row)| {
                row.iter()
                    .enumerate()
                    .map(|(c, &nz)| {
                        nz.then(|| {
                            entries.push((r, c));
                            entries.len() - 1
                        })
                    })
                    .collect()
            })
            .collect();
        BlockSolve {
            blocks: block_triangular(&nonzero),
            nu: jac.len(),
            is_length: is_length.to_vec(),
            slot,
            entries,
        }
    }

    /// The number of entries of `jac`.
    fn nnz(&self) -> usize {
        self.entries.len()
    }

    /// The array expression of the nonzero entries of Φ_u, from the full
    /// matrix of printed entries `full`.
    fn array(&self, full: &[Vec<TokenStream>]) -> TokenStream {
        let e = self.entries.iter().map(|&(r, c)| &full[r][c]);
        quote!([#(#e),*])
    }

    fn lu(b: usize) -> Ident {
        format_ident!("__lu_{}", b)
    }

    /// The scaled entry Φ̃_u[r][c] (the column scale only for lengths: an
    /// angle's is 1), or the entry itself when not `scaled`.
    fn entry(&self, r: usize, c: usize, scaled: bool) -> TokenStream {
        let Some(k) = self.slot[r][c] else {
            return quote!(0.0f64);
        };
        if !scaled {
            quote!(jac[#k])
        } else if self.is_length[c] {
            quote!((jac[#k] * (__scaling.row[#r] * __scaling.col[#c])))
        } else {
            quote!((jac[#k] * __scaling.row[#r]))
        }
    }

    /// Binds the factors of the diagonal blocks; `on_fail(f)` is the
    /// statement run with `f`, the failure (its unknown made global), when
    /// a pivot of a block is at or below the singularity threshold. With
    /// `scaled` false (Newton's inline iteration, whose step does not
    /// depend on the scaling) the blocks of Φ_u itself are factored, and
    /// only a zero or non-finite pivot fails: the singularity of the
    /// solution is judged once, at the end, on the scaled matrix.
    fn factor(
        &self,
        pp: &TokenStream,
        scaled: bool,
        on_fail: &dyn Fn(TokenStream) -> TokenStream,
    ) -> TokenStream {
        let threshold = if scaled {
            quote!(options.singularity_threshold)
        } else {
            quote!(0.0)
        };
        let mut code = TokenStream::new();
        for (b, block) in self.blocks.iter().enumerate() {
            let lu = Self::lu(b);
            let n = block.rows.len();
            let rows = block.rows.iter().map(|&r| {
                let entries = block.cols.iter().map(|&c| self.entry(r, c, scaled));
                quote!([#(#entries),*])
            });
            let cols = &block.cols;
            let fail = on_fail(quote!(f.in_block(&[#(#cols),*])));
            code.extend(quote! {
                let #lu = match #pp::Lu::<#n>::factor(&[#(#rows),*], #threshold) {
                    ::core::result::Result::Ok(lu) => lu,
                    ::core::result::Result::Err(f) => { #fail }
                };
            });
        }
        code
    }

    /// After [`BlockSolve::factor`] at a solution: binds `__conditioning`,
    /// the smallest conditioning of the blocks, and `__det_sign`, the sign
    /// of det Φ_u, running `on_fail(f)` when a conditioning is at or below
    /// the singularity threshold or when the sign is not the branch asked
    /// for.
    fn check(&self, pp: &TokenStream, on_fail: &dyn Fn(TokenStream) -> TokenStream) -> TokenStream {
        let mut code = quote!(let mut __conditioning = 1.0f64;);
        let mut signs = Vec::new();
        for (b, block) in self.blocks.iter().enumerate() {
            let lu = Self::lu(b);
            let cols = &block.cols;
            let fail = on_fail(quote!(f.in_block(&[#(#cols),*])));
            code.extend(quote! {
                match #lu.check(options.singularity_threshold) {
                    ::core::result::Result::Ok(c) => {
                        if c < __conditioning {
                            __conditioning = c;
                        }
                    }
                    ::core::result::Result::Err(f) => { #fail }
                }
            });
            signs.push(quote!(#lu.det_sign()));
        }
        let fail = on_fail(quote!(f));
        // det Φ_u = sign(row order) sign(column order) Π det(block): the
        // blocks list the rows and columns in a permuted order.
        let rows: Vec<usize> = self.blocks.iter().flat_map(|b| b.rows.clone()).collect();
        let cols: Vec<usize> = self.blocks.iter().flat_map(|b| b.cols.clone()).collect();
        let odd = parity(&rows) != parity(&cols);
        let sign = match signs.split_first() {
            Some((first, rest)) if odd => quote!(-(#first #(* #rest)*)),
            Some((first, rest)) => quote!(#first #(* #rest)*),
            None => quote!(1.0f64),
        };
        code.extend(quote! {
            let __det_sign: f64 = #sign;
            if let ::core::result::Result::Err(f) = #pp::branch_check(__det_sign, options) {
                #fail
            }
        });
        code
    }

    /// An expression for x with Φ_u x = `rhs`, after [`BlockSolve::factor`]
    /// with the same `scaled`: block by block, Φ̃_bb y = diag(1/S_b)(rhs_b −
    /// Φ_u,b,done x_done), x_b = diag(unit_b) y (or without the scales).
    fn solve(&self, rhs: &TokenStream, scaled: bool) -> TokenStream {
        let nu = self.nu;
        let mut done: Vec<usize> = Vec::new();
        let mut steps = TokenStream::new();
        for (b, block) in self.blocks.iter().enumerate() {
            let lu = Self::lu(b);
            let entries = block.rows.iter().map(|&r| {
                let known: Vec<TokenStream> = done
                    .iter()
                    .filter_map(|&c| self.slot[r][c].map(|k| quote!(jac[#k] * __x[#c])))
                    .collect();
                if known.is_empty() && !scaled {
                    quote!(__rhs[#r])
                } else if known.is_empty() {
                    quote!((__rhs[#r] * __scaling.row[#r]))
                } else if !scaled {
                    quote!((__rhs[#r] - (#(#known)+*)))
                } else {
                    // Parenthesised, as every array element that is an
                    // operation (see `Printer::element`).
                    quote!(((__rhs[#r] - (#(#known)+*)) * __scaling.row[#r]))
                }
            });
            let store = block.cols.iter().enumerate().map(|(slot, &c)| {
                if scaled && self.is_length[c] {
                    quote!(__x[#c] = __y[#slot] * __scaling.col[#c];)
                } else {
                    quote!(__x[#c] = __y[#slot];)
                }
            });
            steps.extend(quote! {
                let __y = #lu.solve(&[#(#entries),*]);
                #( #store )*
            });
            done.extend(&block.cols);
        }
        quote!({
            let __rhs: [f64; #nu] = #rhs;
            let mut __x = [0.0f64; #nu];
            #steps
            __x
        })
    }
}

/// Whether the permutation `p` (of 0..n) is odd.
fn parity(p: &[usize]) -> bool {
    let mut seen = vec![false; p.len()];
    let mut odd = false;
    for start in 0..p.len() {
        let mut k = start;
        let mut length = 0;
        while !seen[k] {
            seen[k] = true;
            k = p[k];
            length += 1;
        }
        // A cycle of length m is m − 1 transpositions.
        if length > 0 && length % 2 == 0 {
            odd = !odd;
        }
    }
    odd
}

/// The binding of `__scaling` (`kinematics_core::solve::Scaling`) from the
/// term scales of `scale.rs`, evaluated from the parameters and the bound
/// drivers `q_…`; `on_fail(f)` runs when a scale overflows.
fn scaling_code(
    g: &Graph,
    scales: &Scales,
    leaf: &dyn Fn(Leaf) -> TokenStream,
    params: usize,
    pp: &TokenStream,
    on_fail: &TokenStream,
) -> TokenStream {
    let length_leaf = crate::scale::length_leaf(params);
    let leaf = move |l: Leaf| {
        if l == length_leaf {
            quote!(__length)
        } else {
            leaf(l)
        }
    };
    let has_lengths = scales.is_length.iter().any(|&l| l);
    let stages = if has_lengths {
        vec![scales.fixed.clone(), scales.full.clone()]
    } else {
        vec![scales.fixed.clone()]
    };
    let sched = schedule(g, &stages);
    let (pr, lets) = bind(g, &sched, &leaf);
    let fixed: Vec<_> = scales.fixed.iter().map(|&i| pr.element(i)).collect();
    let full = if has_lengths {
        let full = scales.full.iter().map(|&i| pr.element(i));
        quote!(&[#(#full),*])
    } else {
        quote!(&__fixed)
    };
    let is_length = &scales.is_length;
    let ne = scales.fixed.len();
    let lets0 = &lets[0];
    let lets1 = lets.get(1);
    quote! {
        let __scaling = {
            #lets0
            let __fixed: [f64; #ne] = [#(#fixed),*];
            let __length = #pp::characteristic_length(&__fixed);
            #lets1
            match #pp::Scaling::new(#full, __length, [#(#is_length),*]) {
                ::core::result::Result::Ok(s) => s,
                ::core::result::Result::Err(f) => { #on_fail }
            }
        };
    }
}

/// The driver-only nodes of the Newton cone that the unknown-dependent part
/// (or the output list itself) uses: evaluated once before the iteration.
fn driver_frontier(g: &Graph, roots: &[Id], drivers: u32) -> Vec<Id> {
    let live = g.reachable(roots);
    let mut dep = vec![false; g.len()];
    for i in 0..g.len() {
        let node = g.node(Id::from_index(i));
        dep[i] = match node {
            Node::Leaf(Leaf::Q(j)) => j >= drivers,
            _ => node.children().any(|c| dep[c.index()]),
        };
    }
    let mut frontier = vec![false; g.len()];
    for i in 0..g.len() {
        if live[i] && dep[i] {
            for c in g.node(Id::from_index(i)).children() {
                frontier[c.index()] |= !dep[c.index()];
            }
        }
    }
    for r in roots {
        frontier[r.index()] |= !dep[r.index()];
    }
    (0..g.len())
        .filter(|&i| frontier[i] && g.node(Id::from_index(i)).is_operation())
        .map(Id::from_index)
        .collect()
}

/// A sine or cosine argument that moves with one unknown: the unknown u_k
/// itself, or u_k plus an expression free of unknowns (an offset angle, a
/// driver), evaluated before the iteration's other values.
struct TrigArg {
    /// The argument node.
    arg: Id,
    /// Its sine and cosine nodes, either possibly absent.
    sin: Option<Id>,
    cos: Option<Id>,
}

/// The sines and cosines among the nodes reachable from `roots` whose
/// arguments move with one unknown ([`TrigArg`]), in arena order.
fn unknown_trig(g: &Graph, roots: &[Id], drivers: u32) -> Vec<TrigArg> {
    let unknown_of = |id: Id| match g.node(id) {
        Node::Leaf(Leaf::Q(j)) if j >= drivers => Some((j - drivers) as usize),
        _ => None,
    };
    let free = |id: Id| !g.depends_on(id, &|l| matches!(l, Leaf::Q(j) if j >= drivers));
    let live = g.reachable(roots);
    let mut out: Vec<TrigArg> = Vec::new();
    for (i, &is_live) in live.iter().enumerate() {
        let id = Id::from_index(i);
        let Node::Call(f @ (Func::Sin | Func::Cos), a) = g.node(id) else {
            continue;
        };
        let moves = match g.node(a) {
            Node::Leaf(_) => unknown_of(a),
            Node::Add(x, y) => match (unknown_of(x), unknown_of(y)) {
                (Some(k), None) if free(y) => Some(k),
                (None, Some(k)) if free(x) => Some(k),
                _ => None,
            },
            _ => None,
        };
        if moves.is_none() || !is_live {
            continue;
        }
        let at = match out.iter().position(|e| e.arg == a) {
            Some(at) => at,
            None => {
                out.push(TrigArg {
                    arg: a,
                    sin: None,
                    cos: None,
                });
                out.len() - 1
            }
        };
        if f == Func::Sin {
            out[at].sin = Some(id);
        } else {
            out[at].cos = Some(id);
        }
    }
    out
}

/// The bound nodes of stage `stage` that a later stage uses (as an operand
/// or as an output): these are carried out of the stage's evaluation.
fn used_later(
    g: &Graph,
    sched: &Schedule,
    stage: usize,
    _own: &[Id],
    later: &[&Vec<Id>],
) -> Vec<Id> {
    let mut keep = vec![false; g.len()];
    let in_stage = |i: usize| sched.stage_of[i] == Some(stage) && sched.bound[i];
    for i in 0..g.len() {
        if sched.stage_of[i].is_some_and(|s| s > stage) {
            for c in g.node(Id::from_index(i)).children() {
                if in_stage(c.index()) {
                    keep[c.index()] = true;
                }
            }
        }
    }
    for roots in later {
        for r in roots.iter() {
            if in_stage(r.index()) {
                keep[r.index()] = true;
            }
        }
    }
    (0..g.len())
        .filter(|&i| keep[i])
        .map(Id::from_index)
        .collect()
}

/// Operation counts, before and after common-subexpression elimination, of
/// the Newton step (Φ and Φ_u) and of the analysis (Φ_u, both right-hand
/// sides, and every point's position, velocity and acceleration).
pub fn operation_counts(model: &Model, d: &Derived) -> [(&'static str, OpCount); 2] {
    let g = &model.graph;
    let jac: Vec<Id> = d.jac.iter().flatten().copied().collect();
    let newton: Vec<Id> = d.phi.iter().chain(&jac).copied().collect();
    let analysis: Vec<Id> = jac
        .iter()
        .chain(&d.vel_rhs)
        .chain(&d.acc_rhs)
        .chain(d.pos.iter().flatten())
        .chain(d.vel.iter().flatten())
        .chain(d.acc.iter().flatten())
        .chain(d.frames.iter().flat_map(|f| f.omega.iter().chain(&f.alpha)))
        .copied()
        .collect();
    [
        ("residual and Jacobian", op_count(g, &newton)),
        ("velocity, acceleration and points", op_count(g, &analysis)),
    ]
}

/// The full expansion of a checked model.
pub fn expand(def: &Definition, model: &Model, d: &Derived, scales: &Scales) -> TokenStream {
    let id = Idents::new(def);
    let point_dim = model.point_dim;
    let types = types(def, &id, Some(&model.kinds), point_dim);
    let g = &model.graph;
    let leaf = id.leaf();
    let pp = quote!(::kinematics_core::__private);
    let Idents {
        name,
        coords,
        motion,
        params,
        coord,
        q,
        qd,
        qdd,
    } = &id;
    let nd = model.drivers as usize;
    let nu = model.unknowns as usize;
    let ne = model.equations.len();
    let np = model.points.len();
    // Lints the straight-line code may trip by construction: long literals
    // of exact constants, many similar temporaries, long bodies, and
    // coordinates a given function does not need.
    let allow = quote!(#[allow(unused_variables, clippy::unreadable_literal, clippy::similar_names, clippy::too_many_lines, clippy::many_single_char_names, clippy::excessive_precision, clippy::approx_constant)]);
    let (qd_drivers, qd_unknowns) = qd.split_at(nd);
    let (qdd_drivers, qdd_unknowns) = qdd.split_at(nd);
    let (q_drivers, q_unknowns) = q.split_at(nd);
    let (c_drivers, c_unknowns) = coord.split_at(nd);

    // Φ and Φ_u, for Newton.
    let jac_flat: Vec<Id> = d.jac.iter().flatten().copied().collect();
    let sched = schedule(g, std::slice::from_ref(&jac_flat));
    let (pr, lets) = bind(g, &sched, &leaf);
    // Φ_u into a row-major slice, nonzero entries only (the caller zeroes
    // it), with no N×N array of its own.
    let jac_stores = d.jac.iter().enumerate().flat_map(|(r, row)| {
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
    let phi_jac_fn = quote! {
        #[doc(hidden)]
        #[inline]
        #allow
        fn __jacobian_into(&self, d: &[f64; #nd], u: &[f64; #nu], out: &mut [f64]) {
            let [#(#q_drivers),*] = *d;
            let [#(#q_unknowns),*] = *u;
            #(#lets)*
            #(#jac_stores)*
        }
    };

    // Φ alone.
    let sched = schedule(g, std::slice::from_ref(&d.phi));
    let (pr, lets) = bind(g, &sched, &leaf);
    let phi_e: Vec<_> = d.phi.iter().map(|&i| pr.element(i)).collect();
    let phi_fn = quote! {
        #[doc(hidden)]
        #[inline]
        #allow
        fn __phi(&self, d: &[f64; #nd], u: &[f64; #nu]) -> [f64; #ne] {
            let [#(#q_drivers),*] = *d;
            let [#(#q_unknowns),*] = *u;
            #(#lets)*
            [#(#phi_e),*]
        }
    };

    // Point positions alone.
    let pos_flat: Vec<Id> = d.pos.iter().flatten().copied().collect();
    let sched = schedule(g, std::slice::from_ref(&pos_flat));
    let (pr, lets) = bind(g, &sched, &leaf);
    let vector = |pr: &Printer<'_>, c: &[Id]| {
        let e: Vec<_> = c.iter().map(|&i| pr.expr(i)).collect();
        if c.len() == 3 {
            quote!(#pp::Vector3::new(#(#e),*))
        } else {
            quote!(#pp::Vector2::new(#(#e),*))
        }
    };
    let vtype = if point_dim == 3 {
        quote!(#pp::Vector3<f64>)
    } else {
        quote!(#pp::Vector2<f64>)
    };
    let pos_e: Vec<_> = d.pos.iter().map(|c| vector(&pr, c)).collect();
    let positions_fn = quote! {
        /// Positions of the points (in declaration order) at `pose`, which
        /// should be assembled: r_P(q).
        #[must_use]
        #allow
        pub fn point_positions(&self, pose: &#coords) -> [#vtype; #np] {
            #( let #q = pose.#coord; )*
            #(#lets)*
            [#(#pos_e),*]
        }
    };

    // Frame rotations alone.
    let nf = d.frames.len();
    let rot_flat: Vec<Id> = d
        .frames
        .iter()
        .flat_map(|f| f.rotation.iter().flatten().copied())
        .collect();
    let sched = schedule(g, std::slice::from_ref(&rot_flat));
    let (pr, lets) = bind(g, &sched, &leaf);
    let matrix = |pr: &Printer<'_>, m: &[[Id; 3]; 3]| {
        let e: Vec<_> = m.iter().flatten().map(|&i| pr.expr(i)).collect();
        quote!(#pp::Matrix3::new(#(#e),*))
    };
    let rot_e: Vec<_> = d.frames.iter().map(|f| matrix(&pr, &f.rotation)).collect();
    let rotations_fn = quote! {
        /// Rotation matrices R(q) of the frames (in declaration order) at
        /// `pose`.
        #[must_use]
        #allow
        pub fn frame_rotations(&self, pose: &#coords) -> [#pp::Matrix3<f64>; #nf] {
            #( let #q = pose.#coord; )*
            #(#lets)*
            [#(#rot_e),*]
        }
    };

    // Analysis: Φ_u and −Φ_d d'; solve; −Φ_d d'' − γ; solve; points.
    let vel_stage: Vec<Id> = jac_flat.iter().chain(&d.vel_rhs).copied().collect();
    let acc_stage = d.acc_rhs.clone();
    let pt_stage: Vec<Id> = d
        .pos
        .iter()
        .chain(&d.vel)
        .chain(&d.acc)
        .flatten()
        .copied()
        .chain(d.frames.iter().flat_map(|f| {
            f.rotation
                .iter()
                .chain(&f.origin)
                .flatten()
                .chain(&f.omega)
                .chain(&f.alpha)
                .copied()
                .collect::<Vec<_>>()
        }))
        .collect();
    // Output expressions under a given schedule's names.
    let blocks = BlockSolve::new(g, &d.jac, &scales.is_length);
    let nnz = blocks.nnz();
    let jac_rows_of = |pr: &Printer<'_>| -> TokenStream {
        let full: Vec<Vec<TokenStream>> = d
            .jac
            .iter()
            .map(|row| row.iter().map(|&i| pr.element(i)).collect())
            .collect();
        blocks.array(&full)
    };
    let points_of = |pr: &Printer<'_>| -> Vec<TokenStream> {
        (0..np)
            .map(|k| {
                let (p, v, a) = (
                    vector(pr, &d.pos[k]),
                    vector(pr, &d.vel[k]),
                    vector(pr, &d.acc[k]),
                );
                quote!(#pp::PointMotion { position: #p, velocity: #v, acceleration: #a })
            })
            .collect()
    };
    let frames_of = |pr: &Printer<'_>| -> Vec<TokenStream> {
        d.frames
            .iter()
            .map(|f| {
                let r = matrix(pr, &f.rotation);
                let [o, od, odd] = &f.origin;
                let (o, od, odd) = (vector(pr, o), vector(pr, od), vector(pr, odd));
                let (w, al) = (vector(pr, &f.omega), vector(pr, &f.alpha));
                quote!(#pp::FrameState {
                    rotation: #r,
                    origin: #o,
                    velocity: #od,
                    acceleration: #odd,
                    angular_velocity: #w,
                    angular_acceleration: #al,
                })
            })
            .collect()
    };

    // The fused step: Newton with the driver-only part of Φ and Φ_u hoisted
    // out of the loop, and the values the analysis needs kept from the last
    // (converged) Newton evaluation instead of recomputed.
    let newton_roots: Vec<Id> = d.phi.iter().chain(&jac_flat).copied().collect();
    let frontier = driver_frontier(g, &newton_roots, model.drivers);
    let fsched = schedule(
        g,
        &[
            frontier,
            newton_roots.clone(),
            vel_stage.clone(),
            acc_stage.clone(),
            pt_stage.clone(),
        ],
    );
    let cached = used_later(
        g,
        &fsched,
        1,
        &newton_roots,
        &[&vel_stage, &acc_stage, &pt_stage],
    );
    let (fpr, flets) = bind(g, &fsched, &leaf);
    // Newton's common path in `step` carries the sine and cosine of each
    // unknown angle from one iterate to the next (`sin_cos_after`): the
    // same schedule, with those nodes read from variables. The step of the
    // argument is the difference of its evaluated values, so that the
    // carried values follow the argument as evaluated in floating point
    // (an offset of 1e20 rad leaves u + γ unchanged by a small step in u).
    let mut given = HashMap::new();
    let (mut trig_setup, mut trig_eval) = (TokenStream::new(), TokenStream::new());
    for (n, t) in unknown_trig(g, &newton_roots, model.drivers)
        .into_iter()
        .enumerate()
    {
        // The argument as an expression of u_k and values bound before the
        // iteration (the part free of unknowns is driver-only or constant).
        let arg = fpr.body(t.arg);
        let (sv, cv, av) = (
            format_ident!("__sin_{}", n),
            format_ident!("__cos_{}", n),
            format_ident!("__arg_{}", n),
        );
        given.extend(t.sin.map(|id| (id, sv.clone())));
        given.extend(t.cos.map(|id| (id, cv.clone())));
        trig_setup.extend(quote! {
            let (mut #sv, mut #cv, mut #av) = (0.0f64, 0.0f64, ::core::primitive::f64::NAN);
        });
        trig_eval.extend(quote! {
            let __x = #arg;
            (#sv, #cv) = #pp::sin_cos_after(#sv, #cv, __x, __x - #av);
            #av = __x;
        });
    }
    let (_, fast_lets) = bind_given(g, &fsched, &leaf, given);
    let f1_fast = &fast_lets[1];
    let newton_factor = blocks.factor(&pp, false, &|_| quote!(break false));
    let newton_solve = blocks.solve(&quote!(phi), false);
    let fail_here = |f: TokenStream| quote!(return ::core::result::Result::Err(#pp::describe(#f, &Self::__NAMES, &[#(#q),*])););
    let analysis_factor = blocks.factor(&pp, true, &fail_here);
    // The linear solve of the general Newton solver: Φ_u x = rhs through
    // the factored blocks, at the last evaluation's `jac`.
    let solver = {
        let factor = blocks.factor(
            &pp,
            true,
            &|f| quote!(return ::core::result::Result::Err(#f);),
        );
        let solve = blocks.solve(&quote!(*rhs), true);
        quote! {
            |jac: &[f64; #nnz], rhs: &[f64; #nu]| -> ::core::result::Result<[f64; #nu], #pp::Failure> {
                #factor
                ::core::result::Result::Ok(#solve)
            }
        }
    };
    let analysis_check = blocks.check(&pp, &fail_here);
    let analysis_factor = quote!(#analysis_factor #analysis_check);
    let scaling = {
        let leaf = id.leaf();
        scaling_code(
            g,
            scales,
            &leaf,
            params.len(),
            &pp,
            &quote!(return ::core::result::Result::Err(#pp::describe(f, &Self::__NAMES, &[#(#q_drivers),*]));),
        )
    };
    let cached_names: Vec<&Ident> = cached.iter().filter_map(|id| fpr.names.get(id)).collect();
    let nc = cached_names.len();
    let (f0, f1, f2, f3, f4) = (&flets[0], &flets[1], &flets[2], &flets[3], &flets[4]);
    let fphi: Vec<_> = d.phi.iter().map(|&i| fpr.element(i)).collect();
    let fjac_rows = jac_rows_of(&fpr);
    let fvel: Vec<_> = d.vel_rhs.iter().map(|&i| fpr.element(i)).collect();
    let facc: Vec<_> = d.acc_rhs.iter().map(|&i| fpr.element(i)).collect();
    let fpoints = points_of(&fpr);
    let fframes = frames_of(&fpr);

    // Assembly alone, with the same hoisting.
    let asched = schedule(
        g,
        &[
            driver_frontier(g, &newton_roots, model.drivers),
            newton_roots.clone(),
        ],
    );
    let (apr, alets) = bind(g, &asched, &leaf);
    let (a0, a1) = (&alets[0], &alets[1]);
    let aphi: Vec<_> = d.phi.iter().map(|&i| apr.element(i)).collect();
    let ajac_rows = jac_rows_of(&apr);

    let sched = schedule(g, &[vel_stage, acc_stage, pt_stage]);
    let (pr, lets) = bind(g, &sched, &leaf);
    let (lets1, lets2, lets3) = (&lets[0], &lets[1], &lets[2]);
    let jac_rows = jac_rows_of(&pr);
    let vel_e: Vec<_> = d.vel_rhs.iter().map(|&i| pr.element(i)).collect();
    let acc_e: Vec<_> = d.acc_rhs.iter().map(|&i| pr.element(i)).collect();
    let fvel_solve = blocks.solve(&quote!([#(#fvel),*]), true);
    let facc_solve = blocks.solve(&quote!([#(#facc),*]), true);
    let vel_solve = blocks.solve(&quote!([#(#vel_e),*]), true);
    let acc_solve = blocks.solve(&quote!([#(#acc_e),*]), true);
    let points_e = points_of(&pr);
    let frames_e = frames_of(&pr);
    let frame_names: Vec<String> = def
        .frames
        .iter()
        .map(|f| f.name.unraw().to_string())
        .collect();
    let all_q = q.iter();
    let finite_out = |vals: &[Ident]| {
        let names: Vec<String> = c_unknowns.iter().map(|c| c.unraw().to_string()).collect();
        quote!(#( #pp::finite(#pp::Input::Computed, #names, #vals)?; )*)
    };
    let check_qd = finite_out(qd_unknowns);
    let check_qdd = finite_out(qdd_unknowns);
    let rate_values: Vec<TokenStream> = qd_unknowns
        .iter()
        .chain(qdd_unknowns)
        .map(|v| quote!(#v))
        .collect();
    let check_rates = guarded(&rate_values, &quote!(#check_qd #check_qdd));
    let driver_names: Vec<String> = c_drivers.iter().map(|c| c.unraw().to_string()).collect();
    let unknown_names: Vec<String> = c_unknowns.iter().map(|c| c.unraw().to_string()).collect();
    let param_names: Vec<String> = params.iter().map(|c| c.unraw().to_string()).collect();
    let coord_names: Vec<String> = coord.iter().map(|c| c.unraw().to_string()).collect();
    let eq_names: Vec<&str> = model.equations.iter().map(|e| e.text.as_str()).collect();
    let point_names: Vec<String> = def
        .points
        .iter()
        .map(|p| p.name.unraw().to_string())
        .collect();
    let lengths: Vec<&Ident> = def
        .params
        .iter()
        .filter(|p| p.length)
        .map(|p| &p.name)
        .collect();
    let length_names: Vec<String> = lengths.iter().map(|c| c.unraw().to_string()).collect();
    let validate_checks = guarded(
        &params.iter().map(|p| quote!(self.#p)).collect::<Vec<_>>(),
        &quote!(#( #pp::finite(#pp::Input::Parameter, #param_names, self.#params)?; )*),
    );
    let validate_checks = quote! {
        #validate_checks
        #( #pp::positive(#length_names, self.#lengths)?; )*
    };
    let input_values: Vec<TokenStream> = c_drivers
        .iter()
        .chain(c_unknowns)
        .map(|c| quote!(start.#c))
        .chain(qd_drivers.iter().chain(qdd_drivers).map(|v| quote!(#v)))
        .collect();
    let step_inputs = guarded(
        &input_values,
        &quote! {
            #( #pp::finite(#pp::Input::Driver, #driver_names, start.#c_drivers)?; )*
            #( #pp::finite(#pp::Input::Guess, #unknown_names, start.#c_unknowns)?; )*
            #( #pp::finite(#pp::Input::DriverRate, #driver_names, #qd_drivers)?; )*
            #( #pp::finite(#pp::Input::DriverAcceleration, #driver_names, #qdd_drivers)?; )*
        },
    );
    let pose_values: Vec<TokenStream> = c_drivers
        .iter()
        .chain(c_unknowns)
        .map(|c| quote!(pose.#c))
        .chain(qd_drivers.iter().chain(qdd_drivers).map(|v| quote!(#v)))
        .collect();
    let analyze_inputs = guarded(
        &pose_values,
        &quote! {
            #( #pp::finite(#pp::Input::Driver, #driver_names, pose.#c_drivers)?; )*
            #( #pp::finite(#pp::Input::Guess, #unknown_names, pose.#c_unknowns)?; )*
            #( #pp::finite(#pp::Input::DriverRate, #driver_names, #qd_drivers)?; )*
            #( #pp::finite(#pp::Input::DriverAcceleration, #driver_names, #qdd_drivers)?; )*
        },
    );
    let start_values: Vec<TokenStream> = c_drivers
        .iter()
        .chain(c_unknowns)
        .map(|c| quote!(start.#c))
        .collect();
    let assemble_inputs = guarded(
        &start_values,
        &quote! {
            #( #pp::finite(#pp::Input::Driver, #driver_names, start.#c_drivers)?; )*
            #( #pp::finite(#pp::Input::Guess, #unknown_names, start.#c_unknowns)?; )*
        },
    );
    // Outputs: one sum over every point and frame component (any NaN or
    // infinity makes it non-finite), then the named checks if it is not.
    let mut out_terms: Vec<TokenStream> = Vec::new();
    for k in 0..np {
        for field in [quote!(position), quote!(velocity), quote!(acceleration)] {
            for c in 0..point_dim {
                out_terms.push(quote!(motion.points[#k].#field[#c]));
            }
        }
    }
    for k in 0..nf {
        for c in 0..9usize {
            out_terms.push(quote!(motion.frames[#k].rotation[#c]));
        }
        for field in [
            quote!(origin),
            quote!(velocity),
            quote!(acceleration),
            quote!(angular_velocity),
            quote!(angular_acceleration),
        ] {
            for c in 0..3usize {
                out_terms.push(quote!(motion.frames[#k].#field[#c]));
            }
        }
    }
    let output_sum = if out_terms.is_empty() {
        quote!(0.0f64)
    } else {
        quote!(#(#out_terms)+*)
    };
    let coordinate_info = model.kinds.iter().enumerate().map(|(j, k)| {
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
    let counts = {
        let [(n0, n), (a0, a)] = operation_counts(model, d);
        let (nt, ns, at, as_) = (n.tree, n.shared, a.tree, a.shared);
        quote!([(#n0, #nt, #ns), (#a0, #at, #as_)])
    };

    quote! {
        #types

        impl #name {
            /// Number of drivers (prescribed inputs).
            pub const DRIVERS: usize = #nd;
            /// Number of unknowns (solved joint variables).
            pub const UNKNOWNS: usize = #nu;
            /// Number of scalar loop-closure equations.
            pub const EQUATIONS: usize = #ne;
            /// Number of points of interest.
            pub const POINTS: usize = #np;
            /// Number of body frames.
            pub const FRAMES: usize = #nf;
            /// Floating-point operations of the generated code: for the Newton
            /// step and for the analysis, the count if every expression were
            /// written out as a tree, then the count after common-subexpression
            /// elimination (what the emitted code evaluates).
            #[doc(hidden)]
            pub const __OPERATION_COUNTS: [(&'static str, u64, usize); 2] = #counts;
            #[doc(hidden)]
            const __NAMES: #pp::Names = #pp::Names {
                coordinates: &[#(#coord_names),*],
                drivers: #nd,
                equations: &[#(#eq_names),*],
            };

            /// Checks that every parameter is finite.
            ///
            /// # Errors
            /// [`Error::NonFinite`](::kinematics_core::Error::NonFinite) naming the parameter.
            pub fn validate(&self) -> #pp::Result<(), #pp::Error> {
                #validate_checks
                ::core::result::Result::Ok(())
            }

            /// Assembles the mechanism: solves the loop-closure equations
            /// Φ(d, u) = 0 for the unknowns u by Newton–Raphson, with the
            /// drivers d and the starting guess of u taken from `start`. The
            /// result is the assembly branch nearest the guess.
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
                #assemble_inputs
                let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
                #scaling
                #a0
                let mut u = [#(start.#c_unknowns),*];
                let mut phi = [0.0f64; #ne];
                let mut jac = [0.0f64; #nnz];
                let solved = #pp::newton(&mut u, &mut phi, &mut jac, &__scaling, options, |u, phi, jac| {
                    let [#(#q_unknowns),*] = *u;
                    #a1
                    *phi = [#(#aphi),*];
                    *jac = #ajac_rows;
                }, #solver);
                let [#(#q_unknowns),*] = u;
                if let ::core::result::Result::Err(f) = solved {
                    return ::core::result::Result::Err(#pp::describe(f, &Self::__NAMES, &[#(#q),*]));
                }
                // The singularity and the branch are judged at the solution.
                #analysis_factor
                let _ = (__conditioning, __det_sign);
                ::core::result::Result::Ok(#coords { #( #coord: #q ),* })
            }

            /// Assembles at the drivers of `start` from its unknowns (as
            /// [`Self::assemble`]) and analyses the motion there (as
            /// [`Self::analyze`]), in one pass: the last Newton evaluation's
            /// sines, cosines and Jacobian are reused, not recomputed. The
            /// step of a simulation that advances the drivers.
            ///
            /// # Errors
            /// As [`Self::assemble`] and [`Self::analyze`].
            pub fn step(
                &self,
                start: &#coords,
                rates: impl #pp::DriverValues<#nd>,
                accelerations: impl #pp::DriverValues<#nd>,
            ) -> #pp::Result<#motion, #pp::Error> {
                self.__step(start, rates, accelerations, &#pp::Options::DEFAULT)
            }

            /// [`Self::step`] with explicit solver options.
            ///
            /// # Errors
            /// As [`Self::step`], and invalid options.
            pub fn step_with(
                &self,
                start: &#coords,
                rates: impl #pp::DriverValues<#nd>,
                accelerations: impl #pp::DriverValues<#nd>,
                options: &#pp::Options,
            ) -> #pp::Result<#motion, #pp::Error> {
                self.__step(start, rates, accelerations, options)
            }

            /// The body of [`Self::step`] and [`Self::step_with`]: inlined
            /// into each, so that with the default options their checks fold
            /// away at compile time.
            #[doc(hidden)]
            #[inline(always)]
            #allow
            #[allow(unused_assignments)]
            fn __step(
                &self,
                start: &#coords,
                rates: impl #pp::DriverValues<#nd>,
                accelerations: impl #pp::DriverValues<#nd>,
                options: &#pp::Options,
            ) -> #pp::Result<#motion, #pp::Error> {
                options.validate()?;
                self.validate()?;
                let [#(#qd_drivers),*] = rates.into_array();
                let [#(#qdd_drivers),*] = accelerations.into_array();
                #step_inputs
                let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
                #scaling
                let __weights = __scaling.weights(options);
                #f0
                let mut cache = [0.0f64; #nc];
                let mut u = [#(start.#c_unknowns),*];
                // Newton's common path, evaluated inline; anything off it
                // (damping, round-off, failure) goes to the general solver.
                let mut fast = #pp::FastNewton::new();
                #trig_setup
                let on_path = loop {
                    let [#(#q_unknowns),*] = u;
                    #trig_eval
                    #f1_fast
                    cache = [#(#cached_names),*];
                    let phi = [#(#fphi),*];
                    let jac: [f64; #nnz] = #fjac_rows;
                    match fast.assess(&phi, &__weights, options) {
                        #pp::Next::Continue => {}
                        #pp::Next::Converged => break true,
                        #pp::Next::Fallback => break false,
                    }
                    #newton_factor
                    fast.advance(&mut u, &#newton_solve);
                };
                if !on_path {
                    u = [#(start.#c_unknowns),*];
                    let mut phi = [0.0f64; #ne];
                    let mut jac = [0.0f64; #nnz];
                    let solved = #pp::newton(&mut u, &mut phi, &mut jac, &__scaling, options, |u, phi, jac| {
                        let [#(#q_unknowns),*] = *u;
                        #f1
                        *phi = [#(#fphi),*];
                        *jac = #fjac_rows;
                        cache = [#(#cached_names),*];
                    }, #solver);
                    if let ::core::result::Result::Err(f) = solved {
                        let [#(#q_unknowns),*] = u;
                        return ::core::result::Result::Err(#pp::describe(f, &Self::__NAMES, &[#(#q),*]));
                    }
                }
                let [#(#q_unknowns),*] = u;
                let [#(#cached_names),*] = cache;
                #f2
                let jac: [f64; #nnz] = #fjac_rows;
                #analysis_factor
                let [#(#qd_unknowns),*] = #fvel_solve;
                #f3
                let [#(#qdd_unknowns),*] = #facc_solve;
                #check_rates
                #f4
                let motion = #motion {
                    q: #coords { #( #coord: #q ),* },
                    qd: #coords { #( #coord: #qd ),* },
                    qdd: #coords { #( #coord: #qdd ),* },
                    points: [#(#fpoints),*],
                    frames: [#(#fframes),*],
                    conditioning: __conditioning,
                    det_sign: __det_sign,
                };
                if !(#output_sum).is_finite() {
                    #pp::finite_outputs(
                        &motion.points,
                        <Self as #pp::Mechanism>::POINT_NAMES,
                        &motion.frames,
                        <Self as #pp::Mechanism>::FRAME_NAMES,
                    )?;
                }
                ::core::result::Result::Ok(motion)
            }

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
            #[inline(always)]
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
                #analyze_inputs
                #( let #all_q = pose.#coord; )*
                #scaling
                #lets1
                let jac: [f64; #nnz] = #jac_rows;
                #analysis_factor
                let [#(#qd_unknowns),*] = #vel_solve;
                #lets2
                let [#(#qdd_unknowns),*] = #acc_solve;
                #check_rates
                #lets3
                let motion = #motion {
                    q: *pose,
                    qd: #coords { #( #coord: #qd ),* },
                    qdd: #coords { #( #coord: #qdd ),* },
                    points: [#(#points_e),*],
                    frames: [#(#frames_e),*],
                    conditioning: __conditioning,
                    det_sign: __det_sign,
                };
                if !(#output_sum).is_finite() {
                    #pp::finite_outputs(
                        &motion.points,
                        <Self as #pp::Mechanism>::POINT_NAMES,
                        &motion.frames,
                        <Self as #pp::Mechanism>::FRAME_NAMES,
                    )?;
                }
                ::core::result::Result::Ok(motion)
            }

            /// Residuals Φ_i of the loop-closure equations at `pose` (zero
            /// when assembled), in the order of [`Self::EQUATIONS`].
            #[must_use]
            pub fn residual(&self, pose: &#coords) -> [f64; #ne] {
                self.__phi(&[#(pose.#c_drivers),*], &[#(pose.#c_unknowns),*])
            }

            #positions_fn
            #rotations_fn
            #phi_jac_fn
            #phi_fn
        }

        #[automatically_derived]
        impl #pp::Mechanism for #name {
            type Coords = #coords;
            type Motion = #motion;
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
                let (::core::result::Result::Ok(r), ::core::result::Result::Ok(a)) =
                    (<[f64; #nd]>::try_from(rates), <[f64; #nd]>::try_from(accelerations))
                else {
                    return ::core::result::Result::Err(#pp::Error::InvalidOption {
                        name: "rates and accelerations",
                        #[allow(clippy::cast_precision_loss)]
                        value: rates.len().max(accelerations.len()) as f64,
                        requirement: "must have one value per driver",
                    });
                };
                #name::step_with(self, start, r, a, options)
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
